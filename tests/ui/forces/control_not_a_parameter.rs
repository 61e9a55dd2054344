use dirac::prelude::*;

#[reduced_lagrangian(shape(x), group(theta), rule = midpoint, controls(torque), force = |dq| tau * dq.theta)]
fn rotor(q: Config, v: Velocity, tau: f64) -> f64 {
    0.5 * v.theta * v.theta + 0.5 * v.x * v.x - 0.5 * q.x * q.x
}

fn main() {}
