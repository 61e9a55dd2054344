use dirac::prelude::*;

#[reduced_lagrangian(shape(x, y), group(theta), connection = [0.0, 1.0])]
fn particle(q0: Config, q1: Config, h: f64, m: f64) -> f64 {
    let (dx, dy, dg) = (q1.x - q0.x, q1.y - q0.y, q1.theta - q0.theta);
    0.5 * m / h * (dx * dx + dy * dy + dg * dg)
}

fn main() {}
