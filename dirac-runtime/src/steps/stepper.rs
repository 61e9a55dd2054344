//! The one stepping abstraction: what every integrator — the reduced (+)/(−) equations
//! ([`crate::ReducedIntegrator`]), the unreduced ones ([`crate::UnreducedIntegrator`]), a
//! composition ([`crate::Composition`]) and an atlas ([`crate::atlas::AtlasIntegrator`]) —
//! provides, so that the one driver ([`crate::driver`]) gives all of them `run`, `integrate`,
//! ensembles and stop conditions (as argmin's `Executor` drives any `Solver`, and diffsol asks each
//! method for `step` and gives all of them `solve`).
//!
//! A stepper states its state, the record a step leaves besides the new state, the trajectory
//! `integrate` collects, the input checks made before the first step, and a per-run
//! [workspace](Stepper::Workspace): the linear-solver workspaces (for the sparse backend the
//! symbolic factorization, its memory and the factors chord iterations reuse) and the memory of
//! the last steps that Newton's guess extrapolates from ([`History`]). A workspace is built once
//! per run and travels with it — through every stage of a composition and every chart of an
//! atlas — so after the first factorization no step allocates.
//!
//! A step's size travels with the run, not with the system: the run loop owns each step's context, a
//! [`StepAt`] (the step's index `k`, its size `h_k` and its controls `u_k`), and hands it to
//! [`Stepper::step_with`] / [`Stepper::step_into`] — the system's own `h` for a fixed-step run, a
//! schedule's `h_k`, the last step onto an end time, `γ_i h_k` for a composition's stage. With
//! adaptive steps ([`crate::adaptive`]) the clock is the state's time coordinate
//! ([`Stepper::physical_time`]) and the run loop makes the checks of the time transformation once
//! for every stepper — the start's monitor and energy level set before the first step, the
//! monitor and the direction of time after each step — each stepper saying only what it alone
//! knows ([`Stepper::monitor`], [`Stepper::level_set`]).

use std::fmt::Debug;

use nalgebra::SVector;

use crate::error::StepError;
pub(crate) use crate::model::{same_step, system_at};
use crate::newton::{NewtonFailure, NewtonSolution};

/// What one step is taken at: its index `k`, its size `h` and its controls `u` — the step's
/// context, which the run loop owns and hands to [`Stepper::step_with`] /
/// [`Stepper::step_into`], and which a composition passes on to its stages at `γ_i h`
/// ([`Self::scaled`]).
///
/// The size is the step parameter of the discrete Lagrangian `L_d(q_k, q_{k+1}; h_k)`: the
/// system's own [`crate::System::time_step`] for a fixed-step run, a schedule's `h_k`, the last
/// step onto an end time, or, with adaptive steps ([`crate::adaptive`]), the fictitious step
/// `ε_k` (the physical step `Δt_k ≈ g(x_k) ε_k`, eq. (2) of the time transformation). The
/// controls are listed in the order of [`crate::System::CONTROLS`]; empty: the values the system
/// holds.
///
/// ```
/// use dirac_runtime::StepAt;
///
/// let at = StepAt::new(3, 0.1).with_controls(&[1.0, 2.0]);
/// assert_eq!((at.k, at.h, at.u), (3, 0.1, &[1.0, 2.0][..]));
/// assert_eq!(at.scaled(-0.5).h, -0.05);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepAt<'u> {
    /// The step's index: the step from state `k` to state `k + 1` (what its errors name).
    pub k: usize,
    /// The step's size `h_k` (with adaptive steps the fictitious `ε_k`).
    pub h: f64,
    /// The step's controls `u_k`; empty: the values the system holds.
    pub u: &'u [f64],
}

impl<'u> StepAt<'u> {
    /// Step `k` of size `h`, with the controls the system holds.
    #[inline]
    pub fn new(k: usize, h: f64) -> Self {
        Self { k, h, u: &[] }
    }

    /// The same step with the controls `u`.
    #[inline]
    pub fn with_controls(self, u: &'u [f64]) -> Self {
        Self { u, ..self }
    }

    /// The same step (index and controls) of size `h`.
    #[inline]
    pub fn with_size(self, h: f64) -> Self {
        Self { h, ..self }
    }

    /// The stage of a composition at `γ h` ([`crate::compose`]): the same index and controls,
    /// the size scaled by `gamma` (negative for a backward stage).
    #[inline]
    pub fn scaled(self, gamma: f64) -> Self {
        Self {
            h: gamma * self.h,
            ..self
        }
    }
}

