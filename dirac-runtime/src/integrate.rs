//! Marching the reduced (+)/(−) equations and the unreduced equations step by step.

use std::marker::PhantomData;

use nalgebra::{SMatrix, SVector};

use crate::error::{IntegrationError, StepError, Steps};
use crate::lu::Lu;
use crate::newton::{self, NewtonFailure, NewtonOptions, NewtonSolution};
use crate::state::{CanonicalState, ReducedState};
pub use crate::system::Variant;
use crate::system::{join, split, LagrangianHessian, Minus, Plus, Reduced, Side, Unreduced};

/// What one step cost (the default: nothing yet, as a sum over stages starts).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepStats {
    /// Newton corrections (linear solves) taken.
    pub iterations: usize,
    /// Step Jacobians factored. On the sparse backend a step first corrects with the factors of
    /// an earlier step (chord iterations, [`crate::newton::solve_with`]), so this is often 0
    /// there; on the dense backend it is the number of corrections.
    pub factorizations: usize,
    /// `‖R‖∞` at the accepted solution.
    pub residual: f64,
    /// The residual tolerance the step was accepted against, `abs_tol + rel_tol · ρ` with `ρ`
    /// the momentum scale of the step (see [`NewtonOptions`]). A step may also be accepted on a
    /// small Newton correction, after which `residual` is at round-off level: compare the two to
    /// see how the step converged.
    pub tolerance: f64,
    /// Reciprocal condition estimate (1-norm) of the last step Jacobian factored; `None` when
    /// the initial guess already solved the step.
    pub rcond: Option<f64>,
}

impl StepStats {
    fn from_solution<V>(s: &NewtonSolution<V>, tolerance: f64) -> Self {
        Self {
            iterations: s.iterations,
            factorizations: s.factorizations,
            residual: s.residual,
            tolerance,
            rcond: s.rcond,
        }
    }
}

/// Summary statistics over the steps of a trajectory.
pub trait StepStatsExt {
    /// Mean Newton corrections per step (0 for no steps).
    fn mean_iterations(&self) -> f64;
    /// Largest accepted residual.
    fn max_residual(&self) -> f64;
    /// The worst (smallest) reciprocal condition estimate and the step where it occurred.
    fn worst_rcond(&self) -> Option<(usize, f64)>;
}

impl StepStatsExt for [StepStats] {
    fn mean_iterations(&self) -> f64 {
        if self.is_empty() {
            return 0.0;
        }
        self.iter().map(|s| s.iterations as f64).sum::<f64>() / self.len() as f64
    }

    fn max_residual(&self) -> f64 {
        self.iter().map(|s| s.residual).fold(0.0, f64::max)
    }

    fn worst_rcond(&self) -> Option<(usize, f64)> {
        self.iter()
            .enumerate()
            .filter_map(|(k, s)| s.rcond.map(|r| (k, r)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
    }
}

/// What a step produced besides the new state: the solved group unknown (`u`; `()` for the
/// unreduced equations) and the Newton statistics. Passed to the observer of a streaming run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepRecord<U> {
    /// The reduced group unknown of the step (see [`Trajectory::increments`]).
    pub increment: U,
    /// Newton statistics of the step.
    pub stats: StepStats,
}

/// The outcome of a streaming run ([`ReducedIntegrator::run`], [`UnreducedIntegrator::run`]):
/// the last state and statistics accumulated over the steps, in memory independent of the
/// number of steps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RunSummary<St> {
    /// The time step `h`.
    pub h: f64,
    /// Completed steps.
    pub steps: usize,
    /// The state after the last completed step (the initial state if none).
    pub last: St,
    /// Newton corrections over all steps.
    pub iterations: usize,
    /// Most Newton corrections in one step.
    pub max_iterations: usize,
    /// Step Jacobians factored over all steps (see [`StepStats::factorizations`]).
    pub factorizations: usize,
    /// Largest accepted residual.
    pub max_residual: f64,
    /// The worst (smallest) reciprocal condition estimate of a step Jacobian, and its step.
    pub worst_rcond: Option<(usize, f64)>,
}

impl<St> RunSummary<St> {
    fn new(h: f64, initial: St) -> Self {
        Self {
            h,
            steps: 0,
            last: initial,
            iterations: 0,
            max_iterations: 0,
            factorizations: 0,
            max_residual: 0.0,
            worst_rcond: None,
        }
    }

