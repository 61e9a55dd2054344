//! An atlas of charts (§6 of the paper): integrate in a chart in which the group acts by
//! translation, and change chart "whenever it is necessary".
//!
//! A system whose configuration space is not globally `Σ × G` (the double spherical pendulum on
//! `S² × S²`, Remark 7.1) is described by several charts, each an annotated discrete Lagrangian in
//! its own coordinates `q = (x, g)` with the same group acting by translation of `g`. A
//! [`ChartTransition`] (emitted by `#[chart_transition]`) maps one chart's coordinates to
//! another's; the [`AtlasIntegrator`] steps in one chart and switches when a chart-quality
//! indicator asks for it, recording every switch.
//!
//! # The momentum transformation
//!
//! Both charts trivialize the same action by translation, so the transition is equivariant,
//! `φ(x, g + a) = φ(x, g) + (0, a)`; that is (checked by the macro at compile time)
//!
//! ```text
//! φ(x, g) = (ψ(x), g + c(x)),        Dφ = [[Dψ, 0], [Dc, I]].
//! ```
//!
//! A state `(q, p) ∈ T*Q` changes chart by the cotangent lift of `φ`, `p_new = Dφ^{-T} p_old`,
//! which is a symplectomorphism; since `Dφᵀ = [[Dψᵀ, Dcᵀ], [0, I]]`, `p_old = Dφᵀ p_new` reads
//!
//! ```text
//! p_x,old = Dψᵀ p_x,new + Dcᵀ p_g,new,        p_g,old = p_g,new.
//! ```
//!
//! With the trivialization (3.6), `μ = J(q, p) = p_g` and `w = p_x + Bᵀ μ` (`B` the chart's
//! connection matrix), the reduced state `(x, w, μ, g)` therefore changes as
//!
//! ```text
//! x_new = ψ(x_old)
//! μ_new = μ_old                                                  (the momentum map is intrinsic)
//! w_new = Dψ^{-T} (w_old − B_oldᵀ μ − Dcᵀ μ) + B_newᵀ μ
//! g_new = g_old + c(x_old)
//! ```
//!
//! `μ` is copied, so it is carried over bit for bit. The discrete flows of the two charts'
//! discrete Lagrangians differ (each is a quadrature in its own coordinates), but each step is
//! symplectic and so is the lift: the composed map — steps in one chart, a switch, steps in the
//! next — is symplectic and conserves `μ` exactly, as the paper's §6 argues for the variational
//! principle.

use std::any::Any;

use nalgebra::{SMatrix, SVector};

use crate::error::{StepError, Steps};
use crate::linalg::Lu;
use crate::reduced::{reduced_guess, ReducedIntegrator, ReducedStep, ReducedWorkspace};
use crate::state::{ReducedState, UnreducedState};
use crate::stepper::{check_inputs, Collect, History, StepAt, StepStats, Stepper};
use crate::system::{join, split, Reduced, Side, Variant};

/// A change of chart `φ : q_old ↦ q_new`, equivariant for the translation of the group
/// coordinates (see the [module documentation](self)). `#[chart_transition]` implements it
/// with straight-line code for `φ` and `Dφ`.
pub trait ChartTransition<const S: usize, const K: usize, const N: usize> {
    /// `φ(q)`.
    fn map(&self, q: &SVector<f64, N>) -> SVector<f64, N>;

    /// `φ(q)` and `Dφ(q)` (`Dφ[(i, j)] = ∂φ_i/∂q_j`), from one straight-line function.
    fn map_jacobian(&self, q: &SVector<f64, N>) -> (SVector<f64, N>, SMatrix<f64, N, N>);

    /// The cotangent lift `(q, p) ↦ (φ(q), Dφ(q)^{-T} p)`; `None` where `Dφ` is singular (the
    /// point is on the singular set of one of the two charts).
    fn lift(&self, state: &UnreducedState<N>) -> Option<UnreducedState<N>> {
        let (q, d) = self.map_jacobian(&state.q);
        let lu = Lu::new(d)?;
        Some(UnreducedState {
            q,
            p: lu.solve_transpose(&state.p),
        })
    }
}

