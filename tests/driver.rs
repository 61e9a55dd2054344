//! The one driver: every integrator — reduced, unreduced, composed, atlas — gets `run`,
//! `integrate`, ensembles and a stop condition from the same code, and a run's workspace travels
//! through every stage of a composition, so that after the first factorization no step
//! allocates.

#[path = "common/child.rs"]
mod child;

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicUsize, Ordering};

use dirac::paper::atlas::PAPER;
use dirac::paper::DoubleSphericalPendulum;
use dirac::prelude::*;
use dirac::runtime::driver::parameters;
use dirac::systems::kepler::Kepler;

#[path = "../examples/common/toda.rs"]
mod toda;

/// Counts the allocations of the current thread (the test harness runs tests on several
/// threads; a global count would see the others').
struct Counting;

thread_local! {
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

// SAFETY: forwards to the system allocator; the counter is a const-initialized thread-local
// `Cell`, which neither allocates nor can be accessed re-entrantly from another thread.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let _ = ALLOCATIONS.try_with(|c| c.set(c.get() + 1));
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let _ = ALLOCATIONS.try_with(|c| c.set(c.get() + 1));
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn allocations() -> usize {
    ALLOCATIONS.with(Cell::get)
}

/// The 200-particle Toda lattice (sparse backend) composed by the triple jump, through `run`:
/// after the first macro step no step allocates (each stage keeps its workspace: symbolic
/// factorization, scratch, factors), and chord iterations reuse each stage's factors, so far
/// fewer Jacobians are factored than stage steps are taken. Before the driver, every stage of
/// every step built a fresh sparse workspace (147 allocations per macro step).
#[test]
fn a_composed_sparse_run_allocates_nothing_after_its_first_step() {
    let sys = toda::Toda {
        h: 0.05,
        m: 1.0,
        d: 1.0,
    };
    let start = toda::initial(&sys, 0.1, 0.3, 0.05);
    let composed = Composition::new(
        ReducedIntegrator::plus(sys, NewtonOptions::default()),
        CompositionMethod::TRIPLE_JUMP,
    );
    let steps = 40;
    let mut at_state = vec![0usize; steps + 1];
    let summary = composed
        .run(start)
        .steps(steps)
        .observe(|k, _, _, _| at_state[k] = allocations())
        .stream()
        .expect("the lattice steps");
    assert_eq!(summary.step_count, steps);
    let per_step: Vec<usize> = at_state.windows(2).map(|w| w[1] - w[0]).collect();
    // The counter counts: the first step builds the workspaces (sparse symbolic analyses).
    assert!(
        per_step[0] > 0,
        "the first step's allocations were not counted"
    );
    assert!(
        per_step[1..].iter().all(|&a| a == 0),
        "allocations per macro step after the first: {:?}",
        &per_step[1..]
    );
    let stage_steps = 3 * steps;
    assert!(
        summary.factorizations * 10 <= stage_steps,
        "{} Jacobians factored in {stage_steps} stage steps",
        summary.factorizations
    );
    // μ is exact through every stage of every step.
    assert_eq!(summary.last.mu, start.mu);
}

/// What a stepper's runs must agree on: `run` observes what `integrate` keeps, a stop condition
/// ends both after the same state, and the ensemble members are the sequential runs bit for bit.
fn the_driver_is_one<I>(integrator: &I, starts: &[I::State], steps: usize)
where
    I: Drive + Sync,
    I::State: PartialEq,
    I::Trajectory: Send + PartialEq,
{
    let first = &starts[0];
    let traj = integrator
        .run(first.clone())
        .steps(steps)
        .collect()
        .expect("integrates");
    let mut observed = Vec::new();
    let summary = integrator
        .run(first.clone())
        .steps(steps)
        .observe(|k, _, state, record| {
            assert_eq!(record.is_none(), k == 0);
            observed.push(state.clone());
        })
        .stream()
        .expect("runs");
    assert_eq!(summary.step_count, steps);
    assert!(!summary.stopped);
    assert_eq!(observed.len(), steps + 1);
    assert_eq!(summary.last, observed[steps]);

    // Stop after the third state: the same prefix, flagged.
    let stopped = integrator
        .run(first.clone())
        .steps(steps)
        .stop(|k, _, _| k == 3)
        .observe(|_, _, _, _| {})
        .stream()
        .expect("runs");
    assert!(stopped.stopped);
    assert_eq!(stopped.step_count, 3);
    assert_eq!(stopped.last, observed[3]);
    let short = integrator
        .run(first.clone())
        .steps(steps)
        .stop(|k, _, _| k == 3)
        .collect()
        .expect("integrates");
    assert_eq!(short.completed_steps(), 3);
    let prefix = integrator
        .run(first.clone())
        .steps(3)
        .collect()
        .expect("integrates");
    assert_eq!(short, prefix);
    // The largest cap with a stop condition: the trajectory grows as the run proceeds.
    let capped = integrator
        .run(first.clone())
        .steps(usize::MAX)
        .stop(|k, _, _| k == 3)
        .collect()
        .expect("integrates");
    assert_eq!(capped, prefix);

    // An end time of two and a half steps: three steps, the last one shortened to land on it.
    let h = integrator.time_step();
    let mut times = Vec::new();
    let to_end = integrator
        .run(first.clone())
        .end_time(2.5 * h)
        .observe(|k, t, _, _| times.push((k, t)))
        .stream()
        .expect("runs");
    assert_eq!((to_end.step_count, to_end.t), (3, 2.5 * h));
    assert_eq!(times[..3], [(0, 0.0), (1, h), (2, 2.0 * h)]);
    assert_eq!(times[3], (3, 2.5 * h));
    assert!(to_end.last != observed[3], "the last step is a half step");

    // The output stride: every 4th state and the last.
    let mut seen = Vec::new();
    integrator
        .run(first.clone())
        .steps(steps)
        .every(4)
        .observe(|k, _, _, _| seen.push(k))
        .stream()
        .expect("runs");
    let mut expected: Vec<usize> = (0..=steps).step_by(4).collect();
    if !steps.is_multiple_of(4) {
        expected.push(steps);
    }
    assert_eq!(seen, expected);

    // A schedule at the system's own step is the fixed-step run bit for bit; a schedule of
    // another size is another run.
    let mut scheduled = Vec::new();
    integrator
        .run(first.clone())
        .steps(steps)
        .schedule(move |_, _, _| h)
        .observe(|_, _, s, _| scheduled.push(s.clone()))
        .stream()
        .expect("runs");
    assert_eq!(scheduled, observed);
    let halved = integrator
        .run(first.clone())
        .end_time(2.0 * h)
        .schedule(move |_, _, _| 0.5 * h)
        .stream()
        .expect("runs");
    assert_eq!((halved.step_count, halved.t), (4, 2.0 * h));

    // Ensembles: members in input order, each the sequential run bit for bit.
    let members = integrator.ensemble(starts).steps(steps).collect();
    for (member, start) in members.iter().zip(starts) {
        let sequential = integrator
            .run(start.clone())
            .steps(steps)
            .collect()
            .expect("integrates");
        assert_eq!(member.as_ref().expect("member integrates"), &sequential);
    }
    assert_eq!(members[0].as_ref().ok(), Some(&traj));
    // On a pool of its own, to an end time: the same members.
    let on_two = integrator
        .ensemble(starts)
        .end_time(steps as f64 * h)
        .threads(2)
        .collect();
    for (a, b) in on_two.iter().zip(&members) {
        let (a, b) = (a.as_ref().expect("member"), b.as_ref().expect("member"));
        assert_eq!(a.completed_steps(), b.completed_steps());
    }
    let observed: Vec<AtomicUsize> = starts.iter().map(|_| AtomicUsize::new(0)).collect();
    let streamed = integrator.ensemble(starts).steps(steps).stream(|i| {
        let count = &observed[i];
        move |_: usize, _: f64, _: &I::State, _: Option<&I::Record>| {
            count.fetch_add(1, Ordering::Relaxed);
        }
    });
    for (((_, result), start), count) in streamed.iter().zip(starts).zip(&observed) {
        let sequential = integrator
            .run(start.clone())
            .steps(steps)
            .observe(|_, _, _, _| {})
            .stream()
            .expect("runs");
        assert_eq!(result.as_ref().expect("member runs"), &sequential);
        assert_eq!(count.load(Ordering::Relaxed), steps + 1);
    }
}

#[test]
fn a_composition_gets_run_ensembles_and_a_stop_condition_from_the_driver() {
    let sys = Kepler::unit(0.05);
    let base = ReducedIntegrator::plus(sys, NewtonOptions::default());
    let composed = Composition::new(base, CompositionMethod::TRIPLE_JUMP);
    let starts: Vec<_> = [0.3, 0.5, 0.7]
        .iter()
        .map(|&e| sys.periapsis_state(1.0, e))
        .collect();
    the_driver_is_one(&composed, &starts, 30);
    // The unreduced composition too.
    let unreduced = Composition::new(
        UnreducedIntegrator::new(sys, NewtonOptions::default()),
        CompositionMethod::TRIPLE_JUMP,
    );
    let canonical: Vec<_> = starts.iter().map(|s| sys.untrivialize(s)).collect();
    the_driver_is_one(&unreduced, &canonical, 30);
}

#[test]
fn the_atlas_gets_run_ensembles_and_a_stop_condition_from_the_driver() {
    let sys = DoubleSphericalPendulum::paper();
    let atlas = sys.atlas(NewtonOptions::default());
    let initial = DoubleSphericalPendulum::paper_initial_state();
    let mut other = initial;
    other.w[0] += 0.01;
    the_driver_is_one(&atlas, &[(PAPER, initial), (PAPER, other)], 25);
}

#[test]
fn the_plain_integrators_get_the_same_driver() {
    let sys = DoubleSphericalPendulum::paper();
    let initial = DoubleSphericalPendulum::paper_initial_state();
    let mut other = initial;
    other.w[1] -= 0.02;
    let reduced = ReducedIntegrator::plus(sys, NewtonOptions::default());
    the_driver_is_one(&reduced, &[initial, other], 25);
    let minus = ReducedIntegrator::minus(sys, NewtonOptions::default());
    the_driver_is_one(&minus, &[initial, other], 25);
    let unreduced = UnreducedIntegrator::new(sys, NewtonOptions::default());
    the_driver_is_one(
        &unreduced,
        &[sys.untrivialize(&initial), sys.untrivialize(&other)],
        25,
    );
}

/// An ensemble over parameter sets is an ensemble of integrators: each member is the sequential
/// run of its own system, bit for bit, in input order; a member with a bad parameter fails alone
/// with its typed error.
#[test]
fn an_ensemble_over_parameter_sets() {
    let masses = [20.0, 25.0, f64::NAN, 30.0];
    let member = |&m: &f64| {
        let sys = DoubleSphericalPendulum {
            m1: m,
            ..DoubleSphericalPendulum::paper()
        };
        (
            ReducedIntegrator::plus(sys, NewtonOptions::default()),
            DoubleSphericalPendulum::paper_initial_state(),
        )
    };
    let results = parameters(&masses, member).steps(20).collect();
    for (m, result) in masses.iter().zip(&results) {
        let (integ, start) = member(m);
        match integ.run(start).steps(20).collect() {
            Ok(t) => assert_eq!(result.as_ref().ok(), Some(&t)),
            Err(e) => {
                let failed = result.as_ref().expect_err("the same member fails");
                assert_eq!(failed.source, e.source);
                assert!(m.is_nan());
            }
        }
    }
    assert_eq!(results.iter().filter(|r| r.is_err()).count(), 1);
}

#[path = "../examples/common/toda_n.rs"]
mod toda_n;

/// An element-wise system sized at run time (heap-backed states, the run-time pattern) through
/// `run`: no step without a factorization allocates, on the sparse LU and on conjugate
/// gradients (serial assembly: the counter is per thread).
#[test]
fn an_element_wise_run_allocates_nothing_per_step() {
    use dirac::runtime::element::{ElementIntegrator, Parallel, StepSolver};
    for linear in [StepSolver::Direct, StepSolver::Iterative] {
        let sys = toda_n::TodaN {
            m: 1.0,
            d: 0.0,
            h: 0.05,
            n: 500,
        };
        let integ = ElementIntegrator::new(sys, NewtonOptions::default())
            .with_parallel(Parallel::Never)
            .with_solver(linear);
        let start = toda_n::initial(&sys, 0.1, 0.3, 0.05);
        let mut before = allocations();
        let at_start = before;
        let (mut counted, mut allocating) = (0, Vec::new());
        integ
            .run(start)
            .steps(300)
            .observe(|k, _, _, record| {
                let now = allocations();
                if let Some(stats) = record {
                    if k > 1 && stats.factorizations == 0 {
                        counted += 1;
                        if now != before {
                            allocating.push((k, now - before));
                        }
                    }
                }
                before = allocations();
            })
            .stream()
            .expect("runs");
        // The counter counts: the run's workspace (pattern, solver) was allocated.
        assert!(
            allocations() > at_start + 10,
            "{linear:?}: the counter saw no allocation"
        );
        assert!(
            counted > 250,
            "{linear:?}: only {counted} steps without a factorization"
        );
        assert!(
            allocating.is_empty(),
            "{linear:?}: steps that allocated: {allocating:?}"
        );
    }
}

/// The constrained integrators (reduced and unreduced) and an element-wise system through the
/// same configured run.
#[test]
fn constrained_and_element_wise_integrators_get_the_same_driver() {
    use dirac::runtime::element::ElementIntegrator;
    let sys = ConstrainedPendulum {
        h: 0.02,
        m: 1.0,
        l: 1.3,
    };
    let tight = NewtonOptions {
        abs_tol: 1e-13,
        rel_tol: 1e-14,
        ..NewtonOptions::default()
    };
    let start = |theta: f64| {
        let (x, y) = (1.3 * theta.sin(), -1.3 * theta.cos());
        UnreducedState::new([x, y], [1.3 * 0.2 * theta.cos(), 1.3 * 0.2 * theta.sin()])
    };
    let unreduced = ConstrainedIntegrator::new(sys, tight);
    the_driver_is_one(&unreduced, &[start(0.3), start(0.5)], 17);
    let bead = ConstrainedBead {
        h: 0.02,
        m: 1.0,
        r: 1.0,
    };
    let reduced = ReducedConstrainedIntegrator::plus(bead, tight);
    let s = |phase: f64| {
        let c = UnreducedState::new(
            [phase.cos(), phase.sin(), 0.0],
            [-0.7 * phase.sin(), 0.7 * phase.cos(), 0.4],
        );
        bead.trivialize(&c)
    };
    the_driver_is_one(&reduced, &[s(0.1), s(0.4)], 17);
    let lattice = toda_n::TodaN {
        m: 1.0,
        d: 0.0,
        h: 0.05,
        n: 40,
    };
    let element = ElementIntegrator::new(lattice, NewtonOptions::default());
    the_driver_is_one(
        &element,
        &[
            toda_n::initial(&lattice, 0.1, 0.3, 0.05),
            toda_n::initial(&lattice, 0.2, 0.1, 0.0),
        ],
        17,
    );
}

/// A planar pendulum in Cartesian coordinates on its circle (holonomic constraint).
#[reduced_lagrangian(shape(x, y), group(), rule = midpoint,
    constraints = |q| [q.x * q.x + q.y * q.y - l * l])]
