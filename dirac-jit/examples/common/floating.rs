//! What the floating-base examples share: a stored point of a floating tree (the base's pose,
//! its rotation row by row then its position, then the joints' scalars) read as a pose and as
//! the model's configuration, and a pose written as a state takes it.

use dirac_multibody::nalgebra::{DVector, Matrix3, Vector3};
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

/// A state's parts at the stored point `point` and the model's velocity `v` (the base's body
/// angular and linear velocity, then the joints' rates), as `JitLie::state` takes them per
/// coordinate: the base's 12 numbers and each joint's scalar; the momenta `M(q) v`, the
/// base's linear momentum turned into space (the pose's momentum is `(Π, p)` with `p` in
/// space).
pub fn state_parts(model: &Model, point: &[f64], v: &[f64]) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
    let config = configuration(model, point);
    let p = model.mass_matrix(&config).expect("a configuration") * DVector::from_column_slice(v);
    let (r, _) = base_pose(point);
    let linear = r * Vector3::new(p[3], p[4], p[5]);
    let mut q_parts = vec![point[..12].to_vec()];
    let mut p_parts = vec![vec![p[0], p[1], p[2], linear.x, linear.y, linear.z]];
    for j in 12..point.len() {
        q_parts.push(vec![point[j]]);
        p_parts.push(vec![p[j - 6]]);
    }
    (q_parts, p_parts)
}

/// The slices of each part, as `JitLie::state` takes them.
pub fn slices(parts: &[Vec<f64>]) -> Vec<&[f64]> {
    parts.iter().map(Vec::as_slice).collect()
}
