//! The two-sphere `S²` (`direction(n)`, [`S2`]): a unit vector stored with an orthonormal frame.

use nalgebra::{Matrix3, Vector3};

use super::so3::{check_rotation, frame, orthogonality_defect, MATRIX_SUFFIXES};
use super::{matrix, store_matrix, vector, CoordinateKind, Group, SpatialMomentum};

/// Largest accepted `| |n| − 1 |` of a direction given to a state: within it the direction is
/// normalized (a rounding-level correction), beyond it the state is refused
/// ([`crate::StepError::OffManifold`]), for a system compiled in ([`direction_frame`], checked by
/// every integrator's input checks) and for one given as text alike.
pub const UNIT_TOLERANCE: f64 = 1e-9;

/// The frame a state stores for the direction `n` (what a compiled-in system's
/// `Config::to_point` stores): [`frame`] of `n` when `n` is a unit vector to
/// [`UNIT_TOLERANCE`]; otherwise the same frame with `n` itself, unnormalized, as its third
/// column — a point off the manifold, which every integrator's input checks refuse with
/// [`crate::StepError::OffManifold`], naming the direction and its length. A direction that is
/// not a unit vector is a mistake in the input, not something to normalize silently: the run
/// would integrate another initial state than the one given.
pub fn direction_frame(n: &Vector3<f64>) -> Matrix3<f64> {
    let length = n.norm();
    if (length - 1.0).abs() <= UNIT_TOLERANCE {
        return frame(n);
    }
    // Finite columns around any `n` (a zero or non-finite `n` borrows the z axis's frame), so
    // that the checks report the length rather than a non-finite state.
    let mut f = if length > 0.0 && length.is_finite() {
        frame(n)
    } else {
        Matrix3::identity()
    };
    f.set_column(2, n);
    f
}

/// `v / |v|`.
fn unit(v: Vector3<f64>) -> Vector3<f64> {
    v / v.norm()
}

/// The shortest-arc rotation `M(a, b)` taking `e3` to `u = (a, b, 1)/√(1 + a² + b²)`: the
/// rotation about `e3 × u` by the angle between them, `M(−a, −b) = M(a, b)ᵀ`.
fn shortest_arc(a: f64, b: f64) -> Matrix3<f64> {
    let s = 1.0 / (1.0 + a * a + b * b).sqrt();
    let (ux, uy, uz) = (a * s, b * s, s);
    let d = 1.0 + uz;
    let (t00, t11, t01) = (ux * ux / d, uy * uy / d, ux * uy / d);
    Matrix3::new(1.0 - t00, -t01, ux, -t01, 1.0 - t11, uy, -ux, -uy, uz)
}

/// The two-sphere: `direction(n)`.
///
/// * point: the frame `F = [e1 e2 n]` (a rotation whose third column is `n`, see [`frame`]), 9
///   entries row by row;
/// * chart: `(a, b)`, the retraction `φ(a, b) = (n + a e1 + b e2) / |n + a e1 + b e2|` (the
///   sphere's, so `|n| = 1` to round-off at every step), the frame carried along by the
///   shortest-arc rotation `M(a, b)` taking `e3` to `(a, b, 1)/√(1 + a² + b²)` and made
///   orthonormal to the new `n` again, so `dφ(0) (a, b) = a e1 + b e2`; inverted by a sign since
///   `M(a, b)ᵀ = M(−a, −b)`;
/// * momentum: the components `(e1·P, e2·P)` of the momentum `P` in the frame;
/// * spatial momentum: `π = n × P` with `P = P1 e1 + P2 e2` (rotations `n ↦ A n`; no linear
///   part);
/// * value: the unit vector `n` (shape `(3,)`), momentum value `P` as a vector in space (shape
///   `(3,)`, its component along `n` dropped).
#[derive(Clone, Copy, Debug, Default)]
pub struct S2;

