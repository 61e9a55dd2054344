use dirac::prelude::*;

const N: usize = 3;

#[reduced_lagrangian(shape(x[N]), group(theta))]
fn chain(q0: Config, q1: Config, h: f64, m: f64) -> f64 {
    let dx = q1.x[0] - q0.x[0];
    0.5 * m / h * (dx * dx + (q1.theta - q0.theta).powi(2))
}

fn main() {}
