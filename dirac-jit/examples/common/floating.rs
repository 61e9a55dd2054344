//! What the floating-base examples share: a stored point of a floating tree (the base's pose,
//! its rotation row by row then its position, then the joints' scalars) read as a pose and as
//! the model's configuration, and a pose written as a state takes it.

use dirac_multibody::nalgebra::{Matrix3, Vector3};
use dirac_multibody::{Configuration, JointPosition, Model, Pose};

/// The base's attitude and position in a stored point (the rotation row by row, then `x`).
pub fn base_pose(q: &[f64]) -> (Matrix3<f64>, Vector3<f64>) {
    (
        Matrix3::from_fn(|i, j| q[3 * i + j]),
        Vector3::new(q[9], q[10], q[11]),
    )
}

/// A pose's 12 numbers as a state takes them: the rotation row by row, then the position.
pub fn pose_numbers(r: &Matrix3<f64>, x: &Vector3<f64>) -> Vec<f64> {
    let mut out: Vec<f64> = r.transpose().as_slice().to_vec();
    out.extend_from_slice(x.as_slice());
    out
}

/// The model's configuration at a stored point: the base's pose, then the joints' scalars in
/// the model's (and the text's) order.
pub fn configuration(model: &Model, q: &[f64]) -> Configuration {
    let (r, x) = base_pose(q);
    let mut config = model.neutral_configuration();
    config.positions[0] = JointPosition::Pose(Pose::new(r, x));
    for (j, position) in config.positions.iter_mut().enumerate().skip(1) {
        *position = JointPosition::Scalar(q[11 + j]);
    }
    config
}
