use dirac::prelude::*;

#[reduced_lagrangian(group(theta))]
fn particle(q0: Config, q1: Config, h: f64, m: f64) -> f64 {
    let dg = q1.theta - q0.theta;
    0.5 * m / h * dg * dg
}

fn main() {}
