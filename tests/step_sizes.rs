//! A step size per step: schedules keep the order of the method and the momentum map exactly,
//! an end time is reached exactly, trajectories carry the time of each state, and a fixed step
//! through any policy is the fixed-step run bit for bit.

use std::f64::consts::PI;

use dirac::paper::{DoubleSphericalPendulum, DSP_STEPS, DSP_T};
use dirac::prelude::*;
use dirac::systems::kepler::Kepler;

/// The smooth schedule `h_k = h (1 + ½ sin(2π t_k / T))`: sizes between `h/2` and `3h/2`.
fn smooth(h: f64, period: f64) -> impl FnMut(usize, f64, &ReducedState<1, 1>) -> f64 + Clone {
    move |_, t, _| h * (1.0 + 0.5 * (2.0 * PI * t / period).sin())
}

/// Kepler, e = 0.5, over one period under the smooth schedule: the error at the end time against
/// the closed form falls at order 2, the end time is reached exactly, and `μ` (the angular
/// momentum) is the initial one bit for bit at every state.
#[test]
fn a_smooth_schedule_keeps_order_two_and_mu_on_kepler() {
    let (a, e, period) = (1.0, 0.5, 2.0 * PI);
    let error = |n: usize| {
        let h = period / n as f64;
        let sys = Kepler::unit(h);
        let start = sys.periapsis_state(a, e);
        let traj = ReducedIntegrator::plus(sys, NewtonOptions::default())
            .run(start)
            .end_time(period)
            .schedule(smooth(h, period))
            .collect()
            .expect("integrates");
        assert_eq!(*traj.times.last().unwrap(), period, "the end time, exactly");
        assert_eq!(traj.times.len(), traj.states.len());
        assert!(traj.times.windows(2).all(|w| w[1] > w[0]));
        // The sizes vary: between h/2 and 3h/2 (the last one shortened to land on T).
        let sizes = &traj.step_sizes;
        let (lo, hi) = sizes[..sizes.len() - 1]
            .iter()
            .fold((f64::MAX, 0.0_f64), |(l, u), &s| (l.min(s), u.max(s)));
        assert!(
            lo < 0.6 * h && hi > 1.4 * h,
            "sizes in [{lo}, {hi}], h = {h}"
        );
        assert!(
            traj.states.iter().all(|s| s.mu == start.mu),
            "μ bit for bit"
        );
        let exact = sys.exact(a, e, period);
        let last = traj.last();
        (last.x[0] - exact.x[0])
            .abs()
            .max((last.g[0] - exact.g[0]).abs())
            .max((last.w[0] - exact.w[0]).abs())
    };
    let (e1, e2, e3) = (error(200), error(400), error(800));
    let (o1, o2) = ((e1 / e2).log2(), (e2 / e3).log2());
    assert!(
        (o1 - 2.0).abs() < 0.15 && (o2 - 2.0).abs() < 0.15,
        "orders {o1}, {o2} ({e1:e} {e2:e} {e3:e})"
    );
}

