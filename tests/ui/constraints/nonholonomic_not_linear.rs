use dirac::prelude::*;

// A nonholonomic constraint is linear in the velocity: `v.x * v.x` is not.
#[reduced_lagrangian(shape(theta), group(x, y), rule = midpoint,
    nonholonomic = |q, v| [q.theta.cos() * v.y - v.x * v.x])]
fn sleigh(q: Config, v: Velocity, m: f64) -> f64 {
    0.5 * m * (v.x * v.x + v.y * v.y + v.theta * v.theta)
}

fn main() {}
