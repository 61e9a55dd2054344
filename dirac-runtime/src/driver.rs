//! The one driver: the run loop, trajectories, stop conditions and ensembles, written once for
//! every [`Stepper`].
//!
//! [`Drive`] is implemented for every stepper, so the reduced, unreduced, composed and atlas
//! integrators all have the same methods: [`Drive::run`] (stream every state to an observer, in
//! memory independent of the run's length), [`Drive::integrate`] (keep every state),
//! [`Drive::run_until`] and [`Drive::integrate_until`] (stop when a condition on the state
//! holds), and [`Drive::integrate_ensemble`] / [`Drive::run_ensemble`] (many initial states in
//! parallel). Parameter sets are ensembles of steppers: [`integrate_parameters`].
//!
//! Every run checks its inputs before the first step ([`Stepper::check`]), builds one workspace
//! ([`Stepper::workspace`]) and steps in it; a failed step ends the run with a typed
//! [`IntegrationError`] that carries the step index, the residual and everything computed
//! before it.

use crate::ensemble::map;
use crate::error::{IntegrationError, StepError, Steps};
use crate::stepper::{Collect, StepStats, Stepper};

/// Where a controlled run ([`Drive::run_controlled`], [`Drive::integrate_controlled`]) takes
/// the controls `u_k` of each step, in the order of [`crate::DiscreteLagrangian::CONTROLS`].
///
/// Implemented by feedback laws — any closure `|k, state, u| { … }` that writes `u_k` into `u`
/// from the step index and the state the step starts from — and by [`ControlSequence`], a
/// precomputed sequence.
pub trait ControlLaw<St> {
    /// Writes the controls of step `k`, taken from `state`, into `u` (as many values as the
    /// system declares). Returns `false` when it has none for this step (a sequence past its
    /// end): the run then stops with [`StepError::InvalidControls`].
    fn controls(&mut self, k: usize, state: &St, u: &mut [f64]) -> bool;

    /// The number of values the law has per step when it is fixed (a [`ControlSequence`]'s row
    /// length), for the error of a step it has no controls for; `None` (the default) for a
    /// law that writes whatever the system declares.
    fn values_per_step(&self) -> Option<usize> {
        None
    }
}

impl<St, F: FnMut(usize, &St, &mut [f64])> ControlLaw<St> for F {
    fn controls(&mut self, k: usize, state: &St, u: &mut [f64]) -> bool {
        self(k, state, u);
        true
    }
}

/// A precomputed control sequence: row `k` is `u_k`.
#[derive(Clone, Copy, Debug)]
pub struct ControlSequence<'a> {
    values: &'a [f64],
    m: usize,
}

impl<'a> ControlSequence<'a> {
    /// The sequence whose rows are `rows[k] = u_k`.
    pub fn rows<const M: usize>(rows: &'a [[f64; M]]) -> Self {
        Self {
            values: rows.as_flattened(),
            m: M,
        }
    }

    /// The sequence stored row after row in `values`, `m` controls per row.
    pub fn flat(values: &'a [f64], m: usize) -> Self {
        Self { values, m }
    }

    /// The number of steps it covers.
    pub fn len(&self) -> usize {
        self.values.len().checked_div(self.m).unwrap_or(0)
    }

    /// Whether it covers no step.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

impl<St> ControlLaw<St> for ControlSequence<'_> {
    fn controls(&mut self, k: usize, _state: &St, u: &mut [f64]) -> bool {
        if self.m != u.len() || k >= self.len() {
            return false;
        }
        u.copy_from_slice(&self.values[k * self.m..(k + 1) * self.m]);
        true
    }

    fn values_per_step(&self) -> Option<usize> {
        Some(self.m)
    }
}