/// The reduced state `(x, w, μ, g)` in the new chart (module documentation): `μ` is copied,
/// `w_new = Dψ^{-T} (w − B_oldᵀ μ − Dcᵀ μ) + B_newᵀ μ`. `None` where `Dψ` is singular or the
/// result is not finite. (Users call [`AtlasIntegrator::express`].)
#[doc(hidden)]
pub fn transform_state<T, const S: usize, const K: usize, const N: usize>(
    transition: &T,
    state: &ReducedState<S, K>,
    b_old: &SMatrix<f64, K, S>,
    b_new: &SMatrix<f64, K, S>,
) -> Option<ReducedState<S, K>>
where
    T: ChartTransition<S, K, N> + ?Sized,
{
    let (q, d) = transition.map_jacobian(&join::<S, K, N>(&state.x, &state.g));
    let d_psi: SMatrix<f64, S, S> = d.fixed_view::<S, S>(0, 0).into_owned();
    let d_c: SMatrix<f64, K, S> = d.fixed_view::<K, S>(S, 0).into_owned();
    let lu = Lu::new(d_psi)?;
    let mu = state.mu;
    let p_x_old = state.w - b_old.transpose() * mu;
    let p_x_new = lu.solve_transpose(&(p_x_old - d_c.transpose() * mu));
    let (x, g) = split::<S, K, N>(&q);
    let next = ReducedState {
        x,
        w: p_x_new + b_new.transpose() * mu,
        mu,
        g,
    };
    next.is_finite().then_some(next)
}

/// One chart as the atlas sees it: a reduced stepper in its own coordinates. Implemented by
/// [`ReducedIntegrator`]; object safe, so an atlas holds charts of different types, each with
/// its own workspace type behind `dyn Any` (built once per run).
pub trait Chart<const S: usize, const K: usize, const N: usize> {
    /// A fresh workspace for this chart's steps ([`Stepper::workspace`]).
    fn chart_workspace(&self) -> Box<dyn Any>;

    /// Takes the step `at` (step `k` of size `h` with the controls `u`; empty: the chart
    /// system's own) from `state`, Newton starting at `guess`, in `workspace` (one that
    /// [`Self::chart_workspace`] built; another is reported as [`StepError::InvalidAtlas`]). Every chart declares the forces in
    /// its own coordinates; a virtual work written the same way in each is the cotangent lift of
    /// one force.
    fn chart_step(
        &self,
        workspace: &mut dyn Any,
        at: StepAt<'_>,
        state: &ReducedState<S, K>,
        guess: &SVector<f64, N>,
    ) -> Result<(ReducedState<S, K>, ReducedStep<K>), StepError>;

    /// The number of controls the chart's system declares.
    fn chart_control_dim(&self) -> usize;

    /// The checks of a run starting in this chart ([`Stepper::check`]).
    fn chart_check(&self, initial: &ReducedState<S, K>) -> Result<(), StepError>;

    /// Which reduced equations the chart solves.
    fn variant(&self) -> Variant;

    /// The chart's connection matrix `B`.
    fn connection(&self) -> SMatrix<f64, K, S>;

    /// The time step `h`.
    fn time_step(&self) -> f64;

    /// The parameter values.
    fn parameter_values(&self) -> Vec<f64>;
}

impl<L, D, const S: usize, const K: usize, const N: usize> Chart<S, K, N>
    for ReducedIntegrator<L, D, S, K, N>
where
    D: Side,
    L: Reduced<D, S, K, N>,
    L::Linear: 'static,
{
    fn chart_workspace(&self) -> Box<dyn Any> {
        Box::new(Stepper::workspace(self))
    }

    fn chart_step(
        &self,
        workspace: &mut dyn Any,
        at: StepAt<'_>,
        state: &ReducedState<S, K>,
        guess: &SVector<f64, N>,
    ) -> Result<(ReducedState<S, K>, ReducedStep<K>), StepError> {
        let Some(workspace) = workspace.downcast_mut::<ReducedWorkspace<L::Linear, S, K>>() else {
            return Err(StepError::InvalidAtlas {
                reason: "a chart was given the workspace of another chart",
            });
        };
        self.solve_step(&mut workspace.solver, at, state, guess)
    }

    fn chart_control_dim(&self) -> usize {
        self.system().control_count()
    }

    fn chart_check(&self, initial: &ReducedState<S, K>) -> Result<(), StepError> {
        Stepper::check(self, initial)
    }

    fn variant(&self) -> Variant {
        ReducedIntegrator::variant(self)
    }

    fn connection(&self) -> SMatrix<f64, K, S> {
        self.system().connection()
    }

    fn time_step(&self) -> f64 {
        self.system().time_step()
    }

    fn parameter_values(&self) -> Vec<f64> {
        self.system().parameter_values()
    }
}

