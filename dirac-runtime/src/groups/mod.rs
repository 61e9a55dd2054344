//! The configuration spaces of systems on rotation groups, each kind of coordinate one
//! implementation of [`Group`]: what the runtime computes numerically on a coordinate's block of
//! the stored point, the chart and the momentum (in the spirit of manif's `LieGroupBase`, one
//! interface every group implements, so the integrators of [`crate::lie`] are written once).
//!
//! | keyword | implementation | point | chart | retraction `φ_q(z)` |
//! | --- | --- | --- | --- | --- |
//! | `shape(x)` | [`Scalar`] | `x` (1) | 1 | `x + ξ` |
//! | `group(x)` | [`Translation`] | `x` (1) | 1 | `x + ξ` |
//! | `rotation(R)` | [`So3`] | `R` row by row (9) | 3 | `R cay(ξ)` |
//! | `direction(n)` | [`S2`] | its frame `[e1 e2 n]` row by row (9) | 2 | `n` along `a e1 + b e2`, normalized |
//! | `pose(X)` | [`Pose`] | `R` row by row, then `x` (12) | 6 | `(R cay(ξ), x + v)` |
//!
//! Every retraction is centred (`φ_q(0) = q`) and inverted by a sign,
//! `φ_{φ_q(z)}(−z) = q`, which the (−) integrator relies on (see the
//! [`crate::lie` documentation](crate::lie#the-equations)). The momentum of a coordinate is the
//! covector `p·η = ⟨P, dφ_q(0) η⟩` in its chart.
//!
//! A coordinate's kind as the integrators, the output and the systems see it is a
//! [`CoordinateKind`]: a reference to one implementation, compared by name, with one constant
//! per implementation and [`CoordinateKind::by_name`] over the one registration list
//! ([`CoordinateKind::ALL`]). Adding a group is its file here (the implementation and its
//! constant), its `mod` line and one line of that list in this file, and its symbolic
//! counterpart in the compiler (`dirac-compiler/src/ir/group/`, with its line of that crate's
//! list).

mod pose;
mod s2;
mod scalar;
mod so3;

use std::fmt;
use std::hash::{Hash, Hasher};
use std::ops::{Add, AddAssign};

use nalgebra::{Matrix3, Vector3};

pub use pose::Pose;
pub use s2::{direction_frame, S2, UNIT_TOLERANCE};
pub use scalar::{Scalar, Translation};
pub use so3::{cayley, frame, hat, orthogonality_defect, rows, vee, So3};

/// Largest accepted `‖RᵀR − I‖∞` (and `|det R − 1|`) of an initial rotation or frame.
pub const MANIFOLD_TOLERANCE: f64 = 1e-10;

/// The spatial momentum of rigid motions `(A, a)·y = A y + a` of space at a state: the angular
/// part `π` (the momentum map of rotating every rotation, direction and pose together,
/// `R ↦ A R`, `n ↦ A n`, `(R, x) ↦ (A R, A x)`) and the linear part `ℓ` (that of translating
/// every pose, `x ↦ x + a`). Scalars contribute to neither.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SpatialMomentum {
    /// `π = Σ_rotations R Π + Σ_directions n × P + Σ_poses (R Π + x × p)`.
    pub angular: Vector3<f64>,
    /// `ℓ = Σ_poses p`.
    pub linear: Vector3<f64>,
}

impl Add for SpatialMomentum {
    type Output = SpatialMomentum;

    fn add(self, other: SpatialMomentum) -> SpatialMomentum {
        SpatialMomentum {
            angular: self.angular + other.angular,
            linear: self.linear + other.linear,
        }
    }
}

impl AddAssign for SpatialMomentum {
    fn add_assign(&mut self, other: SpatialMomentum) {
        *self = *self + other;
    }
}

