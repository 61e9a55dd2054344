//! Configurations on rotation groups: rotations `R ∈ SO(3)`, directions `n ∈ S²`, poses
//! `(R, x) ∈ SE(3)` and ordinary scalars, stepped by a Lie group variational integrator whose residual and Jacobian
//! `#[reduced_lagrangian]` derives from the discrete Lagrangian `L_d(q0, q1)` written with
//! matrices and vectors (`rotation(R)`, `direction(n)` in the attribute).
//!
//! # Charts centred at the current point
//!
//! The configuration space is `Q = R^m × SO(3)^a × (S²)^b`, of dimension `N = m + 3a + 2b`. At
//! each point `q` the integrator works in a chart `φ_q : R^N → Q` centred at `q` (`φ_q(0) = q`),
//! one block per coordinate:
//!
//! * a scalar `x`: `φ(ξ) = x + ξ`;
//! * a rotation `R`: `φ(ξ) = R cay(ξ)`, with the Cayley retraction
//!   `cay(ξ) = (I − ξ̂/2)⁻¹ (I + ξ̂/2) = I + 4/(4 + |ξ|²) (ξ̂ + ξ̂²/2)` ([`cayley`]), so that
//!   `dφ(0) η = R η̂`: the left trivialization, the body frame;
//! * a direction `n`, stored with an orthonormal frame `F = [e1 e2 n]` (a rotation whose third
//!   column is `n`, see [`frame`]): `φ(a, b) = (n + a e1 + b e2) / |n + a e1 + b e2|` (the
//!   sphere's retraction, so `|n| = 1` to round-off at every step), the frame carried along by
//!   the rotation that takes `e3` to `(a, b, 1)/√(1 + a² + b²)` by the shortest arc and made
//!   orthonormal to the new `n` again, so `dφ(0) (a, b) = a e1 + b e2`;
//! * a pose `(R, x)`: `φ(ξ, v) = (R cay(ξ), x + v)`, the rotation's chart and the translation in
//!   space, so `dφ(0) (η, ζ) = (R η̂, ζ)`.
//!
//! Each kind of coordinate is one implementation of [`Group`] (see [`crate::groups`]): its
//! point, chart, manifold check, spatial momentum and output names are written there once, and
//! the integrators below call them block by block.
//!
//! A configuration is stored as its point `q ∈ R^P` (scalars, then for each rotation its 9
//! entries row by row, for each direction its frame's 9 entries row by row, in the order the
//! attribute declares them), and a step's unknown is the chart coordinate `z ∈ R^N` of the next
//! point. The step is a smooth map of `z` (no angle, no chart switch) and the next point is
//! formed by products of rotations: it stays on the group to round-off with no projection.
//!
//! # The equations
//!
//! The momentum `p ∈ R^N` is the covector in the chart at its centre, `p·η = ⟨P, dφ_q(0) η⟩`:
//! for a rotation the left-trivialized momentum `Π ∈ so(3)*` (`⟨P, R η̂⟩ = Π·η`), for a
//! direction the components `e_a·P` of its momentum in the frame, for a scalar its momentum.
//! What a state stores is the *discrete* Legendre momentum of the two lines below, not the
//! continuous `∂L/∂Ω = JΩ` of some angular velocity. For the free rigid body it is
//! `Π_k = vee(F_k J_d − J_d F_kᵀ)/h`; for `F_k = cay(hΩ)` that is
//! `JΩ − (h/2) JΩ × Ω + O(h²)`, the momentum at the start of a step whose velocity mid-step is
//! `Ω` (Euler's `Π̇ = Π × Ω + M` run back half a step). A potential adds its torque by the
//! trapezoid rule: `Π_k` moves by `−(h/2) M(R_k)` (for the heavy top's `m g l e3ᵀ R e3`,
//! `M = m g l Rᵀe3 × e3`). So `Π_k` and `JΩ` differ at first order in `h`. To start a run from
//! an attitude and an angular velocity, take the momentum of the first discrete step with that
//! velocity: [`LieLagrangian::discrete_legendre_state`]. With the
//! variations `δq_k = dφ_{q_k}(0) η_k` — on a rotation `δR = R η̂`, the variations of the Lie
//! group variational integrators (Lee, Leok & McClamroch 2005, 2007; Bou-Rabee & Marsden 2009
//! for the Hamilton–Pontryagin form; Lee, Leok & McClamroch 2009 on two-spheres) — the discrete
//! Hamilton–Pontryagin principle `δ Σ L_d(q_k, q_{k+1}) = 0` gives
//! `D2 L_d(q_{k−1}, q_k)·δq_k + D1 L_d(q_k, q_{k+1})·δq_k = 0` for every `η_k`, and with the
//! discrete Legendre transforms in the trivialization the position–momentum form of the discrete
//! Lagrange–Dirac equations (the paper's Definition 2.7, on a Lie group):
//!
//! ```text
//! p_k · η     = −D1 L_d(q_k, q_{k+1}) · dφ_{q_k}(0) η
//! p_{k+1} · η =  D2 L_d(q_k, q_{k+1}) · dφ_{q_{k+1}}(0) η        for every η ∈ R^N.
//! ```
//!
//! On a rotation these read `Π_k = −T*_e L_{R_k}(D1 L_d)`, `Π_{k+1} = T*_e L_{R_{k+1}}(D2 L_d)`,
//! with `T*_e L_R(G) = vee(Rᵀ G − Gᵀ R)` for the matrix `G` of partial derivatives in the
//! entries. A step knows `(q_k, p_k)` and solves the first line for `z`, `q_{k+1} = φ_{q_k}(z)`:
//! with the chart Lagrangian `L̃(ξ0, ξ1) = L_d(φ_{q_k}(ξ0), φ_{q_k}(ξ1))` the residual is
//! `R(z) = D1 L̃(0, z) + p_k` and its Jacobian `D2 D1 L̃(0, z)`, both straight-line code the
//! compiler derives through `φ` ([`LieLagrangian`]); the second line is then explicit.
//!
//! The (−) equations of Definition 2.8 (`q_{k+1}^− = q_k`, `p_k = −D1 L_d(q_{k+1}^−, q_{k+1})`,
//! `p_{k+1} = D2 L_d(q_{k+1}^−, q_{k+1})`) trivialize at the other end: their unknown is the
//! coordinate `w` of the current point in the chart centred at the next one,
//! `q_k = φ_{q_{k+1}}(w)` ([`LieIntegrator::minus`]). Each chart is inverted by a sign:
//! `R_k = R_{k+1} cay(w)` is `R_{k+1} = R_k cay(w)ᵀ = R_k cay(−w)`; a scalar's `x_k = x_{k+1} + w`
//! is `x_{k+1} = x_k − w`; a direction's frame is moved by the shortest-arc rotation `M(w)`
//! taking `e3` to `(a, b, 1)/√(1 + a² + b²)`, and `M(w)ᵀ = M(−w)` (a rotation about the opposite
//! axis by the same angle), so `q_{k+1} = φ_{q_k}(−w)` for every kind. The momenta are the same
//! covectors in the same charts, so the (−) equations are the (+) equations at `z = −w`: the
//! (−) integrator solves `−R(−w) = 0` (whose Jacobian in `w` is `R`'s in `z`) and takes the same
//! steps as the (+) one — bit for bit, negation being exact.
//!
//! For the free rigid body `L_d = tr((I − F_k) J_d)/h`, `F_k = R_kᵀ R_{k+1}`,
//! `J_d = ½ tr(J) I − J`, the first line is the LGVI's `h Π_k = vee(F_k J_d − J_d F_kᵀ)` and the
//! second `Π_{k+1} = F_kᵀ Π_k`.
//!
//! # What is kept
//!
//! The step map is the discrete flow of `L_d`: symplectic on `T*Q`. If `L_d` is invariant under
//! the rotation of every rotation, direction and pose coordinate together (`R ↦ g R`,
//! `n ↦ g n`, `x ↦ g x`, scalars fixed), differentiating `L_d(g q_k, g q_{k+1}) = L_d(q_k, q_{k+1})` in `g` along `ζ`
//! gives `D1 L_d·(ζ̂ q_k) + D2 L_d·(ζ̂ q_{k+1}) = 0`; with `ζ̂ R = R (Rᵀζ)^` and
//! `⟨P, ζ × n⟩ = ζ·(n × P)` this is the discrete Noether theorem for the spatial angular momentum
//! ([`LieIntegrator::spatial_momentum`])
//!
//! ```text
//! π = Σ_rotations R Π + Σ_directions n × P + Σ_poses (R Π + x × p),        π_{k+1} = π_k,
//! ```
//!
//! and if it is invariant under translating every pose together (`x ↦ x + a`) the linear
//! momentum `ℓ = Σ_poses p` is kept likewise ([`LieIntegrator::linear_momentum`]); both are
//! kept up to the residual Newton accepts (not bit for bit: the update is not a copy). A
//! rotation about one axis only (a body in a uniform field) keeps that component of `π`.
//!
//! A symmetric `L_d` (`L_d(q0, q1; −h) = −L_d(q1, q0; h)`, e.g. the rigid body's above or a
//! midpoint-type rule) gives a symmetric step of order 2, which the compositions of
//! [`crate::compose`] raise to order 4 and 6.
//!
//! # Sizes, fixed or chosen at run time
//!
//! The integrators are generic over the sizes `P` (a stored point) and `N` (the chart) as
//! nalgebra [`Dim`]s ([`LieIntegratorOf`], [`ReducedLieIntegratorOf`], their states
//! [`LieStateOf`], [`ReducedLieStateOf`]), through one dimension-generic trait, [`LieModel`]
//! (and [`SymmetricLieModel`] for the reduced step), whose functions write into the vectors they
//! are given (see [`model`]):
//!
//! * a system compiled in implements [`LieLagrangian<P, N>`](LieLagrangian) at `const` sizes and
//!   is a `LieModel<Const<P>, Const<N>>` by a blanket impl. Its vectors are fixed-size
//!   `SVector`s on the stack and its step the fixed-size code it was before the sizes became
//!   type parameters; [`LieState<P, N>`](LieState), [`LieIntegrator<L, P, N>`](LieIntegrator)
//!   and the other `const` spellings name the generic types at `Const` sizes (and `LieState` is
//!   `Copy`);
//! * a system whose size is known only when it is given (a text with any number of rotations,
//!   directions, poses and scalars: `dirac_jit::DynJitLie`) implements `LieModel<Dyn, Dyn>`. Its
//!   vectors are `DVector`s; the step's unknown, residual, chart coordinate, Jacobian buffer and
//!   the history Newton extrapolates are in the run's workspace ([`LieWorkspaceOf`]), built once
//!   per run, and the driver steps into the memory of the state before, so the unreduced step
//!   allocates nothing (the reduced step's corrections copy the state: two vectors per step). A
//!   state of other sizes than the system's is refused before the first step
//!   ([`StepError::OffManifold`]).