    fn record(&mut self, next: St, stats: &StepStats) {
        if let Some(r) = stats.rcond {
            if self.worst_rcond.is_none_or(|(_, w)| r < w) {
                self.worst_rcond = Some((self.steps, r));
            }
        }
        self.steps += 1;
        self.last = next;
        self.iterations += stats.iterations;
        self.factorizations += stats.factorizations;
        self.max_iterations = self.max_iterations.max(stats.iterations);
        self.max_residual = self.max_residual.max(stats.residual);
    }

    /// Mean Newton corrections per step (0 for no steps).
    pub fn mean_iterations(&self) -> f64 {
        if self.steps == 0 {
            0.0
        } else {
            self.iterations as f64 / self.steps as f64
        }
    }

    /// The time reached.
    pub fn time(&self) -> f64 {
        self.steps as f64 * self.h
    }
}

impl<St> Steps for RunSummary<St> {
    fn completed_steps(&self) -> usize {
        self.steps
    }
}

/// A reduced trajectory: states `0..=steps()` at times `t_k = k h`, and for each step the solved
/// group unknown and the Newton statistics.
#[derive(Clone, Debug, PartialEq)]
pub struct Trajectory<const S: usize, const K: usize> {
    /// The time step `h`.
    pub h: f64,
    /// The equations that produced it.
    pub variant: Variant,
    /// `states[k]` is the state at `t_k`.
    pub states: Vec<ReducedState<S, K>>,
    /// The reduced group unknown of step `k`: `g_k^+` for [`Variant::Plus`], `g_{k+1}^−` for
    /// [`Variant::Minus`].
    pub increments: Vec<SVector<f64, K>>,
    /// Newton statistics of each step.
    pub stats: Vec<StepStats>,
}

/// An unreduced trajectory `(q_k, p_k)`, `k = 0..=steps()`.
#[derive(Clone, Debug, PartialEq)]
pub struct CanonicalTrajectory<const N: usize> {
    /// The time step `h`.
    pub h: f64,
    /// `states[k]` is the state at `t_k`.
    pub states: Vec<CanonicalState<N>>,
    /// Newton statistics of each step.
    pub stats: Vec<StepStats>,
}

macro_rules! trajectory_accessors {
    ($state:ty) => {
        /// Number of completed steps.
        pub fn steps(&self) -> usize {
            self.states.len() - 1
        }

        /// The time of state `k`.
        pub fn time(&self, k: usize) -> f64 {
            k as f64 * self.h
        }

        /// The last state.
        pub fn last(&self) -> &$state {
            self.states
                .last()
                .expect("a trajectory holds its initial state")
        }

        /// Mean Newton corrections per step (0 for an empty trajectory).
        pub fn mean_iterations(&self) -> f64 {
            self.stats.mean_iterations()
        }

        /// Largest accepted residual over the steps.
        pub fn max_residual(&self) -> f64 {
            self.stats.max_residual()
        }

        /// The worst (smallest) reciprocal condition estimate of a step Jacobian, and its step.
        pub fn worst_rcond(&self) -> Option<(usize, f64)> {
            self.stats.worst_rcond()
        }
    };
}

impl<const S: usize, const K: usize> Trajectory<S, K> {
    trajectory_accessors!(ReducedState<S, K>);
}

impl<const S: usize, const K: usize> Steps for Trajectory<S, K> {
    fn completed_steps(&self) -> usize {
        self.steps()
    }
}

impl<const N: usize> Steps for CanonicalTrajectory<N> {
    fn completed_steps(&self) -> usize {
        self.steps()
    }
}

impl<const N: usize> CanonicalTrajectory<N> {
    trajectory_accessors!(CanonicalState<N>);
}

/// Maps a Newton failure of step `k` to the public error.
fn step_error(k: usize, failure: NewtonFailure) -> StepError {
    match failure {
        NewtonFailure::NotConverged {
            iterations,
            residual,
        } => StepError::NotConverged {
            step: k,
            iterations,
            residual,
        },
        NewtonFailure::Singular { residual } => StepError::SingularJacobian { step: k, residual },
        NewtonFailure::IllConditioned { rcond, residual } => StepError::IllConditioned {
            step: k,
            rcond,
            residual,
        },
        NewtonFailure::NonFinite { residual } => StepError::NonFinite {
            step: k,
            what: "the step equations",
            residual,
        },
    }
}

/// The checks made before the first step: a valid time step, finite parameters and state.
fn check_inputs(h: f64, parameters: &[f64], state_is_finite: bool) -> Result<(), StepError> {
    if !(h.is_finite() && h > 0.0) {
        return Err(StepError::InvalidTimeStep { h });
    }
    let non_finite = |what| StepError::NonFinite {
        step: 0,
        what,
        residual: f64::INFINITY,
    };
    if parameters.iter().any(|p| !p.is_finite()) {
        return Err(non_finite("the parameters"));
    }
    if !state_is_finite {
        return Err(non_finite("the initial state"));
    }
    Ok(())
}

