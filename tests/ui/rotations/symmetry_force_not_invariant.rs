use dirac::prelude::*;

// A torque fixed in space is not invariant under the rotations of the body.
#[reduced_lagrangian(rotation(r), symmetry(r), force = |dq0, dq1| 0.5 * h * tau * ((q0.r.transpose() * Vector3::x()).dot(&dq0.r) + (q1.r.transpose() * Vector3::x()).dot(&dq1.r)))]
fn pushed(q0: Config, q1: Config, h: f64, tau: f64) -> f64 {
    let f = q0.r.transpose() * q1.r;
    (Matrix3::identity() - f).trace() / h
}

fn main() {}