mod adaptive;
pub mod diagnostics;
mod integrator;
pub mod model;
pub mod reduced;
mod sensitivity;
#[cfg(test)]
mod tests;

pub use crate::groups::{
    cayley, direction_frame, frame, hat, orthogonality_defect, rows, vee, CoordinateKind, Group,
    SpatialMomentum, MANIFOLD_TOLERANCE, UNIT_TOLERANCE,
};
pub use integrator::{
    LieForm, LieIntegrator, LieIntegratorIn, LieIntegratorOf, LieWorkspace, LieWorkspaceOf,
    UnreducedForm,
};
pub use model::{LieHistory, LieModel, SymmetricLieModel};
pub use reduced::{
    LieSymmetric, ReducedForm, ReducedLieIntegrator, ReducedLieIntegratorOf, ReducedLieState,
    ReducedLieStateOf, ReducedLieTrajectory, ReducedLieTrajectoryOf, RotationSymmetry,
};

use nalgebra::allocator::Allocator;
use nalgebra::{Const, DefaultAllocator, Dim, Dyn, Matrix3, OVector, SVector};

use crate::error::{StepError, Steps};
use crate::linalg::LinearSolver;
use crate::model::System;
use crate::reduced::trajectory_accessors;
use crate::stepper::{Collect, StepStats, StepStatsExt, Stepper};

