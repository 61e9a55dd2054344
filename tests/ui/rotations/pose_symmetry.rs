use dirac::prelude::*;

// A pose is not reduced by `symmetry(..)`: only rotation and direction coordinates are listed.
#[reduced_lagrangian(pose(body), symmetry(body))]
fn free(q0: Config, q1: Config, h: f64, m: f64) -> f64 {
    let f = q0.body.rotation.transpose() * q1.body.rotation;
    let dx = q1.body.translation - q0.body.translation;
    (Matrix3::identity() - f).trace() / h + 0.5 * m * dx.norm_squared() / h
}

fn main() {}
