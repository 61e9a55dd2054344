//! Sizes as data: what the integrators on rotation groups call, at a size fixed at compile time
//! or chosen at run time.
//!
//! The integrators of [`crate::lie`] are generic over nalgebra's [`Dim`]: `P` the length of a
//! stored point, `N` that of the chart and the momentum. A system compiled in
//! (`#[reduced_lagrangian(rotation(R), ..)]`) implements [`LieLagrangian<P, N>`](super::LieLagrangian)
//! at `const` sizes and is a [`LieModel<Const<P>, Const<N>>`] through the blanket impl below: its
//! vectors are nalgebra's fixed-size `SVector`s, on the stack, and a step runs the same
//! fixed-size code it ran before the sizes became type parameters. A system whose size is known
//! only at run time (a system given as text with any number of rotations, directions, poses and
//! scalars) implements [`LieModel<Dyn, Dyn>`] directly: its vectors are `DVector`s, allocated
//! once per run in the run's workspace ([`LieWorkspace`](super::LieWorkspace)), and its steps
//! write into them, so that a step allocates nothing.
//!
//! The methods take their outputs as arguments (`*_into`) for that reason: a fixed-size system's
//! blanket impl assigns the vector its by-value method returns, which the compiler inlines to
//! the code it ran before.

use nalgebra::allocator::Allocator;
use nalgebra::{Const, DefaultAllocator, Dim, OVector, SVector};

use super::{CoordinateKind, LieLagrangian, LiePartials, LieSymmetric, RotationSymmetry};
use crate::linalg::LinearSolver;
use crate::model::System;
use crate::stepper::same_step;