/// The outcome of a streaming run ([`Drive::run`]): the last state and statistics accumulated
/// over the steps, in memory independent of the number of steps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RunSummary<St> {
    /// The time step `h`.
    pub h: f64,
    /// Completed steps.
    pub steps: usize,
    /// The state after the last completed step (the initial state if none).
    pub last: St,
    /// Whether the run ended early because its stop condition held ([`Drive::run_until`]).
    pub stopped: bool,
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
            stopped: false,
            iterations: 0,
            max_iterations: 0,
            factorizations: 0,
            max_residual: 0.0,
            worst_rcond: None,
        }
    }

    fn record(&mut self, stats: &StepStats) {
        if let Some(r) = stats.rcond {
            if self.worst_rcond.is_none_or(|(_, w)| r < w) {
                self.worst_rcond = Some((self.steps, r));
            }
        }
        self.steps += 1;
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

/// What a run returns: its summary, or the typed failure with the summary up to it.
pub type RunResult<St> = Result<RunSummary<St>, Box<IntegrationError<RunSummary<St>>>>;

/// What `integrate` returns: the trajectory, or the typed failure with the trajectory computed up
/// to it. Also the result of one member of an ensemble.
pub type MemberResult<T> = Result<T, Box<IntegrationError<T>>>;

/// The driver's methods, for every [`Stepper`] (see the [module documentation](self)).
pub trait Drive: Stepper {
    /// Integrates `steps` steps from `initial` without storing them: `observe(k, state, step)`
    /// sees every state `k = 0..=steps` as it is computed, with the record of the step that
    /// produced it (`None` for the initial state), so a run needs memory independent of its
    /// length — keep every `k`-th state, accumulate statistics, write to a file. One workspace
    /// serves the whole run. The summary (last state, Newton statistics) is returned, or on
    /// failure kept in the error with the step index and residual; the initial state is observed
    /// even when the input checks reject it.
    fn run(
        &self,
        initial: Self::State,
        steps: usize,
        observe: impl FnMut(usize, &Self::State, Option<&Self::Record>),
    ) -> RunResult<Self::State> {
        self.run_until(initial, steps, |_, _| false, observe)
    }

    /// [`Self::run`] that ends early, after the first step `k` whose new state satisfies
    /// `stop(k, state)` (`k` the index of the state, from 1): the summary then has
    /// [`RunSummary::stopped`] set and `steps = k`. At most `max_steps` steps are taken.
    fn run_until(
        &self,
        initial: Self::State,
        max_steps: usize,
        stop: impl FnMut(usize, &Self::State) -> bool,
        observe: impl FnMut(usize, &Self::State, Option<&Self::Record>),
    ) -> RunResult<Self::State> {
        self.run_controlled_until(initial, max_steps, None, stop, observe)
    }

    /// [`Self::run`] with the controls of every step from `controls`: a feedback law
    /// `|k, state, u| …` or a [`ControlSequence`]. Before step `k` the law writes `u_k` (one
    /// value per control the system declares, [`crate::DiscreteLagrangian::CONTROLS`]); the
    /// step solves the forced equations with those values. A sequence that ends before the
    /// run, or a value that is not finite, ends the run with a typed error.
    fn run_controlled(
        &self,
        initial: Self::State,
        steps: usize,
        mut controls: impl ControlLaw<Self::State>,
        observe: impl FnMut(usize, &Self::State, Option<&Self::Record>),
    ) -> RunResult<Self::State> {
        self.run_controlled_until(initial, steps, Some(&mut controls), |_, _| false, observe)
    }

    /// The one run loop: [`Self::run_until`] with the controls of every step from `controls`
    /// (`None`: the values the system holds).
    fn run_controlled_until(
        &self,
        initial: Self::State,
        max_steps: usize,
        mut controls: Option<&mut dyn ControlLaw<Self::State>>,
        mut stop: impl FnMut(usize, &Self::State) -> bool,
        mut observe: impl FnMut(usize, &Self::State, Option<&Self::Record>),
    ) -> RunResult<Self::State> {
        let mut summary = RunSummary::new(self.time_step(), initial);
        let fail = |source, summary| Box::new(IntegrationError::new(source, summary, max_steps));
        observe(0, &summary.last, None);
        if let Err(e) = self.check(&summary.last) {
            return Err(fail(e, summary));
        }
        let mut workspace = self.workspace();
        // The controls' buffer: allocated once per run, empty without a control law.
        let mut u = vec![
            0.0;
            if controls.is_some() {
                self.control_dim()
            } else {
                0
            }
        ];
        // Two states per run, swapped after every step: `summary.last` holds the current one,
        // `next` receives the step (a heap-backed state reuses its memory, see
        // `Stepper::step_into`).
        let mut next = summary.last.clone();
        for k in 0..max_steps {
            if let Some(law) = controls.as_mut() {
                if !law.controls(k, &summary.last, &mut u) {
                    let e = StepError::InvalidControls {
                        step: k,
                        expected: u.len(),
                        found: law.values_per_step().unwrap_or(u.len()),
                    };
                    return Err(fail(e, summary));
                }
            }
            match self.step_into(&mut workspace, k, &summary.last, &u, &mut next) {
                Ok(record) => {
                    std::mem::swap(&mut summary.last, &mut next);
                    summary.record(record.as_ref());
                    observe(k + 1, &summary.last, Some(&record));
                    if stop(k + 1, &summary.last) {
                        summary.stopped = true;
                        break;
                    }
                }
                Err(source) => return Err(fail(source, summary)),
            }
        }
        Ok(summary)
    }

    /// Integrates `steps` steps from `initial` and keeps every state and every step's record.
    /// Newton starts each step from an extrapolation of the last steps. On failure the error
    /// holds the trajectory computed so far. For long runs that need not keep every state, see
    /// [`Self::run`].
    fn integrate(&self, initial: Self::State, steps: usize) -> MemberResult<Self::Trajectory> {
        self.integrate_until(initial, steps, |_, _| false)
    }

    /// [`Self::integrate`] that ends early, after the first state satisfying `stop` (see
    /// [`Self::run_until`]).
    fn integrate_until(
        &self,
        initial: Self::State,
        max_steps: usize,
        stop: impl FnMut(usize, &Self::State) -> bool,
    ) -> MemberResult<Self::Trajectory> {
        self.collect(initial, max_steps, None, stop)
    }

    /// [`Self::integrate`] with the controls of every step from `controls` (see
    /// [`Self::run_controlled`]).
    fn integrate_controlled(
        &self,
        initial: Self::State,
        steps: usize,
        mut controls: impl ControlLaw<Self::State>,
    ) -> MemberResult<Self::Trajectory> {
        self.collect(initial, steps, Some(&mut controls), |_, _| false)
    }

    /// The trajectory of [`Self::run_controlled_until`].
    #[doc(hidden)]
    fn collect(
        &self,
        initial: Self::State,
        max_steps: usize,
        controls: Option<&mut dyn ControlLaw<Self::State>>,
        stop: impl FnMut(usize, &Self::State) -> bool,
    ) -> MemberResult<Self::Trajectory> {
        let mut trajectory = Self::Trajectory::start(self, max_steps);
        let outcome =
            self.run_controlled_until(initial, max_steps, controls, stop, |_, state, record| {
                trajectory.push(state, record)
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

    /// Integrates `steps` steps from each of `initials` in parallel (rayon's thread pool, one
    /// workspace per member), keeping every state of every member. Results come in input
    /// order; each is bit for bit what [`Self::integrate`] gives for that member, and a failed
    /// member is an `Err` at its position that leaves the others unaffected.
    fn integrate_ensemble(
        &self,
        initials: &[Self::State],
        steps: usize,
    ) -> Vec<MemberResult<Self::Trajectory>>
    where
        Self: Sync,
        Self::Trajectory: Send,
    {
        map(initials, |initial| self.integrate(initial.clone(), steps))
    }

    /// Runs `steps` steps from each of `initials` in parallel without storing trajectories: each
    /// member gets its own observer from `observer(member)`, which sees every state of that
    /// member (see [`Self::run`]); the observer is returned with the member's summary, or with
    /// its typed error.
    #[allow(clippy::type_complexity)]
    fn run_ensemble<O>(
        &self,
        initials: &[Self::State],
        steps: usize,
        observer: impl Fn(usize) -> O + Sync + Send,
    ) -> Vec<(O, RunResult<Self::State>)>
    where
        Self: Sync,
        O: FnMut(usize, &Self::State, Option<&Self::Record>) + Send,
    {
        let members: Vec<(usize, Self::State)> = initials.iter().cloned().enumerate().collect();
        map(&members, |(i, initial)| {
            let mut observe = observer(*i);
            let result = self.run(initial.clone(), steps, &mut observe);
            (observe, result)
        })
    }
}

impl<T: Stepper + ?Sized> Drive for T {}

/// The ensemble over parameter sets: for each item of `parameters`, `member(item)` builds an
/// integrator (a system with those parameters, any [`Drive`]r) and its initial state, which is
/// integrated for `steps` steps; in parallel, results in input order (see [`Drive::integrate`]).
pub fn integrate_parameters<P, I>(
    parameters: &[P],
    steps: usize,
    member: impl Fn(&P) -> (I, I::State) + Sync + Send,
) -> Vec<MemberResult<I::Trajectory>>
where
    P: Sync,
    I: Drive,
    I::Trajectory: Send,
{
    map(parameters, |p| {
        let (integrator, initial) = member(p);
        integrator.integrate(initial, steps)
    })
}
