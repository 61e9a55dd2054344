//! A declared domain, `domain(r > 0.0)`: Kepler's problem in polar coordinates at a step too
//! coarse for its periapsis passage reaches `r < 0` — a solution of the step equations that
//! means nothing — and every integrator kind stops there with a typed error naming the
//! coordinate and its value, the states before it kept; at a fine step the same runs go on.

use dirac::prelude::*;

/// Kepler's problem in polar coordinates with the midpoint rule, as `dirac::systems::Kepler`,
/// its domain declared.
#[reduced_lagrangian(shape(r), group(phi), domain(r > 0.0))]
fn kepler(q0: Config, q1: Config, h: f64, k: f64) -> f64 {
    let r = 0.5 * (q0.r + q1.r);
    let (dr, dphi) = ((q1.r - q0.r) / h, (q1.phi - q0.phi) / h);
    h * (0.5 * (dr * dr + r * r * dphi * dphi) + k / r)
}

/// The same Lagrangian without a domain: what a run returned before domains were declared.
#[reduced_lagrangian(shape(r), group(phi))]
fn kepler_unbounded(q0: Config, q1: Config, h: f64, k: f64) -> f64 {
    let r = 0.5 * (q0.r + q1.r);
    let (dr, dphi) = ((q1.r - q0.r) / h, (q1.phi - q0.phi) / h);
    h * (0.5 * (dr * dr + r * r * dphi * dphi) + k / r)
}

/// Adaptive steps on Kepler's problem, its domain declared (a bound on the time coordinate too:
/// a bound may name a group coordinate).
#[reduced_lagrangian(
    shape(r), group(phi, t), time(t), adapt = |q| q.r.powf(1.5), rule = midpoint,
    domain(r > 0.0, t >= 0.0)
)]
fn kepler_adaptive(q: Config, v: Velocity, k: f64) -> f64 {
    0.5 * (v.r * v.r + q.r * q.r * v.phi * v.phi) + k / q.r
}

const E: f64 = 0.9;
const COARSE: f64 = 0.2;
const FINE: f64 = 0.01;
/// About one and a half orbits (period 2π) at the coarse step.
const STEPS: usize = 50;

/// The reduced state at periapsis of the orbit with semi-major axis 1 and eccentricity `e`.
fn periapsis(e: f64) -> ReducedState<1, 1> {
    ReducedState::new([1.0 - e], [0.0], [(1.0 - e * e).sqrt()], [0.0])
}

fn unreduced_periapsis(e: f64) -> UnreducedState<2> {
    let s = periapsis(e);
    UnreducedState::new([s.x[0], s.g[0]], [s.w[0], s.mu[0]])
}

/// The error of a run that left the domain: the step, the coordinate and its value.
fn out_of_domain(e: &StepError) -> (usize, &str, f64) {
    match e {
        StepError::OutOfDomain {
            step,
            initial: false,
            coordinate,
            value,
            bound,
        } => {
            assert_eq!(bound, "> 0", "{e}");
            (*step, coordinate.as_str(), *value)
        }
        other => panic!("expected OutOfDomain after a step, got {other:?}"),
    }
}

/// The step at which the coarse runs first reach `r < 0` (the sixth step, index 5).
const FIRST_NEGATIVE: usize = 5;

/// Without a declared domain the coarse step returns `r < 0` as success: what the domain is for.
#[test]
fn without_a_domain_the_coarse_step_returns_negative_radii_as_success() {
    let sys = KeplerUnbounded { h: COARSE, k: 1.0 };
    let t = ReducedIntegrator::plus(sys, NewtonOptions::default())
        .run(periapsis(E))
        .steps(STEPS)
        .collect()
        .unwrap();
    let first = t.states.iter().position(|s| s.x[0] <= 0.0).unwrap();
    assert_eq!(first, FIRST_NEGATIVE + 1);
    assert!(
        t.states
            .iter()
            .map(|s| s.x[0])
            .fold(f64::INFINITY, f64::min)
            < -50.0
    );
}

