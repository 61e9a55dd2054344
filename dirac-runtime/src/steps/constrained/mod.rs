//! Holonomic constraints `φ(q) = 0`: the constrained discrete Lagrange–Dirac equations in
//! RATTLE form, unreduced ([`ConstrainedIntegrator`]) and reduced
//! ([`ReducedConstrainedIntegrator`]), on the one Newton driver and either backend.
//!
//! A step is two Newton solves on saddle-point (KKT) systems that `#[reduced_lagrangian]`
//! emits from `constraints = |q| [..]`:
//!
//! ```text
//! position   p_k + D1 L_d(q_k, q_{k+1}) + f_d^− − Dφ(q_k)ᵀ λ_k = 0,   φ(q_{k+1}) = 0
//! momentum   p̃ = D2 L_d(q_k, q_{k+1}) + f_d^+
//! projection ∂L/∂v(q_{k+1}, v) − Dφ(q_{k+1})ᵀ ν = p̃,   Dφ(q_{k+1}) v = 0,   p_{k+1} = ∂L/∂v(q_{k+1}, v)
//! ```
//!
//! (Marsden & West §3.5: the discrete Hamilton principle on the constraint manifold `C`; the
//! projection keeps the momenta on `C`'s cotangent space, as RATTLE does; derivation in the
//! compiler's `ir::constraint`). The multipliers `(λ_k, ν_{k+1})` are reported per step. For a
//! constraint invariant under the symmetry the reduced step keeps `μ` exact (or its forced
//! Noether balance): the constraint forces have no group component.
//!
//! The unreduced and the reduced steps are the same sequence of solves on different states; a
//! [`Form`] states only where they differ, and one [`ConstrainedStepper`] takes the step for all
//! three forms ([`UnreducedForm`], [`Plus`](crate::Plus), [`Minus`](crate::Minus)).

use nalgebra::SVector;

use crate::continuous::{
    unreduced_energies, ContinuousEnergies, ContinuousLagrangian, LegendreError,
};
use crate::error::{StepError, Steps};
use crate::linalg::LinearSolver;
use crate::newton::{self, inf_norm, NewtonOptions};
use crate::reduced::trajectory_accessors;
use crate::state::UnreducedState;
use crate::stepper::{
    check_inputs, flat_level_set, step_error, system_at, Collect, History, LevelSet, StepAt,
    StepStats, StepStatsExt, Stepper,
};
use crate::system::DiscreteLagrangian;

mod form;
pub use form::{Form, UnreducedForm};

/// The constraints of a `#[reduced_lagrangian]` system with `constraints = ..` or
/// `nonholonomic = ..`: `M` of them, the same for every [`Form`] of the step.
pub trait Constraints<const S: usize, const K: usize, const N: usize, const M: usize>:
    DiscreteLagrangian<S, K, N>
{
    /// Whether the constraints are holonomic, `φ(q) = 0` (`constraints = ..`), or
    /// nonholonomic, `A(q) v = 0` (`nonholonomic = ..`, imposed at the step's midpoint).
    const HOLONOMIC: bool = true;
    /// Whether the constraints are holonomic: [`Self::HOLONOMIC`], or what only the value knows
    /// (a system given at run time), which is what the steps read.
    fn holonomic(&self) -> bool {
        Self::HOLONOMIC
    }
    /// `φ(q)` (zero for nonholonomic constraints, which restrict velocities only).
    fn constraint(&self, q: &SVector<f64, N>) -> SVector<f64, M>;
}

