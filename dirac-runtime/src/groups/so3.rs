//! The rotation group's maps the integrators and users share: `ξ̂`, `vee`, the Cayley
//! retraction, frames of directions, and the orthogonality defect.

use nalgebra::{Matrix3, Vector3};

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