fn constrained_pendulum(q: Config, v: Velocity, m: f64, l: f64) -> f64 {
    0.5 * m * (v.x * v.x + v.y * v.y) - 9.81 * m * q.y
}

/// A bead on a vertical cylinder of radius `r`, free to slide along and around it: the
/// translation along the axis is a symmetry.
#[reduced_lagrangian(shape(x, y), group(z), rule = midpoint,
    constraints = |q| [q.x * q.x + q.y * q.y - r * r])]
fn constrained_bead(q: Config, v: Velocity, m: f64, r: f64) -> f64 {
    0.5 * m * (v.x * v.x + v.y * v.y + v.z * v.z) - 0.5 * (q.x - 0.3) * (q.x - 0.3)
}

/// `integrate_until` with a cap of 10¹¹ steps (far more states than memory holds) and a stop
/// condition after three: every integrator's trajectory grows as the run proceeds rather than
/// reserving room for every step before the first one (an allocation that fails and aborts
/// the process).
#[test]
fn a_huge_step_cap_reserves_no_memory_up_front() {
    const CAP: usize = 100_000_000_000;
    if !child::in_child(
        "a_huge_step_cap_reserves_no_memory_up_front",
        None,
        "every trajectory grew",
    ) {
        return;
    }
    fn three<I: Drive>(integrator: &I, start: I::State) {
        let traj = integrator
            .run(start)
            .steps(CAP)
            .stop(|k, _, _| k == 3)
            .collect()
            .expect("integrates");
        assert_eq!(traj.completed_steps(), 3);
    }
    let kepler = Kepler::unit(0.05);
    let start = kepler.periapsis_state(1.0, 0.5);
    three(
        &ReducedIntegrator::plus(kepler, NewtonOptions::default()),
        start,
    );
    three(
        &UnreducedIntegrator::new(kepler, NewtonOptions::default()),
        kepler.untrivialize(&start),
    );
    three(
        &Composition::new(
            ReducedIntegrator::plus(kepler, NewtonOptions::default()),
            CompositionMethod::TRIPLE_JUMP,
        ),
        start,
    );
    let pendulum = DoubleSphericalPendulum::paper();
    three(
        &pendulum.atlas(NewtonOptions::default()),
        (PAPER, DoubleSphericalPendulum::paper_initial_state()),
    );
    let lattice = toda_n::TodaN {
        m: 1.0,
        d: 1.0,
        h: 0.05,
        n: 50,
    };
    three(
        &dirac::runtime::element::ElementIntegrator::new(lattice, NewtonOptions::default()),
        toda_n::initial(&lattice, 0.1, 0.3, 0.05),
    );
    println!("every trajectory grew");
}

