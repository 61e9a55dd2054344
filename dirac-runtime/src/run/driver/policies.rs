//! What a run is configured with, besides its length: the control law, the step-size policy,
//! the stop condition and the observer, each a trait with its closure form and its default; and
//! the step policy of adaptive steps ([`adaptive_step`]).

use crate::error::StepError;
use crate::stepper::{check_adaptive_step, StepAt, Stepper};

/// Where a controlled run ([`Run::controls`](super::Run::controls)) takes the controls `u_k` of each step, in the order
/// of [`crate::System::CONTROLS`].
///
/// Implemented by feedback laws — any closure `|k, t, state, u| { … }` that writes `u_k` into `u`
/// from the step index, the time and the state the step starts from — and by
/// [`ControlSequence`], a precomputed sequence.
pub trait ControlLaw<St> {
    /// Writes the controls of step `k`, taken at time `t` from `state`, into `u` (as many values
    /// as the system declares). Returns `false` when it has none for this step (a sequence past
    /// its end): the run then stops with [`StepError::InvalidControls`](crate::StepError::InvalidControls).
    fn controls(&mut self, k: usize, t: f64, state: &St, u: &mut [f64]) -> bool;

    /// The number of values the law has per step when it is fixed (a [`ControlSequence`]'s row
    /// length), for the error of a step it has no controls for; `None` (the default) for a
    /// law that writes whatever the system declares.
    fn values_per_step(&self) -> Option<usize> {
        None
    }

    /// Whether the run has controls at all (`false` for [`NoControls`], the default).
    fn given(&self) -> bool {
        true
    }
}

impl<St, F: FnMut(usize, f64, &St, &mut [f64])> ControlLaw<St> for F {
    fn controls(&mut self, k: usize, t: f64, state: &St, u: &mut [f64]) -> bool {
        self(k, t, state, u);
        true
    }
}

/// No controls: every step runs with the values the system holds (the default of a [`Run`](super::Run)).
#[derive(Clone, Copy, Debug, Default)]
pub struct NoControls;

impl<St> ControlLaw<St> for NoControls {
    fn controls(&mut self, _: usize, _: f64, _: &St, _: &mut [f64]) -> bool {
        true
    }

    fn given(&self) -> bool {
        false
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
    fn controls(&mut self, k: usize, _t: f64, _state: &St, u: &mut [f64]) -> bool {
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

/// How large each step of a run is.
///
/// Implemented by [`Fixed`] (the default: the integrator's own `h`), by [`StepSizes`] (a
/// precomputed sequence `h_0, h_1, …`), both given with
/// [`Run::step_size`](super::Run::step_size), and by [`Schedule`], a closure `|k, t, state| h_k`
/// computed as the run goes (from the step index, the time and the state the step starts
/// from), given with [`Run::schedule`](super::Run::schedule): one way for each kind of input.
/// With adaptive steps every size is a fictitious step `ε_k`.
pub trait StepSize<St> {
    /// Whether every step has the integrator's own size (then `t_k = t_0 + k h`, bit for bit
    /// the fixed-step run).
    const FIXED: bool = false;

    /// The size of step `k`, from `state` at time `t`; `h` is the integrator's own step.
    /// `None` when the policy has no size for this step (a schedule past its end): the run then
    /// stops with [`StepError::ScheduleEnded`](crate::StepError::ScheduleEnded).
    fn step_size(&mut self, k: usize, t: f64, state: &St, h: f64) -> Option<f64>;
}

/// Every step of the integrator's own size `h` (the default of a [`Run`](super::Run)).
#[derive(Clone, Copy, Debug, Default)]
pub struct Fixed;

impl<St> StepSize<St> for Fixed {
    const FIXED: bool = true;

    #[inline]
    fn step_size(&mut self, _: usize, _: f64, _: &St, h: f64) -> Option<f64> {
        Some(h)
    }
}

/// A precomputed sequence of step sizes: step `k` has size `sizes[k]`.
#[derive(Clone, Copy, Debug)]
pub struct StepSizes<'a>(pub &'a [f64]);

impl<St> StepSize<St> for StepSizes<'_> {
    fn step_size(&mut self, k: usize, _: f64, _: &St, _: f64) -> Option<f64> {
        self.0.get(k).copied()
    }
}

/// Step sizes computed as the run goes: the closure `|k, t, state| h_k` of
/// [`Run::schedule`](super::Run::schedule), from the step index, the time and the state the step
/// starts from.
#[derive(Clone, Copy, Debug)]
pub struct Schedule<F>(pub F);

impl<St, F: FnMut(usize, f64, &St) -> f64> StepSize<St> for Schedule<F> {
    fn step_size(&mut self, k: usize, t: f64, state: &St, _: f64) -> Option<f64> {
        Some((self.0)(k, t, state))
    }
}

/// When a run ends early ([`Run::stop`](super::Run::stop)): implemented by every closure `|k, t, state| -> bool`.
pub trait StopCondition<St> {
    /// Whether the condition can end a run early: `false` only for [`Never`], so that a run
    /// asked for a number of steps knows how many states it keeps (and refuses, before the
    /// first step, a trajectory that memory cannot hold).
    const MAY_STOP: bool = true;

