use dirac::prelude::*;

#[reduced_lagrangian(shape(x), group(theta), ranges(h = (0.1, 0.001)))]
fn particle(q0: Config, q1: Config, h: f64, m: f64) -> f64 {
    let (dx, dg) = (q1.x - q0.x, q1.theta - q0.theta);
    0.5 * m / h * (dx * dx + dg * dg)
}

fn main() {}
