use dirac::prelude::*;

#[reduced_lagrangian(shape(x, y), group(), rule = midpoint,
    constraints = |q, v| [q.x * q.x + q.y * q.y - 1.0])]
fn pendulum(q: Config, v: Velocity, m: f64) -> f64 {
    0.5 * m * (v.x * v.x + v.y * v.y) - 9.81 * m * q.y
}

fn main() {}