/// The constrained steps of form `F` ([`UnreducedForm`]: the unreduced equations on `(q, p)`;
/// [`Plus`](crate::Plus) or [`Minus`](crate::Minus): the reduced equations of that side on
/// `(x, w, μ, g)`, for constraints invariant under the symmetry) that `#[reduced_lagrangian]`
/// implements for all three forms: `Z = N + M` unknowns in each solve.
///
/// Every function reads a state of the form, [`Form::State`]: the position step reads the state
/// `s_k` it starts from and `z = (q_{k+1}, λ_k)` (reduced: `z = (x_{k+1}, u, λ_k)` with the
/// group unknown `u` of the side); the projection reads the state after the position step,
/// `s̃` — the configuration `q_{k+1}` with the momentum `p̃` that step leaves (reduced:
/// `(x_{k+1}, w̃_{k+1}, μ_{k+1}, g_{k+1})`) — and `y = (v, ν)`. A type implementing several
/// forms names one with the form: `Constrained::<Plus, S, K, N, M, Z>::constrained_residual(&sys, ..)`.
pub trait Constrained<
    F: Form<S, K, N>,
    const S: usize,
    const K: usize,
    const N: usize,
    const M: usize,
    const Z: usize,
>: Constraints<S, K, N, M>
{
    /// Whether `μ` changes over a reduced step: by a force's group impulse, or by the group
    /// component of nonholonomic constraint forces (the discrete nonholonomic momentum
    /// equation); without either `μ` is copied. Always `false` for [`UnreducedForm`], whose step
    /// has no `μ` of its own.
    const CONSTRAINED_GROUP_FORCED: bool = false;
    /// `μ_{k+1} − μ_k` of a reduced position step at `z`: the forces' group impulse minus the
    /// group component of the constraint impulse `A(q_k)ᵀ λ_k` (read only where
    /// [`Self::CONSTRAINED_GROUP_FORCED`]).
    fn constrained_impulse(&self, _state: &F::State, _z: &SVector<f64, Z>) -> SVector<f64, K> {
        SVector::zeros()
    }
    /// The linear algebra of the position step (dense up to [`crate::DENSE_MAX`] unknowns).
    type PositionLinear: LinearSolver<Vector = SVector<f64, Z>>;
    /// The linear algebra of the projection.
    type ProjectionLinear: LinearSolver<Vector = SVector<f64, Z>>;
    /// A workspace for the position step.
    fn position_solver(&self) -> Self::PositionLinear;
    /// A workspace for the projection.
    fn projection_solver(&self) -> Self::ProjectionLinear;
    /// The position residual at `z` from `state`.
    fn constrained_residual(&self, state: &F::State, z: &SVector<f64, Z>) -> SVector<f64, Z>;
    /// The position residual and its Jacobian.
    fn constrained_residual_jacobian(
        &self,
        state: &F::State,
        z: &SVector<f64, Z>,
    ) -> (
        SVector<f64, Z>,
        <Self::PositionLinear as LinearSolver>::Matrix,
    );
    /// The momentum the position step leaves at `z`: `p̃ = D2 L_d(q_k, q_{k+1}) + f_d^+`
    /// (reduced: `w̃_{k+1} = ∂l/∂x1 + f̃_x^+`).
    fn constrained_momentum(&self, state: &F::State, z: &SVector<f64, Z>) -> F::Momentum;
    /// The projection residual at `y = (v, ν)` from the state `shake` after the position step.
    fn projection_residual(&self, shake: &F::State, y: &SVector<f64, Z>) -> SVector<f64, Z>;
    /// The projection residual and its Jacobian.
    fn projection_residual_jacobian(
        &self,
        shake: &F::State,
        y: &SVector<f64, Z>,
    ) -> (
        SVector<f64, Z>,
        <Self::ProjectionLinear as LinearSolver>::Matrix,
    );
    /// The projected momentum `p_{k+1} = ∂L/∂v(q_{k+1}, v)` (reduced: `(w_{k+1}, μ_{k+1})`,
    /// stacked; `μ` changes only where the constraints have a group component, as
    /// nonholonomic ones may).
    fn projected_momentum(&self, shake: &F::State, y: &SVector<f64, Z>) -> SVector<f64, N>;
}

/// What a constrained step reports besides the new state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConstrainedStep<const M: usize> {
    /// The position multipliers `λ_k` (the constraint impulse `Dφ(q_k)ᵀ λ_k`).
    pub lambda: SVector<f64, M>,
    /// The projection multipliers `ν_{k+1}`.
    pub nu: SVector<f64, M>,
    /// `‖φ(q_{k+1})‖∞` at the accepted step (holonomic constraints); for nonholonomic ones the
    /// position step's residual norm, which bounds the discrete constraint's.
    pub constraint_residual: f64,
    /// Newton statistics of both solves.
    pub stats: StepStats,
}

