//! A periodic Toda lattice of 200 particles, written in the particles' own positions with its
//! common translation declared, integrated by the reduced (+) midpoint rule in constant memory.
//!
//! ```sh
//! cargo run --release --example lattice -- [--steps 100000] [--ensemble 8]
//! ```
//!
//! `L = Σ ½ m ẋ_i² − Σ_i exp(−(x_{i+1} − x_i − d))`, `x_200 ≡ x_0 + 200 d`. The attribute builds
//! the adapted coordinates (group `x[0]`, shape `x[i] − x[0]`), so the reduced integrator has
//! 199 + 1 unknowns per step, solved by the sparse backend on the compile-time pattern of the
//! step Jacobian (tridiagonal plus a dense border). Prints the total momentum μ (exactly
//! conserved), the energy at the step midpoints (bounded, no drift), the time per step, the
//! peak memory (independent of the number of steps: the run streams its states to an observer),
//! and an ensemble of runs from perturbed initial states on one and on all cores.

use std::time::Instant;

use dirac::prelude::*;
use dirac::runtime::ensemble;

#[path = "common/stats.rs"]
mod stats;
use stats::peak_memory_mib;

#[path = "common/cli.rs"]
mod cli;
use cli::{any, at_least, Cli};

#[path = "common/toda.rs"]
mod toda;
use toda::{initial, Toda, N};