/// Integrates a system with the reduced discrete Lagrange–Poincaré–Dirac equations of side `D`:
/// (4.6) ([`ReducedIntegrator::plus`]) or (4.8) ([`ReducedIntegrator::minus`]).
///
/// Each step solves `R(z) = 0` for `z = (x_{k+1}, u)` by Newton's method (see [`Reduced`]), then
/// updates `w_{k+1}` explicitly, sets `μ_{k+1} = μ_k` exactly, and reconstructs the absolute group
/// coordinate `g_{k+1} = g_k ± u + B (x_{k+1} − x_k)` ([`Side::group_increment`]). The side is a
/// type, so a step contains no dispatch on it and a (+) integrator needs only `Reduced<Plus, ..>`.
#[derive(Clone, Debug)]
pub struct ReducedIntegrator<L, D, const S: usize, const K: usize, const N: usize> {
    system: L,
    options: NewtonOptions,
    /// `Some(choice)` forces the eliminated (where available) or the general path; `None` takes
    /// the compiler's verdict.
    eliminate: Option<bool>,
    side: PhantomData<D>,
}

impl<L, const S: usize, const K: usize, const N: usize> ReducedIntegrator<L, Plus, S, K, N>
where
    L: Reduced<Plus, S, K, N>,
{
    /// The (+) integrator of eq. (4.6).
    pub fn plus(system: L, options: NewtonOptions) -> Self {
        Self::new(system, options)
    }
}

impl<L, const S: usize, const K: usize, const N: usize> ReducedIntegrator<L, Minus, S, K, N>
where
    L: Reduced<Minus, S, K, N>,
{
    /// The (−) integrator of eq. (4.8), with the signs of Definition 2.8.
    pub fn minus(system: L, options: NewtonOptions) -> Self {
        Self::new(system, options)
    }
}

