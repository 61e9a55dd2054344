use dirac::prelude::*;

// A body in gravity is not invariant under every rigid motion of its pose.
#[reduced_lagrangian(pose(body), symmetry(body))]
fn falling(q0: Config, q1: Config, h: f64, m: f64) -> f64 {
    let f = q0.body.rotation.transpose() * q1.body.rotation;
    let dx = q1.body.translation - q0.body.translation;
    (Matrix3::identity() - f).trace() / h + 0.5 * m * dx.norm_squared() / h
        - 0.5 * h * m * 9.81 * (q0.body.translation.z + q1.body.translation.z)
}

fn main() {}