/// One integrator as the driver sees it. Implemented by every integrator of this crate; see the
/// [module documentation](self).
pub trait Stepper {
    /// The state a step maps.
    type State: Clone + Debug + Send + Sync + 'static;
    /// What a step reports besides the new state: at least its Newton statistics.
    type Record: AsRef<StepStats> + Clone + Debug + Send + Sync;
    /// What a run carries from step to step: linear-solver workspaces and the warm-start memory.
    type Workspace;
    /// What a collected run ([`crate::Run::collect`]) keeps: every state and every record.
    type Trajectory: Collect<Self> + crate::error::Steps + Debug;

    /// The time step `h` of one step.
    fn time_step(&self) -> f64;

    /// The checks made before the first step: a valid time step, finite parameters and initial
    /// state, and whatever the integrator adds (a symmetric rule for a composition, consistent
    /// charts for an atlas). An error here is reported with step index 0 and no step taken. With
    /// adaptive steps a run then checks the start's monitor and level set, once for every
    /// stepper (see [`crate::adaptive`]).
    fn check(&self, initial: &Self::State) -> Result<(), StepError>;

    /// A fresh workspace for one run: no history, no factors.
    fn workspace(&self) -> Self::Workspace;

    /// The number of controls a step takes ([`crate::System::CONTROLS`]); 0 for a
    /// system without controls.
    fn control_dim(&self) -> usize {
        0
    }

    /// Adaptive steps ([`crate::adaptive`]): the physical time of `state` — its time
    /// coordinate — for a system declared with `time(t), adapt = |q| g`; `None` for a system
    /// stepped in physical time. When it is `Some`, the driver's clock is this time: a run's
    /// times, its stop conditions and observers see `t_k`, a collected trajectory's `times[k]`
    /// are the physical `t_k` (its `step_sizes[k]` the fictitious steps `ε_k`), and an end time
    /// is a physical time, landed on exactly by a last step of the fictitious size that reaches
    /// it.
    fn physical_time(&self, state: &Self::State) -> Option<f64> {
        let _ = state;
        None
    }

    /// Adaptive steps ([`crate::adaptive`]): the monitor `g` at `state` — the rate `dt/dτ` of
    /// the time transformation `dt = g(x) dτ` — of the system of the step `at` (its controls
    /// set: a control law may change the monitor), for a system declared with
    /// `time(t), adapt = |q| g`; `Ok(None)` for a system stepped in physical time, an error for
    /// controls of the wrong number. What the one adaptive check after every step reads
    /// (once for every stepper: the monitor positive and finite, the physical step `Δt_k` of
    /// the sign of the fictitious `ε_k`); each family says only how its state gives the monitor.
    /// The default: `Ok(None)`.
    fn monitor(&self, at: StepAt<'_>, state: &Self::State) -> Result<Option<f64>, StepError> {
        let _ = (at, state);
        Ok(None)
    }

    /// The domain check of the state step `k` reached ([`crate::domain`]): the typed
    /// [`StepError::OutOfDomain`] when it lies outside the domain the system declares
    /// (`domain(...)` in its attribute). Every run calls it after every step (the initial state
    /// is checked by [`Self::check`]), and so does [`Self::step_in`]; [`Self::step_with`] and
    /// [`Self::step_into`] are the bare step. The default: no domain.
    fn check_domain(&self, k: usize, state: &Self::State) -> Result<(), StepError> {
        let _ = (k, state);
        Ok(())
    }

    /// Adaptive steps ([`crate::adaptive`]): where `state` lies with respect to its energy level
    /// set `p_t + E(q, p) = 0` ([`LevelSet`]), which a run's start must lie on (checked by the
    /// run loop with the start's monitor, once for every stepper); `None` where the family has
    /// no energy to compare (a system stepped in physical time, the default).
    fn level_set(&self, state: &Self::State) -> Option<LevelSet> {
        let _ = state;
        None
    }

