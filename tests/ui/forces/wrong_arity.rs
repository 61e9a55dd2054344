use dirac::prelude::*;

// A discrete Lagrangian's forces act on both configurations: `|dq0, dq1|`.
#[reduced_lagrangian(shape(x), group(), force = |dq| -c * dq.x)]
fn damped(q0: Config, q1: Config, h: f64, c: f64) -> f64 {
    let v = (q1.x - q0.x) / h;
    h * (0.5 * v * v - 0.5 * q0.x * q0.x)
}

fn main() {}
