use dirac::prelude::*;

// Constraints need the continuous Legendre map to keep the momenta on the constraint.
#[reduced_lagrangian(shape(x, y), group(), constraints = |q| [q.x * q.x + q.y * q.y - 1.0])]
fn pendulum(q0: Config, q1: Config, h: f64) -> f64 {
    let (vx, vy) = ((q1.x - q0.x) / h, (q1.y - q0.y) / h);
    h * (0.5 * (vx * vx + vy * vy) - 9.81 * q0.y)
}

fn main() {}
