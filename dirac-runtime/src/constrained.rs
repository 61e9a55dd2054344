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

use nalgebra::SVector;

use crate::error::{StepError, Steps};
use crate::linalg::LinearSolver;
use crate::newton::{self, inf_norm, NewtonOptions};
use crate::reduced::trajectory_accessors;
use crate::state::{CanonicalState, ReducedState};
use crate::stepper::{
    check_inputs, predicted_increment, step_error, system_at, Collect, History, StepStats,
    StepStatsExt, Stepper,
};
use crate::system::{DiscreteLagrangian, Reduced, Side};

/// The unreduced constrained steps a `#[reduced_lagrangian]` system with `constraints = ..`
/// implements: `M` constraints, `Z = N + M` unknowns in each solve.
pub trait Constrained<
    const S: usize,
    const K: usize,
    const N: usize,
    const M: usize,
    const Z: usize,
>: DiscreteLagrangian<S, K, N>
{
    /// Whether the constraints are holonomic, `φ(q) = 0` (`constraints = ..`), or
    /// nonholonomic, `A(q) v = 0` (`nonholonomic = ..`, imposed at the step's midpoint).
    const HOLONOMIC: bool = true;
    /// The linear algebra of the position step (dense up to [`crate::DENSE_MAX`] unknowns).
    type PositionLinear: LinearSolver<Vector = SVector<f64, Z>>;
    /// The linear algebra of the projection.
    type ProjectionLinear: LinearSolver<Vector = SVector<f64, Z>>;
    /// A workspace for the position step.
    fn position_solver(&self) -> Self::PositionLinear;
    /// A workspace for the projection.
    fn projection_solver(&self) -> Self::ProjectionLinear;
    /// `φ(q)` (zero for nonholonomic constraints, which restrict velocities only).
    fn constraint(&self, q: &SVector<f64, N>) -> SVector<f64, M>;
    /// The position residual at `z = (q_{k+1}, λ_k)`.
    fn constrained_residual(
        &self,
        q_k: &SVector<f64, N>,
        p_k: &SVector<f64, N>,
        z: &SVector<f64, Z>,
    ) -> SVector<f64, Z>;
    /// The position residual and its Jacobian.
    fn constrained_residual_jacobian(
        &self,
        q_k: &SVector<f64, N>,
        p_k: &SVector<f64, N>,
        z: &SVector<f64, Z>,
    ) -> (
        SVector<f64, Z>,
        <Self::PositionLinear as LinearSolver>::Matrix,
    );
    /// `p̃ = D2 L_d(q_k, q_{k+1}) + f_d^+`.
    fn constrained_momentum(&self, q_k: &SVector<f64, N>, z: &SVector<f64, Z>) -> SVector<f64, N>;
    /// The projection residual at `y = (v, ν)` for the momentum `p̃` at `q1`.
    fn projection_residual(
        &self,
        q1: &SVector<f64, N>,
        p1: &SVector<f64, N>,
        y: &SVector<f64, Z>,
    ) -> SVector<f64, Z>;
    /// The projection residual and its Jacobian.
    fn projection_residual_jacobian(
        &self,
        q1: &SVector<f64, N>,
        p1: &SVector<f64, N>,
        y: &SVector<f64, Z>,
    ) -> (
        SVector<f64, Z>,
        <Self::ProjectionLinear as LinearSolver>::Matrix,
    );
    /// The projected momentum `∂L/∂v(q1, v)`.
    fn projected_momentum(&self, q1: &SVector<f64, N>, y: &SVector<f64, Z>) -> SVector<f64, N>;
}

/// The reduced constrained steps of side `D` (for constraints invariant under the symmetry).
pub trait ReducedConstrained<
    D: Side,
    const S: usize,
    const K: usize,
    const N: usize,
    const M: usize,
    const Z: usize,
