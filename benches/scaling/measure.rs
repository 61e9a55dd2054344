//! Measurement helpers shared by the scratch crates that `examples/scaling.rs` generates (copied
//! verbatim to `src/measure.rs` of each crate, next to `examples/common/stats.rs` as
//! `src/stats.rs` and `examples/common/cli.rs` as `src/cli.rs`). Each crate prints one line starting `scaling:`
//! with `key=value` fields; `examples/scaling.rs` parses it.

use std::hint::black_box;
use std::time::Instant;

use dirac::prelude::*;

/// Target wall time of one timed batch, in seconds.
pub const BATCH_SECONDS: f64 = 0.2;
/// Timed batches per quantity (the median is reported).
pub const BATCHES: usize = 7;

pub use crate::stats::median;

/// Peak resident memory of this process (`VmHWM`), in MiB; NaN where `/proc` is not available
/// (printed as such in the `scaling:` line).
pub fn peak_memory_mib() -> f64 {
    crate::stats::peak_memory_mib().unwrap_or(f64::NAN)
}

/// The operation count and Jacobian nonzeros of the reduced (+) stepper's residual with its
/// Jacobian, parsed from the emitted `GENERATED` text ("reduced (+) stepper: A operations for the
/// residual, B for the residual with its Jacobian (C nonzero entries), ...").
pub fn plus_rj_counts(generated: &str) -> Option<(u64, u64)> {
    let rest = &generated[generated.find("reduced (+) stepper:")?..];
    let at = rest.find(" for the residual with its Jacobian (")?;
    let ops = rest[..at].rsplit(|c: char| !c.is_ascii_digit()).next()?;
    let tail = &rest[at + " for the residual with its Jacobian (".len()..];
    let nnz = tail.split(|c: char| !c.is_ascii_digit()).next()?;
    Some((ops.parse().ok()?, nnz.parse().ok()?))
}

/// How many repetitions of `f` take about [`BATCH_SECONDS`] (at least `min`).
pub fn calibrate(min: usize, mut f: impl FnMut(usize)) -> usize {
    let mut count = min.max(1);
    loop {
        let t0 = Instant::now();
        f(count);
        let s = t0.elapsed().as_secs_f64();
        if s >= 0.02 || count >= 1 << 30 {
            return ((count as f64 * BATCH_SECONDS / s.max(1e-9)).ceil() as usize).max(min);
        }
        count *= 4;
    }
}

/// What dirac's reduced (+) stepper measured on one system.
pub struct Measured<const S: usize, const K: usize> {
    /// `(ops, nnz)` of the (+) residual with its Jacobian.
    pub counts: Option<(u64, u64)>,
    /// Median ns of one `residual_jacobian` evaluation.
    pub rj_ns: f64,
    /// Median ns per step of `run`.
    pub step_ns: f64,
    /// Steps per timed run.
    pub steps: usize,
    /// Mean Newton corrections per step.
    pub iterations: f64,
    /// A state from the run (after a few warm-up steps) where R+J was timed.
    pub state: ReducedState<S, K>,
}

/// Runs `warm` steps from `initial`, then returns the state reached and the solution `z` of its
/// next step (`(x_{k+1}, g_k^+)`).
pub fn state_from_run<L, const S: usize, const K: usize, const N: usize>(
    integ: &ReducedIntegrator<L, Plus, S, K, N>,
    initial: ReducedState<S, K>,
    warm: usize,
) -> (ReducedState<S, K>, SVector<f64, N>, ReducedState<S, K>)
where
    L: Reduced<Plus, S, K, N>,
{
    let state = match integ.run(initial).steps(warm).observe(|_, _, _, _| {}).stream() {
        Ok(s) => s.last,
        Err(e) => panic!("warm-up run failed: {e}"),
    };
    let mut z = SVector::<f64, N>::zeros();
    let next = match integ.run(state).steps(1).observe(|_, _, next, step| {
        if let Some(step) = step {
            z = dirac::runtime::system::join::<S, K, N>(&next.x, &step.group_unknown);
        }
    }).stream() {
        Ok(s) => s.last,
        Err(e) => panic!("step from the run's state failed: {e}"),
    };
    (state, z, next)
}

/// Times dirac on `sys` from `initial`: R+J at a state from the run, and whole runs of `steps`
/// steps; `between` is called after each timed run batch (to interleave another stepper's
/// batches over the same steps).
pub fn measure<L, const S: usize, const K: usize, const N: usize>(
    sys: L,
    generated: &str,
    initial: ReducedState<S, K>,
    mut between: impl FnMut(usize),
) -> Measured<S, K>
where
    L: Reduced<Plus, S, K, N> + Copy,
{
    let integ = ReducedIntegrator::plus(sys, NewtonOptions::default());
    let (state, z, _) = state_from_run(&integ, initial, 20);

    let rj = |count: usize| {
        for _ in 0..count {
            black_box(Reduced::<Plus, S, K, N>::residual_jacobian(
                black_box(&sys),
                black_box(&state.x),
                &state.w,
                &state.mu,
                black_box(&z),
            ));
        }
    };
    let evals = calibrate(1, rj);
    let mut rj_ns = Vec::with_capacity(BATCHES);
    for _ in 0..BATCHES {
        let t0 = Instant::now();
        rj(evals);
        rj_ns.push(t0.elapsed().as_nanos() as f64 / evals as f64);
    }

    let mut iterations = 0.0;
    let mut run = |steps: usize| match integ.run(black_box(initial)).steps(steps).observe(|_, _, _, _| {}).stream() {
        Ok(s) => iterations = s.mean_iterations(),
        Err(e) => panic!("run of {steps} steps failed: {e}"),
    };
    let steps = calibrate(10, &mut run);
    let mut step_ns = Vec::with_capacity(BATCHES);
    for _ in 0..BATCHES {
        let t0 = Instant::now();
        run(steps);
        step_ns.push(t0.elapsed().as_nanos() as f64 / steps as f64);
        between(steps);
    }
    Measured {
        counts: plus_rj_counts(generated),
        rj_ns: median(rj_ns),
        step_ns: median(step_ns),
        steps,
        iterations,
        state,
    }
}

/// Prints the machine-readable line (`extra` appended as given).
pub fn report<const S: usize, const K: usize>(
    system: &str,
    n: usize,
    unknowns: usize,
    m: &Measured<S, K>,
    extra: &str,
) {
    let (ops, nnz) = m.counts.map_or(("NA".into(), "NA".into()), |(a, b)| {
        (a.to_string(), b.to_string())
    });
    println!(
        "scaling: system={system} n={n} unknowns={unknowns} ops={ops} nnz={nnz} rj_ns={:.1} step_ns={:.1} steps={} iterations={:.3} mem_mib={:.1}{extra}",
        m.rj_ns,
        m.step_ns,
        m.steps,
        m.iterations,
        peak_memory_mib()
    );
}