    /// Whether the run ends at state `k` (from 1), at time `t`.
    fn stop(&mut self, k: usize, t: f64, state: &St) -> bool;
}

impl<St, F: FnMut(usize, f64, &St) -> bool> StopCondition<St> for F {
    fn stop(&mut self, k: usize, t: f64, state: &St) -> bool {
        self(k, t, state)
    }
}

/// No stop condition (the default of a [`Run`](super::Run)).
#[derive(Clone, Copy, Debug, Default)]
pub struct Never;

impl<St> StopCondition<St> for Never {
    const MAY_STOP: bool = false;

    #[inline]
    fn stop(&mut self, _: usize, _: f64, _: &St) -> bool {
        false
    }
}

/// What sees the states of a run as they are computed ([`Run::observe`](super::Run::observe)): implemented by every
/// closure `|k, t, state, record| …`, where `record` is the step that produced state `k`
/// (`None` for the initial state).
pub trait Observer<St, R> {
    /// Sees state `k`, at time `t`.
    fn observe(&mut self, k: usize, t: f64, state: &St, record: Option<&R>);
}

impl<St, R, F: FnMut(usize, f64, &St, Option<&R>)> Observer<St, R> for F {
    fn observe(&mut self, k: usize, t: f64, state: &St, record: Option<&R>) {
        self(k, t, state, record)
    }
}

/// No observer (the default of a [`Run`](super::Run)).
#[derive(Clone, Copy, Debug, Default)]
pub struct Unobserved;

impl<St, R> Observer<St, R> for Unobserved {
    #[inline]
    fn observe(&mut self, _: usize, _: f64, _: &St, _: Option<&R>) {}
}

/// Adaptive steps ([`crate::adaptive`]): the run loop's policy after a step of fictitious size
/// `ε_k = at.h` from `last`, at physical time `t`, to `next` (with its `record`), written once for
/// every stepper. The checks of the time transformation `dt = g(x) dτ` (the monitor positive and
/// finite at `next`, `Δt_k` of the sign of `ε_k`: [`check_adaptive_step`]); the clock read from
/// the state's time coordinate ([`Stepper::physical_time`]); and where the step passed a physical
/// `end`, the step retaken from `last` at the fictitious size that lands on `end`
/// ([`crate::adaptive::land_within`], each trial checked alike), which replaces `next` and the
/// record. Returns the size the step was taken with, the physical time it reached and its record.
pub(super) fn adaptive_step<I: Stepper + ?Sized>(
    integrator: &I,
    at: StepAt<'_>,
    (t, last): (f64, &I::State),
    end: Option<f64>,
    next: &mut I::State,
    record: I::Record,
) -> Result<(f64, f64, I::Record), StepError> {
    check_adaptive_step(integrator, at, last, next)?;
    let t_next = integrator.physical_time(next).unwrap_or(f64::NAN);
    let Some(end) = end.filter(|&end| t_next > end) else {
        return Ok((at.h, t_next, record));
    };
    let (eps, (state, landed)) =
        crate::adaptive::land_within(end, t, at.h, (t_next, (next.clone(), record)), |eps| {
            let at = at.with_size(eps);
            let step = integrator.step_with(&mut integrator.workspace(), at, last)?;
            check_adaptive_step(integrator, at, last, &step.0)?;
            Ok((integrator.physical_time(&step.0).unwrap_or(f64::NAN), step))
        })?;
    let t_landed = integrator.physical_time(&state).unwrap_or(f64::NAN);
    *next = state;
    Ok((eps, t_landed, landed))
}