/// A discrete Lagrangian on `Q = R^m × SO(3)^a × (S²)^b`, with the straight-line functions of
/// its Lie group variational step (see the [module documentation](self)). `P` is the length of a
/// stored point, `N = dim Q` that of the chart and the momentum. `#[reduced_lagrangian]`
/// implements it for a function with `rotation(..)` or `direction(..)` coordinates. The rotation
/// family of the one system model ([`System`]: parameters, time step, controls, time coordinate
/// and names are declared there; this family declares no domain, and its integrators refuse a
/// system that does).
pub trait LieLagrangian<const P: usize, const N: usize>:
    System + Clone + Send + Sync + 'static
{
    /// The coordinates, in the order of the point and the chart.
    const COORDINATES: &'static [(&'static str, CoordinateKind)];

    /// The coordinate `i` (its name and kind, in the order of the point and the chart), `None`
    /// past the last: [`Self::COORDINATES`] for a system compiled in; a system given at run time
    /// (whose constants cannot know its coordinates) says them here. What the integrators (the
    /// layout of the point and the chart) and output (column names, metadata) read.
    fn coordinate(&self, i: usize) -> Option<(&str, CoordinateKind)> {
        Self::COORDINATES.get(i).copied()
    }

    /// Adaptive steps: the step monitor `g(q) > 0` at the point `q` (`dt = g dτ`); `None` for a
    /// system stepped in physical time. The time coordinate is [`System::time_index`], an index
    /// into [`Self::COORDINATES`] (a group scalar).
    fn monitor(&self, q: &SVector<f64, P>) -> Option<f64> {
        let _ = q;
        None
    }

    /// The linear algebra of the steps: dense LU on the stack for small `N`.
    type Linear: LinearSolver<Vector = SVector<f64, N>>;

    /// A workspace for [`Self::Linear`], built once per run.
    fn linear_solver(&self) -> Self::Linear;

    /// `L_d(q0, q1)`, evaluated by the user's own function body.
    fn lagrangian(&self, q0: &SVector<f64, P>, q1: &SVector<f64, P>) -> f64;

    /// The point `φ_q(z)` of the chart centred at `q`.
    fn retract(&self, q: &SVector<f64, P>, z: &SVector<f64, N>) -> SVector<f64, P>;

    /// `R(z) = D1 L̃(0, z) + p_k`, the step residual in the chart centred at `q_k`.
    fn residual(
        &self,
        q_k: &SVector<f64, P>,
        p_k: &SVector<f64, N>,
        z: &SVector<f64, N>,
    ) -> SVector<f64, N>;

    /// `R(z)` and its exact Jacobian `D2 D1 L̃(0, z)`, from one straight-line function.
    fn residual_jacobian(
        &self,
        q_k: &SVector<f64, P>,
        p_k: &SVector<f64, N>,
        z: &SVector<f64, N>,
    ) -> (SVector<f64, N>, <Self::Linear as LinearSolver>::Matrix);

    /// The momentum update `p_{k+1} = D2 L_d(q_k, q_{k+1}) · dφ_{q_{k+1}}(0)` at
    /// `q_{k+1} = φ_{q_k}(z)` (`+ f_d^+` with forces); for a [`CoordinateKind::GROUP`]
    /// coordinate the Noether balance `p_k + f_d^− + f_d^+`, which reads `p_k`.
    fn momentum(
        &self,
        q_k: &SVector<f64, P>,
        p_k: &SVector<f64, N>,
        z: &SVector<f64, N>,
    ) -> SVector<f64, N>;

    /// The state at the stored point `q` whose momentum is the discrete Legendre momentum of the
    /// step that leaves `q` with the chart velocity `v`: `p_k = −D1 L_d(q_k, q_{k+1})·dφ_{q_k}(0)`
    /// (the first line of the step equations, with its forces) at `q_{k+1} = φ_{q_k}(h v)`,
    /// computed as `−R(h v)` with `p_k = 0` ([`Self::residual`]). On a rotation `v` is the body
    /// angular velocity `Ω` in the Cayley chart (`R_{k+1} = R_k cay(hΩ)`, so that
    /// `cay⁻¹(R_kᵀ R_{k+1})/h = Ω` exactly), on a direction the frame components of its velocity,
    /// on a scalar its rate. This is how to start a discrete `L_d` from `(R, Ω)`: the run's first
    /// step then moves by `h v` (its Newton solve returns `z = h v` to round-off), and for the
    /// free rigid body `p_k = vee(F J_d − J_d Fᵀ)/h` with `F = cay(hΩ)` (Lee, Leok & McClamroch
    /// 2005), which is `JΩ − (h/2) JΩ × Ω + O(h²)`; a potential moves it by `−(h/2)` times its
    /// torque (see the [module documentation](self)).
    ///
    /// `q` is a stored point (each rotation row by row: build it with the emitted
    /// `<Name>Config::to_point`). `Err` with [`StepError::NonFinite`] when a momentum is not
    /// finite.
    fn discrete_legendre_state(
        &self,
        q: &SVector<f64, P>,
        v: &SVector<f64, N>,
    ) -> Result<LieState<P, N>, StepError> {
        let z = v * self.time_step();
        let p = -self.residual(q, &SVector::zeros(), &z);
        if !q.iter().chain(p.iter()).all(|x| x.is_finite()) {
            return Err(StepError::NonFinite {
                step: 0,
                what: "the discrete Legendre momentum of the first step",
                residual: f64::NAN,
            });
        }
        Ok(LieState { q: *q, p })
    }

    /// The partial derivatives of the step from `(q_k, p_k)` to `q_{k+1} = φ_{q_k}(z)` that its
    /// sensitivity needs ([`LiePartials`]); `None` where the compiler emitted none (systems on
    /// the sparse backend).
    fn step_partials(
        &self,
        _q_k: &SVector<f64, P>,
        _p_k: &SVector<f64, N>,
        _z: &SVector<f64, N>,
    ) -> Option<LiePartials> {
        None
    }
}