/// A change of chart in a trajectory.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Switch<const S: usize, const K: usize> {
    /// The index of the state at which the chart changed: `states[step]` is `after`, and step
    /// `step` (from `t_step` to `t_{step+1}`) is the first taken in the new chart.
    pub step: usize,
    /// The old chart's index.
    pub from: usize,
    /// The new chart's index.
    pub to: usize,
    /// The state in the old chart.
    pub before: ReducedState<S, K>,
    /// The same state in the new chart.
    pub after: ReducedState<S, K>,
    /// Whether the switch rescued a step that failed in the old chart (rather than being asked
    /// for by the quality indicator).
    pub rescue: bool,
}

/// A trajectory on an atlas: `states[j]` at `times[j]` (`t_j = j h` for a fixed step), in chart
/// `charts[j]`.
#[derive(Clone, Debug, PartialEq)]
pub struct AtlasTrajectory<const S: usize, const K: usize> {
    /// The time step `h` (the same in every chart; the default step of a run).
    pub h: f64,
    /// The states, each in its own chart.
    pub states: Vec<ReducedState<S, K>>,
    /// `times[j] = t_j`, the time of `states[j]`.
    pub times: Vec<f64>,
    /// `step_sizes[k]` is the size step `k` was taken with, bit for bit as the run passed it to
    /// the step: `h` itself for a fixed step, `h_k` with a schedule (the last step shortened to
    /// land on an end time); with adaptive steps the fictitious step `ε_k` (the physical step is
    /// `times[k + 1] − times[k]`).
    pub step_sizes: Vec<f64>,
    /// `charts[j]` is the chart of `states[j]`.
    pub charts: Vec<usize>,
    /// Newton statistics of each step.
    pub stats: Vec<StepStats>,
    /// Every change of chart, in order.
    pub switches: Vec<Switch<S, K>>,
}

impl<const S: usize, const K: usize> AtlasTrajectory<S, K> {
    /// Number of completed steps.
    pub fn step_count(&self) -> usize {
        self.states.len() - 1
    }

    /// The last state and its chart.
    pub fn last(&self) -> (usize, &ReducedState<S, K>) {
        let j = self.step_count();
        (self.charts[j], &self.states[j])
    }

    /// User-defined output quantities, e.g. Cartesian positions: `f(chart, state)` per state.
    pub fn output<T>(&self, f: impl Fn(usize, &ReducedState<S, K>) -> T) -> Vec<T> {
        self.charts
            .iter()
            .zip(&self.states)
            .map(|(&c, s)| f(c, s))
            .collect()
    }
}

impl<const S: usize, const K: usize> Steps for AtlasTrajectory<S, K> {
    fn completed_steps(&self) -> usize {
        self.step_count()
    }
}

/// A chart-quality indicator `quality(chart, state)`: larger is better; typically the distance of
/// `state.x` to the chart's singular set.
pub type Quality<'a, const S: usize, const K: usize> =
    Box<dyn Fn(usize, &ReducedState<S, K>) -> f64 + Send + Sync + 'a>;

/// Integrates on an atlas: steps in the current chart, and changes chart when the quality
/// indicator of the current chart falls below a threshold, to the chart where it is largest.
///
/// * With a user indicator ([`AtlasIntegrator::with_quality`]), after each step the indicator is
///   evaluated at the new state; below `switch_below`, the state is mapped into every chart
///   reachable by a declared transition and the atlas moves to the one with the largest indicator
///   (if larger than the current one).
/// * Without one, the built-in fallback is the step Jacobian's conditioning: when a step's
///   reciprocal condition estimate falls below `switch_below`, each reachable chart takes a trial
///   step from the mapped state and the atlas moves to the best conditioned.
///
/// A step that fails in the current chart is retried in the other reachable charts (best quality
/// first); only when every chart fails does the run stop, with the typed error of the current
/// chart's step and the trajectory so far.
pub struct AtlasIntegrator<'a, const S: usize, const K: usize, const N: usize> {
    names: Vec<String>,
    charts: Vec<Box<dyn Chart<S, K, N> + Send + Sync + 'a>>,
    /// `transitions[from][to]`.
    transitions: Vec<Vec<Option<Box<dyn ChartTransition<S, K, N> + Send + Sync + 'a>>>>,
    quality: Option<Quality<'a, S, K>>,
    switch_below: f64,
    /// Whether a transition was declared between charts not added before (or from a chart to
    /// itself), reported by the run's check.
    misdeclared: bool,
}

