//! A nonlinear membrane, its grid chosen on the command line: one build of one element-wise
//! system (`examples/common/membrane.rs`, `coordinates(u[nx][ny])`) serves every grid.
//! `ρ u_tt = ∇·(c² ∇u + β (∇u)³)` on a periodic `nx × ny` grid of spacing `δ = 1/nx` (the x
//! side of the periodic box has length 1, the y side `ny/nx`), `ρ = c² = 1`, `β = 0.5`, midpoint
//! rule in time, the shift `u ↦ u + c` as its symmetry.
//!
//! ```sh
//! cargo run --release --example wave2d                        # 316 × 316 ≈ 10⁵ nodes, 100 steps
//! cargo run --release --example wave2d -- --nx 64 --ny 64 --steps 20 --repeats 1   # CI: ~1 s
//! # all arguments: [--nx NX] [--ny NY] [--steps S] [--h H] [--beta B] [--amplitude A] [--repeats R]
//! #                [--linear auto|direct|iterative]   (the step Jacobian's solver; auto: CG at this size)
//! ```
//!
//! Every run factors the step Jacobian in its first step (there are no factors to reuse yet; the
//! later steps are chord corrections on them) with faer's sparse LU, supernodal on this periodic
//! 2-D pattern (about 2 s at 316 × 316 on the 2-core machine these figures come from); the later
//! steps cost one or two solves with those factors and one or two assembly passes each.
//!
//! The initial state is a Gaussian bump of width 0.1 and amplitude `--amplitude` (0.05: its
//! slope reaches 0.3, where the cubic flux adds `3β u_x²` ≈ 14 % to the stiffness) moving at unit
//! speed in x, on a field drifting at 0.05, with a small ripple in y (`membrane::initial`).
//!
//! The time step. The midpoint rule is implicit and symplectic: `h` above the explicit scheme's
//! CFL limit `δ/(c√2)` is stable, but accuracy decides. The default `h = 0.002` (CFL number
//! `c h/δ = 0.26` at `nx = 128`, 0.63 at 316) keeps the relative spread of the energy at the
//! step midpoints near 2·10⁻⁶ over 200 steps (measured on 128 × 128: `h = 0.004` gives
//! 9·10⁻⁶; with amplitude 0.1, whose bump steepens within the run, `h = 0.001`, 0.002, 0.004,
//! 0.008 give 2·10⁻⁶, 3·10⁻⁵, 3·10⁻⁴, 1·10⁻³, and at 0.008 the chord corrections stall and
//! Newton refactors every few steps: 266 ms per step instead of 8).
//!
//! Printed, all computed: the system's `GENERATED` note; the number of unknowns, the step
//! Jacobian's nonzeros and whether the assembly runs in parallel; the time per step (median of
//! `--repeats` timed runs, each with its workspace built before the clock starts, as
//! `examples/toda_n.rs` does; also its first step and the later ones apart) on all of rayon's
//! threads and on a pool of one thread, interleaved, the final states of every run compared bit
//! for bit; Newton's mean corrections and the factorizations per step (and in which steps); the
//! momentum map `μ = Σ p` and its largest deviation over the run (exact: round-off, in units of
//! `ε Σ|p|`); the energy at the step midpoints — relative spread, and drift (mean of the last
//! tenth of the run minus mean of the first tenth, relative: over a short run this measures the
//! slow oscillation of the bounded energy error, not a secular drift); the process's peak memory
//! (`VmHWM`). Then the targets, each with whether it is met. A failed step ends the example with
//! its typed error and exit code 1; bad arguments with the usage and exit code 2.

use std::time::Instant;

use dirac::prelude::*;
use dirac::runtime::element::StepSolver;
use dirac::runtime::ensemble::rayon;

#[path = "common/stats.rs"]
mod stats;
use stats::{median, peak_memory_mib, range};

#[path = "common/cli.rs"]
mod cli;
use cli::{at_least, greater_than, Cli};

