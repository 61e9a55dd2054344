use dirac::prelude::*;

#[reduced_lagrangian(shape(x[3]), group(theta))]
fn chain(q0: Config, q1: Config, h: f64, m: f64) -> f64 {
    let j = 1.0;
    let dx = q1.x[j] - q0.x[1];
    0.5 * m / h * (dx * dx + (q1.theta - q0.theta).powi(2))
}

fn main() {}