/// `--steps` and `--ensemble` (defaults 100,000 and 8; `--ensemble 0` skips the ensemble); a bad
/// value stops the example with exit code 2.
fn parse_args() -> (usize, usize) {
    let mut cli = Cli::new(
        "lattice",
        "the 200-particle periodic Toda lattice, streamed, and an ensemble on every core",
    );
    let steps = cli.value("--steps", "N", "steps of the run", 100_000, at_least(1));
    let members = cli.value(
        "--ensemble",
        "MEMBERS",
        "members of the ensemble (0: none)",
        8,
        any(),
    );
    cli.finish();
    (steps, members)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (steps, members) = parse_args();
    let sys = Toda {
        m: 1.0,
        d: 1.0,
        h: 0.05,
    };
    let start = initial(&sys, 0.1, 0.3, 0.05);
    let integ = ReducedIntegrator::plus(sys, NewtonOptions::default());
    println!(
        "periodic Toda lattice, n = {N}, h = {}, midpoint rule, reduced (+) equations: {} unknowns per step",
        sys.h,
        N
    );
    println!("  {}", Toda::GENERATED);

    // The energy at each step's midpoint, E((q_k + q_{k+1})/2, (q_{k+1} − q_k)/h), accumulated
    // on the fly: nothing of the trajectory is kept but the previous configuration.
    let (mut e_min, mut e_max) = (f64::INFINITY, f64::NEG_INFINITY);
    let (mut e_first, mut e_last, mut counted) = (0.0, 0.0, 0usize);
    let tenth = (steps / 10).max(1);
    let mut mu_deviation = 0.0f64;
    let mut previous: Option<SVector<f64, N>> = None;
    let mu0 = start.mu;
    let began = Instant::now();
    let summary = integ
        .run(start)
        .steps(steps)
        .observe(|k, _, state, _| {
            mu_deviation = mu_deviation.max((state.mu - mu0).amax());
            let q = dirac::runtime::system::join::<199, 1, N>(&state.x, &state.g);
            if let Some(q0) = previous {
                let e = sys.energy(&(0.5 * (q0 + q)), &((q - q0) / sys.h));
                e_min = e_min.min(e);
                e_max = e_max.max(e);
                if k <= tenth {
                    e_first += e;
                }
                if k > steps - tenth {
                    e_last += e;
                    counted += 1;
                }
            }
            previous = Some(q);
        })
        .stream()?;
    let seconds = began.elapsed().as_secs_f64();
    let mean = |s: f64, n: usize| s / n.max(1) as f64;
    let spread = e_max - e_min;
    let drift = mean(e_last, counted) - mean(e_first, tenth.min(steps));
    println!(
        "  {steps} steps (T = {:.0}): {:.1} µs per step, {:.3} corrections per step (max {}), {} Jacobians factored, worst rcond {:.2e}",
        summary.t,
        1e6 * seconds / steps as f64,
        summary.mean_iterations(),
        summary.max_iterations,
        summary.factorizations,
        summary.worst_rcond.map_or(f64::NAN, |(_, r)| r),
    );
    println!(
        "  total momentum μ = {:.15}: max |μ_k − μ_0| = {mu_deviation:e} (exact)",
        mu0[0]
    );
    println!(
        "  energy at the midpoints: spread {spread:.3e} ({:.2e} relative), drift (last tenth − first tenth) {drift:.2e} ({:+.3} × spread)",
        spread / e_max.abs().max(e_min.abs()),
        drift / spread
    );
    if let Some(mib) = peak_memory_mib() {
        println!(
            "  peak memory of the process: {mib:.1} MiB (the states are streamed, not stored)"
        );
    }

    // The same step raised to order 4 by the triple jump (three stages per macro step), through
    // the same driver: each stage keeps its own workspace, so its factors are reused by chord
    // iterations across macro steps and no step allocates. The ratio of the time per macro step
    // to the time per base step (three stages should cost about 3×) is measured here, base and
    // composition interleaved three times, the median printed with the spread.
    let composed = Composition::new(integ.clone(), CompositionMethod::TRIPLE_JUMP);
    let compose_steps = (steps / 10).clamp(100, 2000);
    // Seconds per step of a run, and the Jacobians it factored.
    let timed_run = |stepper: &dyn Fn() -> Option<(usize, usize)>| {
        let began = Instant::now();
        let (n, factorizations) = stepper().unwrap_or((usize::MAX, 0));
        (began.elapsed().as_secs_f64() / n as f64, factorizations)
    };
    let summary_of = |r: Result<RunSummary<ReducedState<199, 1>>, _>| {
        r.ok()
            .map(|s: RunSummary<_>| (s.step_count, s.factorizations))
    };
    let mut ratios = Vec::new();
    let (mut base_us, mut composed_us, mut composed_factorizations) = (0.0, 0.0, 0);
    for _ in 0..3 {
        let (base, _) = timed_run(&|| {
            summary_of(
                integ
                    .run(start)
                    .steps(compose_steps)
                    .observe(|_, _, _, _| {})
                    .stream(),
            )
        });
        let (triple, factorizations) = timed_run(&|| {
            summary_of(
                composed
                    .run(start)
                    .steps(compose_steps)
                    .observe(|_, _, _, _| {})
                    .stream(),
            )
        });
        ratios.push(triple / base);
        (base_us, composed_us, composed_factorizations) =
            (1e6 * base, 1e6 * triple, factorizations);
    }
    ratios.sort_by(f64::total_cmp);
    println!(
        "  triple jump (order 4, 3 stages) through the same driver, {compose_steps} macro steps: {composed_us:.1} µs per macro step against {base_us:.1} µs per base step (last of 3): ratio median {:.2} (range {:.2} to {:.2}; target ≤ 3.5); {composed_factorizations} Jacobians factored in {} stage steps",
        ratios[1], ratios[0], ratios[2], 3 * compose_steps
    );

    // An ensemble: the same lattice from `members` perturbed initial states, on one thread and on
    // every core; each member has its own typed result. `--ensemble 0` skips it.
    if members == 0 {
        return Ok(());
    }
    let ensemble_steps = (steps / 10).max(1);
    let starts: Vec<ReducedState<199, 1>> = (0..members)
        .map(|j| initial(&sys, 0.1 + 0.01 * j as f64, 0.3, 0.05))
        .collect();
    let timed = |threads: usize| -> Result<(f64, usize), Box<dyn std::error::Error>> {
        let pool = ensemble::rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()?;
        let began = Instant::now();
        let results = pool.install(|| {
            integ
                .ensemble(&starts)
                .steps(ensemble_steps)
                .stream(|_| |_, _, _, _| {})
        });
        let ok = results.iter().filter(|(_, r)| r.is_ok()).count();
        Ok((began.elapsed().as_secs_f64(), ok))
    };
    let cores = std::thread::available_parallelism().map_or(1, |c| c.get());
    let (t1, ok1) = timed(1)?;
    let (tp, okp) = timed(cores)?;
    println!(
        "  ensemble of {members} members × {ensemble_steps} steps: {ok1}/{members} ok on 1 thread in {t1:.2} s, {okp}/{members} ok on {cores} threads in {tp:.2} s: speed-up {:.2}, parallel efficiency {:.0}%",
        t1 / tp,
        100.0 * t1 / tp / cores as f64
    );
    Ok(())
}
