//! The reduced integrator: the reduced (+) and (−) discrete Lagrange–Poincaré–Dirac equations,
//! eqs. (4.6) and (4.8), marched step by step.

use std::marker::PhantomData;

use nalgebra::{SMatrix, SVector};

use crate::error::{StepError, Steps};
use crate::linalg::{Lu, RCOND_CLEARANCE};
use crate::newton::{self, inf_norm, NewtonOptions};
use crate::state::ReducedState;
use crate::stepper::{
    predicted_increment, same_step, step_error, system_at, Collect, History, StepAt, StepStats,
    StepStatsExt, Stepper,
};
use crate::system::{join, split, Minus, Plus, Reduced, Side, Variant};

/// What a reduced step reports besides the new state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReducedStep<const K: usize> {
    /// The solved group unknown `u` of the step: `g_k^+` for [`Variant::Plus`] (eq. (4.6)),
    /// `g_{k+1}^−` for [`Variant::Minus`]; the group coordinate advances by
    /// [`Side::group_increment`]`(u) + B (x_{k+1} − x_k)`.
    pub group_unknown: SVector<f64, K>,
    /// Newton statistics of the step.
    pub stats: StepStats,
}

impl<const K: usize> AsRef<StepStats> for ReducedStep<K> {
    fn as_ref(&self) -> &StepStats {
        &self.stats
    }
}

/// A reduced trajectory: states `0..=step_count()` at their times `t_k` (`k h` for a fixed step), and
/// for each step the solved group unknown and the Newton statistics.
#[derive(Clone, Debug, PartialEq)]
pub struct Trajectory<const S: usize, const K: usize> {
    /// The integrator's time step `h` (the default step of a run; see [`Self::times`] for the
    /// time of each state).
    pub h: f64,
    /// The equations that produced it.
    pub variant: Variant,
    /// `states[k]` is the state at `times[k]`.
    pub states: Vec<ReducedState<S, K>>,
    /// `times[k] = t_k`, the time of `states[k]` (`k h` exactly for a fixed step).
    pub times: Vec<f64>,
    /// `step_sizes[k]` is the size step `k` was taken with, bit for bit as the run passed it to
    /// the step: `h` itself for a fixed step, `h_k` with a schedule (the last step shortened to
    /// land on an end time); with adaptive steps the fictitious step `ε_k` (the physical step is
    /// `times[k + 1] − times[k]`).
    pub step_sizes: Vec<f64>,
    /// The group unknown of step `k` ([`ReducedStep::group_unknown`]).
    pub group_unknowns: Vec<SVector<f64, K>>,
    /// Newton statistics of each step.
    pub stats: Vec<StepStats>,
}