impl<const M: usize> AsRef<StepStats> for ConstrainedStep<M> {
    fn as_ref(&self) -> &StepStats {
        &self.stats
    }
}

/// A constrained trajectory: states, the multipliers of each step and its statistics.
#[derive(Clone, Debug, PartialEq)]
pub struct ConstrainedTrajectory<St, const M: usize> {
    /// The integrator's time step `h` (the default step of a run).
    pub h: f64,
    /// `states[k]` is the state at `times[k]`.
    pub states: Vec<St>,
    /// `times[k] = t_k`, the time of `states[k]` (`k h` exactly for a fixed step).
    pub times: Vec<f64>,
    /// `step_sizes[k]` is the size step `k` was taken with, bit for bit as the run passed it to
    /// the step: `h` itself for a fixed step, `h_k` with a schedule (the last step shortened to
    /// land on an end time); with adaptive steps the fictitious step `ε_k` (the physical step is
    /// `times[k + 1] − times[k]`).
    pub step_sizes: Vec<f64>,
    /// What step `k` reported.
    pub records: Vec<ConstrainedStep<M>>,
    /// Newton statistics of each step.
    pub stats: Vec<StepStats>,
}

impl<St, const M: usize> ConstrainedTrajectory<St, M> {
    trajectory_accessors!(St);

    /// The largest `‖φ(q_{k+1})‖∞` over the steps.
    pub fn max_constraint_residual(&self) -> f64 {
        self.records
            .iter()
            .fold(0.0, |m, s| m.max(s.constraint_residual))
    }
}

impl<St: std::fmt::Debug, const M: usize> Steps for ConstrainedTrajectory<St, M> {
    fn completed_steps(&self) -> usize {
        self.step_count()
    }
}

/// The workspace of a constrained run: both solvers, the last multipliers and the memory of
/// the last steps' increments.
#[derive(Clone, Debug)]
#[doc(hidden)]
pub struct ConstrainedWorkspace<P, Q, H, const M: usize> {
    /// The position step's linear solver.
    #[doc(hidden)]
    pub position: P,
    /// The projection's linear solver.
    #[doc(hidden)]
    pub projection: Q,
    /// The last two increments (Newton's guess extrapolates them).
    #[doc(hidden)]
    pub history: History<H>,
    /// The last step's multipliers `(λ, ν)`: the next step's guess.
    #[doc(hidden)]
    pub multipliers: Option<(SVector<f64, M>, SVector<f64, M>)>,
}

/// The constraint tolerance of the initial state: `‖φ(q_0)‖∞ = residual ≤ max(abs_tol, rel_tol ·
/// max(scale, 1)) · 10³` with the Newton tolerances and the configuration's scale `‖q_0‖∞`; the
/// typed [`StepError::ConstraintViolated`] otherwise. The check of every constrained
/// integrator, the element-wise one included.
pub(crate) fn check_constraint(
    residual: f64,
    scale: f64,
    options: &NewtonOptions,
) -> Result<(), StepError> {
    let tolerance = options.abs_tol.max(options.rel_tol * scale.max(1.0)) * 1e3;
    if residual <= tolerance {
        Ok(())
    } else {
        Err(StepError::ConstraintViolated {
            residual,
            tolerance,
        })
    }
}

/// `(head, tail)` of `z`: the first `N` components and the last `M`.
fn parts<const N: usize, const M: usize, const Z: usize>(
    z: &SVector<f64, Z>,
) -> (SVector<f64, N>, SVector<f64, M>) {
    const { assert!(N + M == Z, "Z must be N + M") };
    (
        z.fixed_rows::<N>(0).into_owned(),
        z.fixed_rows::<M>(N).into_owned(),
    )
}

