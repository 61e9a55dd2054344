//! The rotation group `SO(3)` (`rotation(R)`, [`So3`]), and the maps of rotations the
//! integrators and users share: `ξ̂`, `vee`, the Cayley retraction, frames of directions, and
//! the orthogonality defect.

use nalgebra::{Matrix3, Vector3};

use super::{
    matrix, store_matrix, vector, CoordinateKind, Group, SpatialMomentum, MANIFOLD_TOLERANCE,
};

/// `‖MᵀM − I‖∞` (largest entry).
pub fn orthogonality_defect(m: &Matrix3<f64>) -> f64 {
    (m.transpose() * m - Matrix3::identity()).amax()
}

/// `ξ̂`, the skew-symmetric matrix with `ξ̂ v = ξ × v`.
#[inline]
pub fn hat(xi: &Vector3<f64>) -> Matrix3<f64> {
    xi.cross_matrix()
}

/// `vee(A)`, the vector of the skew-symmetric part of `A`: `vee(ξ̂) = ξ`, and
/// `vee(A) = vee((A − Aᵀ)/2)` in general.
#[inline]
pub fn vee(a: &Matrix3<f64>) -> Vector3<f64> {
    Vector3::new(
        0.5 * (a[(2, 1)] - a[(1, 2)]),
        0.5 * (a[(0, 2)] - a[(2, 0)]),
        0.5 * (a[(1, 0)] - a[(0, 1)]),
    )
}

/// The Cayley retraction `cay(ξ) = (I − ξ̂/2)⁻¹ (I + ξ̂/2) = I + 4/(4 + |ξ|²) (ξ̂ + ξ̂²/2)`: a
/// rotation for every `ξ ∈ R³`, with `cay(ξ) = exp(ξ̂) + O(|ξ|³)`.
#[inline]
pub fn cayley(xi: &Vector3<f64>) -> Matrix3<f64> {
    let s = hat(xi);
    Matrix3::identity() + (4.0 / (4.0 + xi.norm_squared())) * (s + 0.5 * s * s)
}

/// An orthonormal frame `[e1 e2 n]` (a rotation) whose third column is the unit vector `n` (`n`
/// is normalized first): the branch-free construction of Duff et al. (2017), continuous except
/// where `n_z` changes sign with `n_x = n_y = 0`.
pub fn frame(n: &Vector3<f64>) -> Matrix3<f64> {
    let n = n.normalize();
    let sign = 1.0_f64.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    let e1 = Vector3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    let e2 = Vector3::new(b, sign + n.y * n.y * a, -n.y);
    Matrix3::from_columns(&[e1, e2, n])
}

/// A rotation stored row by row, as in a point.
pub fn rows(m: &Matrix3<f64>) -> [f64; 9] {
    [
        m[(0, 0)],
        m[(0, 1)],
        m[(0, 2)],
        m[(1, 0)],
        m[(1, 1)],
        m[(1, 2)],
        m[(2, 0)],
        m[(2, 1)],
        m[(2, 2)],
    ]
}

/// The entries of a 3 × 3 matrix stored row by row, as output column suffixes.
pub(super) const MATRIX_SUFFIXES: [&str; 9] =
    ["00", "01", "02", "10", "11", "12", "20", "21", "22"];

/// `cay⁻¹(F) = 2 vee(F − Fᵀ)/(1 + tr F)`: the `ξ` with `cay(ξ) = F`, for any rotation `F` by
/// less than π.
pub(super) fn cayley_inverse(f: &Matrix3<f64>) -> Vector3<f64> {
    vee(f) * (4.0 / (1.0 + f.trace()))
}

/// Whether the stored matrix `m` (`what` `name`: "the rotation `R`") is a rotation to
/// [`MANIFOLD_TOLERANCE`]: `‖MᵀM − I‖∞` and `|det M − 1|` within it.
pub(super) fn check_rotation(what: &str, name: &str, m: &Matrix3<f64>) -> Result<(), String> {
    let (defect, det) = (orthogonality_defect(m), m.determinant());
    if defect > MANIFOLD_TOLERANCE || (det - 1.0).abs() > MANIFOLD_TOLERANCE {
        return Err(format!(
            "{what} `{name}` has |MᵀM − I| = {defect:.3e} and det M = {det}, tolerance \
             {MANIFOLD_TOLERANCE:.0e}; build rotations with `dirac::lie::cayley`, nalgebra's \
             `Rotation3`, or directions with `Config::to_point`"
        ));
    }
    Ok(())
}

/// Largest `‖RᵀR − I‖∞` of a rotation given as a value ([`Group::point_from_value`]): the
/// entries of a matrix typed or computed elsewhere, to about 9 digits.
const VALUE_TOLERANCE: f64 = 1e-9;

/// Reads the rotation matrix `value` (row by row) of the coordinate `name` into `q[..9]`;
/// `Err` when it is not a rotation to [`VALUE_TOLERANCE`].
pub(super) fn rotation_from_value(name: &str, value: &[f64], q: &mut [f64]) -> Result<(), String> {
    let r = matrix(value);
    let defect = orthogonality_defect(&r);
    if defect > VALUE_TOLERANCE || r.determinant() < 0.0 {
        return Err(format!(
            "`{name}` is not a rotation (|RᵀR − I| = {defect:.1e}, det R = {:.3})",
            r.determinant()
        ));
    }
    q[..9].copy_from_slice(&value[..9]);
    Ok(())
}