impl<L, D, const S: usize, const K: usize, const N: usize> ReducedIntegrator<L, D, S, K, N>
where
    D: Side,
    L: Reduced<D, S, K, N>,
{
    /// The integrator of side `D` (what [`Self::plus`] and [`Self::minus`] name).
    pub fn new(system: L, options: NewtonOptions) -> Self {
        const { assert!(S + K == N, "the configuration dimension N must be S + K") };
        Self {
            system,
            options,
            eliminate: None,
            side: PhantomData,
        }
    }

    /// Forces the path: `true` solves the group unknowns in closed form wherever the system
    /// provides it ([`Reduced::ELIMINATES_GROUP`]), `false` solves shape and group unknowns
    /// together. Both give the same trajectory to round-off. By default the compiler's verdict
    /// ([`Reduced::ELIMINATION_PAYS`]) decides.
    pub fn with_elimination(mut self, eliminate: bool) -> Self {
        self.eliminate = Some(eliminate);
        self
    }

    /// Whether steps run Newton on the shape unknowns alone, the group unknowns being solved in
    /// closed form.
    pub fn eliminates_group(&self) -> bool {
        L::ELIMINATES_GROUP && self.eliminate.unwrap_or(L::ELIMINATION_PAYS)
    }

    /// The system being integrated.
    pub fn system(&self) -> &L {
        &self.system
    }

    /// The Newton options.
    pub fn options(&self) -> &NewtonOptions {
        &self.options
    }

    /// Which equations are solved.
    pub fn variant(&self) -> Variant {
        D::VARIANT
    }

    /// Takes step `k` from `state`, starting Newton at `guess` for `z = (x_{k+1}, u)`.
    /// Returns the new state, the solved group unknown `u` and the step's statistics.
    ///
    /// Builds a fresh linear-solver workspace ([`Reduced::linear_solver`]): free for the dense
    /// backend, a symbolic factorization and its memory for the sparse one. Loops over steps
    /// should build one with [`Self::workspace`] and call [`Self::step_in`], as
    /// [`Self::integrate`] and [`Self::run`] do.
    pub fn step(
        &self,
        k: usize,
        state: &ReducedState<S, K>,
        guess: &SVector<f64, N>,
    ) -> Result<(ReducedState<S, K>, SVector<f64, K>, StepStats), StepError> {
        self.step_in(&mut self.workspace(), k, state, guess)
    }

    /// The linear-solver workspace a step runs in, to be reused by every step of a run.
    pub fn workspace(&self) -> L::Linear {
        self.system.linear_solver()
    }

    /// [`Self::step`] in the workspace `solver` (from [`Self::workspace`]): after the first
    /// factorization no step allocates.
    pub fn step_in(
        &self,
        solver: &mut L::Linear,
        k: usize,
        state: &ReducedState<S, K>,
        guess: &SVector<f64, N>,
    ) -> Result<(ReducedState<S, K>, SVector<f64, K>, StepStats), StepError> {
        let sys = &self.system;
        let (x, w, mu) = (&state.x, &state.w, &state.mu);
        let rho = newton::inf_norm(w).max(newton::inf_norm(mu));
        if self.eliminates_group() {
            return self.eliminated_step(k, state, guess, rho);
        }
        // The residual alone is evaluated with w_{k+1} (one straight line): where Newton accepts
        // that iterate, the momentum update is already known.
        let mut tested: Option<(SVector<f64, N>, SVector<f64, S>)> = None;
        let solution = newton::solve_with(
            solver,
            *guess,
            rho,
            &self.options,
            |z| {
                let (r, w1) = sys.residual_momentum(x, w, mu, z);
                tested = Some((*z, w1));
                r
            },
            |z| sys.residual_jacobian(x, w, mu, z),
        )
        .map_err(|failure| step_error(k, failure))?;
        let w1 = tested.and_then(|(z, w1)| (z == solution.z).then_some(w1));
        self.finish_step(
            k,
            state,
            solution.z,
            w1,
            StepStats::from_solution(&solution, self.options.residual_tolerance(rho)),
        )
    }

    /// A step with the group unknowns eliminated: Newton on `x_{k+1}` alone, then the group
    /// unknowns in closed form.
    fn eliminated_step(
        &self,
        k: usize,
        state: &ReducedState<S, K>,
        guess: &SVector<f64, N>,
        rho: f64,
    ) -> Result<(ReducedState<S, K>, SVector<f64, K>, StepStats), StepError> {
        let sys = &self.system;
        let (x, w, mu) = (&state.x, &state.w, &state.mu);
        let x_guess: SVector<f64, S> = guess.fixed_rows::<S>(0).into_owned();
        // The `None` arms cannot be taken (`eliminates_group` checked the system's flag); they
        // yield NaN, which the solver reports as a typed error rather than a panic.
        let nan_s = || SVector::<f64, S>::repeat(f64::NAN);
        let solution = newton::solve(
            x_guess,
            rho,
            &self.options,
            |x1| sys.eliminated_residual(x, w, mu, x1).unwrap_or_else(nan_s),
            |x1| {
                sys.eliminated_residual_jacobian(x, w, mu, x1)
                    .unwrap_or_else(|| (nan_s(), SMatrix::repeat(f64::NAN)))
            },
        )
        .map_err(|failure| step_error(k, failure))?;
        let group = sys
            .eliminated_group(x, w, mu, &solution.z)
            .unwrap_or_else(|| SVector::repeat(f64::NAN));
        let block = sys.eliminated_group_block(x, w, mu, &solution.z);
        // The closed form divides by the group block A, whose degeneracy (e.g. where the symmetry
        // action is not free) the shape Jacobian J_S no longer shows: measure A against the scale
        // of J_S, 1 / (‖A⁻¹‖₁ ‖J_S‖₁), and record the worse of that and rcond(J_S).
        // As for J_S (see `newton::checked_rcond`), the cheap upper bound on ‖A⁻¹‖₁ decides when
        // it clears the threshold, and Hager's estimate otherwise.
        let min_rcond = self.options.min_rcond;
        let pivot_rcond = match (block, solution.jacobian_norm1) {
            (Some(a), Some(norm_s)) if norm_s > 0.0 => Some(Lu::new(a).map_or(0.0, |lu| {
                let inverse = lu.inverse_norm1_bound();
                let bound = if inverse.is_finite() {
                    (1.0 / (inverse * norm_s)).min(1.0)
                } else {
                    0.0
                };
                if bound >= newton::RCOND_CLEARANCE * min_rcond {
                    bound
                } else {
                    (lu.rcond() * lu.norm1() / norm_s).min(1.0)
                }
            })),
            _ => None,
        };
        let rcond = match (solution.rcond, pivot_rcond) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        };
        if let Some(r) = rcond {
            if r < self.options.min_rcond {
                return Err(StepError::IllConditioned {
                    step: k,
                    rcond: r,
                    residual: solution.residual,
                });
            }
        }
        let z = join::<S, K, N>(&solution.z, &group);
        let stats = StepStats {
            iterations: solution.iterations,
            factorizations: solution.factorizations,
            residual: solution.residual,
            tolerance: self.options.residual_tolerance(rho),
            rcond,
        };
        self.finish_step(k, state, z, None, stats)
    }

    /// The explicit updates after the unknowns `z = (x_{k+1}, u)` are known; `w1` is `w_{k+1}`
    /// if the solve already evaluated it at `z`.
    fn finish_step(
        &self,
        k: usize,
        state: &ReducedState<S, K>,
        z: SVector<f64, N>,
        w1: Option<SVector<f64, S>>,
        stats: StepStats,
    ) -> Result<(ReducedState<S, K>, SVector<f64, K>, StepStats), StepError> {
        let sys = &self.system;
        let (x, mu) = (&state.x, &state.mu);
        let (x1, u) = split::<S, K, N>(&z);
        let next = ReducedState {
            x: x1,
            w: w1.unwrap_or_else(|| sys.momentum(x, &z)),
            mu: *mu,
            g: state.g + D::group_increment(u) + sys.h_d0(x, &x1),
        };
        if !next.is_finite() {
            return Err(StepError::NonFinite {
                step: k,
                what: "the updated state",
                residual: stats.residual,
            });
        }
        Ok((next, u, stats))
    }

    /// Integrates `steps` steps from `initial` and keeps every state.
    ///
    /// Newton starts each step from [`reduced_guess`], a quadratic extrapolation of the last
    /// shape points and a linear one of the last group unknowns. On failure the error holds the
    /// trajectory computed so far. For long runs that need not keep every state, see
    /// [`Self::run`].
    pub fn integrate(
        &mut self,
        initial: ReducedState<S, K>,
        steps: usize,
    ) -> Result<Trajectory<S, K>, Box<IntegrationError<Trajectory<S, K>>>> {
        self.collect(initial, steps)
    }

    /// [`Self::integrate`] through a shared reference (what an ensemble member runs).
    pub(crate) fn collect(
        &self,
        initial: ReducedState<S, K>,
        steps: usize,
    ) -> Result<Trajectory<S, K>, Box<IntegrationError<Trajectory<S, K>>>> {
        let mut trajectory = Trajectory {
            h: self.system.time_step(),
            variant: D::VARIANT,
            states: Vec::with_capacity(steps + 1),
            increments: Vec::with_capacity(steps),
            stats: Vec::with_capacity(steps),
        };
        let outcome = self.run(initial, steps, |_, state, step| {
            trajectory.states.push(*state);
            if let Some(step) = step {
                trajectory.increments.push(step.increment);
                trajectory.stats.push(step.stats);
            }
        });
        match outcome {
            Ok(_) => Ok(trajectory),
            Err(e) => Err(Box::new(IntegrationError::new(
                e.source,
                trajectory,
                e.requested,
            ))),
        }
    }

    /// Integrates `steps` steps from `initial` without storing them: `observe(k, state, step)`
    /// sees every state `k = 0..=steps` as it is computed (with the step that produced it, `None`
    /// for the initial state), so a run needs memory independent of its length — keep every
    /// `k`-th state, accumulate statistics, write to a file. One linear-solver workspace serves
    /// the whole run, and no step allocates. The summary (last state, Newton statistics) is
    /// returned, or on failure kept in the error with the step index and residual.
    pub fn run(
        &self,
        initial: ReducedState<S, K>,
        steps: usize,
        mut observe: impl FnMut(usize, &ReducedState<S, K>, Option<&StepRecord<SVector<f64, K>>>),
    ) -> Result<RunSummary<ReducedState<S, K>>, Box<IntegrationError<RunSummary<ReducedState<S, K>>>>>
    {
        let mut summary = RunSummary::new(self.system.time_step(), initial);
        let fail = |source, summary| Box::new(IntegrationError::new(source, summary, steps));
        // The initial state is part of what a failed run keeps, even if it is invalid.
        observe(0, &initial, None);
        if let Err(e) = check_inputs(
            summary.h,
            &self.system.parameter_values(),
            initial.is_finite(),
        ) {
            return Err(fail(e, summary));
        }
        let mut solver = self.workspace();
        let mut state = initial;
        // The shape increments and group unknowns of the last two steps, newest first.
        let mut last: Option<(SVector<f64, S>, SVector<f64, K>)> = None;
        let mut before: Option<(SVector<f64, S>, SVector<f64, K>)> = None;
        for k in 0..steps {
            let guess = reduced_guess::<S, K, N>(&state.x, last.as_ref(), before.as_ref());
            match self.step_in(&mut solver, k, &state, &guess) {
                Ok((next, u, stats)) => {
                    before = last;
                    last = Some((next.x - state.x, u));
                    let record = StepRecord {
                        increment: u,
                        stats,
                    };
                    summary.record(next, &stats);
                    observe(k + 1, &next, Some(&record));
                    state = next;
                }
                Err(source) => return Err(fail(source, summary)),
            }
        }
        Ok(summary)
    }
}

