use dirac::prelude::*;

// A top in a field is not invariant under every rotation of its attitude.
#[reduced_lagrangian(rotation(r), symmetry(r))]
fn top(q0: Config, q1: Config, h: f64, mgl: f64) -> f64 {
    let f = q0.r.transpose() * q1.r;
    (Matrix3::identity() - f).trace() / h - 0.5 * h * mgl * (q0.r[(2, 2)] + q1.r[(2, 2)])
}

fn main() {}