impl<'a, const S: usize, const K: usize, const N: usize> Default for AtlasIntegrator<'a, S, K, N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<'a, const S: usize, const K: usize, const N: usize> AtlasIntegrator<'a, S, K, N> {
    /// An empty atlas with the conditioning fallback at `rcond < 1e-3`.
    pub fn new() -> Self {
        Self {
            names: Vec::new(),
            charts: Vec::new(),
            transitions: Vec::new(),
            quality: None,
            switch_below: 1e-3,
            misdeclared: false,
        }
    }

    /// Adds a chart; its index is the number of charts added before it.
    pub fn chart(mut self, name: &str, chart: impl Chart<S, K, N> + Send + Sync + 'a) -> Self {
        self.names.push(name.to_owned());
        self.charts.push(Box::new(chart));
        for row in &mut self.transitions {
            row.push(None);
        }
        self.transitions
            .push((0..self.charts.len()).map(|_| None).collect());
        self
    }

    /// Declares the transition from chart `from` to chart `to`. Both must be distinct charts
    /// added before: otherwise the transition is dropped and every run of the atlas fails its
    /// input check with [`StepError::InvalidAtlas`].
    pub fn transition(
        mut self,
        from: usize,
        to: usize,
        transition: impl ChartTransition<S, K, N> + Send + Sync + 'a,
    ) -> Self {
        match self
            .transitions
            .get_mut(from)
            .and_then(|row| row.get_mut(to))
        {
            Some(slot) if from != to => *slot = Some(Box::new(transition)),
            _ => self.misdeclared = true,
        }
        self
    }

    /// A user-supplied chart-quality indicator: switch when `quality(chart, state) < switch_below`.
    pub fn with_quality(
        mut self,
        switch_below: f64,
        quality: impl Fn(usize, &ReducedState<S, K>) -> f64 + Send + Sync + 'a,
    ) -> Self {
        self.quality = Some(Box::new(quality));
        self.switch_below = switch_below;
        self
    }

    /// The conditioning fallback: switch when a step's reciprocal condition estimate falls below
    /// `switch_below` (and drop any user indicator).
    pub fn with_conditioning(mut self, switch_below: f64) -> Self {
        self.quality = None;
        self.switch_below = switch_below;
        self
    }

    /// The charts' names, in index order.
    pub fn chart_names(&self) -> &[String] {
        &self.names
    }

    /// `state` (in chart `from`) expressed in chart `to`, through the declared transition;
    /// `None` without a transition or where it is singular.
    pub fn express(
        &self,
        from: usize,
        state: &ReducedState<S, K>,
        to: usize,
    ) -> Option<ReducedState<S, K>> {
        if from == to {
            return Some(*state);
        }
        let t = self.transitions.get(from)?.get(to)?.as_ref()?;
        transform_state::<_, S, K, N>(
            t.as_ref(),
            state,
            &self.charts[from].connection(),
            &self.charts[to].connection(),
        )
    }

    /// The chart to move to from `chart` at `state`, with the state there, if one is better
    /// (trial steps of the conditioning fallback run in the charts' workspaces, the step `at`).
    fn better_chart(
        &self,
        workspaces: &mut [Box<dyn Any>],
        at: StepAt<'_>,
        chart: usize,
        state: &ReducedState<S, K>,
        current: f64,
    ) -> Option<(usize, ReducedState<S, K>)> {
        let mut best: Option<(f64, usize, ReducedState<S, K>)> = None;
        for (to, (target, workspace)) in self.charts.iter().zip(workspaces).enumerate() {
            let Some(mapped) = (to != chart)
                .then(|| self.express(chart, state, to))
                .flatten()
            else {
                continue;
            };
            let q = match &self.quality {
                Some(quality) => quality(to, &mapped),
                None => target
                    .chart_step(workspace.as_mut(), at, &mapped, &fresh_guess(&mapped))
                    .map_or(0.0, |(_, step)| step.stats.rcond.unwrap_or(1.0)),
            };
            if q > current && best.as_ref().is_none_or(|b| q > b.0) {
                best = Some((q, to, mapped));
            }
        }
        best.map(|(_, to, s)| (to, s))
    }
}