/// The paper's double spherical pendulum from its state with `μ ≠ 0`, under the smooth schedule
/// to an end time that is not a multiple of `h`: order 2 against a fine fixed-step reference,
/// `μ` bit for bit, the unreduced integrator's momentum map to round-off.
#[test]
fn a_smooth_schedule_keeps_order_two_and_mu_on_the_double_spherical_pendulum() {
    let end = 20.3;
    let mut start = DoubleSphericalPendulum::paper_initial_state();
    start.mu[0] = 2.0e5;
    let run = |n: usize, schedule: bool| {
        let h = end / n as f64;
        let sys = DoubleSphericalPendulum {
            h,
            ..DoubleSphericalPendulum::paper()
        };
        let integ = ReducedIntegrator::plus(sys, NewtonOptions::default());
        let traj = if schedule {
            integ
                .run(start)
                .end_time(end)
                .schedule(move |_, t, _| h * (1.0 + 0.5 * (2.0 * PI * t / end).sin()))
                .collect()
        } else {
            integ.run(start).end_time(end).collect()
        }
        .expect("integrates");
        assert_eq!(*traj.times.last().unwrap(), end);
        assert!(
            traj.states.iter().all(|s| s.mu == start.mu),
            "μ bit for bit"
        );
        *traj.last()
    };
    let reference = run(16_000, false);
    let error = |n: usize| (run(n, true).x - reference.x).amax();
    let (e1, e2) = (error(100), error(200));
    let order = (e1 / e2).log2();
    assert!((order - 2.0).abs() < 0.2, "order {order} ({e1:e}, {e2:e})");

    // The unreduced integrator under the same schedule: its momentum map p_ϑ1 is conserved to
    // round-off, and it follows the reduced run.
    let h = end / 100.0;
    let sys = DoubleSphericalPendulum {
        h,
        ..DoubleSphericalPendulum::paper()
    };
    let tight = NewtonOptions {
        abs_tol: 1e-14,
        rel_tol: 1e-15,
        ..NewtonOptions::default()
    };
    let law =
        move |_: usize, t: f64, _: &UnreducedState<4>| h * (1.0 + 0.5 * (2.0 * PI * t / end).sin());
    let unreduced = UnreducedIntegrator::new(sys, tight)
        .run(sys.untrivialize(&start))
        .end_time(end)
        .schedule(law)
        .collect()
        .expect("integrates");
    let j0 = start.mu[0];
    for s in &unreduced.states {
        assert!(
            (sys.momentum_map(s)[0] - j0).abs() <= 1e-9 * j0,
            "{}",
            sys.momentum_map(s)[0]
        );
    }
    let reduced = run(100, true);
    let back = sys.trivialize(unreduced.last());
    assert!(
        (back.x - reduced.x).amax() < 1e-9,
        "{}",
        (back.x - reduced.x).amax()
    );
}

/// An end time that is not a multiple of `h` is reached exactly by a shortened last step: the
/// run is the fixed-step run up to the last full step, bit for bit, and then one step of the
/// remainder, as a schedule of those sizes gives.
#[test]
fn an_end_time_that_is_not_a_multiple_of_h_is_reached_exactly() {
    let sys = Kepler::unit(0.1);
    let integ = ReducedIntegrator::plus(sys, NewtonOptions::default());
    let start = sys.periapsis_state(1.0, 0.3);
    let end = 1.05;
    let traj = integ.run(start).end_time(end).collect().unwrap();
    assert_eq!(traj.step_count(), 11);
    assert_eq!(traj.times[10], 10.0 * 0.1);
    assert_eq!(traj.times[11], end);
    let fixed = integ.run(start).steps(10).collect().unwrap();
    assert_eq!(traj.states[..11], fixed.states[..]);
    assert_eq!(traj.times[..11], fixed.times[..]);
    // The same sizes as a schedule.
    let mut sizes = vec![0.1; 10];
    sizes.push(end - 1.0);
    let scheduled = integ
        .run(start)
        .end_time(end)
        .step_size(StepSizes(&sizes))
        .collect()
        .unwrap();
    assert_eq!(scheduled.states, traj.states);
    // A multiple of h is not disturbed: 10 full steps, the last landing on the end time.
    let whole = integ.run(start).end_time(1.0).collect().unwrap();
    assert_eq!(whole.states, fixed.states);
    assert_eq!(*whole.times.last().unwrap(), 1.0);
    // With a cap, whichever comes first ends the run.
    let capped = integ.run(start).end_time(end).steps(4).collect().unwrap();
    assert_eq!(capped.step_count(), 4);
    // A streamed run reports the time reached.
    let summary = integ.run(start).end_time(end).stream().unwrap();
    assert_eq!((summary.step_count, summary.t), (11, end));
    // A later start time shifts the clock and nothing else.
    let later = integ
        .run(start)
        .start_time(2.0)
        .steps(10)
        .collect()
        .unwrap();
    assert_eq!(later.states, fixed.states);
    assert_eq!(later.times[10], 2.0 + 10.0 * 0.1);
}

