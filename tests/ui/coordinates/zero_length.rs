use dirac::prelude::*;

#[reduced_lagrangian(shape(x[0], y), group(theta))]
fn particle(q0: Config, q1: Config, h: f64, m: f64) -> f64 {
    let (dy, dg) = (q1.y - q0.y, q1.theta - q0.theta);
    0.5 * m / h * (dy * dy + dg * dg)
}

fn main() {}
