use dirac::prelude::*;

// A pose is reduced by every rigid motion, alone: not by the rotations about an axis.
#[reduced_lagrangian(pose(body), symmetry(body, axis = z))]
fn free(q0: Config, q1: Config, h: f64, m: f64) -> f64 {
    let f = q0.body.rotation.transpose() * q1.body.rotation;
    let dx = q1.body.translation - q0.body.translation;
    (Matrix3::identity() - f).trace() / h + 0.5 * m * dx.norm_squared() / h
}

fn main() {}