/// A run of 10¹¹ steps that keeps every state (no stop condition, no end time) under a 4 GB
/// address-space limit (`ulimit -v`, in a child process so that an abort ends the child, not the
/// harness): no trajectory can hold 10¹¹ states, and every kind says so before the first step
/// with the typed `StepError::OutOfMemory`, where the run used to grow its vectors until the
/// allocator aborted the process.
#[cfg(target_os = "linux")]
#[test]
fn a_run_keeping_more_states_than_memory_holds_is_refused_before_the_first_step() {
    const NAME: &str =
        "a_run_keeping_more_states_than_memory_holds_is_refused_before_the_first_step";
    const STEPS: usize = 100_000_000_000;
    if !child::in_child(NAME, Some(4000000), "refused: 5 kinds") {
        return;
    }
    fn refused<I: Drive>(integrator: &I, start: I::State) {
        let err = integrator
            .run(start)
            .steps(STEPS)
            .collect()
            .expect_err("10^11 states do not fit in 4 GB");
        assert!(
            matches!(err.source, StepError::OutOfMemory { bytes, .. } if bytes >= STEPS as u128),
            "{:?}",
            err.source
        );
        println!("typed error: {}", err.source);
    }
    let kepler = Kepler::unit(0.05);
    let start = kepler.periapsis_state(1.0, 0.5);
    let plus = ReducedIntegrator::plus(kepler, NewtonOptions::default());
    refused(&plus, start);
    refused(
        &UnreducedIntegrator::new(kepler, NewtonOptions::default()),
        kepler.untrivialize(&start),
    );
    refused(
        &Composition::new(plus, CompositionMethod::TRIPLE_JUMP),
        start,
    );
    let pendulum = DoubleSphericalPendulum::paper();
    refused(
        &pendulum.atlas(NewtonOptions::default()),
        (PAPER, DoubleSphericalPendulum::paper_initial_state()),
    );
    let lattice = toda_n::TodaN {
        m: 1.0,
        d: 1.0,
        h: 0.05,
        n: 50,
    };
    refused(
        &dirac::runtime::element::ElementIntegrator::new(lattice, NewtonOptions::default()),
        toda_n::initial(&lattice, 0.1, 0.3, 0.05),
    );
    println!("refused: 5 kinds");
}