/// Newton's initial guess for the step from `x`, `z = (x_{k+1}, group unknown)`, from the last
/// two steps, each given as its shape increment `x_{j+1} − x_j` and its group unknown (newest
/// first; `None` before the start): the shape advances by the extrapolated increment (`x` at the
/// first step, `x + Δ_{k−1}` at the second, then `x + 2 Δ_{k−1} − Δ_{k−2}`, the quadratic through
/// the last three points, whose error is `O(h³)` against the linear one's `O(h²)`), and the group
/// unknown by the same rule one order lower (`0`, the last one, then `2 g_{k−1} − g_{k−2}`: it is
/// itself an increment).
pub fn reduced_guess<const S: usize, const K: usize, const N: usize>(
    x: &SVector<f64, S>,
    last: Option<&(SVector<f64, S>, SVector<f64, K>)>,
    before: Option<&(SVector<f64, S>, SVector<f64, K>)>,
) -> SVector<f64, N> {
    match (last, before) {
        (Some((dx1, g1)), Some((dx2, g2))) => {
            join::<S, K, N>(&(x + (2.0 * dx1 - dx2)), &(2.0 * g1 - g2))
        }
        (Some((dx1, g1)), None) => join::<S, K, N>(&(x + dx1), g1),
        _ => join::<S, K, N>(x, &SVector::zeros()),
    }
}

