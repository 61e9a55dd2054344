use dirac::prelude::*;

#[reduced_lagrangian(shape(x), group(), rule = midpoint)]
fn particle(q0: Config, q1: Config, h: f64, m: f64) -> f64 {
    let dx = q1.x - q0.x;
    0.5 * m / h * dx * dx
}

fn main() {}