/// One kind of coordinate of a system on rotation groups, numerically: its block of the stored
/// point `q` (`point_len` entries), of the chart and of the momentum (`chart_len` entries each).
/// Each method reads and writes that block only (slices of exactly those lengths), so the
/// integrators run over the coordinates in order, calling the kind of each.
///
/// A coordinate's *value* is what a user gives and gets back for it from a system given at run
/// time (Python, the command line): a number, a rotation matrix, a unit vector, a pose; its
/// *momentum value* is its momentum in the same terms.
pub trait Group: Send + Sync + fmt::Debug + 'static {
    /// The keyword that declares the coordinate in the attribute (`"rotation"` for
    /// `rotation(R)`).
    fn name(&self) -> &'static str;

    /// Entries of the stored point.
    fn point_len(&self) -> usize;

    /// Entries of the chart, and of the momentum.
    fn chart_len(&self) -> usize;

    /// The suffix of each entry of the stored point in output column names (`q_<name>_<suffix>`,
    /// or `q_<name>` for an empty suffix), `point_len` of them.
    fn point_suffixes(&self) -> &'static [&'static str];

    /// The suffix of each momentum component in output column names, `chart_len` of them.
    fn chart_suffixes(&self) -> &'static [&'static str];

    /// `out = φ_q(z)`, the point of the chart centred at `q` (what the compiler emits
    /// symbolically for a system; here for checks and hand-written systems).
    fn retract(&self, q: &[f64], z: &[f64], out: &mut [f64]);

    /// `z` with `φ_base(z) = point`, the inverse of [`Self::retract`] where the chart reaches
    /// `point`.
    fn chart_inverse(&self, base: &[f64], point: &[f64], z: &mut [f64]);

    /// The departure of the point from the manifold (`‖RᵀR − I‖∞` of a stored rotation or
    /// frame), 0 for a coordinate on a vector space.
    fn manifold_defect(&self, q: &[f64]) -> f64 {
        let _ = q;
        0.0
    }

    /// Whether the stored point of the coordinate `name` is on the manifold (to
    /// [`MANIFOLD_TOLERANCE`]); `Err` with the reason a state is refused
    /// ([`crate::StepError::OffManifold`]). Finiteness is checked by the caller.
    fn check(&self, name: &str, q: &[f64]) -> Result<(), String> {
        let _ = (name, q);
        Ok(())
    }

    /// The block's contribution to the [`SpatialMomentum`] at `(q, p)`.
    fn spatial_momentum(&self, q: &[f64], p: &[f64]) -> SpatialMomentum {
        let _ = (q, p);
        SpatialMomentum::default()
    }

    /// `zeta` = the chart components at `q` of the infinitesimal rotation about the unit axis
    /// `e` (`ζ̂ R = R (Rᵀe)^`, `δn = e × n`, `δx = e × x`): the generator the reduction by the
    /// rotations about an axis reads, whose pairing with `p` is `e·π`. Zero for a coordinate
    /// the rotations do not move.
    fn rotation_generator(&self, q: &[f64], e: &Vector3<f64>, zeta: &mut [f64]) {
        let _ = (q, e);
        zeta.fill(0.0);
    }

    /// Adds to `p_next` (the momentum at `q_next`) the residual covector `r` of a step from `q`,
    /// carried to `q_next` so that the block's [`SpatialMomentum`] (or, for a scalar, its
    /// momentum) moves by that of `r` at `q`: Newton's accepted residual is then carried
    /// into the new momentum and the discrete Noether balance holds to round-off (see the
    /// (+) step's compensation in [`crate::lie`]).
    fn carry_residual(&self, q: &[f64], q_next: &[f64], r: &[f64], p_next: &mut [f64]);

    /// Brings a stored point that a step's round-off moved off the manifold back onto it, by a
    /// correction of the size of that departure (the identity in exact arithmetic): for a
    /// stored rotation (a rotation's, a pose's attitude), one Newton–Schulz step `R (3I − RᵀR)/2` towards the nearest
    /// rotation, which squares the orthogonality defect. Without it
    /// the product `R_k cay(ξ_k)` of many steps drifts off `SO(3)` as a random walk of
    /// round-off, and every quantity that reads `R` (a momentum map `R Π`) with it. The default
    /// does nothing: a vector space, and a direction, whose frame the retraction rebuilds
    /// orthonormal to the new unit vector at every step.
    fn reproject(&self, q: &mut [f64]) {
        let _ = q;
    }

    /// The NumPy shape of one value (`[]` for a number, `[3, 3]` for a rotation matrix).
    fn value_shape(&self) -> &'static [usize];

    /// The NumPy shape of one momentum value (a velocity has the same shape).
    fn momentum_shape(&self) -> &'static [usize];

    /// Entries of a value.
    fn value_len(&self) -> usize {
        self.value_shape().iter().product()
    }

    /// Entries of a momentum value (and of a velocity).
    fn momentum_value_len(&self) -> usize {
        self.momentum_shape().iter().product()
    }

    /// Stores the value of the coordinate `name` (its [`Self::value_len`] entries, matrices
    /// row by row) as its point; `Err` with the reason when it is not on the manifold (the
    /// caller checks the count and finiteness).
    fn point_from_value(&self, name: &str, value: &[f64], q: &mut [f64]) -> Result<(), String>;

    /// Appends the value of the stored point `q` (the inverse of [`Self::point_from_value`]).
    fn value(&self, q: &[f64], out: &mut Vec<f64>);

    /// The chart momentum `p` at the point `q` of the momentum value `value`.
    fn momentum_from_value(&self, q: &[f64], value: &[f64], p: &mut [f64]);

    /// Appends the momentum value of the chart momentum `p` at `q` (the inverse of
    /// [`Self::momentum_from_value`] on the covectors the chart reaches).
    fn momentum_value(&self, q: &[f64], p: &[f64], out: &mut Vec<f64>);
}