/// Newton's initial guess for `q_{k+1}` in the unreduced equations from the last two
/// increments `q_{j+1} − q_j`, newest first: `q`, `q + Δ_{k−1}`, then `q + 2 Δ_{k−1} − Δ_{k−2}`
/// (see [`reduced_guess`]).
pub fn canonical_guess<const N: usize>(
    q: &SVector<f64, N>,
    last: Option<&SVector<f64, N>>,
    before: Option<&SVector<f64, N>>,
) -> SVector<f64, N> {
    match (last, before) {
        (Some(dq1), Some(dq2)) => q + (2.0 * dq1 - dq2),
        (Some(dq1), None) => q + dq1,
        _ => *q,
    }
}

/// The Jacobian `M` of one step of the unreduced map `(q_k, p_k) ↦ (q_{k+1}, p_{k+1})`, in
/// blocks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepJacobian<const N: usize> {
    /// `∂q_{k+1}/∂q_k`.
    pub dq_dq: SMatrix<f64, N, N>,
    /// `∂q_{k+1}/∂p_k`.
    pub dq_dp: SMatrix<f64, N, N>,
    /// `∂p_{k+1}/∂q_k`.
    pub dp_dq: SMatrix<f64, N, N>,
    /// `∂p_{k+1}/∂p_k`.
    pub dp_dp: SMatrix<f64, N, N>,
}

impl<const N: usize> StepJacobian<N> {
    /// How far `Mᵀ Ω M = Ω` (`Ω = [[0, I], [−I, 0]]`) is from holding, relative to the size of
    /// the terms. In blocks `M = [[A, B], [C, D]]` the condition is `AᵀC = CᵀA`, `BᵀD = DᵀB` and
    /// `AᵀD − CᵀB = I`; each residual is divided by the size of the products it cancels
    /// (`‖A‖‖C‖`, `‖B‖‖D‖`, `max(1, ‖A‖‖D‖ + ‖C‖‖B‖)`, max-norms of entries), so the result is
    /// dimensionless — the blocks can differ by many orders of magnitude (`∂p/∂q ≈ m l²/h`).
    /// Zero for a symplectic map; round-off gives ~1e-15 to 1e-12.
    pub fn symplecticity_defect(&self) -> f64 {
        let (a, b, c, d) = (&self.dq_dq, &self.dq_dp, &self.dp_dq, &self.dp_dp);
        let n = N as f64;
        let rel = |m: SMatrix<f64, N, N>, scale: f64| m.amax() / scale.max(f64::MIN_POSITIVE);
        let qq = rel(
            a.transpose() * c - c.transpose() * a,
            n * a.amax() * c.amax(),
        );
        let pp = rel(
            b.transpose() * d - d.transpose() * b,
            n * b.amax() * d.amax(),
        );
        let qp = rel(
            a.transpose() * d - c.transpose() * b - SMatrix::<f64, N, N>::identity(),
            (n * (a.amax() * d.amax() + c.amax() * b.amax())).max(1.0),
        );
        qq.max(pp).max(qp)
    }
}