    /// Takes the step `at` (its index `k`, size `h` and controls `u`, see [`StepAt`]) from
    /// `state` in `workspace`.
    ///
    /// `at.h` is the step's own size: [`Self::time_step`] for a fixed-step run (then the step is
    /// the system's own, bit for bit), any other positive value for a step-size schedule or the
    /// last step onto an end time, `γ_i h` for a stage of a composition. A variational step of
    /// size `h_k` is the discrete Lagrangian `L_d(q_k, q_{k+1}; h_k)`'s step: see the guide's
    /// chapter on integrators for what a sequence of such steps keeps. `at.u` lists the controls
    /// in the order of [`crate::System::CONTROLS`] (empty: the values the system holds). Newton
    /// starts from the guess that the workspace's memory of the previous steps (and their sizes)
    /// extrapolates, and on success the step is added to that memory. Fails with the typed error
    /// of step `at.k`; the workspace is then still valid (a later call starts from the memory of
    /// the last successful steps).
    ///
    /// The default steps into a copy of `state` with [`Self::step_into`], all that a stepper
    /// with heap-backed states needs; the default of [`Self::step_into`] is this method, so a
    /// stepper implements at least one of the two (one implementing neither would call itself
    /// without end).
    fn step_with(
        &self,
        workspace: &mut Self::Workspace,
        at: StepAt<'_>,
        state: &Self::State,
    ) -> Result<(Self::State, Self::Record), StepError> {
        let mut next = state.clone();
        let record = self.step_into(workspace, at, state, &mut next)?;
        Ok((next, record))
    }

    /// [`Self::step_with`] into `next`, whose memory a stepper with heap-backed states reuses
    /// (the driver keeps two states per run and swaps them, so such a run allocates no state
    /// per step). The default moves the result of [`Self::step_with`] into `next` (what a
    /// stepper with fixed-size states, which implements [`Self::step_with`], needs); on failure
    /// `next` is unspecified.
    #[inline]
    fn step_into(
        &self,
        workspace: &mut Self::Workspace,
        at: StepAt<'_>,
        state: &Self::State,
        next: &mut Self::State,
    ) -> Result<Self::Record, StepError> {
        let (state, record) = self.step_with(workspace, at, state)?;
        *next = state;
        Ok(record)
    }

    /// [`Self::step_with`] of size [`Self::time_step`] with the controls the system holds, the
    /// new state checked as a run checks it: with adaptive steps the monitor and the sign of the
    /// physical step ([`crate::adaptive`]), then the declared domain ([`Self::check_domain`]).
    fn step_in(
        &self,
        workspace: &mut Self::Workspace,
        k: usize,
        state: &Self::State,
    ) -> Result<(Self::State, Self::Record), StepError> {
        let at = StepAt::new(k, self.time_step());
        let (next, record) = self.step_with(workspace, at, state)?;
        check_adaptive_step(self, at, state, &next)?;
        self.check_domain(k, &next)?;
        Ok((next, record))
    }

    /// One step `k` from `state` in a fresh workspace (Newton starts without history). A loop
    /// over steps should keep one workspace and call [`Self::step_in`], as the driver does.
    fn step(
        &self,
        k: usize,
        state: &Self::State,
    ) -> Result<(Self::State, Self::Record), StepError> {
        self.step_in(&mut self.workspace(), k, state)
    }
}

/// A momentum map's value, or [`StepError::NonFinite`] when it is not finite (a state that is
/// not): what every integrator's `momentum_map` returns, the run-time-sized ones included (which
/// can also fail on sizes).
pub(crate) fn finite_momentum_map<const K: usize>(
    value: nalgebra::SVector<f64, K>,
) -> Result<nalgebra::SVector<f64, K>, StepError> {
    if value.iter().all(|v| v.is_finite()) {
        Ok(value)
    } else {
        Err(StepError::NonFinite {
            step: 0,
            what: "the momentum map (the state is not finite)",
            residual: f64::NAN,
        })
    }
}

/// The most states (or step records) a trajectory reserves room for before the first step
/// ([`reserved`]).
pub(crate) const RESERVED_STATES: usize = 1 << 12;

/// The size of step `k` of a trajectory with state times `times`, `t_{k+1} − t_k`; `h` where
/// the times are missing (a trajectory built by hand).
pub(crate) fn step_between(times: &[f64], k: usize, h: f64) -> f64 {
    match (times.get(k), times.get(k + 1)) {
        (Some(t0), Some(t1)) => t1 - t0,
        _ => h,
    }
}

/// An empty vector with room for `len` items, but for no more than [`RESERVED_STATES`]: what
/// [`Collect::start`] gives each of a trajectory's vectors. A run asked for `steps` steps may
/// stop long before (a stop condition, a failed step) and may be asked for more steps than
/// memory holds (`usize::MAX` with a stop condition), so room for every step is not reserved
/// before the first one; beyond the reserved room the vectors grow as the run proceeds, by
/// doubling, so a step still allocates nothing in the amortized sense (`log₂(steps/4096)`
/// reallocations over a run).
pub(crate) fn reserved<T>(len: usize) -> Vec<T> {
    Vec::with_capacity(len.min(RESERVED_STATES))
}