/// The partial derivatives of a step in the charts at its nominal points (see
/// [`LieIntegrator::sensitivity`]): the step from `q' = φ_{q_k}(δ)` with momentum `p` to
/// `q'_{k+1} = φ_{q_{k+1}}(w)` solves `R̃(w; δ, p, u) = 0` (with `∂R̃/∂p = I`) and sets
/// `p_{k+1} = O(w; δ, u)`; each block is a derivative at `δ = 0`, `w = 0`.
#[derive(Clone, Debug, PartialEq)]
pub struct LiePartials {
    /// `∂R̃/∂w`.
    pub r_w: nalgebra::DMatrix<f64>,
    /// `∂R̃/∂δ`.
    pub r_y: nalgebra::DMatrix<f64>,
    /// `∂R̃/∂u`.
    pub r_u: nalgebra::DMatrix<f64>,
    /// `∂O/∂w`.
    pub o_w: nalgebra::DMatrix<f64>,
    /// `∂O/∂δ`.
    pub o_y: nalgebra::DMatrix<f64>,
    /// `∂O/∂u`.
    pub o_u: nalgebra::DMatrix<f64>,
}

/// A state `(q, p)` of a system on rotation groups at sizes `P` (a stored point) and `N` (the
/// chart), fixed ([`Const`]) or chosen at run time ([`Dyn`]): the stored point `q` (see
/// [`CoordinateKind`]) and the momentum `p` in the chart at `q` (body momenta for rotations,
/// frame components for directions). [`LieState<P, N>`](LieState) names it at fixed sizes,
/// [`DynLieState`] at sizes chosen at run time.
#[derive(Clone, Debug, PartialEq)]
pub struct LieStateOf<P: Dim, N: Dim>
where
    DefaultAllocator: Allocator<P> + Allocator<N>,
{
    /// The stored point.
    pub q: OVector<f64, P>,
    /// The momentum in the chart centred at `q`.
    pub p: OVector<f64, N>,
}

