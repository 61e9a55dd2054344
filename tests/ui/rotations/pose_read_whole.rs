use dirac::prelude::*;

// A pose is read one part at a time: `q1.body.translation`, not `q1.body`.
#[reduced_lagrangian(pose(body))]
fn free(q0: Config, q1: Config, h: f64, m: f64) -> f64 {
    let f = q0.body.rotation.transpose() * q1.body.rotation;
    let dx = q1.body - q0.body.translation;
    (Matrix3::identity() - f).trace() / h + 0.5 * m * dx.norm_squared() / h
}

fn main() {}