#[path = "common/membrane.rs"]
mod membrane;
use membrane::Membrane;

/// The width of the initial bump (the box's x side is 1).
const WIDTH: f64 = 0.1;

struct Options {
    nx: usize,
    ny: usize,
    steps: usize,
    h: f64,
    beta: f64,
    amplitude: f64,
    repeats: usize,
    linear: StepSolver,
}

/// The command line: `--help` lists it; a bad value stops the example with exit code 2.
fn parse_args() -> Options {
    let min = <Membrane as ElementLagrangian>::MIN_SIZE.max(2);
    let mut cli = Cli::new(
        "wave2d",
        "a 2-D nonlinear wave equation on a periodic grid, one build for every grid size",
    );
    let o = Options {
        nx: cli.value("--nx", "NX", "grid nodes along x", 316, at_least(min)),
        ny: cli.value("--ny", "NY", "grid nodes along y", 316, at_least(min)),
        steps: cli.value(
            "--steps",
            "S",
            "steps per run (the drift compares tenths of the run)",
            100,
            at_least(10),
        ),
        h: cli.value("--h", "H", "time step", 0.002, greater_than(0.0)),
        beta: cli.value(
            "--beta",
            "B",
            "β, the coefficient of the cubic flux",
            0.5,
            at_least(0.0),
        ),
        amplitude: cli.value(
            "--amplitude",
            "A",
            "amplitude of the initial Gaussian bump",
            0.05,
            greater_than(0.0),
        ),
        repeats: cli.value("--repeats", "R", "timed runs", 1, at_least(1)),
        linear: cli.choice(
            "--linear",
            "the step Jacobian's solver",
            "auto",
            &[
                ("auto", StepSolver::Auto),
                ("direct", StepSolver::Direct),
                ("iterative", StepSolver::Iterative),
            ],
        ),
    };
    cli.finish();
    o
}

/// How many of the values of `a` and `b` differ in their bits (all of them if the lengths do).
fn differing_bits(a: &ElementState, b: &ElementState) -> usize {
    if a.q.len() != b.q.len() || a.p.len() != b.p.len() {
        return a.q.len().max(b.q.len()) + a.p.len().max(b.p.len());
    }
    let count = |x: &DVector<f64>, y: &DVector<f64>| {
        x.iter()
            .zip(y.iter())
            .filter(|(u, v)| u.to_bits() != v.to_bits())
            .count()
    };
    count(&a.q, &b.q) + count(&a.p, &b.p)
}

/// One timed run.
struct Timed {
    /// Seconds per step over the whole run.
    per_step: f64,
    /// Seconds of the first step (no factors yet: it factors the Jacobian).
    first: f64,
    /// Seconds per step over the later steps (chord corrections on the first step's factors).
    later: f64,
    last: ElementState,
    parallel: bool,
}

/// `steps` steps from `start` in the driver's way (two states swapped, nothing allocated), the
/// workspace built before the clock starts.
fn timed_run(
    integ: &ElementIntegrator<Membrane>,
    start: &ElementState,
    steps: usize,
) -> Result<Timed, StepError> {
    let mut ws = integ.workspace();
    let parallel = ws.is_parallel();
    let (mut state, mut next) = (start.clone(), start.clone());
    let t0 = Instant::now();
    let mut first = 0.0;
    for k in 0..steps {
        integ.step_into(
            &mut ws,
            StepAt::new(k, integ.time_step()),
            &state,
            &mut next,
        )?;
        std::mem::swap(&mut state, &mut next);
        if k == 0 {
            first = t0.elapsed().as_secs_f64();
        }
    }
    let total = t0.elapsed().as_secs_f64();
    Ok(Timed {
        per_step: total / steps as f64,
        first,
        later: (total - first) / (steps - 1) as f64,
        last: state,
        parallel,
    })
}

fn fail(what: &str, e: impl std::fmt::Display) -> ! {
    eprintln!("wave2d: {what} failed: {e}");
    std::process::exit(1)
}