>: Reduced<D, S, K, N>
{
    /// Whether `μ` changes over a step: by a force's group impulse, or by the group component of
    /// nonholonomic constraint forces (the discrete nonholonomic momentum equation); without
    /// either `μ` is copied.
    const CONSTRAINED_GROUP_FORCED: bool = false;
    /// `μ_{k+1} − μ_k` of the position step at `z`: the forces' group impulse minus the group
    /// component of the constraint impulse `A(q_k)ᵀ λ_k`.
    fn reduced_constrained_impulse(
        &self,
        _x_k: &SVector<f64, S>,
        _z: &SVector<f64, Z>,
    ) -> SVector<f64, K> {
        SVector::zeros()
    }
    /// The linear algebra of the position step.
    type ReducedPositionLinear: LinearSolver<Vector = SVector<f64, Z>>;
    /// The linear algebra of the projection.
    type ReducedProjectionLinear: LinearSolver<Vector = SVector<f64, Z>>;
    /// A workspace for the position step.
    fn reduced_position_solver(&self) -> Self::ReducedPositionLinear;
    /// A workspace for the projection.
    fn reduced_projection_solver(&self) -> Self::ReducedProjectionLinear;
    /// The position residual at `z = (x_{k+1}, u, λ_k)`.
    fn reduced_constrained_residual(
        &self,
        x_k: &SVector<f64, S>,
        w_k: &SVector<f64, S>,
        mu_k: &SVector<f64, K>,
        z: &SVector<f64, Z>,
    ) -> SVector<f64, Z>;
    /// The position residual and its Jacobian.
    fn reduced_constrained_residual_jacobian(
        &self,
        x_k: &SVector<f64, S>,
        w_k: &SVector<f64, S>,
        mu_k: &SVector<f64, K>,
        z: &SVector<f64, Z>,
    ) -> (
        SVector<f64, Z>,
        <Self::ReducedPositionLinear as LinearSolver>::Matrix,
    );
    /// `w̃_{k+1} = ∂l/∂x1 + f̃_x^+` at `z`.
    fn reduced_constrained_momentum(
        &self,
        x_k: &SVector<f64, S>,
        z: &SVector<f64, Z>,
    ) -> SVector<f64, S>;
    /// The projection residual at `y = (v, ν)` for `(w̃_{k+1}, μ_{k+1})` at `x1`.
    fn reduced_projection_residual(
        &self,
        x1: &SVector<f64, S>,
        w1: &SVector<f64, S>,
        mu1: &SVector<f64, K>,
        y: &SVector<f64, Z>,
    ) -> SVector<f64, Z>;
    /// The projection residual and its Jacobian.
    fn reduced_projection_residual_jacobian(
        &self,
        x1: &SVector<f64, S>,
        w1: &SVector<f64, S>,
        mu1: &SVector<f64, K>,
        y: &SVector<f64, Z>,
    ) -> (
        SVector<f64, Z>,
        <Self::ReducedProjectionLinear as LinearSolver>::Matrix,
    );
    /// The projected `(w_{k+1}, μ_{k+1})`, stacked (`μ` changes only where the constraints
    /// have a group component, as nonholonomic ones may).
    fn reduced_projected_momentum(
        &self,
        x1: &SVector<f64, S>,
        mu1: &SVector<f64, K>,
        y: &SVector<f64, Z>,
    ) -> SVector<f64, N>;
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
    /// What step `k` reported.
    pub steps: Vec<ConstrainedStep<M>>,
    /// Newton statistics of each step.
    pub stats: Vec<StepStats>,
}

impl<St, const M: usize> ConstrainedTrajectory<St, M> {
    trajectory_accessors!(St);

    /// The largest `‖φ(q_{k+1})‖∞` over the steps.
    pub fn max_constraint_residual(&self) -> f64 {
        self.steps
            .iter()
            .fold(0.0, |m, s| m.max(s.constraint_residual))
    }
}

impl<St: std::fmt::Debug, const M: usize> Steps for ConstrainedTrajectory<St, M> {
    fn completed_steps(&self) -> usize {
        self.steps()
    }
}

/// The workspace of a constrained run: both solvers, the last multipliers and the memory of
/// the last steps' increments.
#[derive(Clone, Debug)]
pub struct ConstrainedWorkspace<P, Q, H, const M: usize> {
    /// The position step's linear solver.
    pub position: P,
    /// The projection's linear solver.
    pub projection: Q,
    /// The last two increments (Newton's guess extrapolates them).
    pub history: History<H>,
    /// The last step's multipliers `(λ, ν)`: the next step's guess.
    pub multipliers: Option<(SVector<f64, M>, SVector<f64, M>)>,
}