/// A trajectory that a collected run ([`crate::Run::collect`]) fills, state by state.
pub trait Collect<St: Stepper + ?Sized>: Sized {
    /// An empty trajectory of `stepper` for a run of at most `steps` steps (with room reserved
    /// up front for at most a few thousand: a long run grows as it goes).
    fn start(stepper: &St, steps: usize) -> Self;
    /// Appends the state at time `t`; `step` is the step that produced it (`None` for the
    /// initial state): the size it was taken with, exactly as the run passed it to
    /// [`Stepper::step_into`] (the step parameter `h_k`: with adaptive steps the fictitious step
    /// `ε_k`), and its record.
    fn push(&mut self, t: f64, state: &St::State, step: Option<(f64, &St::Record)>);

    /// Makes room for `additional` more states like `state` (with their times and records), or
    /// says that memory cannot hold them: [`StepError::OutOfMemory`], where a push would abort
    /// the process in the allocator. A collected run calls it before every push, and once before
    /// the first step for every state of a run whose length is known (a number of steps without
    /// a stop condition or an end time), so that a run longer than memory holds is refused
    /// before it starts. The default makes no room (a trajectory kept elsewhere).
    fn try_reserve(&mut self, state: &St::State, additional: usize) -> Result<(), StepError> {
        let _ = (state, additional);
        Ok(())
    }
}

/// Room for `additional` more items in `v`, growing as a push would (doubling); the typed
/// [`StepError::OutOfMemory`] naming `what` when it cannot be allocated: what a trajectory's
/// [`Collect::try_reserve`] does for each of its vectors.
pub(crate) fn try_grow<T>(v: &mut Vec<T>, additional: usize, what: &str) -> Result<(), StepError> {
    if v.capacity() - v.len() >= additional {
        return Ok(());
    }
    v.try_reserve(additional).map_err(|_| {
        let items = (v.len() as u128 + additional as u128).max(2 * v.capacity() as u128);
        StepError::OutOfMemory {
            what: format!(
                "the trajectory's {what} ({} kept, room for {additional} more asked for)",
                v.len()
            ),
            bytes: items * std::mem::size_of::<T>() as u128,
        }
    })
}

/// The [`Collect`] methods of a trajectory that keeps `states`, `times`, `step_sizes` (the size
/// of each step) and `stats` (each step's [`StepStats`]), and for each `field: "what"` another
/// vector of one item per step:
///
/// - `collect_steps!(start(stepper: Stepper) { init: value, .. }, State, Record, ..)`: `start`,
///   the trajectory with the fields `init` (read from `stepper`) and empty vectors with room
///   for a run's first states ([`reserved`]), and what follows;
/// - `collect_steps!(State, Record, |record| stats, field: "what" = item, ..)`: `push`, which
///   keeps a copy of the state, its time and, for a state a step produced, the step's size,
///   `stats` and each `item` (all read from the step's `record`), and `try_reserve`;
/// - `collect_steps!(try_reserve(State), field: "what", ..)`: `try_reserve` alone, for a
///   trajectory that pushes its own way; `then reserve` after the fields calls
///   `reserve(state, additional)` last (room for what each state holds on the heap).
///
/// `try_reserve` asks for room in every vector ([`try_grow`], the error naming `what`).
macro_rules! collect_steps {
    (try_reserve($state:ty) $(, $field:ident: $what:literal)* $(; then $reserve:path)?) => {
        fn try_reserve(
            &mut self,
            _state: &$state,
            additional: usize,
        ) -> Result<(), crate::error::StepError> {
            crate::stepper::try_grow(&mut self.states, additional, "states")?;
            crate::stepper::try_grow(&mut self.times, additional, "times")?;
            crate::stepper::try_grow(&mut self.step_sizes, additional, "step sizes")?;
            crate::stepper::try_grow(&mut self.stats, additional, "step statistics")?;
            $(crate::stepper::try_grow(&mut self.$field, additional, $what)?;)*
            $($reserve(_state, additional)?;)?
            Ok(())
        }
    };
    (
        start($stepper:ident: $integrator:ty) { $($init:ident: $value:expr),* $(,)? },
        $state:ty, $record:ty, |$r:ident| $stats:expr
        $(, $field:ident: $what:literal = $item:expr)* $(; then $reserve:path)?
    ) => {
        fn start($stepper: &$integrator, steps: usize) -> Self {
            Self {
                $($init: $value,)*
                states: crate::stepper::reserved(steps.saturating_add(1)),
                times: crate::stepper::reserved(steps.saturating_add(1)),
                step_sizes: crate::stepper::reserved(steps),
                stats: crate::stepper::reserved(steps),
                $($field: crate::stepper::reserved(steps),)*
            }
        }

        crate::stepper::collect_steps!(
            $state, $record, |$r| $stats $(, $field: $what = $item)* $(; then $reserve)?
        );
    };
    (
        $state:ty, $record:ty, |$r:ident| $stats:expr
        $(, $field:ident: $what:literal = $item:expr)* $(; then $reserve:path)?
    ) => {
        fn push(&mut self, t: f64, state: &$state, step: Option<(f64, &$record)>) {
            self.states.push(Clone::clone(state));
            self.times.push(t);
            if let Some((h, $r)) = step {
                self.step_sizes.push(h);
                self.stats.push($stats);
                $(self.$field.push($item);)*
            }
        }

        crate::stepper::collect_steps!(try_reserve($state) $(, $field: $what)* $(; then $reserve)?);
    };
}
pub(crate) use collect_steps;

