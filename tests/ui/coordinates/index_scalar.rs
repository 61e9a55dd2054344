use dirac::prelude::*;

#[reduced_lagrangian(shape(x[2], y), group(theta))]
fn particle(q0: Config, q1: Config, h: f64, m: f64) -> f64 {
    let (dx, dy) = (q1.x[0] - q0.x[0], q1.y[0] - q0.y);
    0.5 * m / h * (dx * dx + dy * dy + (q1.theta - q0.theta).powi(2))
}

fn main() {}
