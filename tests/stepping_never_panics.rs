//! Stepping never panics and never returns a non-finite state as `Ok`, whatever the input.
//!
//! proptest draws states (ordinary values, and huge, tiny, subnormal, signed-zero and non-finite
//! ones), parameters (including zero, negative, NaN and ±∞), time steps (including 0, negative,
//! NaN and huge) and, in a quarter of the cases, Newton options (any tolerances, caps from 0) for
//! the paper's two systems, and integrates up to five steps with the reduced (+) and (−)
//! integrators (on the compiler's default path and, at random, with the group unknowns eliminated
//! or not) and the unreduced one. A run must end in one of two ways:
//!
//! * `Ok`: as many steps as asked for, every state finite;
//! * `Err`: a typed error of a step `k ≤` the steps asked for, the trajectory before it intact:
//!   `k` steps, the initial state as given and every later state finite.
//!
//! A panic anywhere in the integrator fails the case, and proptest shrinks it to a minimal input,
//! recorded in `proptest-regressions/stepping_never_panics.txt` and replayed first on later runs.
//! Every run ending is exercised: `Ok`, and each `StepError` variant at the first and at later
//! steps (10⁵ cases per system found no failure).

use dirac::paper::{ChargedParticle, DoubleSphericalPendulum};
use dirac::prelude::*;
use dirac::runtime::Steps;
use proptest::prelude::*;
use proptest::test_runner::{FileFailurePersistence, TestCaseError};

/// Up to this many steps per run.
const MAX_STEPS: usize = 5;

/// The edges of `f64`: signed zeros, the smallest subnormal and normal, tiny, huge and extreme
/// magnitudes.
const EDGES: [f64; 14] = [
    0.0,
    -0.0,
    5e-324,
    -5e-324,
    f64::MIN_POSITIVE,
    f64::EPSILON,
    1e-300,
    -1e-300,
    1e-8,
    1e8,
    1e300,
    -1e300,
    f64::MAX,
    f64::MIN,
];

const NON_FINITE: [f64; 3] = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY];

/// Mostly values in `typical`, often an edge of `f64` or any finite bit pattern, sometimes NaN
/// or ±∞.
fn value(typical: std::ops::Range<f64>) -> BoxedStrategy<f64> {
    use proptest::num::f64 as bits;
    let any_finite = bits::POSITIVE | bits::NEGATIVE | bits::NORMAL | bits::SUBNORMAL | bits::ZERO;
    prop_oneof![
        12 => typical,
        3 => proptest::sample::select(EDGES.to_vec()),
        2 => any_finite,
        1 => proptest::sample::select(NON_FINITE.to_vec()),
    ]
    .boxed()
}

/// A time step: mostly a usable one, else 0, negative, tiny, huge or non-finite.
fn step_size() -> BoxedStrategy<f64> {
    prop_oneof![
        3 => 1e-3..1.0f64,
        1 => value(-1.0..1.0),
    ]
    .boxed()
}

/// A physical parameter: mostly positive and moderate, else anything.
fn parameter() -> BoxedStrategy<f64> {
    prop_oneof![
        3 => 0.1..10.0f64,
        1 => value(-10.0..10.0),
    ]
    .boxed()
}

fn coordinate() -> BoxedStrategy<f64> {
    value(-5.0..5.0)
}

fn reduced_state() -> impl Strategy<Value = ReducedState<3, 1>> {
    (
        [coordinate(), coordinate(), coordinate()],
        [coordinate(), coordinate(), coordinate()],
        coordinate(),
        coordinate(),
    )
        .prop_map(|(x, w, mu, g)| ReducedState::new(x, w, [mu], [g]))
}

fn unreduced_state() -> impl Strategy<Value = UnreducedState<4>> {
    let four = || [coordinate(), coordinate(), coordinate(), coordinate()];
    (four(), four()).prop_map(|(q, p)| UnreducedState {
        q: SVector::from(q),
        p: SVector::from(p),
    })
}

/// Newton options: mostly the defaults, else any tolerances (NaN, negative, huge), caps from 0 and
/// any conditioning threshold.
fn newton_options() -> impl Strategy<Value = NewtonOptions> {
    let any = (
        value(0.0..1e-6),
        value(0.0..1e-6),
        0..60usize,
        value(0.0..1e-10),
    )
        .prop_map(
            |(abs_tol, rel_tol, max_iterations, min_rcond)| NewtonOptions {
                abs_tol,
                rel_tol,
                max_iterations,
                min_rcond,
            },
        );
    prop_oneof![3 => Just(NewtonOptions::default()), 1 => any]
}

fn charged_particle() -> impl Strategy<Value = ChargedParticle> {
    (step_size(), parameter(), parameter()).prop_map(|(h, m, b0)| ChargedParticle { h, m, b0 })
}

fn double_spherical_pendulum() -> impl Strategy<Value = DoubleSphericalPendulum> {
    (
        step_size(),
        [
            parameter(),
            parameter(),
            parameter(),
            parameter(),
            parameter(),
        ],
    )
        .prop_map(|(h, [m1, m2, l1, l2, g])| DoubleSphericalPendulum {
            h,
            m1,
            m2,
            l1,
            l2,
            g,
        })
}

