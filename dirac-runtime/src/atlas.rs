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

use nalgebra::{SMatrix, SVector};

use crate::error::{IntegrationError, StepError, Steps};
use crate::integrate::{reduced_guess, ReducedIntegrator, StepStats, Variant};
use crate::lu::Lu;
use crate::state::{CanonicalState, ReducedState};
use crate::system::{join, split, Reduced, Side};

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
    fn lift(&self, state: &CanonicalState<N>) -> Option<CanonicalState<N>> {
        let (q, d) = self.map_jacobian(&state.q);
        let lu = Lu::new(d)?;
        Some(CanonicalState {
            q,
            p: lu.solve_transpose(&state.p),
        })
    }
}

/// The reduced state `(x, w, μ, g)` in the new chart (module documentation): `μ` is copied,
/// `w_new = Dψ^{-T} (w − B_oldᵀ μ − Dcᵀ μ) + B_newᵀ μ`. `None` where `Dψ` is singular or the
/// result is not finite.
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
/// [`ReducedIntegrator`]; object safe, so an atlas holds charts of different types.
pub trait Chart<const S: usize, const K: usize, const N: usize> {
    /// Takes step `k` from `state` (see [`ReducedIntegrator::step`]).
    #[allow(clippy::type_complexity)]
    fn step(
        &self,
        k: usize,
        state: &ReducedState<S, K>,
        guess: &SVector<f64, N>,
    ) -> Result<(ReducedState<S, K>, SVector<f64, K>, StepStats), StepError>;

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
{
    fn step(
        &self,
        k: usize,
        state: &ReducedState<S, K>,
        guess: &SVector<f64, N>,
    ) -> Result<(ReducedState<S, K>, SVector<f64, K>, StepStats), StepError> {
        ReducedIntegrator::step(self, k, state, guess)
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

/// A trajectory on an atlas: `states[j]` at `t_j = j h`, in chart `charts[j]`.
#[derive(Clone, Debug, PartialEq)]
pub struct AtlasTrajectory<const S: usize, const K: usize> {
    /// The time step `h` (the same in every chart).
    pub h: f64,
    /// The states, each in its own chart.
    pub states: Vec<ReducedState<S, K>>,
    /// `charts[j]` is the chart of `states[j]`.
    pub charts: Vec<usize>,
    /// Newton statistics of each step.
    pub stats: Vec<StepStats>,
    /// Every change of chart, in order.
    pub switches: Vec<Switch<S, K>>,
}

impl<const S: usize, const K: usize> AtlasTrajectory<S, K> {
    /// Number of completed steps.
    pub fn steps(&self) -> usize {
        self.states.len() - 1
    }

    /// The last state and its chart.
    pub fn last(&self) -> (usize, &ReducedState<S, K>) {
        let j = self.steps();
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
        self.steps()
    }
}

/// What a memory-constant run ([`AtlasIntegrator::run`]) returns: the switches and the number
/// of completed steps.
#[derive(Clone, Debug, PartialEq)]
pub struct AtlasRun<const S: usize, const K: usize> {
    /// Number of completed steps.
    pub steps: usize,
    /// Every change of chart, in order.
    pub switches: Vec<Switch<S, K>>,
    /// The last state and its chart.
    pub last: (usize, ReducedState<S, K>),
}

impl<const S: usize, const K: usize> Steps for AtlasRun<S, K> {
    fn completed_steps(&self) -> usize {
        self.steps
    }
}

/// A chart-quality indicator `quality(chart, state)`: larger is better; typically the distance of
/// `state.x` to the chart's singular set.
pub type Quality<'a, const S: usize, const K: usize> =
    Box<dyn Fn(usize, &ReducedState<S, K>) -> f64 + 'a>;

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
    charts: Vec<Box<dyn Chart<S, K, N> + 'a>>,
    /// `transitions[from][to]`.
    transitions: Vec<Vec<Option<Box<dyn ChartTransition<S, K, N> + 'a>>>>,
    quality: Option<Quality<'a, S, K>>,
    switch_below: f64,
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
        }
    }

    /// Adds a chart; its index is the number of charts added before it.
    pub fn chart(mut self, name: &str, chart: impl Chart<S, K, N> + 'a) -> Self {
        self.names.push(name.to_owned());
        self.charts.push(Box::new(chart));
        for row in &mut self.transitions {
            row.push(None);
        }
        self.transitions
            .push((0..self.charts.len()).map(|_| None).collect());
        self
    }