/// `(head, tail)` joined.
fn joined<const N: usize, const M: usize, const Z: usize>(
    head: &SVector<f64, N>,
    tail: &SVector<f64, M>,
) -> SVector<f64, Z> {
    const { assert!(N + M == Z, "Z must be N + M") };
    let mut z = SVector::<f64, Z>::zeros();
    z.fixed_rows_mut::<N>(0).copy_from(head);
    z.fixed_rows_mut::<M>(N).copy_from(tail);
    z
}

/// Integrates the constrained equations of form `F` (see the [module documentation](self)):
/// [`ConstrainedIntegrator`] for the unreduced ones, [`ReducedConstrainedIntegrator`] for
/// each reduced side.
#[derive(Clone, Debug)]
pub struct ConstrainedStepper<
    L,
    F,
    const S: usize,
    const K: usize,
    const N: usize,
    const M: usize,
    const Z: usize,
> {
    system: L,
    options: NewtonOptions,
    form: std::marker::PhantomData<F>,
}

/// Integrates the unreduced constrained equations (see the [module documentation](self)).
pub type ConstrainedIntegrator<
    L,
    const S: usize,
    const K: usize,
    const N: usize,
    const M: usize,
    const Z: usize,
> = ConstrainedStepper<L, UnreducedForm, S, K, N, M, Z>;

/// Integrates the reduced constrained equations of side `D` (see the [module
/// documentation](self)).
pub type ReducedConstrainedIntegrator<
    L,
    D,
    const S: usize,
    const K: usize,
    const N: usize,
    const M: usize,
    const Z: usize,
> = ConstrainedStepper<L, D, S, K, N, M, Z>;

/// The workspace of a constrained run of form `F`.
type Workspace<
    L,
    F,
    const S: usize,
    const K: usize,
    const N: usize,
    const M: usize,
    const Z: usize,
> = ConstrainedWorkspace<
    <L as Constrained<F, S, K, N, M, Z>>::PositionLinear,
    <L as Constrained<F, S, K, N, M, Z>>::ProjectionLinear,
    <F as Form<S, K, N>>::Increment,
    M,
>;

impl<L, F, const S: usize, const K: usize, const N: usize, const M: usize, const Z: usize>
    ConstrainedStepper<L, F, S, K, N, M, Z>
where
    F: Form<S, K, N>,
    L: Constrained<F, S, K, N, M, Z>,
{
    /// The constrained integrator of `system` in the form `F`: [`ConstrainedIntegrator::new`]
    /// for the unreduced equations; the reduced sides are named by
    /// [`ReducedConstrainedIntegrator::plus`] and [`ReducedConstrainedIntegrator::minus`].
    pub fn new(system: L, options: NewtonOptions) -> Self {
        Self {
            system,
            options,
            form: std::marker::PhantomData,
        }
    }

    /// The system being integrated.
    pub fn system(&self) -> &L {
        &self.system
    }

    /// The Newton options of both solves.
    pub fn options(&self) -> &NewtonOptions {
        &self.options
    }

    /// The momentum map `J(q, p) = p_g` of the declared translations at `state` (a reduced
    /// state's `μ`). Constraint forces that are not invariant change it along a run. A `Result`
    /// as on every integrator: [`StepError::NonFinite`] for a state that is not finite.
    pub fn momentum_map(&self, state: &F::State) -> Result<SVector<f64, K>, StepError> {
        crate::stepper::finite_momentum_map(
            self.system.momentum_map(&F::unreduced(&self.system, state)),
        )
    }

    /// The continuous energy of a trajectory of this integrator at its nodes and midpoints
    /// ([`crate::continuous_energies`], reduced states mapped back by eq. (3.7)).
    pub fn energies(
        &self,
        trajectory: &ConstrainedTrajectory<F::State, M>,
    ) -> Result<ContinuousEnergies, LegendreError>
    where
        L: ContinuousLagrangian<N>,
    {
        let states: Vec<UnreducedState<N>> = trajectory
            .states
            .iter()
            .map(|s| F::unreduced(&self.system, s))
            .collect();
        unreduced_energies(&self.system, &states, &trajectory.times, trajectory.h)
    }
}