/// What one declared coordinate of a system on rotation groups is: a reference to its
/// [`Group`], compared, hashed and printed by the group's [`Group::name`]. One constant per
/// group (`CoordinateKind::ROTATION`, ..); [`CoordinateKind::by_name`] finds one by its keyword.
/// Its methods delegate to the group.
#[derive(Clone, Copy)]
pub struct CoordinateKind(pub &'static dyn Group);

impl CoordinateKind {
    /// Every kind: the one registration list (each kind's constant, `CoordinateKind::ROTATION`
    /// and the others, is defined beside its implementation, named by its keyword in capitals:
    /// the name the code `#[reduced_lagrangian]` emits refers to).
    pub const ALL: &'static [CoordinateKind] = &[
        CoordinateKind::SCALAR,
        CoordinateKind::GROUP,
        CoordinateKind::ROTATION,
        CoordinateKind::DIRECTION,
        CoordinateKind::POSE,
    ];

    /// The kind declared by the attribute keyword `name` (`"rotation"`), `None` for another
    /// word.
    ///
    /// ```
    /// use dirac_runtime::lie::CoordinateKind;
    ///
    /// assert_eq!(CoordinateKind::by_name("pose"), Some(CoordinateKind::POSE));
    /// assert_eq!(CoordinateKind::by_name("rotation").map(|k| k.chart_len()), Some(3));
    /// assert_eq!(CoordinateKind::by_name("quaternion"), None);
    /// ```
    pub fn by_name(name: &str) -> Option<CoordinateKind> {
        CoordinateKind::ALL
            .iter()
            .copied()
            .find(|k| k.name() == name)
    }

    /// The group.
    pub fn group(self) -> &'static dyn Group {
        self.0
    }

    /// The attribute keyword ([`Group::name`]).
    pub fn name(self) -> &'static str {
        self.0.name()
    }

    /// Entries of the stored point.
    pub fn point_len(self) -> usize {
        self.0.point_len()
    }

    /// Entries of the chart (and of the momentum).
    pub fn chart_len(self) -> usize {
        self.0.chart_len()
    }
}

impl PartialEq for CoordinateKind {
    fn eq(&self, other: &Self) -> bool {
        self.name() == other.name()
    }
}

impl Eq for CoordinateKind {}

impl Hash for CoordinateKind {
    fn hash<H: Hasher>(&self, state: &mut H) {
        self.name().hash(state);
    }
}

impl fmt::Debug for CoordinateKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "CoordinateKind({})", self.name())
    }
}

impl fmt::Display for CoordinateKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The 3 × 3 matrix stored row by row in `q[..9]`.
fn matrix(q: &[f64]) -> Matrix3<f64> {
    Matrix3::from_fn(|i, j| q[3 * i + j])
}