/// The coarse step stops with the typed error on the plus and minus sides, unreduced, and in the
/// triple jump of each: the step, the coordinate and its negative value named, the states before
/// it kept (bit for bit those of the run without a domain), the message saying what to do.
#[test]
fn the_coarse_step_stops_at_the_domain_on_every_integrator_kind() {
    let sys = Kepler { h: COARSE, k: 1.0 };
    let free = KeplerUnbounded { h: COARSE, k: 1.0 };
    let options = NewtonOptions::default();
    let reference = ReducedIntegrator::plus(free, options)
        .run(periapsis(E))
        .steps(FIRST_NEGATIVE)
        .collect()
        .unwrap();

    let check_reduced = |what: &str, e: Box<IntegrationError<Trajectory<1, 1>>>| {
        let (step, coordinate, value) = out_of_domain(&e.source);
        assert_eq!((step, coordinate), (FIRST_NEGATIVE, "r"), "{what}");
        assert!(value < 0.0, "{what}: {value}");
        let kept = &e.trajectory.states;
        assert_eq!(kept.len(), FIRST_NEGATIVE + 1, "{what}");
        assert!(kept.iter().all(|s| s.x[0] > 0.0), "{what}");
        assert_eq!(e.trajectory.completed_steps(), FIRST_NEGATIVE, "{what}");
        let message = e.source.to_string();
        assert!(
            message.contains("step 5")
                && message.contains("r = -0.6")
                && message.contains("smaller"),
            "{what}: {message}"
        );
        kept.clone()
    };
    let plus = ReducedIntegrator::plus(sys, options)
        .run(periapsis(E))
        .steps(STEPS)
        .collect()
        .unwrap_err();
    assert_eq!(check_reduced("plus", plus), reference.states);
    let minus = ReducedIntegrator::minus(sys, options)
        .run(periapsis(E))
        .steps(STEPS)
        .collect()
        .unwrap_err();
    check_reduced("minus", minus);

    let unreduced = UnreducedIntegrator::new(sys, options)
        .run(unreduced_periapsis(E))
        .steps(STEPS)
        .collect()
        .unwrap_err();
    let (step, coordinate, value) = out_of_domain(&unreduced.source);
    assert_eq!((step, coordinate), (FIRST_NEGATIVE, "r"));
    assert!(value < 0.0);
    assert_eq!(unreduced.trajectory.states.len(), FIRST_NEGATIVE + 1);
    assert!(unreduced.trajectory.states.iter().all(|s| s.q[0] > 0.0));

    // The triple jump: its macro steps reach r < 0 at the same step.
    let composed = Composition::new(
        ReducedIntegrator::plus(sys, options),
        CompositionMethod::TRIPLE_JUMP,
    )
    .run(periapsis(E))
    .steps(STEPS)
    .collect()
    .unwrap_err();
    let (step, coordinate, value) = out_of_domain(&composed.source);
    assert_eq!((step, coordinate), (FIRST_NEGATIVE, "r"));
    assert!(value < 0.0);
    assert_eq!(composed.trajectory.states.len(), FIRST_NEGATIVE + 1);
    assert!(composed.trajectory.states.iter().all(|s| s.x[0] > 0.0));
    let composed = Composition::new(
        ReducedIntegrator::minus(sys, options),
        CompositionMethod::TRIPLE_JUMP,
    )
    .run(periapsis(E))
    .steps(STEPS)
    .collect()
    .unwrap_err();
    assert_eq!(out_of_domain(&composed.source).0, FIRST_NEGATIVE);
    assert_eq!(composed.trajectory.states.len(), FIRST_NEGATIVE + 1);

    // A streamed run stops there too, its summary at the last state inside the domain.
    let streamed = ReducedIntegrator::plus(sys, options)
        .run(periapsis(E))
        .steps(STEPS)
        .stream()
        .unwrap_err();
    assert_eq!(out_of_domain(&streamed.source).0, FIRST_NEGATIVE);
    assert_eq!(streamed.trajectory.step_count, FIRST_NEGATIVE);
    assert_eq!(streamed.trajectory.last, reference.states[FIRST_NEGATIVE]);
}