/// A state of a system on rotation groups at fixed sizes: `P` entries of a stored point, `N` of
/// the chart (see [`LieStateOf`]). On the stack, and `Copy`.
pub type LieState<const P: usize, const N: usize> = LieStateOf<Const<P>, Const<N>>;

/// A state of a system on rotation groups whose sizes are chosen at run time (see
/// [`LieStateOf`]).
pub type DynLieState = LieStateOf<Dyn, Dyn>;

impl<const P: usize, const N: usize> Copy for LieStateOf<Const<P>, Const<N>> {}

impl<const P: usize, const N: usize> LieStateOf<Const<P>, Const<N>> {
    crate::state::qp_state!(
        /// The state from a stored point and a momentum (arrays or nalgebra vectors), the layout in
        /// the name: each rotation's 9 entries **row by row** (`R[(0, 0)], R[(0, 1)], R[(0, 2)],
        /// R[(1, 0)], …`, as [`rows`] gives them), each direction's frame and each pose's rotation
        /// the same way (a pose's position after it). A matrix's nalgebra slice (`R.as_slice()`,
        /// `Matrix3::from_slice`) is column by column: passed here it would be read as `Rᵀ`, itself
        /// a rotation that no check can tell apart. From matrices, the emitted
        /// `sys.state(&<Name>Config { r: R, .. }, &momenta)` (or `<Name>Config::to_point`) takes a
        /// `Matrix3` and has no layout to get wrong.
        from_row_major(SVector<f64, P>, SVector<f64, N>)
    );
}

