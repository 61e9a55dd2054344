//! Rigid placements: a rotation and a translation, composed as elements of SE(3).

use nalgebra::{Matrix3, Vector3};

/// A rigid placement `X = (R, p)` of a frame B in a frame A: a point with coordinates `x_B` in B
/// has coordinates `x_A = R x_B + p` in A. Composition is the product in SE(3),
/// `(R₁, p₁)(R₂, p₂) = (R₁R₂, p₁ + R₁p₂)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// The rotation `R` (orthonormal, determinant 1): B's axes in A's coordinates, as columns.
    pub rotation: Matrix3<f64>,
    /// The translation `p`: B's origin in A's coordinates.
    pub translation: Vector3<f64>,
}

impl Default for Pose {
    fn default() -> Self {
        Self::identity()
    }
}

impl Pose {
    /// The identity placement.
    #[must_use]
    pub fn identity() -> Self {
        Self {
            rotation: Matrix3::identity(),
            translation: Vector3::zeros(),
        }
    }

    /// The placement `(R, p)`.
    #[must_use]
    pub fn new(rotation: Matrix3<f64>, translation: Vector3<f64>) -> Self {
        Self {
            rotation,
            translation,
        }
    }

    /// A pure translation.
    #[must_use]
    pub fn from_translation(translation: Vector3<f64>) -> Self {
        Self {
            rotation: Matrix3::identity(),
            translation,
        }
    }

    /// A pure rotation.
    #[must_use]
    pub fn from_rotation(rotation: Matrix3<f64>) -> Self {
        Self {
            rotation,
            translation: Vector3::zeros(),
        }
    }

    /// URDF's `<origin xyz rpy>`: `R = R_z(yaw) R_y(pitch) R_x(roll)` (fixed axes x, y, z in that
    /// order), `p = xyz`.
    #[must_use]
    pub fn from_xyz_rpy(xyz: [f64; 3], rpy: [f64; 3]) -> Self {
        let [roll, pitch, yaw] = rpy;
        let rotation = axis_angle(&Vector3::z(), yaw)
            * axis_angle(&Vector3::y(), pitch)
            * axis_angle(&Vector3::x(), roll);
        Self {
            rotation,
            translation: Vector3::from(xyz),
        }
    }

    /// The product `self · other`: `other`'s placement, given in `self`'s frame, expressed in
    /// the frame `self` is placed in.
    #[must_use]
    pub fn compose(&self, other: &Pose) -> Pose {
        Pose {
            rotation: self.rotation * other.rotation,
            translation: self.translation + self.rotation * other.translation,
        }
    }

    /// A point's coordinates in the outer frame: `R x + p`.
    #[must_use]
    pub fn transform_point(&self, x: &Vector3<f64>) -> Vector3<f64> {
        self.rotation * x + self.translation
    }

    /// The largest entry of `|RᵀR − I|`, or `|det R − 1|` if larger: zero for a rotation.
    #[must_use]
    pub fn rotation_defect(rotation: &Matrix3<f64>) -> f64 {
        let gram = rotation.transpose() * rotation - Matrix3::identity();
        gram.amax().max((rotation.determinant() - 1.0).abs())
    }
}

/// The rotation by `angle` about the unit vector `axis` (Rodrigues' formula,
/// `R = I + sin θ [a]× + (1 − cos θ) [a]×²`).
#[must_use]
pub fn axis_angle(axis: &Vector3<f64>, angle: f64) -> Matrix3<f64> {
    let k = skew(axis);
    let (s, c) = angle.sin_cos();
    Matrix3::identity() + k * s + k * k * (1.0 - c)
}

/// The cross-product matrix `[a]×`, with `[a]× b = a × b`.
#[must_use]
pub fn skew(a: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -a.z, a.y, a.z, 0.0, -a.x, -a.y, a.x, 0.0)
}
