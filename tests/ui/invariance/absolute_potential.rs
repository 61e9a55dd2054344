use dirac::prelude::*;

// A pendulum potential written in the group coordinate: `cos θ` changes when θ is translated.
#[reduced_lagrangian(shape(x), group(theta))]
fn particle(q0: Config, q1: Config, h: f64, m: f64) -> f64 {
    let (dx, dg) = (q1.x - q0.x, q1.theta - q0.theta);
    0.5 * m / h * (dx * dx + dg * dg) - h * q0.theta.cos()
}

fn main() {}
