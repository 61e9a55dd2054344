use dirac::prelude::*;

// θ1² − θ0² is not a function of θ1 − θ0: translating both by g adds 2g(θ1 − θ0).
#[reduced_lagrangian(shape(x), group(theta))]
fn particle(q0: Config, q1: Config, h: f64, m: f64) -> f64 {
    let dx = q1.x - q0.x;
    0.5 * m / h * (dx * dx + q1.theta * q1.theta - q0.theta * q0.theta)
}

fn main() {}
