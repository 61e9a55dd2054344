use dirac::prelude::*;

#[reduced_lagrangian(direction(n))]
fn pendulum(q0: Config, q1: Config, h: f64, g: f64) -> f64 {
    let c = q0.n * q1.n;
    c / h - h * g * q0.n.z
}

fn main() {}