/// The rotation group: `rotation(R)`.
///
/// * point: `R ∈ SO(3)`, 9 entries row by row (body → space);
/// * chart: `ξ ∈ R³`, the retraction `φ_R(ξ) = R cay(ξ)` ([`cayley`]), so
///   `dφ_R(0) η = R η̂`: the left trivialization, the body frame; inverted by a sign since
///   `cay(ξ)ᵀ = cay(−ξ)`;
/// * momentum: the body momentum `Π ∈ so(3)*`, `⟨P, R η̂⟩ = Π·η`;
/// * spatial momentum: `π = R Π` (rotations `R ↦ A R`; no linear part);
/// * value: the matrix (shape `(3, 3)`), momentum value `Π` (shape `(3,)`).
#[derive(Clone, Copy, Debug, Default)]
pub struct So3;

impl Group for So3 {
    fn name(&self) -> &'static str {
        "rotation"
    }

    fn point_len(&self) -> usize {
        9
    }

    fn chart_len(&self) -> usize {
        3
    }

    fn point_suffixes(&self) -> &'static [&'static str] {
        &MATRIX_SUFFIXES
    }

    fn chart_suffixes(&self) -> &'static [&'static str] {
        &["x", "y", "z"]
    }

    fn retract(&self, q: &[f64], z: &[f64], out: &mut [f64]) {
        store_matrix(&(matrix(q) * cayley(&vector(z))), out);
    }

    /// `cay⁻¹(R_baseᵀ R)`, for any rotation by less than π.
    fn chart_inverse(&self, base: &[f64], point: &[f64], z: &mut [f64]) {
        let xi = cayley_inverse(&(matrix(base).transpose() * matrix(point)));
        z.copy_from_slice(xi.as_slice());
    }

    fn reproject(&self, q: &mut [f64]) {
        super::reproject_rotation(&mut q[..9]);
    }

    fn manifold_defect(&self, q: &[f64]) -> f64 {
        orthogonality_defect(&matrix(q))
    }

    fn check(&self, name: &str, q: &[f64]) -> Result<(), String> {
        check_rotation("the rotation", name, &matrix(q))
    }

    fn spatial_momentum(&self, q: &[f64], p: &[f64]) -> SpatialMomentum {
        SpatialMomentum {
            angular: matrix(q) * vector(p),
            linear: Vector3::zeros(),
        }
    }

    /// `Rᵀ e`: `ê R = R (Rᵀe)^`.
    fn rotation_generator(&self, q: &[f64], e: &Vector3<f64>, zeta: &mut [f64]) {
        zeta.copy_from_slice((matrix(q).transpose() * e).as_slice());
    }

    /// `F_kᵀ r` with `F_k = R_kᵀ R_{k+1}`: `R_{k+1} F_kᵀ r = R_k r`.
    fn carry_residual(&self, q: &[f64], q_next: &[f64], r: &[f64], p_next: &mut [f64]) {
        let f = matrix(q).transpose() * matrix(q_next);
        let t = f.transpose() * vector(r);
        for (p, t) in p_next.iter_mut().zip(t.iter()) {
            *p += t;
        }
    }

    fn value_shape(&self) -> &'static [usize] {
        &[3, 3]
    }

    fn momentum_shape(&self) -> &'static [usize] {
        &[3]
    }

    fn point_from_value(&self, name: &str, value: &[f64], q: &mut [f64]) -> Result<(), String> {
        rotation_from_value(name, value, q)
    }

    fn value(&self, q: &[f64], out: &mut Vec<f64>) {
        out.extend_from_slice(&q[..9]);
    }

    fn momentum_from_value(&self, _q: &[f64], value: &[f64], p: &mut [f64]) {
        p.copy_from_slice(&value[..3]);
    }

    fn momentum_value(&self, _q: &[f64], p: &[f64], out: &mut Vec<f64>) {
        out.extend_from_slice(&p[..3]);
    }
}

impl CoordinateKind {
    /// A rotation matrix `R ∈ SO(3)` (`rotation(R)`): 9 entries of the point (row by row), 3 of
    /// the chart (the body-frame algebra element).
    pub const ROTATION: CoordinateKind = CoordinateKind(&So3);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cayley_is_a_rotation_close_to_the_exponential() {
        let xi = Vector3::new(0.3, -0.2, 0.5);
        let c = cayley(&xi);
        assert!(orthogonality_defect(&c) < 1e-15);
        assert!((c.determinant() - 1.0).abs() < 1e-15);
        // cay(ξ) = exp(ξ̂) + O(|ξ|³): the defect shrinks by 8 when ξ halves.
        let err = |s: f64| {
            let x = xi * s;
            (cayley(&x) - nalgebra::Rotation3::new(x).into_inner()).amax()
        };
        let ratio = err(0.02) / err(0.01);
        assert!((ratio - 8.0).abs() < 0.1, "ratio {ratio}");
    }

    #[test]
    fn frames_are_rotations_with_n_last() {
        for n in [
            Vector3::new(0.0, 0.0, 1.0),
            Vector3::new(0.0, 0.0, -1.0),
            Vector3::new(0.3, -0.4, 0.5),
            Vector3::new(-1.0, 2.0, -0.1),
        ] {
            let f = frame(&n);
            assert!(orthogonality_defect(&f) < 1e-15, "{n}");
            assert!((f.determinant() - 1.0).abs() < 1e-15, "{n}");
            assert!((f.column(2) - n.normalize()).amax() < 1e-16);
        }
    }

    #[test]
    fn hat_and_vee_are_inverse() {
        let xi = Vector3::new(0.1, -2.0, 3.5);
        assert_eq!(vee(&hat(&xi)), xi);
        assert_eq!(
            hat(&xi) * Vector3::new(1.0, 2.0, 3.0),
            xi.cross(&Vector3::new(1.0, 2.0, 3.0))
        );
    }
}