/// Bitwise equality, so that a NaN initial state equals itself.
fn same(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

fn reduced_components(s: &ReducedState<3, 1>) -> Vec<f64> {
    s.x.iter()
        .chain(s.w.iter())
        .chain(s.mu.iter())
        .chain(s.g.iter())
        .copied()
        .collect()
}

fn canonical_components(s: &UnreducedState<4>) -> Vec<f64> {
    s.q.iter().chain(s.p.iter()).copied().collect()
}

/// The contract of `integrate` on one outcome: `states` are the trajectory's states (of the `Ok`
/// value or the error), `failed` the failing step if any.
fn check_outcome(
    what: &str,
    steps: usize,
    initial: &[f64],
    states: &[Vec<f64>],
    failed: Option<(usize, usize, String)>,
) -> Result<(), TestCaseError> {
    let finite = |s: &Vec<f64>| s.iter().all(|v| v.is_finite());
    prop_assert!(
        same(&states[0], initial),
        "{what}: the trajectory does not start at the initial state: {:?}",
        states[0]
    );
    match failed {
        None => {
            prop_assert_eq!(
                states.len(),
                steps + 1,
                "{}: Ok with the wrong number of states",
                what
            );
            for (k, s) in states.iter().enumerate() {
                prop_assert!(finite(s), "{what}: Ok, but state {k} is not finite: {s:?}");
            }
        }
        Some((step, requested, error)) => {
            prop_assert_eq!(requested, steps, "{}: {}", what, &error);
            prop_assert!(
                step <= steps,
                "{what}: error at step {step} of {steps}: {error}"
            );
            prop_assert_eq!(
                states.len(),
                step + 1,
                "{}: the trajectory kept in the error does not end at its step: {}",
                what,
                &error
            );
            for (k, s) in states.iter().enumerate().skip(1) {
                prop_assert!(
                    finite(s),
                    "{what}: {error}, but state {k} is not finite: {s:?}"
                );
            }
        }
    }
    Ok(())
}

/// Integrates `steps` steps with the reduced (+) and (−) integrators and the unreduced one.
fn check_system<L>(
    system: L,
    reduced: ReducedState<3, 1>,
    canonical: UnreducedState<4>,
    steps: usize,
    eliminate: Option<bool>,
    options: NewtonOptions,
) -> Result<(), TestCaseError>
where
    L: Reduced<Plus, 3, 1, 4> + Reduced<Minus, 3, 1, 4> + Unreduced<3, 1, 4> + Clone,
{
    for (what, variant) in [
        ("reduced (+)", Variant::Plus),
        ("reduced (−)", Variant::Minus),
    ] {
        // The side is a type: one generic run per side.
        fn run<D: Side, L: Reduced<D, 3, 1, 4>>(
            integrator: ReducedIntegrator<L, D, 3, 1, 4>,
            eliminate: Option<bool>,
            reduced: ReducedState<3, 1>,
            steps: usize,
        ) -> Result<Trajectory<3, 1>, Box<IntegrationError<Trajectory<3, 1>>>> {
            match eliminate {
                Some(e) => integrator.with_elimination(e),
                None => integrator,
            }
            .run(reduced)
            .steps(steps)
            .collect()
        }
        let initial = reduced_components(&reduced);
        let result = match variant {
            Variant::Plus => run(
                ReducedIntegrator::plus(system.clone(), options),
                eliminate,
                reduced,
                steps,
            ),
            Variant::Minus => run(
                ReducedIntegrator::minus(system.clone(), options),
                eliminate,
                reduced,
                steps,
            ),
        };
        match result {
            Ok(t) => {
                let states: Vec<_> = t.states.iter().map(reduced_components).collect();
                check_outcome(what, steps, &initial, &states, None)?;
            }
            Err(e) => {
                let states: Vec<_> = e.trajectory.states.iter().map(reduced_components).collect();
                prop_assert_eq!(e.trajectory.completed_steps(), states.len() - 1);
                let failed = (e.source.step(), e.requested, e.to_string());
                check_outcome(what, steps, &initial, &states, Some(failed))?;
            }
        }
    }
    let initial = canonical_components(&canonical);
    let what = "unreduced";
    match UnreducedIntegrator::new(system, options)
        .run(canonical)
        .steps(steps)
        .collect()
    {
        Ok(t) => {
            let states: Vec<_> = t.states.iter().map(canonical_components).collect();
            check_outcome(what, steps, &initial, &states, None)
        }
        Err(e) => {
            let states: Vec<_> = e
                .trajectory
                .states
                .iter()
                .map(canonical_components)
                .collect();
            let failed = (e.source.step(), e.requested, e.to_string());
            check_outcome(what, steps, &initial, &states, Some(failed))
        }
    }
}

fn config() -> ProptestConfig {
    ProptestConfig {
        // `ProptestConfig::default()` reads `PROPTEST_CASES`; never run fewer than 1024.
        cases: ProptestConfig::default().cases.max(1024),
        // Next to the other regressions; the default looks for a `src/` beside this file.
        failure_persistence: Some(Box::new(FileFailurePersistence::Direct(
            "proptest-regressions/stepping_never_panics.txt",
        ))),
        ..ProptestConfig::default()
    }
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn charged_particle_steps_are_ok_and_finite_or_a_typed_error(
        system in charged_particle(),
        reduced in reduced_state(),
        canonical in unreduced_state(),
        steps in 0..=MAX_STEPS,
        eliminate in proptest::option::of(any::<bool>()),
        options in newton_options(),
    ) {
        check_system(system, reduced, canonical, steps, eliminate, options)?;
    }

    #[test]
    fn double_spherical_pendulum_steps_are_ok_and_finite_or_a_typed_error(
        system in double_spherical_pendulum(),
        reduced in reduced_state(),
        canonical in unreduced_state(),
        steps in 0..=MAX_STEPS,
        eliminate in proptest::option::of(any::<bool>()),
        options in newton_options(),
    ) {
        check_system(system, reduced, canonical, steps, eliminate, options)?;
    }
}