impl<L, const S: usize, const K: usize, const N: usize, const M: usize, const Z: usize>
    ConstrainedStepper<L, crate::Plus, S, K, N, M, Z>
where
    L: Constrained<crate::Plus, S, K, N, M, Z>,
{
    /// The constrained (+) equations.
    pub fn plus(system: L, options: NewtonOptions) -> Self {
        Self::new(system, options)
    }
}

impl<L, const S: usize, const K: usize, const N: usize, const M: usize, const Z: usize>
    ConstrainedStepper<L, crate::Minus, S, K, N, M, Z>
where
    L: Constrained<crate::Minus, S, K, N, M, Z>,
{
    /// The constrained (−) equations.
    pub fn minus(system: L, options: NewtonOptions) -> Self {
        Self::new(system, options)
    }
}

/// One constrained step `k` of form `F` from `state` for `sys` (the system with this step's
/// controls and time step): the position step's Newton solve from the guess that `ws`'s
/// history extrapolates (the multipliers from the last step's), the state it leaves
/// ([`Form::shake`]), the projection's Newton solve from the secant velocity, and the projected
/// state. On success the step's increment and multipliers enter `ws`.
fn step<L, F, const S: usize, const K: usize, const N: usize, const M: usize, const Z: usize>(
    sys: &L,
    options: &NewtonOptions,
    ws: &mut Workspace<L, F, S, K, N, M, Z>,
    k: usize,
    state: &F::State,
) -> Result<(F::State, ConstrainedStep<M>), StepError>
where
    F: Form<S, K, N>,
    L: Constrained<F, S, K, N, M, Z>,
{
    let h = sys.time_step();
    let (lambda0, nu0) = ws
        .multipliers
        .unwrap_or((SVector::zeros(), SVector::zeros()));
    let mut configuration = F::guess(state, &ws.history, h);
    // Adaptive steps: a run's first step starts from the motion in fictitious time, not rest.
    if ws.history.last.is_none() && sys.time_index().is_some() {
        let start = F::unreduced(sys, state);
        if let Some(dq) = sys.adaptive_increment(&start.q, &start.p, h) {
            configuration = F::moved(sys, state, &dq);
        }
    }
    let guess = joined::<N, M, Z>(&configuration, &lambda0);
    let rho = F::scale(state);
    let first = newton::solve_with(
        &mut ws.position,
        guess,
        rho,
        options,
        |z| sys.constrained_residual(state, z),
        |z| sys.constrained_residual_jacobian(state, z),
    )
    .map_err(|failure| step_error(k, failure))?;
    let mut stats = StepStats::from_solution(&first, options.residual_tolerance(rho));
    let (_, lambda) = parts::<N, M, Z>(&first.z);
    let (shake, increment) = F::shake(sys, state, &first.z);
    let rho2 = F::scale(&shake);
    let y0 = joined::<N, M, Z>(&F::secant(state, &shake, h), &nu0);
    let second = newton::solve_with(
        &mut ws.projection,
        y0,
        rho2,
        options,
        |y| sys.projection_residual(&shake, y),
        |y| sys.projection_residual_jacobian(&shake, y),
    )
    .map_err(|failure| step_error(k, failure))?;
    stats.accumulate(&StepStats::from_solution(
        &second,
        options.residual_tolerance(rho2),
    ));
    let (_, nu) = parts::<N, M, Z>(&second.z);
    let next = F::projected(&shake, &sys.projected_momentum(&shake, &second.z));
    if !F::is_finite(&next) {
        return Err(StepError::NonFinite {
            step: k,
            what: "the updated state",
            residual: stats.residual,
        });
    }
    ws.history.push(increment, h);
    ws.multipliers = Some((lambda, nu));
    let constraint_residual = if sys.holonomic() {
        inf_norm(&sys.constraint(&F::configuration(sys, &next)))
    } else {
        first.residual
    };
    Ok((
        next,
        ConstrainedStep {
            lambda,
            nu,
            constraint_residual,
            stats,
        },
    ))
}