/// The constraint tolerance of the initial state: `‖φ(q_0)‖∞ ≤ max(abs_tol, rel_tol · scale)`
/// with the Newton tolerances and the configuration's scale.
fn check_constraint<const M: usize>(
    phi: SVector<f64, M>,
    scale: f64,
    options: &NewtonOptions,
) -> Result<(), StepError> {
    let residual = inf_norm(&phi);
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

/// Integrates the unreduced constrained equations (see the [module documentation](self)).
#[derive(Clone, Debug)]
pub struct ConstrainedIntegrator<
    L,
    const S: usize,
    const K: usize,
    const N: usize,
    const M: usize,
    const Z: usize,
> {
    system: L,
    options: NewtonOptions,
}

impl<L, const S: usize, const K: usize, const N: usize, const M: usize, const Z: usize>
    ConstrainedIntegrator<L, S, K, N, M, Z>
where
    L: Constrained<S, K, N, M, Z>,
{
    /// The constrained integrator of `system`.
    pub fn new(system: L, options: NewtonOptions) -> Self {
        Self { system, options }
    }

    /// The system being integrated.
    pub fn system(&self) -> &L {
        &self.system
    }
}

impl<L, const S: usize, const K: usize, const N: usize, const M: usize, const Z: usize> Stepper
    for ConstrainedIntegrator<L, S, K, N, M, Z>
where
    L: Constrained<S, K, N, M, Z>,
{
    type State = CanonicalState<N>;
    type Record = ConstrainedStep<M>;
    type Workspace =
        ConstrainedWorkspace<L::PositionLinear, L::ProjectionLinear, SVector<f64, N>, M>;
    type Trajectory = ConstrainedTrajectory<CanonicalState<N>, M>;

    fn time_step(&self) -> f64 {
        self.system.time_step()
    }

    /// The inputs, and `‖φ(q_0)‖∞` within the Newton tolerances (×10³): a typed
    /// [`StepError::ConstraintViolated`] otherwise.
    fn check(&self, initial: &CanonicalState<N>) -> Result<(), StepError> {
        check_inputs(
            self.system.time_step(),
            &self.system.parameter_values(),
            initial.is_finite(),
        )?;
        if !L::HOLONOMIC {
            return Ok(());
        }
        check_constraint(
            self.system.constraint(&initial.q),
            inf_norm(&initial.q),
            &self.options,
        )
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
        L::CONTROLS.len()
    }

    fn step_with(
        &self,
        ws: &mut Self::Workspace,
        k: usize,
        h: f64,
        state: &CanonicalState<N>,
        u: &[f64],
    ) -> Result<(CanonicalState<N>, ConstrainedStep<M>), StepError> {
        let owned = system_at(&self.system, k, h, u)?;
        let sys = owned.as_ref().unwrap_or(&self.system);
        let (q, p) = (&state.q, &state.p);
        let dq = predicted_increment(&ws.history, h);
        let (lambda0, nu0) = ws
            .multipliers
            .unwrap_or((SVector::zeros(), SVector::zeros()));
        let guess = joined::<N, M, Z>(&dq.map_or(*q, |d| q + d), &lambda0);
        let rho = inf_norm(p);
        let first = newton::solve_with(
            &mut ws.position,
            guess,
            rho,
            &self.options,
            |z| sys.constrained_residual(q, p, z),
            |z| sys.constrained_residual_jacobian(q, p, z),
        )
        .map_err(|failure| step_error(k, failure))?;
        let mut stats = StepStats::from_solution(&first, self.options.residual_tolerance(rho));
        let (q1, lambda) = parts::<N, M, Z>(&first.z);
        let p_shake = sys.constrained_momentum(q, &first.z);
        let rho2 = inf_norm(&p_shake);
        let y0 = joined::<N, M, Z>(&((q1 - q) / h), &nu0);
        let second = newton::solve_with(
            &mut ws.projection,
            y0,
            rho2,
            &self.options,
            |y| sys.projection_residual(&q1, &p_shake, y),
            |y| sys.projection_residual_jacobian(&q1, &p_shake, y),
        )
        .map_err(|failure| step_error(k, failure))?;
        stats.accumulate(&StepStats::from_solution(
            &second,
            self.options.residual_tolerance(rho2),
        ));
        let (_, nu) = parts::<N, M, Z>(&second.z);
        let next = CanonicalState {
            q: q1,
            p: sys.projected_momentum(&q1, &second.z),
        };
        if !next.is_finite() {
            return Err(StepError::NonFinite {
                step: k,
                what: "the updated state",
                residual: stats.residual,
            });
        }
        ws.history.push(q1 - q, h);
        ws.multipliers = Some((lambda, nu));
        Ok((
            next,
            ConstrainedStep {
                lambda,
                nu,
                constraint_residual: if L::HOLONOMIC {
                    inf_norm(&sys.constraint(&q1))
                } else {
                    first.residual
                },
                stats,
            },
        ))
    }
}

impl<L, const S: usize, const K: usize, const N: usize, const M: usize, const Z: usize>
    Collect<ConstrainedIntegrator<L, S, K, N, M, Z>> for ConstrainedTrajectory<CanonicalState<N>, M>
where
    L: Constrained<S, K, N, M, Z>,
{
    fn start(integrator: &ConstrainedIntegrator<L, S, K, N, M, Z>, steps: usize) -> Self {
        ConstrainedTrajectory {
            h: integrator.system.time_step(),
            states: crate::stepper::reserved(steps.saturating_add(1)),
            times: crate::stepper::reserved(steps.saturating_add(1)),
            steps: crate::stepper::reserved(steps),
            stats: crate::stepper::reserved(steps),
        }
    }

    fn push(&mut self, t: f64, state: &CanonicalState<N>, record: Option<&ConstrainedStep<M>>) {
        self.states.push(*state);
        self.times.push(t);
        if let Some(step) = record {
            self.steps.push(*step);
            self.stats.push(step.stats);
        }
    }
}

/// Integrates the reduced constrained equations of side `D` (see the [module
/// documentation](self)).
#[derive(Clone, Debug)]
pub struct ReducedConstrainedIntegrator<
    L,
    D,
    const S: usize,
    const K: usize,
    const N: usize,
    const M: usize,
    const Z: usize,
> {
    system: L,
    options: NewtonOptions,
    side: std::marker::PhantomData<D>,
}

impl<L, D, const S: usize, const K: usize, const N: usize, const M: usize, const Z: usize>
    ReducedConstrainedIntegrator<L, D, S, K, N, M, Z>
where
    D: Side,
    L: ReducedConstrained<D, S, K, N, M, Z>,
{
    /// The reduced constrained integrator of side `D`.
    pub fn new(system: L, options: NewtonOptions) -> Self {
        Self {
            system,
            options,
            side: std::marker::PhantomData,
        }
    }

    /// The system being integrated.
    pub fn system(&self) -> &L {
        &self.system
    }
}

impl<L, const S: usize, const K: usize, const N: usize, const M: usize, const Z: usize>
    ReducedConstrainedIntegrator<L, crate::Plus, S, K, N, M, Z>
where
    L: ReducedConstrained<crate::Plus, S, K, N, M, Z>,
{
    /// The constrained (+) equations.
    pub fn plus(system: L, options: NewtonOptions) -> Self {
        Self::new(system, options)
    }
}

impl<L, const S: usize, const K: usize, const N: usize, const M: usize, const Z: usize>
    ReducedConstrainedIntegrator<L, crate::Minus, S, K, N, M, Z>
where
    L: ReducedConstrained<crate::Minus, S, K, N, M, Z>,
{
    /// The constrained (−) equations.
    pub fn minus(system: L, options: NewtonOptions) -> Self {
        Self::new(system, options)
    }
}

impl<L, D, const S: usize, const K: usize, const N: usize, const M: usize, const Z: usize> Stepper
    for ReducedConstrainedIntegrator<L, D, S, K, N, M, Z>
where
    D: Side,
    L: ReducedConstrained<D, S, K, N, M, Z> + Constrained<S, K, N, M, Z>,
{
    type State = ReducedState<S, K>;
    type Record = ConstrainedStep<M>;
    type Workspace = ConstrainedWorkspace<
        L::ReducedPositionLinear,
        L::ReducedProjectionLinear,
        (SVector<f64, S>, SVector<f64, K>),
        M,
    >;
    type Trajectory = ConstrainedTrajectory<ReducedState<S, K>, M>;

    fn time_step(&self) -> f64 {
        self.system.time_step()
    }

    /// The inputs, and `‖φ(q_0)‖∞` within the Newton tolerances (×10³).
    fn check(&self, initial: &ReducedState<S, K>) -> Result<(), StepError> {
        check_inputs(
            self.system.time_step(),
            &self.system.parameter_values(),
            initial.is_finite(),
        )?;
        if !<L as Constrained<S, K, N, M, Z>>::HOLONOMIC {
            return Ok(());
        }
        let q = self.system.untrivialize(initial).q;
        check_constraint(self.system.constraint(&q), inf_norm(&q), &self.options)
    }

    fn workspace(&self) -> Self::Workspace {
        ConstrainedWorkspace {
            position: self.system.reduced_position_solver(),
            projection: self.system.reduced_projection_solver(),
            history: History::default(),
            multipliers: None,
        }
    }

    fn control_dim(&self) -> usize {
        L::CONTROLS.len()
    }

    fn step_with(
        &self,
        ws: &mut Self::Workspace,
        k: usize,
        h: f64,
        state: &ReducedState<S, K>,
        u: &[f64],
    ) -> Result<(ReducedState<S, K>, ConstrainedStep<M>), StepError> {
        let owned = system_at(&self.system, k, h, u)?;
        let sys = owned.as_ref().unwrap_or(&self.system);
        let (x, w, mu) = (&state.x, &state.w, &state.mu);
        let dx = predicted_increment(&ws.history.map(|l| l.0), h);
        let du = predicted_increment(&ws.history.map(|l| l.1), h);
        let (lambda0, nu0) = ws
            .multipliers
            .unwrap_or((SVector::zeros(), SVector::zeros()));
        let head: SVector<f64, N> = crate::system::join::<S, K, N>(
            &dx.map_or(*x, |d| x + d),
            &du.unwrap_or_else(SVector::zeros),
        );
        let guess = joined::<N, M, Z>(&head, &lambda0);
        let rho = inf_norm(w).max(inf_norm(mu));
        let first = newton::solve_with(
            &mut ws.position,
            guess,
            rho,
            &self.options,
            |z| sys.reduced_constrained_residual(x, w, mu, z),
            |z| sys.reduced_constrained_residual_jacobian(x, w, mu, z),
        )
        .map_err(|failure| step_error(k, failure))?;
        let mut stats = StepStats::from_solution(&first, self.options.residual_tolerance(rho));
        let (zq, lambda) = parts::<N, M, Z>(&first.z);
        let (x1, group_unknown) = crate::system::split::<S, K, N>(&zq);
        let w_shake = sys.reduced_constrained_momentum(x, &first.z);
        let mu1 = if L::CONSTRAINED_GROUP_FORCED {
            mu + sys.reduced_constrained_impulse(x, &first.z)
        } else {
            *mu
        };
        let g1 = state.g + D::group_increment(group_unknown) + sys.h_d0(x, &x1);
        // The velocity guess: the step's secant in the configuration (x, g).
        let v_guess = crate::system::join::<S, K, N>(&((x1 - x) / h), &((g1 - state.g) / h));
        let rho2 = inf_norm(&w_shake).max(inf_norm(&mu1));
        let y0 = joined::<N, M, Z>(&v_guess, &nu0);
        let second = newton::solve_with(
            &mut ws.projection,
            y0,
            rho2,
            &self.options,
            |y| sys.reduced_projection_residual(&x1, &w_shake, &mu1, y),
            |y| sys.reduced_projection_residual_jacobian(&x1, &w_shake, &mu1, y),
        )
        .map_err(|failure| step_error(k, failure))?;
        stats.accumulate(&StepStats::from_solution(
            &second,
            self.options.residual_tolerance(rho2),
        ));
        let (_, nu) = parts::<N, M, Z>(&second.z);
        let (w_new, mu_new) =
            crate::system::split::<S, K, N>(&sys.reduced_projected_momentum(&x1, &mu1, &second.z));
        let next = ReducedState {
            x: x1,
            w: w_new,
            mu: mu_new,
            g: g1,
        };
        if !next.is_finite() {
            return Err(StepError::NonFinite {
                step: k,
                what: "the updated state",
                residual: stats.residual,
            });
        }
        ws.history.push((x1 - x, group_unknown), h);
        ws.multipliers = Some((lambda, nu));
        let constraint_residual = if <L as Constrained<S, K, N, M, Z>>::HOLONOMIC {
            inf_norm(&sys.constraint(&sys.untrivialize(&next).q))
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
}

impl<L, D, const S: usize, const K: usize, const N: usize, const M: usize, const Z: usize>
    Collect<ReducedConstrainedIntegrator<L, D, S, K, N, M, Z>>
    for ConstrainedTrajectory<ReducedState<S, K>, M>
where
    D: Side,
    L: ReducedConstrained<D, S, K, N, M, Z> + Constrained<S, K, N, M, Z>,
{
    fn start(integrator: &ReducedConstrainedIntegrator<L, D, S, K, N, M, Z>, steps: usize) -> Self {
        ConstrainedTrajectory {
            h: integrator.system.time_step(),
            states: crate::stepper::reserved(steps.saturating_add(1)),
            times: crate::stepper::reserved(steps.saturating_add(1)),
            steps: crate::stepper::reserved(steps),
            stats: crate::stepper::reserved(steps),
        }
    }

    fn push(&mut self, t: f64, state: &ReducedState<S, K>, record: Option<&ConstrainedStep<M>>) {
        self.states.push(*state);
        self.times.push(t);
        if let Some(step) = record {
            self.steps.push(*step);
            self.stats.push(step.stats);
        }
    }
}
