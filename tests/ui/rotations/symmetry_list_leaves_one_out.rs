use dirac::prelude::*;

// The coupling compares n1 with n2: rotating n1 alone is not a symmetry.
#[reduced_lagrangian(direction(n1, n2), symmetry(n1, axis = z))]
fn pair(q0: Config, q1: Config, h: f64, k: f64) -> f64 {
    let (d1, d2) = (q1.n1 - q0.n1, q1.n2 - q0.n2);
    0.5 * (d1.norm_squared() + d2.norm_squared()) / h - h * k * q0.n1.dot(&q0.n2)
}

fn main() {}