/// Integrates the unreduced discrete Lagrange–Dirac equations on `Q` (Definitions 2.7/2.8,
/// see [`Unreduced`]): the baseline that knows nothing of the symmetry.
#[derive(Clone, Debug)]
pub struct UnreducedIntegrator<L, const S: usize, const K: usize, const N: usize> {
    system: L,
    options: NewtonOptions,
}

impl<L, const S: usize, const K: usize, const N: usize> UnreducedIntegrator<L, S, K, N>
where
    L: Unreduced<S, K, N>,
{
    /// The (+) discrete Lagrange–Dirac equations (Definition 2.7).
    pub fn plus(system: L, options: NewtonOptions) -> Self {
        Self { system, options }
    }

    /// The (−) discrete Lagrange–Dirac equations (Definition 2.8). Unconstrained, with
    /// `q_{k+1}^− = q_k`, they are the same equations as the (+) ones, so this is the same
    /// integrator; it exists so code can name the variant it means.
    pub fn minus(system: L, options: NewtonOptions) -> Self {
        Self::plus(system, options)
    }

    /// The system being integrated.
    pub fn system(&self) -> &L {
        &self.system
    }

    /// The Newton options.
    pub fn options(&self) -> &NewtonOptions {
        &self.options
    }

    /// Takes step `k` from `state`, starting Newton at `guess` for `q_{k+1}`, in a fresh
    /// workspace (see [`ReducedIntegrator::step`]; loops use [`Self::step_in`]).
    pub fn step(
        &self,
        k: usize,
        state: &CanonicalState<N>,
        guess: &SVector<f64, N>,
    ) -> Result<(CanonicalState<N>, StepStats), StepError> {
        self.step_in(&mut self.workspace(), k, state, guess)
    }

    /// The linear-solver workspace a step runs in, to be reused by every step of a run.
    pub fn workspace(&self) -> L::UnreducedLinear {
        self.system.unreduced_linear_solver()
    }

    /// [`Self::step`] in the workspace `solver` (from [`Self::workspace`]).
    pub fn step_in(
        &self,
        solver: &mut L::UnreducedLinear,
        k: usize,
        state: &CanonicalState<N>,
        guess: &SVector<f64, N>,
    ) -> Result<(CanonicalState<N>, StepStats), StepError> {
        let sys = &self.system;
        let (q, p) = (&state.q, &state.p);
        let rho = newton::inf_norm(p);
        let solution = newton::solve_with(
            solver,
            *guess,
            rho,
            &self.options,
            |z| sys.unreduced_residual(q, p, z),
            |z| sys.unreduced_residual_jacobian(q, p, z),
        )
        .map_err(|failure| step_error(k, failure))?;
        let next = CanonicalState {
            q: solution.z,
            p: sys.unreduced_momentum(q, &solution.z),
        };
        if !next.is_finite() {
            return Err(StepError::NonFinite {
                step: k,
                what: "the updated state",
                residual: solution.residual,
            });
        }
        Ok((
            next,
            StepStats::from_solution(&solution, self.options.residual_tolerance(rho)),
        ))
    }

    /// Integrates `steps` steps from `initial` and keeps every state, starting Newton from
    /// [`canonical_guess`], a quadratic extrapolation of the last configurations. On failure the
    /// error holds the trajectory computed so far. See [`Self::run`] for runs in constant memory.
    pub fn integrate(
        &mut self,
        initial: CanonicalState<N>,
        steps: usize,
    ) -> Result<CanonicalTrajectory<N>, Box<IntegrationError<CanonicalTrajectory<N>>>> {
        self.collect(initial, steps)
    }

    /// [`Self::integrate`] through a shared reference (what an ensemble member runs).
    pub(crate) fn collect(
        &self,
        initial: CanonicalState<N>,
        steps: usize,
    ) -> Result<CanonicalTrajectory<N>, Box<IntegrationError<CanonicalTrajectory<N>>>> {
        let mut trajectory = CanonicalTrajectory {
            h: self.system.time_step(),
            states: Vec::with_capacity(steps + 1),
            stats: Vec::with_capacity(steps),
        };
        let outcome = self.run(initial, steps, |_, state, step| {
            trajectory.states.push(*state);
            if let Some(step) = step {
                trajectory.stats.push(step.stats);
            }
        });
        match outcome {
            Ok(_) => Ok(trajectory),
            Err(e) => Err(Box::new(IntegrationError::new(
                e.source,
                trajectory,
                e.requested,
            ))),
        }
    }

    /// Integrates without storing the trajectory: `observe(k, state, step)` sees every state
    /// (see [`ReducedIntegrator::run`]).
    pub fn run(
        &self,
        initial: CanonicalState<N>,
        steps: usize,
        mut observe: impl FnMut(usize, &CanonicalState<N>, Option<&StepRecord<()>>),
    ) -> Result<RunSummary<CanonicalState<N>>, Box<IntegrationError<RunSummary<CanonicalState<N>>>>>
    {
        let mut summary = RunSummary::new(self.system.time_step(), initial);
        let fail = |source, summary| Box::new(IntegrationError::new(source, summary, steps));
        // The initial state is part of what a failed run keeps, even if it is invalid.
        observe(0, &initial, None);
        if let Err(e) = check_inputs(
            summary.h,
            &self.system.parameter_values(),
            initial.is_finite(),
        ) {
            return Err(fail(e, summary));
        }
        let mut solver = self.workspace();
        let mut state = initial;
        // The increments of the last two steps, newest first.
        let (mut last, mut before): (Option<SVector<f64, N>>, Option<SVector<f64, N>>) =
            (None, None);
        for k in 0..steps {
            let guess = canonical_guess(&state.q, last.as_ref(), before.as_ref());
            match self.step_in(&mut solver, k, &state, &guess) {
                Ok((next, stats)) => {
                    before = last;
                    last = Some(next.q - state.q);
                    summary.record(next, &stats);
                    observe(
                        k + 1,
                        &next,
                        Some(&StepRecord {
                            increment: (),
                            stats,
                        }),
                    );
                    state = next;
                }
                Err(source) => return Err(fail(source, summary)),
            }
        }
        Ok(summary)
    }
}