    /// Declares the transition from chart `from` to chart `to`.
    ///
    /// # Panics
    /// If either index is not a chart added before (a programming error at set-up).
    pub fn transition(
        mut self,
        from: usize,
        to: usize,
        transition: impl ChartTransition<S, K, N> + 'a,
    ) -> Self {
        assert!(
            from < self.charts.len() && to < self.charts.len() && from != to,
            "transition {from} → {to}: both must be distinct charts added before"
        );
        self.transitions[from][to] = Some(Box::new(transition));
        self
    }

    /// A user-supplied chart-quality indicator: switch when `quality(chart, state) < switch_below`.
    pub fn with_quality(
        mut self,
        switch_below: f64,
        quality: impl Fn(usize, &ReducedState<S, K>) -> f64 + 'a,
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

    /// The chart to move to from `chart` at `state`, with the state there, if one is better.
    fn better_chart(
        &self,
        k: usize,
        chart: usize,
        state: &ReducedState<S, K>,
        current: f64,
    ) -> Option<(usize, ReducedState<S, K>)> {
        let mut best: Option<(f64, usize, ReducedState<S, K>)> = None;
        for to in 0..self.charts.len() {
            let Some(mapped) = (to != chart)
                .then(|| self.express(chart, state, to))
                .flatten()
            else {
                continue;
            };
            let q = match &self.quality {
                Some(quality) => quality(to, &mapped),
                None => self.charts[to]
                    .step(k, &mapped, &fresh_guess(&mapped))
                    .map_or(0.0, |(_, _, stats)| stats.rcond.unwrap_or(1.0)),
            };
            if q > current && best.as_ref().is_none_or(|b| q > b.0) {
                best = Some((q, to, mapped));
            }
        }
        best.map(|(_, to, s)| (to, s))
    }

    /// Integrates `steps` steps from `initial` in chart `chart`, keeping every state.
    pub fn integrate(
        &self,
        chart: usize,
        initial: ReducedState<S, K>,
        steps: usize,
    ) -> Result<AtlasTrajectory<S, K>, Box<IntegrationError<AtlasTrajectory<S, K>>>> {
        let mut states = Vec::with_capacity(steps + 1);
        let mut charts = Vec::with_capacity(steps + 1);
        let mut stats = Vec::with_capacity(steps);
        let result = self.run(chart, initial, steps, |event| match event {
            Event::State {
                chart,
                state,
                stats: s,
            } => {
                states.push(*state);
                charts.push(chart);
                if let Some(s) = s {
                    stats.push(*s);
                }
            }
            Event::Switch(sw) => {
                // The switched state replaces its old-chart copy.
                if let Some(last) = states.last_mut() {
                    *last = sw.after;
                }
                if let Some(last) = charts.last_mut() {
                    *last = sw.to;
                }
            }
        });
        let h = self.charts.get(chart).map_or(f64::NAN, |c| c.time_step());
        let build = |switches| AtlasTrajectory {
            h,
            states,
            charts,
            stats,
            switches,
        };
        match result {
            Ok(run) => Ok(build(run.switches)),
            Err(e) => {
                let IntegrationError {
                    source,
                    trajectory,
                    requested,
                } = *e;
                Err(Box::new(IntegrationError::new(
                    source,
                    build(trajectory.switches),
                    requested,
                )))
            }
        }
    }

    /// Integrates `steps` steps from `initial` in chart `chart` in constant memory: `observe`
    /// sees every state (with the statistics of the step that produced it) and every switch.
    pub fn run(
        &self,
        chart: usize,
        initial: ReducedState<S, K>,
        steps: usize,
        mut observe: impl FnMut(Event<'_, S, K>),
    ) -> Result<AtlasRun<S, K>, Box<IntegrationError<AtlasRun<S, K>>>> {
        let mut run = AtlasRun {
            steps: 0,
            switches: Vec::new(),
            last: (chart, initial),
        };
        observe(Event::State {
            chart,
            state: &initial,
            stats: None,
        });
        let fail =
            |source, run: AtlasRun<S, K>| Box::new(IntegrationError::new(source, run, steps));
        let Some(first) = self.charts.get(chart) else {
            return Err(fail(
                StepError::InvalidAtlas {
                    reason: "the initial chart index is not a chart of the atlas",
                },
                run,
            ));
        };
        if let Err(e) = check_inputs(first.time_step(), initial.is_finite(), &self.charts) {
            return Err(fail(e, run));
        }
        let (mut c, mut state) = (chart, initial);
        // Newton's guess extrapolates as ReducedIntegrator's does (`reduced_guess`), from the last
        // two increments `(x_{j+1} − x_j, group unknown of step j)`, newest first; after a switch
        // the last increment is recomputed in the new chart.
        let mut last: Option<(SVector<f64, S>, SVector<f64, K>)> = None;
        let mut before: Option<(SVector<f64, S>, SVector<f64, K>)> = None;
        for k in 0..steps {
            let guess = reduced_guess::<S, K, N>(&state.x, last.as_ref(), before.as_ref());
            let (next, g_unknown, stats) = match self.charts[c].step(k, &state, &guess) {
                Ok(ok) => ok,
                Err(error) => {
                    // Rescue: the same step from the same state in the best other chart.
                    let rescued = self.better_chart(k, c, &state, f64::NEG_INFINITY);
                    let Some((to, mapped)) = rescued else {
                        return Err(fail(error, run));
                    };
                    let Ok(ok) = self.charts[to].step(k, &mapped, &fresh_guess(&mapped)) else {
                        return Err(fail(error, run));
                    };
                    let sw = Switch {
                        step: k,
                        from: c,
                        to,
                        before: state,
                        after: mapped,
                        rescue: true,
                    };
                    observe(Event::Switch(&sw));
                    run.switches.push(sw);
                    (c, state, last) = (to, mapped, None);
                    ok
                }
            };
            before = last;
            last = Some((next.x - state.x, g_unknown));
            let previous = state;
            state = next;
            run.steps = k + 1;
            run.last = (c, state);
            observe(Event::State {
                chart: c,
                state: &state,
                stats: Some(&stats),
            });
            // Is the new state still well inside the current chart?
            let current = match &self.quality {
                Some(q) => q(c, &state),
                None => stats.rcond.unwrap_or(1.0),
            };
            if current < self.switch_below {
                if let Some((to, mapped)) = self.better_chart(k + 1, c, &state, current) {
                    let sw = Switch {
                        step: k + 1,
                        from: c,
                        to,
                        before: state,
                        after: mapped,
                        rescue: false,
                    };
                    observe(Event::Switch(&sw));
                    run.switches.push(sw);
                    // The extrapolation continues in the new chart from the previous state mapped
                    // there and the group unknown its increment implies (last line of (4.6)).
                    last = self.express(c, &previous, to).map(|p| {
                        let dg = (mapped.g - p.g) - self.charts[to].connection() * (mapped.x - p.x);
                        let g_unknown = match self.charts[to].variant() {
                            Variant::Plus => dg,
                            Variant::Minus => -dg,
                        };
                        (mapped.x - p.x, g_unknown)
                    });
                    before = None;
                    c = to;
                    state = mapped;
                    run.last = (c, state);
                }
            }
        }
        Ok(run)
    }
}

/// What [`AtlasIntegrator::run`] reports.
#[derive(Clone, Copy, Debug)]
pub enum Event<'s, const S: usize, const K: usize> {
    /// A state: the initial one (`stats: None`) or the result of a step in chart `chart`.
    State {
        /// The chart the state is expressed in.
        chart: usize,
        /// The state.
        state: &'s ReducedState<S, K>,
        /// The statistics of the step that produced it.
        stats: Option<&'s StepStats>,
    },
    /// The last reported state changed chart.
    Switch(&'s Switch<S, K>),
}

/// Newton's start without history: stay put, zero group unknown.
fn fresh_guess<const S: usize, const K: usize, const N: usize>(
    state: &ReducedState<S, K>,
) -> SVector<f64, N> {
    join::<S, K, N>(&state.x, &SVector::zeros())
}

/// The checks made before the first step, as for [`ReducedIntegrator::integrate`].
fn check_inputs<const S: usize, const K: usize, const N: usize>(
    h: f64,
    state_is_finite: bool,
    charts: &[Box<dyn Chart<S, K, N> + '_>],
) -> Result<(), StepError> {
    if !(h.is_finite() && h > 0.0) {
        return Err(StepError::InvalidTimeStep { h });
    }
    let non_finite = |what| StepError::NonFinite {
        step: 0,
        what,
        residual: f64::INFINITY,
    };
    for chart in charts {
        if chart.time_step() != h {
            return Err(StepError::InvalidAtlas {
                reason: "the charts have different time steps",
            });
        }
        if chart.parameter_values().iter().any(|p| !p.is_finite()) {
            return Err(non_finite("the parameters"));
        }
    }
    if !state_is_finite {
        return Err(non_finite("the initial state"));
    }
    Ok(())
}
