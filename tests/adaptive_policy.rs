//! The checks of adaptive steps (the time transformation `dt = g(x) dτ`, see
//! `dirac::runtime::adaptive`) are a step policy of the one run loop: a stepper says only its
//! time coordinate, its monitor and where its state lies with respect to its energy level set,
//! and the run loop (and `Stepper::step_in`) checks the start and every step from that.

use dirac::prelude::*;
use dirac::runtime::stepper::{Collect, LevelSet};

/// The states a run kept.
#[derive(Debug)]
struct Kept(Vec<Vec<f64>>);

impl Steps for Kept {
    fn completed_steps(&self) -> usize {
        self.0.len().saturating_sub(1)
    }
}

/// A stepper with adaptive steps that says only its time coordinate and its monitor: the
/// state `(t, x)`, a step of fictitious size `h` taking `x ↦ x + h` and `t ↦ t + h g` with
/// `g = 1 − x`, or `t ↦ t − h` once `x` passes 2 (time turned back).
struct Clocked;

impl Collect<Clocked> for Kept {
    fn start(_: &Clocked, _: usize) -> Self {
        Kept(Vec::new())
    }

    fn push(&mut self, _: f64, state: &Vec<f64>, _: Option<(f64, &StepStats)>) {
        self.0.push(state.clone());
    }
}

impl Stepper for Clocked {
    type State = Vec<f64>;
    type Record = StepStats;
    type Workspace = ();
    type Trajectory = Kept;

    fn time_step(&self) -> f64 {
        0.25
    }

    fn check(&self, _: &Vec<f64>) -> Result<(), StepError> {
        Ok(())
    }

    fn workspace(&self) {}

    fn physical_time(&self, state: &Vec<f64>) -> Option<f64> {
        Some(state[0])
    }

    fn monitor(&self, _: StepAt<'_>, state: &Vec<f64>) -> Result<Option<f64>, StepError> {
        Ok(Some(1.0 - state[1]))
    }

    fn level_set(&self, state: &Vec<f64>) -> Option<LevelSet> {
        Some(LevelSet {
            p_t: state[1],
            defect: state[1],
            scale: 1.0,
        })
    }

    fn step_with(
        &self,
        _: &mut (),
        at: StepAt<'_>,
        state: &Vec<f64>,
    ) -> Result<(Vec<f64>, StepStats), StepError> {
        let (t, x) = (state[0], state[1]);
        let dt = if x > 0.2 { -at.h } else { at.h * (1.0 - x) };
        Ok((vec![t + dt, x + at.h], StepStats::default()))
    }
}

/// The checks of adaptive steps are the run loop's (and `step_in`'s), made once from what a
/// stepper says (its time, monitor and level set), not in its step: the bare step passes
/// where `step_in` and a run refuse.
#[test]
fn adaptive_checks_are_made_once_for_every_stepper() {
    let at = StepAt::new(3, 0.25);
    // The monitor 1 − x vanishes at x = 1: step_in refuses, the bare step does not.
    let start = vec![0.0, 0.75];
    assert!(Clocked.step_with(&mut (), at, &start).is_ok());
    match Clocked.step_in(&mut (), 3, &start) {
        Err(StepError::InvalidMonitor { step: 3, value }) => assert_eq!(value, 0.0),
        other => panic!("{other:?}"),
    }
    // Time turned back (x > 0.2 before the step).
    match Clocked.step_in(&mut (), 5, &vec![1.0, 0.5]) {
        Err(StepError::TimeReversed { step: 5, dt }) => assert_eq!(dt, -0.25),
        other => panic!("{other:?}"),
    }
    // A run: the start off its level set (defect x = 0.1 > 1e-8), then the time turned back
    // at the step that leaves x = 0.25.
    let error = Clocked.run(vec![0.0, 0.1]).steps(4).collect().unwrap_err();
    assert!(
        matches!(error.source, StepError::OffManifold { .. }),
        "{error}"
    );
    let error = Clocked.run(vec![0.0, 0.0]).steps(4).collect().unwrap_err();
    assert!(
        matches!(error.source, StepError::TimeReversed { step: 1, .. }),
        "{error}"
    );
    assert_eq!(
        error.trajectory.0.len(),
        2,
        "the state before the failed step kept"
    );
}