/// `minus(system, options)`, the (−) integrator (documented by the attributes given), and
/// `variant()`, of an integrator whose `new(system, options)` solves the (+) equations and whose
/// field `variant` says which ones it solves: the flat element-wise one and the one on rotation
/// groups.
macro_rules! plus_or_minus {
    ($(#[$doc:meta])*) => {
        $(#[$doc])*
        pub fn minus(system: L, options: crate::newton::NewtonOptions) -> Self {
            Self {
                variant: crate::system::Variant::Minus,
                ..Self::new(system, options)
            }
        }

        /// Which equations are solved: [`Variant::Plus`](crate::Variant::Plus) ([`Self::new`])
        /// or [`Variant::Minus`](crate::Variant::Minus) ([`Self::minus`]).
        pub fn variant(&self) -> crate::system::Variant {
            self.variant
        }
    };
}
pub(crate) use plus_or_minus;

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
    /// the momentum scale of the step (see [`crate::NewtonOptions`]). A step may also be
    /// accepted on a small Newton correction, after which `residual` is at round-off level:
    /// compare the two to see how the step converged.
    pub tolerance: f64,
    /// Reciprocal condition estimate (1-norm) of the last step Jacobian factored; `None` when
    /// the initial guess already solved the step.
    pub rcond: Option<f64>,
}

impl AsRef<StepStats> for StepStats {
    fn as_ref(&self) -> &StepStats {
        self
    }
}

impl StepStats {
    /// The record of a step that Newton's solve `s` accepted against `tolerance`: what every
    /// integrator's step returns, those of other crates included.
    #[must_use]
    pub fn from_solution<V>(s: &NewtonSolution<V>, tolerance: f64) -> Self {
        Self {
            iterations: s.iterations,
            factorizations: s.factorizations,
            residual: s.residual,
            tolerance,
            rcond: s.rcond,
        }
    }

    /// Folds the statistics of one more stage into those of its macro step: corrections and
    /// factorizations add up, the largest residual (with its tolerance) and the smallest
    /// reciprocal condition estimate are kept.
    pub fn accumulate(&mut self, stage: &StepStats) {
        self.iterations += stage.iterations;
        self.factorizations += stage.factorizations;
        // The tolerance recorded is that of the stage whose residual is the one recorded.
        if stage.residual >= self.residual {
            self.tolerance = stage.tolerance;
        }
        self.residual = self.residual.max(stage.residual);
        self.rcond = match (self.rcond, stage.rcond) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        };
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

/// The increments of the last two steps, newest first, with the sizes of those steps: what
/// Newton's guess for the next step extrapolates from (GeometricIntegrators.jl's extrapolated
/// initial guess, here on a nonuniform grid).
#[doc(hidden)]
#[derive(Clone, Copy, Debug, PartialEq)]
#[doc(hidden)]
pub struct History<T> {
    /// The last step's increment and size.
    pub last: Option<(T, f64)>,
    /// The increment and size of the step before.
    pub before: Option<(T, f64)>,
}

impl<T> Default for History<T> {
    fn default() -> Self {
        Self {
            last: None,
            before: None,
        }
    }
}

impl<T: Copy> History<T> {
    /// Records a new step's increment and its size `h`.
    pub fn push(&mut self, increment: T, h: f64) {
        self.before = self.last.replace((increment, h));
    }

    /// Forgets everything (after a change of coordinates).
    pub fn clear(&mut self) {
        *self = Self::default();
    }

    /// Restarts from one known increment and its step size (after a change of chart, the last
    /// step re-expressed in the new chart), or from nothing.
    pub fn restart(&mut self, last: Option<(T, f64)>) {
        self.last = last;
        self.before = None;
    }

    /// The last increment, without its size.
    pub fn last_increment(&self) -> Option<&T> {
        self.last.as_ref().map(|(d, _)| d)
    }

    /// The last two entries, each mapped by `f` (a component of the increment), with their sizes.
    pub fn map<U>(&self, f: impl Fn(&T) -> U) -> History<U> {
        History {
            last: self.last.as_ref().map(|(d, h)| (f(d), *h)),
            before: self.before.as_ref().map(|(d, h)| (f(d), *h)),
        }
    }
}

/// The next increment, over a step of size `h`, predicted from the last two (each with its step
/// size, newest first): `0` before any step, the last one scaled to `h` after one, then the
/// quadratic through the last three points. On the grid `t_{k−2}, t_{k−1}, t_k` with slopes
/// `v_1 = Δ_{k−1}/h_{k−1}`, `v_2 = Δ_{k−2}/h_{k−2}` (Newton's divided differences) the quadratic
/// gives
///
/// ```text
/// Δ_k = h v_1 + h (h + h_{k−1}) (v_1 − v_2) / (h_{k−1} + h_{k−2}),
/// ```
///
/// with error `O(h³)` against the linear one's `O(h²)`. On a uniform grid this is
/// `2 Δ_{k−1} − Δ_{k−2}`, which is what is computed there (bit for bit the fixed-step guess).
/// The same rule serves a group unknown, which is itself an increment.
pub(crate) fn predicted_increment<const M: usize>(
    history: &History<SVector<f64, M>>,
    h: f64,
) -> Option<SVector<f64, M>> {
    match (&history.last, &history.before) {
        (Some((d1, h1)), Some((d2, h2))) => {
            if same_step(*h1, h) && same_step(*h2, h) {
                Some(2.0 * d1 - d2)
            } else {
                let (v1, v2) = (d1 / *h1, d2 / *h2);
                Some(v1 * h + (v1 - v2) * (h * (h + h1) / (h1 + h2)))
            }
        }
        (Some((d1, h1)), None) => Some(if same_step(*h1, h) {
            *d1
        } else {
            d1 * (h / h1)
        }),
        _ => None,
    }
}

/// The checks every integrator makes before the first step: a positive finite time step, finite
/// parameters and a finite initial state.
pub(crate) fn check_inputs(
    h: f64,
    parameters: &[f64],
    state_is_finite: bool,
) -> Result<(), StepError> {
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

/// Maps a Newton failure of step `k` to the public error (for every integrator, those of other
/// crates included).
#[must_use]
pub fn step_error(k: usize, failure: NewtonFailure) -> StepError {
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
        NewtonFailure::IllConditioned {
            rcond,
            residual,
            tolerance,
        } => StepError::IllConditioned {
            step: k,
            rcond,
            residual,
            tolerance,
        },
        NewtonFailure::NonFinite { residual } => StepError::NonFinite {
            step: k,
            what: "the step equations",
            residual,
        },
    }
}

/// Adaptive steps ([`crate::adaptive`]): the one check after every step of a run with adaptive
/// steps, whatever the stepper — the run loop ([`crate::driver`]) calls it after each step (the
/// last step onto an end time included), as [`Stepper::step_in`] does, and a composition after
/// each of its stages. With the time transformation `dt = g(x) dτ` a step of fictitious size
/// `ε_k = at.h` covers `Δt_k = t_{k+1} − t_k ≈ ε_k g(x_k)`: the monitor `g` at `next` must be
/// positive and finite ([`StepError::InvalidMonitor`]), and `Δt_k`, read from the states' time
/// coordinates ([`Stepper::physical_time`]), must have the sign of `ε_k`
/// ([`StepError::TimeReversed`]). Nothing for a stepper in physical time.
pub(crate) fn check_adaptive_step<I: Stepper + ?Sized>(
    stepper: &I,
    at: StepAt<'_>,
    state: &I::State,
    next: &I::State,
) -> Result<(), StepError> {
    let (Some(t0), Some(t1)) = (stepper.physical_time(state), stepper.physical_time(next)) else {
        return Ok(());
    };
    if let Some(g) = stepper.monitor(at, next)? {
        check_monitor(at.k, g)?;
    }
    check_time_increment(at.k, at.h, t1 - t0)
}

/// Adaptive steps ([`crate::adaptive`]): the typed error of a step `step` of fictitious size `h`
/// whose physical time step `dt` does not have the sign of `h` (zero included).
pub(crate) fn check_time_increment(step: usize, h: f64, dt: f64) -> Result<(), StepError> {
    if dt * h > 0.0 {
        Ok(())
    } else {
        Err(StepError::TimeReversed { step, dt })
    }
}

/// Adaptive steps ([`crate::adaptive`]): the typed error of a monitor value that is not
/// positive and finite, after step `step`.
pub(crate) fn check_monitor(step: usize, value: f64) -> Result<(), StepError> {
    if value > 0.0 && value.is_finite() {
        Ok(())
    } else {
        Err(StepError::InvalidMonitor { step, value })
    }
}

/// The largest accepted relative distance of a run's initial state from its energy level set:
/// `|p_t + E(q, p)| ≤ LEVEL_SET_TOLERANCE · max(|E|, |⟨p_q, u⟩|)`, `u` the physical velocity
/// (see [`crate::adaptive::level_set_defect`]). A state built from a position and a physical velocity by
/// [`crate::ContinuousLagrangian::unreduced_state`] or [`crate::ContinuousLagrangian::reduced_state`] is on the
/// level set to round-off (`~1e-15`); one whose `p_t` was set by hand to another energy is refused
/// ([`StepError::OffManifold`]): it would integrate another orbit than the physical one.
pub const LEVEL_SET_TOLERANCE: f64 = 1e-8;

/// Adaptive steps ([`crate::adaptive`]): where a state lies with respect to its energy level set
/// `p_t + E(q, p) = 0`, on which the solutions of the time-transformed system are the physical
/// ones reparametrized ([`Stepper::level_set`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LevelSet {
    /// The time coordinate's momentum `p_t`.
    pub p_t: f64,
    /// `p_t + E(q, p)`: zero on the level set.
    pub defect: f64,
    /// The scale the defect is measured against, `max(|E|, |⟨p_q, u⟩|)` with `u` the physical
    /// velocity ([`crate::adaptive::level_set_defect`]).
    pub scale: f64,
}

/// Adaptive steps ([`crate::adaptive`]): the one check of a run's start, whatever the stepper,
/// made by the run loop after [`Stepper::check`]: the monitor `g` positive and finite at the
/// initial state ([`StepError::InvalidMonitor`] with step 0), and the state on its energy level
/// set to [`LEVEL_SET_TOLERANCE`] ([`StepError::OffManifold`] otherwise: off the level set the
/// run integrates another orbit). Nothing for a stepper in physical time.
pub(crate) fn check_adaptive_start<I: Stepper + ?Sized>(
    stepper: &I,
    initial: &I::State,
) -> Result<(), StepError> {
    if stepper.physical_time(initial).is_none() {
        return Ok(());
    }
    if let Some(g) = stepper.monitor(StepAt::new(0, stepper.time_step()), initial)? {
        check_monitor(0, g)?;
    }
    let Some(LevelSet { p_t, defect, scale }) = stepper.level_set(initial) else {
        return Ok(());
    };
    if defect.abs() <= LEVEL_SET_TOLERANCE * scale {
        return Ok(());
    }
    Err(StepError::OffManifold {
        reason: format!(
            "an adaptive run starts off its energy level set: the time coordinate's momentum is \
             p_t = {p_t}, but the energy of (q, p) is E = {:.12e} (|p_t + E| = {:.3e}, relative \
             {:.3e} > {LEVEL_SET_TOLERANCE:.0e}); off the level set the run integrates another \
             orbit; build the state from the position and the physical velocity with \
             `sys.unreduced_state(q, v)` or `sys.reduced_state(q, v)`, which set p_t = −E",
            defect - p_t,
            defect.abs(),
            defect.abs() / scale.max(f64::MIN_POSITIVE)
        ),
    })
}

/// The level set of the unreduced state `(q, p)` of a flat system with adaptive steps
/// ([`LevelSet`]; `None` for a system stepped in physical time or a monitor that is not
/// positive): what the flat families' [`Stepper::level_set`] give.
pub(crate) fn flat_level_set<L, const S: usize, const K: usize, const N: usize>(
    sys: &L,
    q: &SVector<f64, N>,
    p: &SVector<f64, N>,
) -> Option<LevelSet>
where
    L: crate::DiscreteLagrangian<S, K, N>,
{
    let j = sys.time_index()?;
    let (defect, scale) = sys.level_set_defect(q, p)?;
    Some(LevelSet {
        p_t: p[S + j],
        defect,
        scale,
    })
}

#[cfg(test)]
mod tests {
    use nalgebra::{Matrix2, Vector2};

    use super::{step_error, try_grow, Collect, StepAt, StepStats, Stepper};
    use crate::error::{StepError, Steps};
    use crate::newton::NewtonOptions;

    /// A stepper with heap-backed states that implements only `step_into`: `q ↦ 2 q + h`, each
    /// step counted in the workspace, the step index recorded as its iterations.
    struct Doubling;

    #[derive(Debug)]
    struct Kept(Vec<Vec<f64>>);

    impl Steps for Kept {
        fn completed_steps(&self) -> usize {
            self.0.len().saturating_sub(1)
        }
    }

    impl Collect<Doubling> for Kept {
        fn start(_: &Doubling, _: usize) -> Self {
            Kept(Vec::new())
        }

        fn push(&mut self, _: f64, state: &Vec<f64>, _: Option<(f64, &StepStats)>) {
            self.0.push(state.clone());
        }
    }

    impl Stepper for Doubling {
        type State = Vec<f64>;
        type Record = StepStats;
        type Workspace = usize;
        type Trajectory = Kept;

        fn time_step(&self) -> f64 {
            0.5
        }

        fn check(&self, _: &Vec<f64>) -> Result<(), StepError> {
            Ok(())
        }

        fn workspace(&self) -> usize {
            0
        }

        fn step_into(
            &self,
            workspace: &mut usize,
            at: StepAt<'_>,
            state: &Vec<f64>,
            next: &mut Vec<f64>,
        ) -> Result<StepStats, StepError> {
            next.clear();
            next.extend(state.iter().map(|q| 2.0 * q + at.h));
            *workspace += 1;
            Ok(StepStats {
                iterations: at.k,
                ..StepStats::default()
            })
        }
    }

    /// A stepper that implements only `step_into` gets `step_with` (and so `step_in` and
    /// `step`) from it: the state `step_into` writes, its record, the workspace it advanced.
    #[test]
    fn step_with_defaults_to_step_into() {
        let mut workspace = Doubling.workspace();
        let (next, record) = Doubling
            .step_with(&mut workspace, StepAt::new(3, 0.25), &vec![1.0, -2.0])
            .unwrap();
        assert_eq!(next, vec![2.25, -3.75]);
        assert_eq!((record.iterations, workspace), (3, 1));
        let (next, record) = Doubling.step(7, &vec![1.0]).unwrap();
        assert_eq!((next, record.iterations), (vec![2.5], 7));
    }

    /// Room for more items than any allocation holds is the typed `OutOfMemory` with the bytes
    /// asked for (room that exists is given, and the vector is left as it was otherwise).
    #[test]
    fn room_memory_cannot_hold_is_a_typed_error_not_an_abort() {
        let mut v: Vec<[f64; 4]> = vec![[0.0; 4]; 3];
        try_grow(&mut v, 10, "states").expect("room for 13 states");
        assert!(v.capacity() >= 13);
        let huge = usize::MAX / 64;
        match try_grow(&mut v, huge, "states") {
            Err(StepError::OutOfMemory { what, bytes }) => {
                assert!(what.contains("states") && what.contains("3 kept"), "{what}");
                assert_eq!(bytes, 32 * (3 + huge as u128));
            }
            other => panic!("{other:?}"),
        }
        assert_eq!(v.len(), 3);
    }

    /// A solve that stops far from a root on an ill-conditioned Jacobian is reported as
    /// ill-conditioned, and its message says that the step did not converge, with the residual
    /// and the tolerance it missed (not that a converged solution is untrustworthy).
    #[test]
    fn an_ill_conditioned_failure_far_from_a_root_says_it_did_not_converge() {
        // The 2-cycle below in the first unknown; the second's derivative 1e-18 makes the
        // Jacobian's reciprocal condition estimate ~1e-18, below the default 1e-13.
        let f = |z: &Vector2<f64>| Vector2::new(z[0].powi(3) - 2.0 * z[0] + 2.0, 1e-18 * z[1]);
        let fj = |z: &Vector2<f64>| (f(z), Matrix2::new(3.0 * z[0] * z[0] - 2.0, 0.0, 0.0, 1e-18));
        let options = NewtonOptions {
            max_iterations: 8,
            ..NewtonOptions::default()
        };
        let failure = crate::newton::solve(Vector2::zeros(), 1.0, &options, f, fj).unwrap_err();
        let error = step_error(4, failure);
        let message = error.to_string();
        assert!(
            matches!(error, crate::StepError::IllConditioned { step: 4, residual, .. } if residual == 2.0),
            "{error:?}"
        );
        assert!(message.contains("did not converge"), "{message}");
        assert!(message.contains("2.000e0"), "{message}");
        assert!(
            !message.contains("the solution cannot be trusted"),
            "{message}"
        );
    }
}
