use dirac::prelude::*;

// The field is vertical: the rotations about the x-axis are not a symmetry.
#[reduced_lagrangian(direction(n), symmetry(n, axis = x))]
fn pendulum(q0: Config, q1: Config, h: f64, g: f64) -> f64 {
    let d = q1.n - q0.n;
    0.5 * d.norm_squared() / h - 0.5 * h * g * (q0.n.z + q1.n.z)
}

fn main() {}