impl LieStateOf<Dyn, Dyn> {
    crate::state::qp_state!(
        /// The state from a stored point and a momentum (slices, `Vec`s, arrays or `DVector`s),
        /// laid out as [`LieState::from_row_major`] says.
        from_row_major(nalgebra::DVector<f64>, nalgebra::DVector<f64>)
    );
}

impl<P: Dim, N: Dim> LieStateOf<P, N>
where
    DefaultAllocator: Allocator<P> + Allocator<N>,
{
    /// Whether every component is finite, at any size.
    pub(crate) fn all_finite(&self) -> bool {
        crate::state::all_finite(&[self.q.as_slice(), self.p.as_slice()])
    }
}

/// A trajectory of a system on rotation groups: the states `S` a run stepped through,
/// `k = 0..=step_count()`, with their times, step sizes and Newton statistics. One type for
/// both forms of the equations: [`LieTrajectoryOf`] of the unreduced states `(q_k, p_k)`,
/// [`ReducedLieTrajectoryOf`] of the reduced ones, at any size ([`LieTrajectory<P, N>`](LieTrajectory)
/// and [`ReducedLieTrajectory<P, N>`](ReducedLieTrajectory) at fixed sizes).
#[derive(Clone, Debug, PartialEq)]
pub struct LieTrajectoryIn<S> {
    /// The integrator's time step `h` (the default step of a run).
    pub h: f64,
    /// `states[k]` is the state at `times[k]`.
    pub states: Vec<S>,
    /// `times[k] = t_k`.
    pub times: Vec<f64>,
    /// `step_sizes[k]` is the size step `k` was taken with, bit for bit as the run passed it to
    /// the step: `h` itself for a fixed step, `h_k` with a schedule (the last step shortened to
    /// land on an end time); with adaptive steps the fictitious step `ε_k` (the physical step is
    /// `times[k + 1] − times[k]`).
    pub step_sizes: Vec<f64>,
    /// Newton statistics of each step.
    pub stats: Vec<StepStats>,
}