impl<L, F, const S: usize, const K: usize, const N: usize, const M: usize, const Z: usize> Stepper
    for ConstrainedStepper<L, F, S, K, N, M, Z>
where
    F: Form<S, K, N>,
    L: Constrained<F, S, K, N, M, Z>,
{
    type State = F::State;
    type Record = ConstrainedStep<M>;
    type Workspace = Workspace<L, F, S, K, N, M, Z>;
    type Trajectory = ConstrainedTrajectory<F::State, M>;

    fn time_step(&self) -> f64 {
        self.system.time_step()
    }

    fn physical_time(&self, state: &F::State) -> Option<f64> {
        self.system
            .time_index()
            .map(|j| F::configuration(&self.system, state)[S + j])
    }

    /// The level set of the state's unreduced form `(q, p)`.
    fn level_set(&self, state: &F::State) -> Option<LevelSet> {
        self.system.time_index()?;
        let start = F::unreduced(&self.system, state);
        flat_level_set(&self.system, &start.q, &start.p)
    }

    /// `g(x)` at the shape `x` of the state's configuration.
    fn monitor(&self, at: StepAt<'_>, state: &F::State) -> Result<Option<f64>, StepError> {
        let owned = system_at(&self.system, at.k, at.h, at.u)?;
        let sys = owned.as_ref().unwrap_or(&self.system);
        let x = F::configuration(sys, state).fixed_rows::<S>(0).into_owned();
        Ok(sys.monitor(&x))
    }

    /// The inputs, and `‖φ(q_0)‖∞` within the Newton tolerances (×10³): a typed
    /// [`StepError::ConstraintViolated`] otherwise.
    fn check(&self, initial: &F::State) -> Result<(), StepError> {
        check_inputs(
            self.system.time_step(),
            &self.system.parameter_values(),
            F::is_finite(initial),
        )?;
        let q = F::configuration(&self.system, initial);
        crate::domain::check_system(&self.system, 0, true, |i| q.get(i).copied())?;
        if !self.system.holonomic() {
            return Ok(());
        }
        check_constraint(
            inf_norm(&self.system.constraint(&q)),
            inf_norm(&q),
            &self.options,
        )
    }

    fn check_domain(&self, k: usize, state: &F::State) -> Result<(), StepError> {
        if self.system.domain().is_empty() {
            return Ok(());
        }
        let q = F::configuration(&self.system, state);
        crate::domain::check_system(&self.system, k, false, |i| q.get(i).copied())
    }

    fn workspace(&self) -> Self::Workspace {
        ConstrainedWorkspace {
            position: self.system.position_solver(),
            projection: self.system.projection_solver(),
            history: History::default(),
            multipliers: None,
        }
    }

    fn control_dim(&self) -> usize {
        self.system.control_count()
    }

    fn step_with(
        &self,
        ws: &mut Self::Workspace,
        at: StepAt<'_>,
        state: &F::State,
    ) -> Result<(F::State, ConstrainedStep<M>), StepError> {
        let StepAt { k, h, u } = at;
        // The system at the step's size and controls (itself for the system's own step).
        let owned = system_at(&self.system, k, h, u)?;
        step(
            owned.as_ref().unwrap_or(&self.system),
            &self.options,
            ws,
            k,
            state,
        )
    }
}

impl<L, F, St, const S: usize, const K: usize, const N: usize, const M: usize, const Z: usize>
    Collect<ConstrainedStepper<L, F, S, K, N, M, Z>> for ConstrainedTrajectory<St, M>
where
    St: Copy,
    F: Form<S, K, N, State = St>,
    L: Constrained<F, S, K, N, M, Z>,
{
    crate::stepper::collect_steps!(
        start(integrator: ConstrainedStepper<L, F, S, K, N, M, Z>) {
            h: integrator.system.time_step(),
        },
        St,
        ConstrainedStep<M>,
        |step| step.stats,
        records: "step records" = *step
    );
}
