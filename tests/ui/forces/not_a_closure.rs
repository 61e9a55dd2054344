use dirac::prelude::*;

#[reduced_lagrangian(shape(x), group(), rule = midpoint, force = -0.1)]
fn damped(q: Config, v: Velocity) -> f64 {
    0.5 * v.x * v.x - 0.5 * q.x * q.x
}

fn main() {}
