use dirac::prelude::*;

// A coupling through the absolute group coordinate: `q0.x * q1.theta` instead of
// `q0.x * (q1.theta - q0.theta)`.
#[reduced_lagrangian(shape(x), group(theta))]
fn particle(q0: Config, q1: Config, h: f64, m: f64) -> f64 {
    let (dx, dg) = (q1.x - q0.x, q1.theta - q0.theta);
    let s = dg + q0.x * q1.theta;
    0.5 * m / h * (dx * dx + s * s)
}

fn main() {}
