use dirac::prelude::*;

// The monitor reads the angle, a group coordinate: it would break that symmetry.
#[reduced_lagrangian(shape(r), group(theta, t), time(t), adapt = |q| q.r * q.theta, rule = midpoint)]
fn kepler(q: Config, v: Velocity, k: f64) -> f64 {
    0.5 * (v.r * v.r + q.r * q.r * v.theta * v.theta) + k / q.r
}

fn main() {}