impl<L, const S: usize, const K: usize, const N: usize> UnreducedIntegrator<L, S, K, N>
where
    L: LagrangianHessian<S, K, N>,
{
    /// The Jacobian of the step map `(q_k, p_k) ↦ (q_{k+1}, p_{k+1})` at a computed step, from the
    /// implicit-function theorem on `D1 L_d(q_k, q_{k+1}) + p_k = 0` and
    /// `p_{k+1} = D2 L_d(q_k, q_{k+1})` with the generated second derivatives: with
    /// `A = D12 L_d`,
    ///
    /// ```text
    /// ∂q_{k+1}/∂q_k = −A⁻¹ D11 L_d      ∂q_{k+1}/∂p_k = −A⁻¹
    /// ∂p_{k+1}/∂q_k = D21 L_d + D22 L_d ∂q_{k+1}/∂q_k      ∂p_{k+1}/∂p_k = D22 L_d ∂q_{k+1}/∂p_k
    /// ```
    ///
    /// The step map of a variational integrator is symplectic, `Mᵀ Ω M = Ω` (see
    /// [`StepJacobian::symplecticity_defect`]). Control and estimation use `M` to propagate
    /// sensitivities and covariances along a trajectory.
    ///
    /// `k` is the index of the step `from → to`, for the error: a singular `D12 L_d`
    /// (`StepError::SingularJacobian`, with no residual to report: NaN).
    pub fn step_jacobian(
        &self,
        k: usize,
        from: &CanonicalState<N>,
        to: &CanonicalState<N>,
    ) -> Result<StepJacobian<N>, StepError> {
        let (d11, d12, d22) = self.system.lagrangian_hessian(&from.q, &to.q);
        let lu = Lu::new(d12).ok_or(StepError::SingularJacobian {
            step: k,
            residual: f64::NAN,
        })?;
        let solve_columns = |m: &SMatrix<f64, N, N>| {
            let mut out = SMatrix::<f64, N, N>::zeros();
            for (c, column) in m.column_iter().enumerate() {
                out.set_column(c, &lu.solve(&column.into_owned()));
            }
            out
        };
        let dq_dq = -solve_columns(&d11);
        let dq_dp = -solve_columns(&SMatrix::identity());
        Ok(StepJacobian {
            dq_dq,
            dq_dp,
            dp_dq: d12.transpose() + d22 * dq_dq,
            dp_dp: d22 * dq_dp,
        })
    }
}