/// The accessors every trajectory of a single-chart integrator has.
macro_rules! trajectory_accessors {
    ($state:ty) => {
        /// Number of completed steps.
        pub fn step_count(&self) -> usize {
            self.states.len().saturating_sub(1)
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
pub(crate) use trajectory_accessors;

impl<const S: usize, const K: usize> Trajectory<S, K> {
    trajectory_accessors!(ReducedState<S, K>);
}

impl<const S: usize, const K: usize> Steps for Trajectory<S, K> {
    fn completed_steps(&self) -> usize {
        self.step_count()
    }
}

impl<L, D, const S: usize, const K: usize, const N: usize> Collect<ReducedIntegrator<L, D, S, K, N>>
    for Trajectory<S, K>
where
    D: Side,
    L: Reduced<D, S, K, N>,
{
    crate::stepper::collect_steps!(
        start(integrator: ReducedIntegrator<L, D, S, K, N>) {
            h: integrator.system.time_step(),
            variant: D::VARIANT,
        },
        ReducedState<S, K>,
        ReducedStep<K>,
        |step| step.stats,
        group_unknowns: "group unknowns" = step.group_unknown
    );
}

/// The workspace of a reduced run: the linear solver of the step Jacobian and the last two
/// steps' increments `(x_{j+1} − x_j, u_j)`, newest first, that Newton's guess extrapolates
/// ([`reduced_guess`]).
#[derive(Clone, Debug)]
pub struct ReducedWorkspace<B, const S: usize, const K: usize> {
    /// The linear solver ([`Reduced::Linear`]).
    #[doc(hidden)]
    pub solver: B,
    /// The last two steps' shape increments and group unknowns.
    #[doc(hidden)]
    pub history: History<(SVector<f64, S>, SVector<f64, K>)>,
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
    /// The integrator of side `D`, for code generic over the side; a program names the side by
    /// its constructor, [`Self::plus`] or [`Self::minus`].
    #[doc(hidden)]
    pub fn new(system: L, options: NewtonOptions) -> Self {
        const { assert!(S + K == N, "the configuration dimension N must be S + K") };
        Self {
            system,
            options,
            eliminate: None,
            side: PhantomData,
        }
    }

    /// The momentum map `μ = J(q, p)` of the declared translations at `state`: its `mu`,
    /// constant along a run of a system without forces (exactly, bit for bit). A `Result` as on
    /// every integrator: [`StepError::NonFinite`] for a `μ` that is not finite.
    pub fn momentum_map(&self, state: &ReducedState<S, K>) -> Result<SVector<f64, K>, StepError> {
        crate::stepper::finite_momentum_map(state.mu)
    }

    /// The continuous energy of a trajectory of this integrator at its nodes and midpoints
    /// ([`crate::reduced_continuous_energies`]).
    pub fn energies(
        &self,
        trajectory: &Trajectory<S, K>,
    ) -> Result<crate::ContinuousEnergies, crate::LegendreError>
    where
        L: crate::ContinuousLagrangian<N>,
    {
        crate::reduced_continuous_energies(&self.system, trajectory)
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
        self.system.eliminates_group()
            && self
                .eliminate
                .unwrap_or_else(|| self.system.elimination_pays())
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

    /// Takes step `k` from `state`, Newton starting at `guess` for `z = (x_{k+1}, u)`, in a
    /// fresh workspace (free for the dense backend; a symbolic factorization and its memory for
    /// the sparse one). Returns the new state and the step's record. Runs use
    /// [`Stepper::step_in`], which keeps one workspace and extrapolates the guess.
    pub fn step_from(
        &self,
        k: usize,
        state: &ReducedState<S, K>,
        guess: &SVector<f64, N>,
    ) -> Result<(ReducedState<S, K>, ReducedStep<K>), StepError> {
        let at = StepAt::new(k, self.system.time_step());
        self.solve_step(&mut self.system.linear_solver(), at, state, guess)
    }

    /// The step `at` (its size `h`, its controls `u`: empty, the system's own) from `state`,
    /// Newton starting at `guess`, in the linear solver `solver`.
    pub(crate) fn solve_step(
        &self,
        solver: &mut L::Linear,
        at: StepAt<'_>,
        state: &ReducedState<S, K>,
        guess: &SVector<f64, N>,
    ) -> Result<(ReducedState<S, K>, ReducedStep<K>), StepError> {
        let StepAt { k, h, u } = at;
        let owned = system_at(&self.system, k, h, u)?;
        let sys = owned.as_ref().unwrap_or(&self.system);
        let (x, w, mu) = (&state.x, &state.w, &state.mu);
        let rho = inf_norm(w).max(inf_norm(mu));
        if self.eliminates_group() {
            return self.eliminated_step(sys, k, state, guess, rho);
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
            sys,
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
        sys: &L,
        k: usize,
        state: &ReducedState<S, K>,
        guess: &SVector<f64, N>,
        rho: f64,
    ) -> Result<(ReducedState<S, K>, ReducedStep<K>), StepError> {
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
                if bound >= RCOND_CLEARANCE * min_rcond {
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
                    tolerance: self.options.residual_tolerance(rho),
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
        self.finish_step(sys, k, state, z, None, stats)
    }

    /// The explicit updates after the unknowns `z = (x_{k+1}, u)` are known; `w1` is `w_{k+1}`
    /// if the solve already evaluated it at `z`. With a group force `μ` advances by the group
    /// impulse (the forced discrete Noether balance, [`Reduced::GROUP_FORCED`]); without one it
    /// is copied.
    fn finish_step(
        &self,
        sys: &L,
        k: usize,
        state: &ReducedState<S, K>,
        z: SVector<f64, N>,
        w1: Option<SVector<f64, S>>,
        stats: StepStats,
    ) -> Result<(ReducedState<S, K>, ReducedStep<K>), StepError> {
        let (x, mu) = (&state.x, &state.mu);
        let (x1, u) = split::<S, K, N>(&z);
        let next = ReducedState {
            x: x1,
            w: w1.unwrap_or_else(|| sys.momentum(x, &z)),
            mu: if L::GROUP_FORCED {
                mu + sys.group_impulse(x, &z)
            } else {
                *mu
            },
            g: state.g + D::group_increment(u) + sys.h_d0(x, &x1),
        };
        if !next.is_finite() {
            return Err(StepError::NonFinite {
                step: k,
                what: "the updated state",
                residual: stats.residual,
            });
        }
        Ok((
            next,
            ReducedStep {
                group_unknown: u,
                stats,
            },
        ))
    }
}

/// The [`Stepper`] methods about a reduced state `(x, w, μ, g)` of a system on vector spaces
/// (the inputs, the declared domain, physical time, the level set of adaptive steps, the step
/// monitor), written once for every integrator on reduced states through its `system()`.
macro_rules! reduced_checks {
    () => {
        fn check(&self, initial: &ReducedState<S, K>) -> Result<(), StepError> {
            let sys = self.system();
            crate::stepper::check_inputs(
                sys.time_step(),
                &sys.parameter_values(),
                initial.is_finite(),
            )?;
            // The domain: outside it the monitor (checked next by the run) need not be defined.
            crate::reduced::reduced_domain(sys, 0, true, initial)
        }

        fn check_domain(&self, k: usize, state: &ReducedState<S, K>) -> Result<(), StepError> {
            crate::reduced::reduced_domain(self.system(), k, false, state)
        }

        fn physical_time(&self, state: &ReducedState<S, K>) -> Option<f64> {
            self.system().time_index().map(|j| state.g[j])
        }

        /// The level set of the state's unreduced form `(q, p)`.
        fn level_set(&self, state: &ReducedState<S, K>) -> Option<crate::stepper::LevelSet> {
            let sys = self.system();
            sys.time_index()?;
            let start = sys.untrivialize(state);
            crate::stepper::flat_level_set(sys, &start.q, &start.p)
        }

        /// `g(x)` at the state's shape `x`.
        fn monitor(
            &self,
            at: crate::stepper::StepAt<'_>,
            state: &ReducedState<S, K>,
        ) -> Result<Option<f64>, StepError> {
            crate::reduced::flat_monitor(self.system(), at, &state.x)
        }
    };
}
pub(crate) use reduced_checks;

impl<L, D, const S: usize, const K: usize, const N: usize> Stepper
    for ReducedIntegrator<L, D, S, K, N>
where
    D: Side,
    L: Reduced<D, S, K, N>,
{
    type State = ReducedState<S, K>;
    type Record = ReducedStep<K>;
    type Workspace = ReducedWorkspace<L::Linear, S, K>;
    type Trajectory = Trajectory<S, K>;

    fn time_step(&self) -> f64 {
        self.system.time_step()
    }

    reduced_checks!();

    fn workspace(&self) -> Self::Workspace {
        ReducedWorkspace {
            solver: self.system.linear_solver(),
            history: History::default(),
        }
    }

    fn control_dim(&self) -> usize {
        self.system.control_count()
    }

    /// Newton starts from [`reduced_guess`], a quadratic extrapolation of the last shape points
    /// and a linear one of the last group unknowns.
    fn step_with(
        &self,
        workspace: &mut Self::Workspace,
        at: StepAt<'_>,
        state: &ReducedState<S, K>,
    ) -> Result<(ReducedState<S, K>, ReducedStep<K>), StepError> {
        let h = at.h;
        let mut guess = reduced_guess::<S, K, N>(&state.x, &workspace.history, h);
        // Adaptive steps: a run's first step starts from the motion in fictitious time, not rest.
        if workspace.history.last.is_none() && self.system.time_index().is_some() {
            let start = self.system.untrivialize(state);
            if let Some(dq) = self.system.adaptive_increment(&start.q, &start.p, h) {
                let (dx, dg) = split::<S, K, N>(&dq);
                let u = D::group_increment(dg - self.system.h_d0(&state.x, &(state.x + dx)));
                guess = join::<S, K, N>(&(state.x + dx), &u);
            }
        }
        let (next, step) = self.solve_step(&mut workspace.solver, at, state, &guess)?;
        workspace
            .history
            .push((next.x - state.x, step.group_unknown), h);
        Ok((next, step))
    }
}

/// `g(x)` at the shape `x` for the system of the step `at` ([`system_at`]: the system itself,
/// or a copy with the step's size and controls): what the flat families' [`Stepper::monitor`]
/// gives.
pub(crate) fn flat_monitor<L, const S: usize, const K: usize, const N: usize>(
    sys: &L,
    at: StepAt<'_>,
    x: &SVector<f64, S>,
) -> Result<Option<f64>, StepError>
where
    L: crate::DiscreteLagrangian<S, K, N>,
{
    let owned = system_at(sys, at.k, at.h, at.u)?;
    Ok(owned.as_ref().unwrap_or(sys).monitor(x))
}

/// The declared domain ([`crate::domain`]) at the configuration `(x, g)` of a reduced state.
pub(crate) fn reduced_domain<L, const S: usize, const K: usize, const N: usize>(
    sys: &L,
    k: usize,
    initial: bool,
    state: &ReducedState<S, K>,
) -> Result<(), StepError>
where
    L: crate::DiscreteLagrangian<S, K, N>,
{
    crate::domain::check_system(sys, k, initial, |i| {
        if i < S {
            state.x.get(i).copied()
        } else {
            state.g.get(i - S).copied()
        }
    })
}

/// Newton's initial guess for the step of size `h` from `x`, `z = (x_{k+1}, u)`, from the last
/// two steps, each given as its shape increment `x_{j+1} − x_j` and its group unknown with the
/// step's size (newest first; none before the start): the shape advances by the extrapolated
/// increment (`x` at the first step, `x + Δ_{k−1}` at the second, then the quadratic through the
/// last three points, `x + 2 Δ_{k−1} − Δ_{k−2}` on a uniform grid, whose error is `O(h³)` against
/// the linear one's `O(h²)`), and the group unknown by the same rule (it is itself an increment);
/// see [`crate::stepper`]'s `predicted_increment` for unequal steps.
#[doc(hidden)]
pub fn reduced_guess<const S: usize, const K: usize, const N: usize>(
    x: &SVector<f64, S>,
    history: &History<(SVector<f64, S>, SVector<f64, K>)>,
    h: f64,
) -> SVector<f64, N> {
    // Every step of a fixed-step run takes this path: the uniform-grid extrapolation
    // `2 Δ_{k−1} − Δ_{k−2}` of both parts at once, the same bits as `predicted_increment`'s.
    if let (Some(((dx1, u1), h1)), Some(((dx2, u2), h2))) = (&history.last, &history.before) {
        if same_step(*h1, h) && same_step(*h2, h) {
            return join::<S, K, N>(&(x + (2.0 * dx1 - dx2)), &(2.0 * u1 - u2));
        }
    }
    let dx = predicted_increment(&history.map(|l| l.0), h);
    let u = predicted_increment(&history.map(|l| l.1), h);
    join::<S, K, N>(
        &dx.map_or(*x, |dx| x + dx),
        &u.unwrap_or_else(SVector::zeros),
    )
}
