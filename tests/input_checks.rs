//! Starts that mean something else than what was given are refused before the first step: a
//! direction that is not a unit vector (compiled in as given as text: one rule), and an adaptive
//! start off its energy level set `p_t = −E`.

use dirac::prelude::*;
use dirac::systems::rotations::{DspOnSpheres, DspOnSpheresConfig};

/// Kepler's problem with adaptive steps, its step following `r^{3/2}`.
#[reduced_lagrangian(shape(r), group(theta, t), time(t), adapt = |q| q.r.powf(1.5), rule = midpoint)]
fn kepler(q: Config, v: Velocity, k: f64) -> f64 {
    0.5 * (v.r * v.r + q.r * q.r * v.theta * v.theta) + k / q.r
}

/// The double spherical pendulum on `S² × S²` from the paper's state with its first direction
/// scaled by `scale`.
fn scaled_start(sys: &DspOnSpheres, scale: f64) -> LieState<18, 4> {
    let paper = sys.paper_initial_state();
    let (config, momenta) = (sys.config(&paper), sys.momenta(&paper));
    let config = DspOnSpheresConfig {
        n1: config.n1 * scale,
        ..config
    };
    sys.state(&config, &momenta)
}

fn off_manifold(e: &StepError) -> &str {
    match e {
        StepError::OffManifold { reason } => reason,
        other => panic!("expected OffManifold, got {other:?}"),
    }
}

/// A direction of length 1.5 given to a compiled-in system's `state` is refused by the run (it
/// was normalized and run before), as the same input given as text is; within the tolerance
/// (`dirac::lie::UNIT_TOLERANCE`, the text's) it is normalized and runs.
#[test]
fn a_direction_that_is_not_a_unit_vector_is_refused() {
    let sys = DspOnSpheres::paper(0.01);
    let integ = LieIntegrator::new(sys, NewtonOptions::default());
    for scale in [1.5, 0.5, 1.0 + 1e-8, 0.0] {
        let e = integ
            .run(scaled_start(&sys, scale))
            .steps(10)
            .collect()
            .unwrap_err();
        let reason = off_manifold(&e.source);
        assert!(
            reason.contains("`n1` is not a unit vector") && reason.contains("tolerance 1e-9"),
            "{scale}: {reason}"
        );
        assert_eq!(e.trajectory.states.len(), 1, "{scale}: no step taken");
    }
    // The reduced integrator makes the same checks.
    let reduced = ReducedLieIntegrator::new(sys, NewtonOptions::default());
    let start = reduced.reduce(&scaled_start(&sys, 1.5));
    let e = reduced.run(start).steps(10).collect().unwrap_err();
    assert!(off_manifold(&e.source).contains("`n1`"));

    // Rounding-level lengths are what a unit vector computed in floating point has: accepted,
    // stored normalized.
    assert!((dirac::lie::UNIT_TOLERANCE - 1e-9).abs() < 1e-24);
    let start = scaled_start(&sys, 1.0 + 1e-12);
    assert!((sys.config(&start).n1.norm() - 1.0).abs() < 1e-15);
    let run = integ.run(start).steps(10).collect().unwrap();
    assert_eq!(run.states.len(), 11);
}

/// An adaptive start whose `p_t` is not `−E` is refused by every integrator (it integrated
/// another orbit before); the start `reduced_state` builds, and one off by round-off, run.
#[test]
fn an_adaptive_start_off_its_level_set_is_refused() {
    let sys = Kepler { h: 0.05, k: 1.0 };
    let (e, r0): (f64, f64) = (0.9, 0.1);
    let omega = (1.0 - e * e).sqrt() / (r0 * r0);
    let on = sys
        .reduced_state([r0, 0.0, 0.0], [0.0, omega, 1.0])
        .unwrap();
    let energy = -on.mu[1];
    assert!((energy + 0.5).abs() < 1e-12, "{energy}");
    let options = NewtonOptions::default();
    let plus = ReducedIntegrator::plus(sys, options);
    assert!(plus.run(on).steps(5).collect().is_ok());

    let mut near = on;
    near.mu[1] *= 1.0 + 1e-12;
    assert!(plus.run(near).steps(5).collect().is_ok());

    let mut off = on;
    off.mu[1] = 0.4; // p_t = 0.4: the level of E = −0.4, not the state's E = −0.5
    let check = |e: &StepError| {
        let reason = off_manifold(e);
        assert!(
            reason.contains("off its energy level set") && reason.contains("p_t = 0.4"),
            "{reason}"
        );
    };
    let error = plus.run(off).steps(5).collect().unwrap_err();
    check(&error.source);
    assert_eq!(error.trajectory.states.len(), 1);
    check(
        &ReducedIntegrator::minus(sys, options)
            .run(off)
            .steps(5)
            .stream()
            .unwrap_err()
            .source,
    );
    check(
        &UnreducedIntegrator::new(sys, options)
            .run(sys.untrivialize(&off))
            .steps(5)
            .collect()
            .unwrap_err()
            .source,
    );
    check(
        &Composition::new(plus.clone(), CompositionMethod::TRIPLE_JUMP)
            .run(off)
            .steps(5)
            .collect()
            .unwrap_err()
            .source,
    );
    // The relative tolerance: a start off by 1e-6 of the energy is refused too.
    let mut slightly = on;
    slightly.mu[1] *= 1.0 + 1e-6;
    assert!(plus.run(slightly).steps(5).collect().is_err());
}

/// A pendulum of unit length in Cartesian coordinates held by a rod, with adaptive steps.
#[reduced_lagrangian(shape(x, y), group(t), time(t), adapt = |q| 1.5 + q.y, rule = midpoint,
    constraints = |q| [q.x * q.x + q.y * q.y - 1.0])]
fn rod(q: Config, v: Velocity, g: f64) -> f64 {
    0.5 * (v.x * v.x + v.y * v.y) - g * q.y
}

/// The constrained integrators check the level set as the others do.
#[test]
fn a_constrained_adaptive_start_off_its_level_set_is_refused() {
    let sys = Rod { h: 0.01, g: 9.81 };
    let theta0: f64 = 1.2;
    let on = sys
        .reduced_state([theta0.sin(), -theta0.cos(), 0.0], [0.0, 0.0, 1.0])
        .unwrap();
    let integ = ReducedConstrainedIntegrator::plus(sys, NewtonOptions::default());
    assert!(integ.run(on).steps(5).collect().is_ok());
    let mut off = on;
    off.mu[0] += 0.5;
    let e = integ.run(off).steps(5).collect().unwrap_err();
    assert!(off_manifold(&e.source).contains("off its energy level set"));
    let unreduced = ConstrainedIntegrator::new(sys, NewtonOptions::default());
    let e = unreduced
        .run(sys.untrivialize(&off))
        .steps(5)
        .collect()
        .unwrap_err();
    assert!(off_manifold(&e.source).contains("off its energy level set"));
}