fn main() {
    let wall = Instant::now();
    let o = parse_args();
    let threads = rayon::current_num_threads();
    let sys = Membrane {
        rho: 1.0,
        c2: 1.0,
        beta: o.beta,
        delta: 1.0 / o.nx as f64,
        h: o.h,
        nx: o.nx,
        ny: o.ny,
    };
    let integ = ElementIntegrator::new(sys, NewtonOptions::default()).with_solver(o.linear);
    let start = membrane::initial(&sys, o.amplitude, WIDTH, 1.0, 0.05);
    let n = start.q.len();

    println!(
        "nonlinear membrane, one build for every grid: {}",
        Membrane::GENERATED
    );
    println!(
        "grid {} × {} (δ = 1/{}, periodic box {:.4} × {:.4}), ρ = {}, c² = {}, β = {}, h = {} (c h/δ = {:.3}), {} steps (t = {})",
        o.nx,
        o.ny,
        o.nx,
        o.nx as f64 * sys.delta,
        o.ny as f64 * sys.delta,
        sys.rho,
        sys.c2,
        sys.beta,
        sys.h,
        sys.c2.sqrt() * sys.h / sys.delta,
        o.steps,
        o.steps as f64 * sys.h
    );
    let ws = integ.workspace();
    println!(
        "unknowns {n}; Jacobian nonzeros {} ({:.2} per row); solver: {}; elements per family {:?}; assembly {} on {threads} rayon thread{}",
        ws.nnz(),
        ws.nnz() as f64 / n as f64,
        ws.linear_solver(),
        ws.elements(),
        if ws.is_parallel() { "parallel" } else { "serial" },
        if threads == 1 { "" } else { "s" }
    );
    drop(ws);

    // One untimed run through the driver, observing every state: the momentum map and the
    // energy at every step's midpoint.
    let mu0 = integ
        .momentum_map(&start)
        .unwrap_or_else(|e| fail("the momentum map", e))[0];
    let abs_p0: f64 = start.p.iter().map(|p| p.abs()).sum();
    let mut mu_deviation = 0.0f64;
    let mut energies = Vec::with_capacity(o.steps);
    let mut previous = start.q.clone();
    let mut factored_at = Vec::new();
    let summary = integ
        .run(start.clone())
        .steps(o.steps)
        .observe(|k, _, state, record| {
            if record.is_some_and(|r| r.factorizations > 0) {
                factored_at.push(k - 1);
            }
            if k > 0 {
                energies.push(integ.energy(&previous, &state.q).unwrap_or(f64::NAN));
                previous.copy_from(&state.q);
            }
            // The driver's states have the system's length: the map is never an error here
            // (an infinite deviation would show it).
            let mu = integ.momentum_map(state).map_or(f64::INFINITY, |mu| mu[0]);
            mu_deviation = mu_deviation.max((mu - mu0).abs());
        })
        .stream()
        .unwrap_or_else(|e| fail("the observed run", format!("{e}; {}", e.source)));

    // Timed: `--repeats` runs on all of rayon's threads, interleaved with as many on a pool of
    // one thread (where `Parallel::Auto` assembles serially).
    let single = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap_or_else(|e| fail("building a one-thread pool", e));
    let (mut all, mut one) = (Vec::new(), Vec::new());
    for _ in 0..o.repeats {
        all.push(
            timed_run(&integ, &start, o.steps)
                .unwrap_or_else(|e| fail(&format!("a timed run on {threads} threads"), e)),
        );
        one.push(
            single
                .install(|| timed_run(&integ, &start, o.steps))
                .unwrap_or_else(|e| fail("a timed run on 1 thread", e)),
        );
    }
    let differences = differing_bits(&all[0].last, &one[0].last);
    let repeat_differences: usize = all
        .iter()
        .chain(&one)
        .map(|t| differing_bits(&summary.last, &t.last))
        .sum();
    let show = |runs: &[Timed], label: &str| {
        let per_step: Vec<f64> = runs.iter().map(|t| t.per_step).collect();
        let (lo, hi) = range(&per_step);
        println!(
            "time per step on {label} ({} assembly): {:.2} ms (median of {} runs of {} steps, range {:.2}–{:.2}); first step {:.3} s, later steps {:.2} ms each",
            if runs[0].parallel { "parallel" } else { "serial" },
            1e3 * median(per_step.clone()),
            runs.len(),
            o.steps,
            1e3 * lo,
            1e3 * hi,
            median(runs.iter().map(|t| t.first).collect()),
            1e3 * median(runs.iter().map(|t| t.later).collect()),
        );
        median(per_step)
    };
    let all_s = show(&all, &format!("{threads} threads"));
    let one_s = show(&one, "1 thread  ");
    println!(
        "speed-up on {threads} threads: {:.2}× per step, {:.2}× on the later steps",
        one_s / all_s,
        median(one.iter().map(|t| t.later).collect())
            / median(all.iter().map(|t| t.later).collect())
    );
    println!(
        "final states on {threads} threads and on 1 thread: {}",
        if differences == 0 {
            format!("identical bit for bit ({} values)", 2 * n)
        } else {
            format!("DIFFER in {differences} of {} values", 2 * n)
        }
    );
    println!(
        "the final states of the {} timed runs against the observed run's: {repeat_differences} differing values",
        all.len() + one.len()
    );
    let steps = summary.step_count as f64;
    println!(
        "Newton: {:.2} corrections per step (at most {}), {} factorizations in {} steps ({:.3} per step; in steps {:?}), largest accepted residual {:.1e}{}",
        summary.mean_iterations(),
        summary.max_iterations,
        summary.factorizations,
        summary.step_count,
        summary.factorizations as f64 / steps,
        factored_at,
        summary.max_residual,
        summary
            .worst_rcond
            .map_or(String::new(), |(k, r)| format!(", worst rcond {r:.1e} (step {k})"))
    );
    println!(
        "momentum map μ = Σp: μ₀ = {mu0:.15e}, max |μ_k − μ₀| = {mu_deviation:.1e} = {:.2} ε·Σ|p₀|",
        mu_deviation / (f64::EPSILON * abs_p0),
    );
    let e_mean = energies.iter().sum::<f64>() / energies.len() as f64;
    let (e_min, e_max) = range(&energies);
    let spread = (e_max - e_min) / e_mean.abs();
    let tenth = (energies.len() / 10).max(1);
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let drift =
        (mean(&energies[energies.len() - tenth..]) - mean(&energies[..tenth])) / e_mean.abs();
    println!(
        "energy at the step midpoints: mean {e_mean:.10e}, relative spread {spread:.2e}, relative drift {drift:+.2e} (last tenth − first tenth, {tenth} steps each)"
    );
    let peak = peak_memory_mib();
    println!(
        "peak memory: {} MiB",
        peak.map_or("-".into(), |m| format!("{m:.1}"))
    );
    let seconds = wall.elapsed().as_secs_f64();
    let yes = |ok: bool| if ok { "met" } else { "NOT MET" };
    // Every step keeps μ_{k+1} = μ_k up to the rounding of one sum: over S steps a random walk
    // of such roundings, about √S ε Σ|p|.
    let mu_bound = 10.0 * (o.steps as f64).sqrt();
    println!(
        "targets: μ exact to round-off (max |Δμ| ≤ 10 √S ε Σ|p| = {mu_bound:.0} ε Σ|p|): {}; energy relative spread ≤ 1e-4: {}; 1 thread ≡ {threads} threads bit for bit: {}; whole example {seconds:.1} s ≤ 60 s: {}",
        yes(mu_deviation <= mu_bound * f64::EPSILON * abs_p0),
        yes(spread <= 1e-4),
        yes(differences == 0 && repeat_differences == 0),
        yes(seconds <= 60.0)
    );
}
