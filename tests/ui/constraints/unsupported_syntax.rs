use dirac::prelude::*;

#[reduced_lagrangian(shape(x, y), group(), rule = midpoint,
    constraints = |q| [if q.x > 0.0 { q.x } else { -q.x } - 1.0])]
fn pendulum(q: Config, v: Velocity, m: f64) -> f64 {
    0.5 * m * (v.x * v.x + v.y * v.y) - 9.81 * m * q.y
}

fn main() {}