/// `m` stored row by row in `out[..9]`.
/// One Newton–Schulz step `R ← R (3I − RᵀR)/2` on the rotation stored row by row in
/// `q[..9]` ([`Group::reproject`]): for `RᵀR = I + E` it leaves a defect of order `E²`.
fn reproject_rotation(q: &mut [f64]) {
    let r = matrix(q);
    store_matrix(
        &(r * (Matrix3::identity() * 3.0 - r.transpose() * r) * 0.5),
        q,
    );
}

fn store_matrix(m: &Matrix3<f64>, out: &mut [f64]) {
    out[..9].copy_from_slice(&rows(m));
}

/// The vector in `v[..3]`.
fn vector(v: &[f64]) -> Vector3<f64> {
    Vector3::new(v[0], v[1], v[2])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every registered kind round-trips its name, and the centred, sign-inverted retraction
    /// and the chart inverse agree: `φ_q(0) = q`, `φ_{φ_q(z)}(−z) = q`, `φ_q⁻¹(φ_q(z)) = z`.
    #[test]
    fn every_kind_is_found_by_its_name_and_its_chart_is_inverted_by_a_sign() {
        for &kind in CoordinateKind::ALL {
            assert_eq!(CoordinateKind::by_name(kind.name()), Some(kind));
            let g = kind.group();
            let (np, nc) = (g.point_len(), g.chart_len());
            assert_eq!(g.point_suffixes().len(), np, "{kind}");
            assert_eq!(g.chart_suffixes().len(), nc, "{kind}");
            // A point on the manifold, from a value.
            let value: Vec<f64> = match g.value_len() {
                1 => vec![0.7],
                3 => Vector3::new(0.3, -0.4, 0.5).normalize().as_slice().to_vec(),
                9 => rows(&cayley(&Vector3::new(0.2, -0.7, 0.4))).to_vec(),
                12 => rows(&cayley(&Vector3::new(0.2, -0.7, 0.4)))
                    .into_iter()
                    .chain([1.5, -2.0, 0.25])
                    .collect(),
                n => panic!("no sample value of {n} entries"),
            };
            let mut q = vec![0.0; np];
            g.point_from_value("c", &value, &mut q).unwrap();
            assert!(g.check("c", &q).is_ok(), "{kind}");
            let z: Vec<f64> = (0..nc).map(|i| 0.3 - 0.17 * i as f64).collect();
            let minus: Vec<f64> = z.iter().map(|v| -v).collect();
            let (mut at0, mut moved, mut back, mut inv) =
                (vec![0.0; np], vec![0.0; np], vec![0.0; np], vec![0.0; nc]);
            g.retract(&q, &vec![0.0; nc], &mut at0);
            g.retract(&q, &z, &mut moved);
            g.retract(&moved, &minus, &mut back);
            g.chart_inverse(&q, &moved, &mut inv);
            let gap = |a: &[f64], b: &[f64]| {
                a.iter()
                    .zip(b)
                    .map(|(x, y)| (x - y).abs())
                    .fold(0.0, f64::max)
            };
            assert!(gap(&at0, &q) < 1e-15, "{kind}: φ_q(0) ≠ q");
            assert!(gap(&back, &q) < 1e-14, "{kind}: φ_(φ_q(z))(−z) ≠ q");
            assert!(gap(&inv, &z) < 1e-14, "{kind}: φ_q⁻¹(φ_q(z)) ≠ z");
            assert!(g.manifold_defect(&moved) < 1e-15, "{kind}");
            let mut again = Vec::new();
            g.value(&q, &mut again);
            assert!(
                gap(&again, &value) < 1e-15,
                "{kind}: the value does not read back"
            );
        }
    }

    #[test]
    fn kinds_compare_by_name() {
        assert_eq!(CoordinateKind::ROTATION, CoordinateKind(&So3));
        assert_ne!(CoordinateKind::SCALAR, CoordinateKind::GROUP);
        assert_eq!(
            format!("{:?}", CoordinateKind::POSE),
            "CoordinateKind(pose)"
        );
    }
}
