use dirac::prelude::*;

// The constraint reads the group coordinate `z` itself: translating `z` is no symmetry of it.
#[reduced_lagrangian(shape(x, y), group(z), rule = midpoint,
    constraints = |q| [q.x * q.x + q.y * q.y + q.z * q.z - 1.0])]
fn bead(q: Config, v: Velocity, m: f64) -> f64 {
    0.5 * m * (v.x * v.x + v.y * v.y + v.z * v.z)
}

fn main() {}
