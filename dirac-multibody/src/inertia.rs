//! The mass properties of a link, their validation and their merging by the parallel-axis
//! theorem.

use nalgebra::{Matrix3, SymmetricEigen, Vector3};

use crate::error::InertiaDefect;
use crate::pose::Pose;

/// A link's mass properties in its own frame: the mass `m`, the centre of mass `c`, and the
/// rotational inertia `I_c` about the centre of mass, in the link frame's axes
/// (`I_c = ∫ (|r|² 1 − r rᵀ) dm`, `r` measured from `c`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Inertial {
    /// The mass `m`.
    pub mass: f64,
    /// The centre of mass `c` in the link frame.
    pub com: Vector3<f64>,
    /// The rotational inertia about the centre of mass, in the link frame's axes.
    pub inertia: Matrix3<f64>,
}

impl Inertial {
    /// Mass properties from their three parts.
    #[must_use]
    pub fn new(mass: f64, com: Vector3<f64>, inertia: Matrix3<f64>) -> Self {
        Self { mass, com, inertia }
    }

    /// No mass.
    #[must_use]
    pub fn zero() -> Self {
        Self {
            mass: 0.0,
            com: Vector3::zeros(),
            inertia: Matrix3::zeros(),
        }
    }

    /// The same mass distribution seen from a frame in which this link's frame is placed at
    /// `placement = (R, p)`: `c' = R c + p`, `I_c' = R I_c Rᵀ`.
    #[must_use]
    pub fn transformed(&self, placement: &Pose) -> Self {
        let r = placement.rotation;
        Self {
            mass: self.mass,
            com: placement.transform_point(&self.com),
            inertia: r * self.inertia * r.transpose(),
        }
    }

    /// The union of two mass distributions given in one frame: masses add, the centre of mass
    /// is the mass-weighted mean, and each inertia is carried to the common centre of mass by
    /// the parallel-axis theorem `I_C = I_c + m (|d|² 1 − d dᵀ)`, `d = c − C`
    /// (Featherstone, *Rigid Body Dynamics Algorithms*, 2008, ch. 2, spatial inertia: the
    /// spatial inertia of two bodies joined rigidly is the sum of theirs).
    #[must_use]
    pub fn merged(&self, other: &Inertial) -> Self {
        let mass = self.mass + other.mass;
        if mass == 0.0 {
            return Self::zero();
        }
        let com = (self.com * self.mass + other.com * other.mass) / mass;
        let inertia = self.inertia
            + parallel_axis(self.mass, &(self.com - com))
            + other.inertia
            + parallel_axis(other.mass, &(other.com - com));
        Self { mass, com, inertia }
    }

    /// Checks that these are the mass properties of a mass distribution: finite, the inertia
    /// symmetric, positive definite when the mass is positive (positive semidefinite when it is
    /// zero), and its principal moments `J₁ ≤ J₂ ≤ J₃` satisfying `J₁ + J₂ ≥ J₃`
    /// (`J₁ + J₂ − J₃ = 2 ∫ z² dm ≥ 0` in principal axes). The comparisons allow a relative
    /// round-off of `1e-12 · tr I`. A negative mass is the caller's error to name.
    pub(crate) fn check(&self) -> Result<(), InertiaDefect> {
        let finite = self.mass.is_finite()
            && self.com.iter().all(|x| x.is_finite())
            && self.inertia.iter().all(|x| x.is_finite());
        if !finite {
            return Err(InertiaDefect::NonFinite);
        }
        let scale = self.inertia.amax().max(f64::MIN_POSITIVE);
        let asymmetry = (self.inertia - self.inertia.transpose()).amax();
        if asymmetry > 1e-12 * scale {
            return Err(InertiaDefect::NotSymmetric { asymmetry });
        }
        let moments = principal_moments(&self.inertia);
        let tol = 1e-12 * (moments[0].abs() + moments[1].abs() + moments[2].abs());
        let positive = if self.mass > 0.0 {
            moments[0] > tol
        } else {
            moments[0] >= -tol
        };
        if !positive {
            return Err(InertiaDefect::NotPositiveDefinite { moments });
        }
        if moments[0] + moments[1] < moments[2] - tol {
            return Err(InertiaDefect::TriangleInequality { moments });
        }
        Ok(())
    }
}

/// The principal moments of a symmetric 3 × 3 inertia (its eigenvalues), ascending.
#[must_use]
pub fn principal_moments(inertia: &Matrix3<f64>) -> [f64; 3] {
    let sym = (inertia + inertia.transpose()) * 0.5;
    let mut moments: [f64; 3] = SymmetricEigen::new(sym).eigenvalues.into();
    moments.sort_by(f64::total_cmp);
    moments
}

/// The parallel-axis term `m (|d|² 1 − d dᵀ)`: the inertia about a point at `−d` from a point
/// mass `m` (Steiner's theorem).
#[must_use]
pub fn parallel_axis(mass: f64, d: &Vector3<f64>) -> Matrix3<f64> {
    (Matrix3::identity() * d.norm_squared() - d * d.transpose()) * mass
}