/// What an atlas step reports besides the new state: its Newton statistics and the changes of
/// chart it made.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AtlasStep<const S: usize, const K: usize> {
    /// Newton statistics of the step (in the chart it was taken in).
    pub stats: StepStats,
    /// A change of chart before the step, which rescued a step that failed in the old chart
    /// (`rescue: true`; its `step` is this step's index).
    pub rescue: Option<Switch<S, K>>,
    /// A change of chart after the step, asked for by the quality indicator (its `step` is the
    /// index of the new state, which the run reports in the new chart).
    pub switch: Option<Switch<S, K>>,
}

impl<const S: usize, const K: usize> AsRef<StepStats> for AtlasStep<S, K> {
    fn as_ref(&self) -> &StepStats {
        &self.stats
    }
}

/// The workspace of an atlas run: one workspace per chart, and the last two increments
/// `(x_{j+1} − x_j, u_j)` in the current chart that Newton's guess extrapolates (as
/// [`ReducedIntegrator`]'s does, [`reduced_guess`]).
pub struct AtlasWorkspace<const S: usize, const K: usize> {
    charts: Vec<Box<dyn Any>>,
    history: History<(SVector<f64, S>, SVector<f64, K>)>,
}

impl<const S: usize, const K: usize> std::fmt::Debug for AtlasWorkspace<S, K> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("AtlasWorkspace")
            .field("charts", &self.charts.len())
            .field("history", &self.history)
            .finish()
    }
}

impl<'a, const S: usize, const K: usize, const N: usize> Collect<AtlasIntegrator<'a, S, K, N>>
    for AtlasTrajectory<S, K>
{
    fn start(atlas: &AtlasIntegrator<'a, S, K, N>, steps: usize) -> Self {
        AtlasTrajectory {
            h: atlas.time_step(),
            states: crate::stepper::reserved(steps.saturating_add(1)),
            times: crate::stepper::reserved(steps.saturating_add(1)),
            step_sizes: crate::stepper::reserved(steps),
            charts: crate::stepper::reserved(steps.saturating_add(1)),
            stats: crate::stepper::reserved(steps),
            switches: Vec::new(),
        }
    }

    fn push(
        &mut self,
        t: f64,
        state: &(usize, ReducedState<S, K>),
        step: Option<(f64, &AtlasStep<S, K>)>,
    ) {
        let record = step.map(|(_, record)| record);
        if let Some(rescue) = record.and_then(|r| r.rescue) {
            // The state the step started from is kept in the chart it was taken in.
            if let (Some(s), Some(c)) = (self.states.last_mut(), self.charts.last_mut()) {
                (*s, *c) = (rescue.after, rescue.to);
            }
            self.switches.push(rescue);
        }
        self.charts.push(state.0);
        self.states.push(state.1);
        self.times.push(t);
        if let Some((h, record)) = step {
            self.step_sizes.push(h);
            self.stats.push(record.stats);
            self.switches.extend(record.switch);
        }
    }

    crate::stepper::collect_steps!(try_reserve((usize, ReducedState<S, K>)), charts: "charts");
}

/// An atlas is a stepper on states `(chart, state)`: the one driver ([`crate::Drive`]) gives it
/// `run`, `integrate`, ensembles and stop conditions.
///
/// A step is taken in the current chart; if it fails, it is retried from the same state in the
/// other reachable charts (best quality first) — a rescue — and only when every chart fails is
/// the run stopped, with the typed error of the current chart's step. After the step, the
/// quality indicator of the new state (or the step's conditioning) decides whether to change
/// chart; the state reported is then the one in the new chart.
impl<'a, const S: usize, const K: usize, const N: usize> Stepper for AtlasIntegrator<'a, S, K, N> {
    type State = (usize, ReducedState<S, K>);
    type Record = AtlasStep<S, K>;
    type Workspace = AtlasWorkspace<S, K>;
    type Trajectory = AtlasTrajectory<S, K>;

    /// The charts' common time step (NaN for an empty atlas).
    fn time_step(&self) -> f64 {
        self.charts.first().map_or(f64::NAN, |c| c.time_step())
    }

