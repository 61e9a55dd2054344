use dirac::prelude::*;

// A spring on the group coordinate breaks the symmetry the reduction uses.
#[reduced_lagrangian(shape(x), group(theta), rule = midpoint, force = |dq| -k * q.theta * dq.theta)]
fn rotor(q: Config, v: Velocity, k: f64) -> f64 {
    0.5 * v.theta * v.theta + 0.5 * v.x * v.x - 0.5 * q.x * q.x
}

fn main() {}