/// `Stepper::step_with` is public: a workspace of another composition, or a state in a chart the
/// atlas does not have, is a typed error, not an index out of bounds.
#[test]
fn a_foreign_workspace_or_chart_index_is_a_typed_error() {
    let kepler = Kepler::unit(0.05);
    let start = kepler.periapsis_state(1.0, 0.5);
    let base = ReducedIntegrator::plus(kepler, NewtonOptions::default());
    let triple = Composition::new(base.clone(), CompositionMethod::TRIPLE_JUMP);
    let single = Composition::new(base, CompositionMethod::BASE);
    let mut foreign = single.workspace();
    let got = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        format!(
            "{:?}",
            triple.step_with(&mut foreign, StepAt::new(0, triple.time_step()), &start)
        )
    }))
    .unwrap_or_else(|_| "a panic".to_string());
    assert!(got.starts_with("Err(InvalidSize"), "{got}");
    let atlas = DoubleSphericalPendulum::paper().atlas(NewtonOptions::default());
    let state = (9, DoubleSphericalPendulum::paper_initial_state());
    let got = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        format!("{:?}", atlas.step(0, &state))
    }))
    .unwrap_or_else(|_| "a panic".to_string());
    assert!(got.starts_with("Err(InvalidAtlas"), "{got}");
}

#[test]
fn integrators_on_rotation_groups_get_the_one_driver() {
    use dirac::systems::rotations::{RigidBody, RigidBodyConfig, RigidBodyMomentum};
    let sys = RigidBody {
        h: 0.02,
        j1: 1.0,
        j2: 2.0,
        j3: 3.0,
    };
    let starts: Vec<_> = [0.1, 0.5, 0.9]
        .iter()
        .map(|&a| {
            sys.state(
                &RigidBodyConfig {
                    r: dirac::lie::cayley(&Vector3::new(a, -0.2, 0.3)),
                },
                &RigidBodyMomentum {
                    r: Vector3::new(0.3, 1.0, -a),
                },
            )
        })
        .collect();
    let integ = LieIntegrator::new(sys, NewtonOptions::default());
    the_driver_is_one(&integ, &starts, 30);
    the_driver_is_one(
        &Composition::new(integ.clone(), CompositionMethod::TRIPLE_JUMP),
        &starts,
        30,
    );
    // An end time that is not a multiple of h is reached exactly, by a shortened last step.
    let traj = integ.run(starts[0]).end_time(0.55).collect().unwrap();
    assert_eq!(*traj.times.last().unwrap(), 0.55);
    assert_eq!(traj.step_count(), 28);
}