    /// Every transition was declared between distinct charts of the atlas; the initial chart
    /// must be a chart of the atlas, and its checks hold for the initial state
    /// ([`Stepper::check`]); every chart has the same time step and finite parameters.
    fn check(&self, &(chart, ref initial): &Self::State) -> Result<(), StepError> {
        if self.misdeclared {
            return Err(StepError::InvalidAtlas {
                reason: "a transition was declared between charts not added before, or from a \
                         chart to itself",
            });
        }
        let Some(first) = self.charts.get(chart) else {
            return Err(StepError::InvalidAtlas {
                reason: "the initial chart index is not a chart of the atlas",
            });
        };
        first.chart_check(initial)?;
        let h = first.time_step();
        for chart in &self.charts {
            if chart.time_step() != h {
                return Err(StepError::InvalidAtlas {
                    reason: "the charts have different time steps",
                });
            }
            check_inputs(h, &chart.parameter_values(), true)?;
        }
        Ok(())
    }

    fn workspace(&self) -> AtlasWorkspace<S, K> {
        AtlasWorkspace {
            charts: self.charts.iter().map(|c| c.chart_workspace()).collect(),
            history: History::default(),
        }
    }

    fn control_dim(&self) -> usize {
        self.charts.first().map_or(0, |c| c.chart_control_dim())
    }

    fn step_with(
        &self,
        workspace: &mut AtlasWorkspace<S, K>,
        at: StepAt<'_>,
        &(chart, ref from): &Self::State,
    ) -> Result<(Self::State, AtlasStep<S, K>), StepError> {
        let (k, h) = (at.k, at.h);
        // `Stepper::step` and `step_with` are public: a chart index or a workspace that is not
        // this atlas's is an error, as in the run's check, not an index out of bounds.
        if chart >= self.charts.len() || workspace.charts.len() != self.charts.len() {
            return Err(StepError::InvalidAtlas {
                reason: "the state's chart index is not a chart of the atlas, or the workspace \
                         is another atlas's",
            });
        }
        let guess = reduced_guess::<S, K, N>(&from.x, &workspace.history, h);
        let (c, state, rescue, (next, step)) =
            match self.charts[chart].chart_step(workspace.charts[chart].as_mut(), at, from, &guess)
            {
                Ok(ok) => (chart, *from, None, ok),
                Err(error) => {
                    // Rescue: the same step from the same state in the best other chart.
                    let Some((to, mapped)) = self.better_chart(
                        &mut workspace.charts,
                        at,
                        chart,
                        from,
                        f64::NEG_INFINITY,
                    ) else {
                        return Err(error);
                    };
                    let Ok(ok) = self.charts[to].chart_step(
                        workspace.charts[to].as_mut(),
                        at,
                        &mapped,
                        &fresh_guess(&mapped),
                    ) else {
                        return Err(error);
                    };
                    workspace.history.clear();
                    let rescue = Switch {
                        step: k,
                        from: chart,
                        to,
                        before: *from,
                        after: mapped,
                        rescue: true,
                    };
                    (to, mapped, Some(rescue), ok)
                }
            };
        workspace
            .history
            .push((next.x - state.x, step.group_unknown), h);
        let mut record = AtlasStep {
            stats: step.stats,
            rescue,
            switch: None,
        };
        // Is the new state still well inside the current chart?
        let current = match &self.quality {
            Some(q) => q(c, &next),
            None => step.stats.rcond.unwrap_or(1.0),
        };
        if current < self.switch_below {
            if let Some((to, mapped)) = self.better_chart(
                &mut workspace.charts,
                StepAt { k: k + 1, ..at },
                c,
                &next,
                current,
            ) {
                // The extrapolation continues in the new chart from the step's start mapped there
                // and the group unknown its increment implies (last line of (4.6)).
                let last = self.express(c, &state, to).map(|p| {
                    let dg = (mapped.g - p.g) - self.charts[to].connection() * (mapped.x - p.x);
                    let u = match self.charts[to].variant() {
                        Variant::Plus => dg,
                        Variant::Minus => -dg,
                    };
                    ((mapped.x - p.x, u), h)
                });
                workspace.history.restart(last);
                record.switch = Some(Switch {
                    step: k + 1,
                    from: c,
                    to,
                    before: next,
                    after: mapped,
                    rescue: false,
                });
                return Ok(((to, mapped), record));
            }
        }
        Ok(((c, next), record))
    }
}

/// Newton's start without history: stay put, zero group unknown.
fn fresh_guess<const S: usize, const K: usize, const N: usize>(
    state: &ReducedState<S, K>,
) -> SVector<f64, N> {
    join::<S, K, N>(&state.x, &SVector::zeros())
}
