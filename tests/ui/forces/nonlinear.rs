use dirac::prelude::*;

#[reduced_lagrangian(shape(x), group(), rule = midpoint, force = |dq| -c * dq.x * dq.x)]
fn damped(q: Config, v: Velocity, c: f64) -> f64 {
    0.5 * v.x * v.x - 0.5 * q.x * q.x
}

fn main() {}