/// Steps taken one by one with `Stepper::step_in` are checked as a run's are.
#[test]
fn a_step_taken_by_hand_is_checked_too() {
    let integ = ReducedIntegrator::plus(Kepler { h: COARSE, k: 1.0 }, NewtonOptions::default());
    let mut workspace = integ.workspace();
    let mut state = periapsis(E);
    let mut k = 0;
    let error = loop {
        match integ.step_in(&mut workspace, k, &state) {
            Ok((next, _)) => state = next,
            Err(e) => break e,
        }
        k += 1;
        assert!(k < STEPS, "no step left the domain");
    };
    assert_eq!(out_of_domain(&error).0, FIRST_NEGATIVE);
    assert!(state.x[0] > 0.0);
}

/// At a step that resolves the periapsis passage the same runs go on, one orbit and more.
#[test]
fn a_fine_step_runs_on() {
    let sys = Kepler { h: FINE, k: 1.0 };
    let options = NewtonOptions::default();
    let steps = (1.2 * std::f64::consts::TAU / FINE) as usize;
    let plus = ReducedIntegrator::plus(sys, options)
        .run(periapsis(E))
        .steps(steps)
        .collect()
        .unwrap();
    assert_eq!(plus.states.len(), steps + 1);
    let minimum = plus
        .states
        .iter()
        .map(|s| s.x[0])
        .fold(f64::INFINITY, f64::min);
    assert!(minimum > 0.09 && minimum <= 0.1, "{minimum}");
    ReducedIntegrator::minus(sys, options)
        .run(periapsis(E))
        .steps(steps)
        .stream()
        .unwrap();
    UnreducedIntegrator::new(sys, options)
        .run(unreduced_periapsis(E))
        .steps(steps)
        .stream()
        .unwrap();
    Composition::new(
        ReducedIntegrator::plus(sys, options),
        CompositionMethod::TRIPLE_JUMP,
    )
    .run(periapsis(E))
    .steps(steps)
    .stream()
    .unwrap();
}

/// A run from outside the domain takes no step: the initial state is refused, also for a
/// system with adaptive steps (before its monitor, which `r < 0` would make undefined).
#[test]
fn an_initial_state_outside_the_domain_is_refused() {
    let sys = Kepler { h: FINE, k: 1.0 };
    let mut outside = periapsis(E);
    outside.x[0] = -0.1;
    let e = ReducedIntegrator::plus(sys, NewtonOptions::default())
        .run(outside)
        .steps(10)
        .collect()
        .unwrap_err();
    assert!(
        matches!(&e.source, StepError::OutOfDomain { initial: true, coordinate, value, .. }
            if coordinate == "r" && *value == -0.1),
        "{:?}",
        e.source
    );
    assert!(e
        .source
        .to_string()
        .contains("the initial state has r = -0.1"));
    assert_eq!(e.trajectory.states.len(), 1);

    let adaptive_sys = KeplerAdaptive { h: 0.05, k: 1.0 };
    let mut start = adaptive_sys
        .reduced_state([0.1, 0.0, 0.0], [0.0, 40.0, 1.0])
        .unwrap();
    let run = |s: ReducedState<1, 2>| {
        ReducedIntegrator::plus(adaptive_sys, NewtonOptions::default())
            .run(s)
            .steps(10)
            .collect()
    };
    assert!(run(start).is_ok());
    start.g[1] = -1.0;
    let e = run(start).unwrap_err();
    assert!(
        matches!(&e.source, StepError::OutOfDomain { initial: true, coordinate, .. } if coordinate == "t"),
        "{:?}",
        e.source
    );
    start.g[1] = 0.0;
    start.x[0] = -0.1;
    let e = run(start).unwrap_err();
    assert!(
        matches!(&e.source, StepError::OutOfDomain { initial: true, coordinate, .. } if coordinate == "r"),
        "{:?}",
        e.source
    );
}
