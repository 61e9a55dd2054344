use dirac::prelude::*;

// Gravity along `z` breaks translation in `z`: `z` cannot be a group coordinate.
#[reduced_lagrangian(shape(x), group(z))]
fn falling(q0: Config, q1: Config, h: f64, m: f64, g: f64) -> f64 {
    let (dx, dz) = (q1.x - q0.x, q1.z - q0.z);
    0.5 * m / h * (dx * dx + dz * dz) - h * m * g * q0.z
}

fn main() {}
