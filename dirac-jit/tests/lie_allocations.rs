//! A system on rotation groups sized at run time allocates nothing per step, reduced or not: its vectors, the
//! step's buffers and the factorization's workspace are built once per run, in the run's
//! workspace, and the driver steps into the memory of the state before (`Stepper::step_into`).
//! Its own test binary: the global allocator here counts the allocations of the current thread.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use dirac::prelude::*;
use dirac::runtime::lie::{cayley, DynLieState, LieIntegratorOf, LieModel, ReducedLieIntegratorOf};
use dirac::runtime::nalgebra::{Dyn, Vector3};

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

const EIGHT_BODIES: &str = include_str!("texts/eight_bodies.rs");

/// The allocations of a streamed run of `steps` steps of `integ` (the (+) or the (−) step)
/// from `start`, and those of each step after the first.
fn run_allocations<L: LieModel<Dyn, Dyn>>(
    integ: &LieIntegratorOf<L, Dyn, Dyn>,
    start: &DynLieState,
    steps: usize,
) -> (usize, Vec<usize>) {
    let mut at_state = vec![0usize; steps + 1];
    let before = allocations();
    let summary = integ
        .run(start.clone())
        .steps(steps)
        .observe(|k, _, _, _| at_state[k] = allocations())
        .stream()
        .expect("the bodies step");
    let total = allocations() - before;
    assert_eq!(summary.step_count, steps);
    let per_step = at_state.windows(2).map(|w| w[1] - w[0]).collect();
    (total, per_step)
}

/// Eight bodies (72 entries of a point, 24 chart coordinates, the sparse factorization): after
/// a run's first step, no step allocates, so a run of 200 steps allocates what a run of 20 does.
#[test]
fn a_run_time_sized_step_allocates_nothing() {
    let code = dirac_jit::compile_lie(&text()).expect("the eight bodies compile");
    let sys = code.instantiate_dyn(&[0.01, 3.0]).unwrap();
    let rows: Vec<Vec<f64>> = (1..=8)
        .map(|i| {
            cayley(&Vector3::new(0.1 * f64::from(i), -0.2, 0.05 * f64::from(i)))
                .transpose()
                .as_slice()
                .to_vec()
        })
        .collect();
    let momenta: Vec<[f64; 3]> = (1..=8)
        .map(|i| [0.3, 1.0 - 0.1 * f64::from(i), -0.2 * f64::from(i)])
        .collect();
    let q: Vec<&[f64]> = rows.iter().map(Vec::as_slice).collect();
    let p: Vec<&[f64]> = momenta.iter().map(|m| &m[..]).collect();
    let s0 = sys.state(&q, &p).unwrap();
    for integ in [
        LieIntegratorOf::new(sys.clone(), NewtonOptions::default()),
        LieIntegratorOf::minus(sys.clone(), NewtonOptions::default()),
    ] {
        // A first run fills this thread's pools (the Jacobian's buffer returns to one).
        run_allocations(&integ, &s0, 5);
        let (short, _) = run_allocations(&integ, &s0, 20);
        let (long, per_step) = run_allocations(&integ, &s0, 200);
        // The counter counts: the run builds its workspace.
        assert!(short > 0, "the run's allocations were not counted");
        assert!(
            per_step[1..].iter().all(|&a| a == 0),
            "allocations per step after the first: {:?}",
            &per_step[1..]
        );
        assert_eq!(
            long, short,
            "a run of 200 steps allocates more than one of 20"
        );
    }
}

/// The text of the eight bodies' function, from its attribute on.
fn text() -> String {
    let at = EIGHT_BODIES
        .find("#[reduced_lagrangian")
        .expect("the file declares the system");
    EIGHT_BODIES[at..].to_owned()
}

/// Three links hanging from a pivot, each a direction, under gravity, reduced by the rotations
/// about the vertical (beyond the fixed-size instances: three directions).
const CHAIN: &str = "
#[reduced_lagrangian(direction(n1, n2, n3), rule = trapezoid, symmetry(n1, n2, n3, axis = z))]
fn chain(q: Config, v: Velocity, g: f64) -> f64 {
    let v2 = v.n1 + v.n2;
    let v3 = v.n1 + v.n2 + v.n3;
    let height = 3.0 * q.n1.z + 2.0 * q.n2.z + q.n3.z;
    0.5 * (v.n1.dot(&v.n1) + v2.dot(&v2) + v3.dot(&v3)) - g * height
}";

/// The reduced step sized at run time (the symmetry's part of the momentum set before and after
/// each step, in the workspace's buffers) allocates nothing per step either.
#[test]
fn a_run_time_sized_reduced_step_allocates_nothing() {
    let code = dirac_jit::compile_lie(CHAIN).expect("the chain compiles");
    let values = code.values_by_name(&[("g", 9.81), ("h", 0.01)]).unwrap();
    let sys = code.instantiate_dyn(&values).unwrap();
    let links: Vec<[f64; 3]> = [0.5f64, 0.7, 0.9]
        .iter()
        .map(|a| [a.sin(), 0.0, -a.cos()])
        .collect();
    let momenta = [[0.0, 0.2, 0.0], [0.0, 0.4, 0.0], [0.0, 0.6, 0.0]];
    let q: Vec<&[f64]> = links.iter().map(|n| &n[..]).collect();
    let p: Vec<&[f64]> = momenta.iter().map(|m| &m[..]).collect();
    let s0 = sys.state(&q, &p).unwrap();
    let integ = ReducedLieIntegratorOf::new(
        code.instantiate_dyn_reduced(&values).unwrap(),
        NewtonOptions::default(),
    );
    let s0 = integ.reduce(&s0);
    let run = |steps: usize| {
        let mut at_state = vec![0usize; steps + 1];
        let before = allocations();
        let summary = integ
            .run(s0.clone())
            .steps(steps)
            .observe(|k, _, _, _| at_state[k] = allocations())
            .stream()
            .expect("the chain swings");
        assert_eq!(summary.step_count, steps);
        assert_eq!(summary.last.mu, s0.mu, "μ, copied from step to step");
        let per_step: Vec<usize> = at_state.windows(2).map(|w| w[1] - w[0]).collect();
        (allocations() - before, per_step)
    };
    run(5);
    let (short, _) = run(20);
    let (long, per_step) = run(200);
    assert!(
        per_step[1..].iter().all(|&a| a == 0),
        "allocations per step after the first: {:?}",
        &per_step[1..]
    );
    assert_eq!(
        long, short,
        "a run of 200 steps allocates more than one of 20"
    );
}