/// A trajectory `(q_k, p_k)` of a system on rotation groups, at any size (see
/// [`LieTrajectoryIn`]).
pub type LieTrajectoryOf<P, N> = LieTrajectoryIn<LieStateOf<P, N>>;

/// A trajectory of a system on rotation groups at fixed sizes (see [`LieTrajectoryIn`]).
pub type LieTrajectory<const P: usize, const N: usize> = LieTrajectoryOf<Const<P>, Const<N>>;

impl<S> LieTrajectoryIn<S> {
    trajectory_accessors!(S);
}

impl<S> Steps for LieTrajectoryIn<S> {
    fn completed_steps(&self) -> usize {
        self.step_count()
    }
}

/// The trajectory of either integrator on rotation groups, unreduced or reduced (any stepper of
/// these states that records its Newton statistics).
impl<St> Collect<St> for LieTrajectoryIn<St::State>
where
    St: Stepper<Record = StepStats>,
{
    crate::stepper::collect_steps!(
        start(integrator: St) {
            h: integrator.time_step(),
        },
        St::State,
        StepStats,
        |stats| *stats
    );
}

/// The forms of the integrator on rotation groups ([`LieForm`]): [`UnreducedForm`] and
/// [`ReducedForm`].
mod sealed {
    pub trait Sealed {}
    impl Sealed for super::UnreducedForm {}
    impl Sealed for super::ReducedForm {}
}

/// One coordinate's place in the point and the chart.
struct Block<'a> {
    name: &'a str,
    kind: CoordinateKind,
    point: usize,
    chart: usize,
}

/// The coordinates of `system` ([`LieModel::coordinate`]) with their places in the point
/// and the chart; allocates nothing (read inside steps).
fn blocks<L: LieModel<P, N>, P: Dim, N: Dim>(system: &L) -> impl Iterator<Item = Block<'_>> + '_
where
    DefaultAllocator: Allocator<P> + Allocator<N>,
{
    let (mut point, mut chart) = (0, 0);
    (0..).map_while(move |i| {
        let (name, kind) = system.coordinate(i)?;
        let block = Block {
            name,
            kind,
            point,
            chart,
        };
        point += kind.point_len();
        chart += kind.chart_len();
        Some(block)
    })
}

impl Block<'_> {
    /// The coordinate's block of the stored point `q`.
    fn of_point<'q>(&self, q: &'q [f64]) -> &'q [f64] {
        &q[self.point..self.point + self.kind.point_len()]
    }

    /// The coordinate's block of a chart vector (a chart coordinate, a momentum).
    fn of_chart<'p>(&self, p: &'p [f64]) -> &'p [f64] {
        &p[self.chart..self.chart + self.kind.chart_len()]
    }

    /// [`Self::of_point`], to write.
    fn of_point_mut<'q>(&self, q: &'q mut [f64]) -> &'q mut [f64] {
        &mut q[self.point..self.point + self.kind.point_len()]
    }

    /// [`Self::of_chart`], to write.
    fn of_chart_mut<'p>(&self, p: &'p mut [f64]) -> &'p mut [f64] {
        &mut p[self.chart..self.chart + self.kind.chart_len()]
    }
}

/// The 3 × 3 matrix stored row by row at `q[at..at + 9]`.
fn matrix_at(q: &[f64], at: usize) -> Matrix3<f64> {
    Matrix3::from_fn(|i, j| q[at + 3 * i + j])
}

/// A zero vector of the size `n`.
fn zeros<D: Dim>(n: D) -> OVector<f64, D>
where
    DefaultAllocator: Allocator<D>,
{
    OVector::zeros_generic(n, nalgebra::U1)
}