/// The three functions of a step on the charts — the residual with its Jacobian, then the two
/// that write one chart vector (the residual, the momentum update) — of the unreduced equations
/// ([`LieModel`]) or the reduced ones ([`SymmetricLieModel`]), which differ only in their names:
/// `declare` writes their signatures in a trait, each with its documentation; `forward` writes
/// them at `Const` sizes for a system compiled in, each assigning what the by-value function of
/// `$source` ([`LieLagrangian`], [`LieSymmetric`]) that it names returns (inlined: the code that
/// function is).
macro_rules! chart_step_functions {
    (declare {
        $(#[$jacobian_doc:meta])* $jacobian:ident;
        $($(#[$doc:meta])* $name:ident),+ $(,)?
    }) => {
        $(#[$jacobian_doc])*
        fn $jacobian(
            &self,
            q_k: &OVector<f64, P>,
            p_k: &OVector<f64, N>,
            z: &OVector<f64, N>,
            r: &mut OVector<f64, N>,
            jacobian: &mut Option<<Self::Linear as LinearSolver>::Matrix>,
        );

        $(
            $(#[$doc])*
            fn $name(
                &self,
                q_k: &OVector<f64, P>,
                p_k: &OVector<f64, N>,
                z: &OVector<f64, N>,
                out: &mut OVector<f64, N>,
            );
        )+
    };
    (forward $source:ident: $jacobian:ident = $by_value_jacobian:ident;
        $($name:ident = $by_value:ident),+ $(,)?) => {
        #[inline]
        fn $jacobian(
            &self,
            q_k: &SVector<f64, P>,
            p_k: &SVector<f64, N>,
            z: &SVector<f64, N>,
            r: &mut SVector<f64, N>,
            jacobian: &mut Option<<Self::Linear as LinearSolver>::Matrix>,
        ) {
            let (r_z, j_z) = $source::$by_value_jacobian(self, q_k, p_k, z);
            *r = r_z;
            *jacobian = Some(j_z);
        }

        $(
            #[inline]
            fn $name(
                &self,
                q_k: &SVector<f64, P>,
                p_k: &SVector<f64, N>,
                z: &SVector<f64, N>,
                out: &mut SVector<f64, N>,
            ) {
                *out = $source::$by_value(self, q_k, p_k, z);
            }
        )+
    };
}

/// A system on rotation groups at sizes `P` (a stored point) and `N` (the chart and the
/// momentum), fixed ([`Const`]) or chosen at run time ([`nalgebra::Dyn`]): what the integrators
/// ([`super::LieIntegrator`], [`super::ReducedLieIntegrator`]) call. Every
/// [`LieLagrangian<P, N>`](super::LieLagrangian) is one at `Const<P>`, `Const<N>`; a system sized
/// at run time implements it at `Dyn`, `Dyn`. The equations are those of
/// [`LieLagrangian`] (see the [module documentation](super)); each method
/// writes its result into the vector it is given, of the sizes [`Self::dims`] says.
pub trait LieModel<P: Dim, N: Dim>: System + Clone + Send + Sync + 'static
where
    DefaultAllocator: Allocator<P> + Allocator<N>,
{
    /// The linear algebra of the steps.
    type Linear: LinearSolver<Vector = OVector<f64, N>>;

    /// The sizes of a stored point and of the chart.
    fn dims(&self) -> (P, N);

    /// The coordinate `i` (its name and kind, in the order of the point and the chart), `None`
    /// past the last ([`LieLagrangian::coordinate`]).
    fn coordinate(&self, i: usize) -> Option<(&str, CoordinateKind)>;

    /// The step monitor `g(q)` of adaptive steps, `None` in physical time.
    fn monitor(&self, q: &OVector<f64, P>) -> Option<f64>;

    /// A workspace for [`Self::Linear`], built once per run.
    fn linear_solver(&self) -> Self::Linear;

    /// `L_d(q0, q1)`.
    fn lagrangian(&self, q0: &OVector<f64, P>, q1: &OVector<f64, P>) -> f64;

    /// Writes the point `φ_q(z)` into `out`.
    fn retract_into(&self, q: &OVector<f64, P>, z: &OVector<f64, N>, out: &mut OVector<f64, P>);

    chart_step_functions!(declare {
        /// Writes `R(z)` into `r` and its Jacobian into `jacobian` (reusing the memory of a
        /// `Some`).
        residual_jacobian_into;
        /// Writes the step residual `R(z) = D1 L̃(0, z) + p_k` into `out`.
        residual_into,
        /// Writes the momentum update `p_{k+1}` at `q_{k+1} = φ_{q_k}(z)` into `out`.
        momentum_into,
    });

    /// The partial derivatives of the step that its sensitivity needs, `None` where none were
    /// compiled ([`LieLagrangian::step_partials`]).
    fn step_partials(
        &self,
        q_k: &OVector<f64, P>,
        p_k: &OVector<f64, N>,
        z: &OVector<f64, N>,
    ) -> Option<LiePartials>;
}

/// A [`LieModel`] with a declared rotation symmetry and the reduced step's functions: what
/// [`super::ReducedLieIntegrator`] calls. Every [`LieSymmetric<P, N>`](super::LieSymmetric) is
/// one at `Const<P>`, `Const<N>`.
pub trait SymmetricLieModel<P: Dim, N: Dim>: LieModel<P, N>
where
    DefaultAllocator: Allocator<P> + Allocator<N>,
{
    /// The declared symmetry.
    fn symmetry(&self) -> RotationSymmetry<'_>;

    /// Whether the forces act on a coordinate the symmetry moves.
    fn symmetry_forced(&self) -> bool;

    chart_step_functions!(declare {
        /// [`LieModel::residual_jacobian_into`] of the reduced step.
        reduced_residual_jacobian_into;
        /// [`LieModel::residual_into`] of the reduced step.
        reduced_residual_into,
        /// [`LieModel::momentum_into`] of the reduced step.
        reduced_momentum_into,
    });
}

impl<L, const P: usize, const N: usize> LieModel<Const<P>, Const<N>> for L
where
    L: LieLagrangian<P, N>,
{
    type Linear = L::Linear;

    #[inline]
    fn dims(&self) -> (Const<P>, Const<N>) {
        (Const, Const)
    }

    #[inline]
    fn coordinate(&self, i: usize) -> Option<(&str, CoordinateKind)> {
        LieLagrangian::coordinate(self, i)
    }

    #[inline]
    fn monitor(&self, q: &OVector<f64, Const<P>>) -> Option<f64> {
        LieLagrangian::monitor(self, q)
    }

    #[inline]
    fn linear_solver(&self) -> Self::Linear {
        LieLagrangian::linear_solver(self)
    }

    #[inline]
    fn lagrangian(&self, q0: &OVector<f64, Const<P>>, q1: &OVector<f64, Const<P>>) -> f64 {
        LieLagrangian::lagrangian(self, q0, q1)
    }

    #[inline]
    fn retract_into(
        &self,
        q: &OVector<f64, Const<P>>,
        z: &OVector<f64, Const<N>>,
        out: &mut OVector<f64, Const<P>>,
    ) {
        *out = LieLagrangian::retract(self, q, z);
    }

    chart_step_functions!(
        forward LieLagrangian: residual_jacobian_into = residual_jacobian;
        residual_into = residual,
        momentum_into = momentum,
    );

    #[inline]
    fn step_partials(
        &self,
        q_k: &OVector<f64, Const<P>>,
        p_k: &OVector<f64, Const<N>>,
        z: &OVector<f64, Const<N>>,
    ) -> Option<LiePartials> {
        LieLagrangian::step_partials(self, q_k, p_k, z)
    }
}

impl<L, const P: usize, const N: usize> SymmetricLieModel<Const<P>, Const<N>> for L
where
    L: LieSymmetric<P, N>,
{
    #[inline]
    fn symmetry(&self) -> RotationSymmetry<'_> {
        LieSymmetric::symmetry(self)
    }

    #[inline]
    fn symmetry_forced(&self) -> bool {
        LieSymmetric::symmetry_forced(self)
    }

    chart_step_functions!(
        forward LieSymmetric: reduced_residual_jacobian_into = reduced_residual_jacobian;
        reduced_residual_into = reduced_residual,
        reduced_momentum_into = reduced_momentum,
    );
}

/// The chart coordinates of a run's last two steps and their sizes, in buffers built once per
/// run: what Newton's first guess extrapolates (the rule of the other integrators' guess,
/// component by component, so the guess is the same to the bit).
#[derive(Clone, Debug)]
pub struct LieHistory<N: Dim>
where
    DefaultAllocator: Allocator<N>,
{
    last: OVector<f64, N>,
    before: OVector<f64, N>,
    /// The sizes of the last step and of the one before, when there were such steps.
    sizes: (Option<f64>, Option<f64>),
}

impl<N: Dim> LieHistory<N>
where
    DefaultAllocator: Allocator<N>,
{
    /// No steps yet, with buffers of `n` components.
    pub(crate) fn new(n: N) -> Self {
        Self {
            last: OVector::zeros_generic(n, nalgebra::U1),
            before: OVector::zeros_generic(n, nalgebra::U1),
            sizes: (None, None),
        }
    }

    /// Records a step's unknown and its size `h` (copied: no allocation).
    pub(crate) fn push(&mut self, unknown: &OVector<f64, N>, h: f64) {
        std::mem::swap(&mut self.last, &mut self.before);
        self.last.copy_from(unknown);
        self.sizes = (Some(h), self.sizes.0);
    }

    /// Writes the guess for a step of size `h` into `out` and says whether there was one: from
    /// two steps `2 Δ₁ − Δ₂` on a uniform grid, else the quadratic extrapolation of the
    /// velocities `Δᵢ/hᵢ`; from one step `Δ₁` (scaled by `h/h₁` for another size).
    pub(crate) fn predict_into(&self, h: f64, out: &mut OVector<f64, N>) -> bool {
        let (d1, d2) = (self.last.as_slice(), self.before.as_slice());
        let out = out.as_mut_slice();
        match self.sizes {
            (Some(h1), Some(h2)) => {
                if same_step(h1, h) && same_step(h2, h) {
                    for ((o, a), b) in out.iter_mut().zip(d1).zip(d2) {
                        *o = 2.0 * a - b;
                    }
                } else {
                    let c = h * (h + h1) / (h1 + h2);
                    for ((o, a), b) in out.iter_mut().zip(d1).zip(d2) {
                        let (v1, v2) = (a / h1, b / h2);
                        *o = v1 * h + (v1 - v2) * c;
                    }
                }
                true
            }
            (Some(h1), None) => {
                if same_step(h1, h) {
                    out.copy_from_slice(d1);
                } else {
                    let c = h / h1;
                    for (o, a) in out.iter_mut().zip(d1) {
                        *o = a * c;
                    }
                }
                true
            }
            _ => false,
        }
    }
}