impl Group for S2 {
    fn name(&self) -> &'static str {
        "direction"
    }

    fn point_len(&self) -> usize {
        9
    }

    fn chart_len(&self) -> usize {
        2
    }

    fn point_suffixes(&self) -> &'static [&'static str] {
        &MATRIX_SUFFIXES
    }

    fn chart_suffixes(&self) -> &'static [&'static str] {
        &["1", "2"]
    }

    /// The next frame `[e1' e2' n']`: `n' = (n + a e1 + b e2)/|n + a e1 + b e2|`, `e1'` the
    /// carried first column `F M(a, b) e1` made orthogonal to `n'` and normalized,
    /// `e2' = n' × e1'`.
    fn retract(&self, q: &[f64], z: &[f64], out: &mut [f64]) {
        let f = matrix(q);
        let carried = f * shortest_arc(z[0], z[1]);
        let n = unit(f.column(2) + f.column(0) * z[0] + f.column(1) * z[1]);
        let t = carried.column(0).into_owned();
        let e1 = unit(t - n * t.dot(&n));
        let e2 = n.cross(&e1);
        store_matrix(&Matrix3::from_columns(&[e1, e2, n]), out);
    }

    /// `(n·e1, n·e2)/(n·n_base)` in the frame of `base`, for any `n` in the open hemisphere
    /// about `n_base`.
    fn chart_inverse(&self, base: &[f64], point: &[f64], z: &mut [f64]) {
        let (f0, f1) = (matrix(base), matrix(point));
        let n = f1.column(2);
        let along = n.dot(&f0.column(2));
        z[0] = n.dot(&f0.column(0)) / along;
        z[1] = n.dot(&f0.column(1)) / along;
    }

    /// `‖FᵀF − I‖∞` of the frame, which bounds `||n| − 1|`.
    fn manifold_defect(&self, q: &[f64]) -> f64 {
        orthogonality_defect(&matrix(q))
    }

    /// `|n|` within [`UNIT_TOLERANCE`] of 1 (the rule a system given as text applies to the
    /// direction it is given), then the frame a rotation.
    fn check(&self, name: &str, q: &[f64]) -> Result<(), String> {
        let m = matrix(q);
        let length = m.column(2).norm();
        if (length - 1.0).abs() > UNIT_TOLERANCE {
            return Err(format!(
                "the direction `{name}` is not a unit vector: |{name}| = {length}, tolerance \
                 {UNIT_TOLERANCE:.0e}; give a unit vector (a direction is not normalized for you: \
                 that would integrate another state than the one given)"
            ));
        }
        check_rotation("the frame of the direction", name, &m)
    }

    fn spatial_momentum(&self, q: &[f64], p: &[f64]) -> SpatialMomentum {
        let f = matrix(q);
        let ambient = f.column(0) * p[0] + f.column(1) * p[1];
        SpatialMomentum {
            angular: f.column(2).cross(&ambient),
            linear: Vector3::zeros(),
        }
    }

    /// `((e × n)·e1, (e × n)·e2)`.
    fn rotation_generator(&self, q: &[f64], e: &Vector3<f64>, zeta: &mut [f64]) {
        let m = matrix(q);
        let turn = e.cross(&m.column(2));
        zeta[0] = turn.dot(&m.column(0));
        zeta[1] = turn.dot(&m.column(1));
    }

    /// The residual carried by the frame: the `e_a^{k+1}` components of `r1 e1^k + r2 e2^k`,
    /// which keeps the momentum map to the size of `r`.
    fn carry_residual(&self, q: &[f64], q_next: &[f64], r: &[f64], p_next: &mut [f64]) {
        let (f0, f1) = (matrix(q), matrix(q_next));
        let ambient = f0.column(0) * r[0] + f0.column(1) * r[1];
        p_next[0] += f1.column(0).dot(&ambient);
        p_next[1] += f1.column(1).dot(&ambient);
    }

    fn value_shape(&self) -> &'static [usize] {
        &[3]
    }

    fn momentum_shape(&self) -> &'static [usize] {
        &[3]
    }

    fn point_from_value(&self, name: &str, value: &[f64], q: &mut [f64]) -> Result<(), String> {
        let n = vector(value);
        if (n.norm() - 1.0).abs() > UNIT_TOLERANCE {
            return Err(format!(
                "`{name}` is not a unit vector (|{name}| = {})",
                n.norm()
            ));
        }
        store_matrix(&frame(&n), q);
        Ok(())
    }

    fn value(&self, q: &[f64], out: &mut Vec<f64>) {
        out.extend_from_slice(&[q[2], q[5], q[8]]);
    }

    fn momentum_from_value(&self, q: &[f64], value: &[f64], p: &mut [f64]) {
        let (f, m) = (matrix(q), vector(value));
        p[0] = f.column(0).dot(&m);
        p[1] = f.column(1).dot(&m);
    }

    fn momentum_value(&self, q: &[f64], p: &[f64], out: &mut Vec<f64>) {
        let f = matrix(q);
        let m = f.column(0) * p[0] + f.column(1) * p[1];
        out.extend_from_slice(m.as_slice());
    }
}

impl CoordinateKind {
    /// A unit vector `n ∈ S²` (`direction(n)`): the 9 entries of its frame `[e1 e2 n]` (row by
    /// row), 2 of the chart.
    pub const DIRECTION: CoordinateKind = CoordinateKind(&S2);
}