/// A trajectory keeps the size each step was taken with, bit for bit: irregular sizes (whose
/// differences of accumulated times are not the sizes themselves), given as a list or computed
/// as the run goes, on the reduced, unreduced and composed integrators; the fixed step's `h`;
/// and the last step shortened to land on an end time.
#[test]
fn a_trajectory_keeps_each_step_size_bit_for_bit() {
    let sys = Kepler::unit(0.05);
    let start = sys.periapsis_state(1.0, 0.3);
    // Irregular sizes in [0.015, 0.085): a golden-ratio sequence, no two alike.
    let sizes: Vec<f64> = (0..40)
        .map(|k| 0.05 * (0.3 + 1.4 * (k as f64 * 0.618_033_988_749_895).fract()))
        .collect();
    let reduced = ReducedIntegrator::plus(sys, NewtonOptions::default());
    let listed = reduced
        .run(start)
        .steps(40)
        .step_size(StepSizes(&sizes))
        .collect()
        .unwrap();
    assert_eq!(listed.step_sizes, sizes);
    // What recomputing them from the times would give is not the sizes: the record is needed.
    assert!((0..40).any(|k| listed.times[k + 1] - listed.times[k] != sizes[k]));
    let computed = reduced
        .run(start)
        .steps(40)
        .schedule(|k, _, _| sizes[k])
        .collect()
        .unwrap();
    assert_eq!(computed.step_sizes, sizes);
    let unreduced = UnreducedIntegrator::new(sys, NewtonOptions::default())
        .run(sys.untrivialize(&start))
        .steps(40)
        .step_size(StepSizes(&sizes))
        .collect()
        .unwrap();
    assert_eq!(unreduced.step_sizes, sizes);
    let composed = Composition::new(reduced.clone(), CompositionMethod::TRIPLE_JUMP)
        .run(start)
        .steps(40)
        .step_size(StepSizes(&sizes))
        .collect()
        .unwrap();
    assert_eq!(composed.step_sizes, sizes);
    // The fixed step: h at every step.
    let fixed = reduced.run(start).steps(10).collect().unwrap();
    assert_eq!(fixed.step_sizes, vec![0.05; 10]);
    // An end time within the list: the sizes up to it, the last one shortened to land on it.
    let end = listed.times[20] + 0.5 * sizes[20];
    let landed = reduced
        .run(start)
        .end_time(end)
        .step_size(StepSizes(&sizes))
        .collect()
        .unwrap();
    assert_eq!(landed.step_sizes[..20], sizes[..20]);
    assert_eq!(landed.step_sizes[20], end - listed.times[20]);
    assert_eq!(landed.step_sizes.len(), 21);
}

/// A schedule that gives the integrator's own step at every step is the fixed-step run, bit for
/// bit (the system is the system itself and Newton's guess is the uniform-grid one), on every
/// integrator kind that takes a time step.
#[test]
fn a_constant_schedule_is_the_fixed_step_run_bit_for_bit() {
    let sys = DoubleSphericalPendulum::paper();
    let h = sys.h;
    let start = DoubleSphericalPendulum::paper_initial_state();
    let options = NewtonOptions::default();
    let reduced = ReducedIntegrator::plus(sys, options);
    let a = reduced.run(start).steps(50).collect().unwrap();
    let b = reduced
        .run(start)
        .steps(50)
        .schedule(|_, _, _| h)
        .collect()
        .unwrap();
    assert_eq!(a.states, b.states);
    let minus = ReducedIntegrator::minus(sys, options);
    let a = minus.run(start).steps(50).collect().unwrap();
    let b = minus
        .run(start)
        .steps(50)
        .step_size(StepSizes(&[h; 50]))
        .collect()
        .unwrap();
    assert_eq!(a.states, b.states);
    let unreduced = UnreducedIntegrator::new(sys, options);
    let c0 = sys.untrivialize(&start);
    let a = unreduced.run(c0).steps(50).collect().unwrap();
    let b = unreduced
        .run(c0)
        .steps(50)
        .schedule(|_, _, _| h)
        .collect()
        .unwrap();
    assert_eq!(a.states, b.states);
    let composed = Composition::new(reduced.clone(), CompositionMethod::TRIPLE_JUMP);
    let a = composed.run(start).steps(20).collect().unwrap();
    let b = composed
        .run(start)
        .steps(20)
        .schedule(|_, _, _| h)
        .collect()
        .unwrap();
    assert_eq!(a.states, b.states);
}

/// A composition under a schedule: each macro step of size `h_k` runs its stages with `γ_i h_k`,
/// so the order-4 triple jump keeps order 4 under the smooth schedule on Kepler.
#[test]
fn a_composition_under_a_smooth_schedule_keeps_its_order() {
    let (a, e, period) = (1.0, 0.5, 2.0 * PI);
    let error = |n: usize| {
        let h = period / n as f64;
        let sys = Kepler::unit(h);
        let start = sys.periapsis_state(a, e);
        let composed = Composition::new(
            ReducedIntegrator::plus(sys, NewtonOptions::default()),
            CompositionMethod::TRIPLE_JUMP,
        );
        let traj = composed
            .run(start)
            .end_time(period)
            .schedule(smooth(h, period))
            .collect()
            .unwrap();
        assert!(traj.states.iter().all(|s| s.mu == start.mu));
        let exact = sys.exact(a, e, period);
        (traj.last().x[0] - exact.x[0])
            .abs()
            .max((traj.last().g[0] - exact.g[0]).abs())
    };
    let (e1, e2) = (error(100), error(200));
    let order = (e1 / e2).log2();
    assert!((order - 4.0).abs() < 0.3, "order {order} ({e1:e}, {e2:e})");
}

/// Misconfigured runs and bad step sizes are typed errors that keep what was computed.
#[test]
fn bad_runs_and_step_sizes_are_typed_errors() {
    let sys = Kepler::unit(0.1);
    let integ = ReducedIntegrator::plus(sys, NewtonOptions::default());
    let start = sys.periapsis_state(1.0, 0.3);
    // No length.
    let e = integ.run(start).collect().unwrap_err();
    assert!(
        matches!(e.source, StepError::InvalidRun { .. }),
        "{}",
        e.source
    );
    assert!(e.source.to_string().contains("steps"));
    // An end time before the start, a stride of 0.
    let e = integ.run(start).end_time(-1.0).stream().unwrap_err();
    assert!(matches!(e.source, StepError::InvalidRun { .. }));
    let e = integ.run(start).steps(3).every(0).stream().unwrap_err();
    assert!(matches!(e.source, StepError::InvalidRun { .. }));
    // A schedule shorter than the run: the steps it covers are kept.
    let e = integ
        .run(start)
        .steps(5)
        .step_size(StepSizes(&[0.1, 0.05, 0.1]))
        .collect()
        .unwrap_err();
    assert_eq!(e.source, StepError::ScheduleEnded { step: 3 });
    assert_eq!(e.trajectory.step_count(), 3);
    assert_eq!(e.trajectory.times[2], 0.1 + 0.05);
    // A size that is not positive and finite, at step 2.
    for bad in [0.0, -0.1, f64::NAN, f64::INFINITY] {
        let e = integ
            .run(start)
            .steps(5)
            .schedule(move |k, _, _| if k == 2 { bad } else { 0.1 })
            .collect()
            .unwrap_err();
        assert!(
            matches!(e.source, StepError::InvalidStepSize { step: 2, .. }),
            "{}",
            e.source
        );
        assert_eq!(e.trajectory.step_count(), 2);
    }
}

/// The output stride: the observer sees every k-th state and the last; a collected trajectory
/// keeps every state all the same.
#[test]
fn the_observer_sees_every_kth_state_and_the_last() {
    let sys = DoubleSphericalPendulum::paper();
    let integ = ReducedIntegrator::plus(sys, NewtonOptions::default());
    let start = DoubleSphericalPendulum::paper_initial_state();
    let mut seen = Vec::new();
    let summary = integ
        .run(start)
        .steps(23)
        .every(5)
        .observe(|k, t, _, _| seen.push((k, t)))
        .stream()
        .unwrap();
    let ks: Vec<usize> = seen.iter().map(|&(k, _)| k).collect();
    assert_eq!(ks, [0, 5, 10, 15, 20, 23]);
    assert_eq!(seen[1].1, 5.0 * sys.h);
    assert_eq!(summary.t, 23.0 * (DSP_T / DSP_STEPS as f64));
    let mut seen = Vec::new();
    let traj = integ
        .run(start)
        .steps(23)
        .every(5)
        .observe(|k, _, _, _| seen.push(k))
        .collect()
        .unwrap();
    assert_eq!(traj.states.len(), 24);
    assert_eq!(seen, [0, 5, 10, 15, 20, 23]);
    // Stopped early: the state it stopped at is observed too.
    let mut seen = Vec::new();
    integ
        .run(start)
        .steps(23)
        .every(5)
        .stop(|k, _, _| k == 7)
        .observe(|k, _, _, _| seen.push(k))
        .stream()
        .unwrap();
    assert_eq!(seen, [0, 5, 7]);
}
