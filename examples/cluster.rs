//! A Lennard-Jones cluster with `n` on the command line: one build of one element-wise system
//! with pair interactions (`examples/common/cluster.rs`, `for i in 0..n { for j in i + 1..n }`)
//! serves every `n`. Reduced units (`m = ε = σ = 1`), midpoint rule, the three translations as
//! its symmetry (K = 3, momentum conserved exactly).
//!
//! ```sh
//! cargo run --release --example cluster                                  # n = 64, 128, 256
//! cargo run --release --example cluster -- --n 27,64 --steps 20 --repeats 1   # CI: ~0.1 s
//! # all arguments: [--n N1,N2,..] [--steps S] [--h H] [--repeats R]
//! ```
//!
//! The initial state (`cluster::initial`): the particles on a jittered cubic lattice of spacing
//! 1.15, just above the pair minimum `2^{1/6} ≈ 1.122`, with small velocities (0.2) and a common
//! drift; the simple cubic lattice is not an equilibrium, so the cluster rearranges and warms
//! up during the run. The default `h = 0.002` is about 1/400 of the period of a pair oscillation
//! at the minimum (`2π/√57.1 ≈ 0.83`); the relative spread of the energy at the step midpoints
//! grows as `h²` (at n = 64 over t = 1.2: 1.3·10⁻⁵, 5.4·10⁻⁵, 2.1·10⁻⁴ for h = 0.001, 0.002,
//! 0.004) and stays bounded over long runs (n = 27, h = 0.004: 3.2·10⁻⁴ after 30 000 steps, the
//! drift then 4·10⁻⁶): over the default 300 steps the "drift" is the warming cluster's slow
//! change of the bounded energy error, not a secular drift.
//!
//! For every `n` (in increasing order), all computed: the unknowns (`3n`), the step Jacobian's
//! nonzeros (every pair couples: the pattern is dense, `(3n)²`); the time per step (median of
//! `--repeats` timed runs, each with its workspace built before the clock starts, as
//! `examples/toda_n.rs` does); Newton's corrections and factorizations per step; the time of one
//! residual + Jacobian assembly, as the run does it (`Parallel::Auto`) and serially, and of one
//! factorization of the step Jacobian (medians, on a factorization workspace of the same
//! pattern), and from the latter and the factorization count the share of the run's time spent
//! factoring; the largest deviation of each of the three
//! momentum components over the run (exact: round-off; also the largest in units of `ε Σ|p|`); the energy at the step midpoints —
//! relative spread, and drift (mean of the last tenth of the run minus mean of the first tenth,
//! relative); the process's peak memory (`VmHWM`). Then the log–log slopes of the step time, the
//! assembly time and the factorization time against `n` (pairs: about 2 for the assembly; up to
//! 3 where the dense factorization dominates). Last, the same cluster written with strided
//! indices (`cluster::StridedCluster`, `coordinates(x[3 * n])`, point `i` at `x[3 * i + d]`,
//! the loops over `d` unrolled by the compiler) at the first `n`: its largest difference to the
//! three-array form over the run and its step time against that form's. A failed step ends the
//! example with its typed error and exit code 1; bad arguments with the usage and exit code 2.

use std::time::Instant;

use dirac::prelude::*;
use dirac::runtime::element::{ElementIntegrator, ElementWorkspace};
use dirac::runtime::linalg::{DynSparseLu, LinearSolver};

// The code `#[reduced_lagrangian]` emits for this system's pair family trips clippy's
// deny-by-default `possible_missing_comma` (reported at the attribute; a lint on generated
// code, not on anything written here).
#[allow(clippy::possible_missing_comma)]
#[path = "common/stats.rs"]
mod stats;
use stats::{loglog_slope, median, peak_memory_mib, range};

#[path = "common/cli.rs"]
mod cli;
use cli::{at_least, greater_than, Cli};

#[path = "common/cluster.rs"]
mod cluster;
use cluster::Cluster;

/// Initial lattice spacing, in units of σ.
const SPACING: f64 = 1.15;
/// Initial velocity scale.
const SPEED: f64 = 0.2;

struct Options {
    sizes: Vec<usize>,
    steps: usize,
    h: f64,
    repeats: usize,
}

/// The command line: `--help` lists it; a bad value stops the example with exit code 2.
fn parse_args() -> Options {
    let min = <Cluster as ElementLagrangian>::MIN_SIZE.max(2);
    let mut cli = Cli::new(
        "cluster",
        "a Lennard-Jones cluster, one build for every number of particles n",
    );
    let mut sizes = cli.list(
        "--n",
        "N1,N2,..",
        "cluster sizes",
        &[64, 128, 256],
        at_least(min),
    );
    sizes.sort_unstable();
    sizes.dedup();
    let o = Options {
        sizes,
        steps: cli.value(
            "--steps",
            "S",
            "steps per run (the drift compares tenths of the run)",
            300,
            at_least(10),
        ),
        h: cli.value("--h", "H", "time step", 0.002, greater_than(0.0)),
        repeats: cli.value("--repeats", "R", "timed runs per size", 3, at_least(1)),
    };
    cli.finish();
    o
}

/// One row of the table.
struct Row {
    n: usize,
    nnz: usize,
    parallel: bool,
    step_ms: Vec<f64>,
    corrections: f64,
    factorizations: usize,
    steps: usize,
    assembly_ms: f64,
    serial_assembly_ms: f64,
    factor_ms: f64,
    mu_deviation: [f64; 3],
    /// `ε Σ_i |p_i|` of the initial state: the round-off scale of a momentum map.
    mu_scale: f64,
    energy_spread: f64,
    energy_drift: f64,
    peak_mib: Option<f64>,
}

impl Row {
    /// The largest momentum deviation in units of [`Self::mu_scale`].
    fn mu_ulps(&self) -> f64 {
        self.mu_deviation.iter().fold(0.0f64, |a, &d| a.max(d)) / self.mu_scale
    }

    fn step_ms(&self) -> f64 {
        median(self.step_ms.clone())
    }

    /// The share of a run's time spent factoring: factorizations × one factorization's time.
    fn factor_share(&self) -> f64 {
        self.factorizations as f64 * self.factor_ms / (self.steps as f64 * self.step_ms())
    }
}

/// Why a size failed: its typed step error, or the run's.
type Failure = Box<dyn std::error::Error>;

/// Median seconds of `f` over `samples` calls.
fn time_median(samples: usize, mut f: impl FnMut()) -> f64 {
    median(
        (0..samples)
            .map(|_| {
                let t0 = Instant::now();
                f();
                t0.elapsed().as_secs_f64()
            })
            .collect(),
    )
}

/// Median milliseconds of one residual + Jacobian assembly as the run does it, of one serial
/// assembly (`Parallel::Never`), and of one factorization of the step Jacobian, at `start` (and
/// the guess `z = q + h p/m`), the last on a factorization workspace of the step's pattern (the
/// same fill-reducing ordering as a run's).
fn time_assembly_and_factor(
    integ: &ElementIntegrator<Cluster>,
    ws: &mut ElementWorkspace,
    start: &ElementState,
) -> Result<(f64, f64, f64), Failure> {
    let n = start.q.len();
    let z = &start.q + &start.p * (integ.system().h / integ.system().m);
    let (mut r, mut j) = (DVector::zeros(n), Vec::new());
    // Checked once: the timed calls below evaluate the same vectors with workspaces of the
    // same system.
    integ.residual_jacobian(
        &mut integ.workspace(),
        &start.q,
        &start.p,
        &z,
        &mut r,
        &mut j,
    )?;
    let mut assemble = |integ: &ElementIntegrator<Cluster>, ws: &mut ElementWorkspace| {
        time_median(5, || {
            std::hint::black_box(
                integ
                    .residual_jacobian(ws, &start.q, &start.p, &z, &mut r, &mut j)
                    .is_ok(),
            );
            std::hint::black_box(&r);
        })
    };
    let serial = integ.clone().with_parallel(Parallel::Never);
    let serial_s = assemble(&serial, &mut serial.workspace());
    let assembly = assemble(integ, ws);
    let (col_ptr, row_idx) = ws.pattern();
    let mut lu = DynSparseLu::new(n, col_ptr.to_vec(), row_idx.to_vec());
    let mut status = Ok(());
    let factor = time_median(3, || status = lu.factor(&j));
    status.map_err(|e| format!("factoring the step Jacobian: {e:?}"))?;
    Ok((1e3 * assembly, 1e3 * serial_s, 1e3 * factor))
}

fn measure(n: usize, o: &Options) -> Result<Row, Failure> {
    let sys = Cluster {
        m: 1.0,
        eps: 1.0,
        sigma: 1.0,
        h: o.h,
        n,
    };
    let integ = ElementIntegrator::new(sys, NewtonOptions::default());
    let start = cluster::initial(&sys, SPACING, SPEED);
    let mut ws = integ.workspace();
    let (nnz, parallel) = (ws.nnz(), ws.is_parallel());

    // One untimed run through the driver, observing every state: the three momentum components
    // and the energy at every step's midpoint.
    let mu0 = integ.momentum_map(&start)?;
    let mut mu_deviation = [0.0f64; 3];
    let mut energies = Vec::with_capacity(o.steps);
    let mut previous = start.q.clone();
    let summary = integ
        .run(start.clone())
        .steps(o.steps)
        .observe(|k, _, state, _| {
            if k > 0 {
                energies.push(integ.energy(&previous, &state.q).unwrap_or(f64::NAN));
                previous.copy_from(&state.q);
            }
            for (d, (mu, m0)) in mu_deviation.iter_mut().zip(
                // The driver's states have the system's length: never an error here (an
                // infinite deviation would show it).
                integ
                    .momentum_map(state)
                    .unwrap_or_else(|_| vec![f64::INFINITY; mu0.len()])
                    .iter()
                    .zip(&mu0),
            ) {
                *d = d.max((mu - m0).abs());
            }
        })
        .stream()
        .map_err(|e| format!("{e}; {}", e.source))?;

    // Timed: the steps alone (the workspace — pattern, ordering, symbolic factorization — is
    // built once per run, before), in the driver's way: two states swapped, nothing allocated.
    let mut step_ms = Vec::new();
    for _ in 0..o.repeats {
        let mut ws = integ.workspace();
        let (mut state, mut next) = (start.clone(), start.clone());
        let t0 = Instant::now();
        for k in 0..o.steps {
            integ.step_into(
                &mut ws,
                StepAt::new(k, integ.time_step()),
                &state,
                &mut next,
            )?;
            std::mem::swap(&mut state, &mut next);
        }
        step_ms.push(1e3 * t0.elapsed().as_secs_f64() / o.steps as f64);
        if state != summary.last {
            return Err("a timed run ended in another state than the observed run".into());
        }
    }
    let (assembly_ms, serial_assembly_ms, factor_ms) =
        time_assembly_and_factor(&integ, &mut ws, &start)?;

    let e_mean = energies.iter().sum::<f64>() / energies.len() as f64;
    let (e_min, e_max) = range(&energies);
    let tenth = (energies.len() / 10).max(1);
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    Ok(Row {
        n,
        nnz,
        parallel,
        step_ms,
        corrections: summary.mean_iterations(),
        factorizations: summary.factorizations,
        steps: summary.step_count,
        assembly_ms,
        serial_assembly_ms,
        factor_ms,
        mu_deviation,
        mu_scale: f64::EPSILON * start.p.iter().map(|p| p.abs()).sum::<f64>(),
        energy_spread: (e_max - e_min) / e_mean.abs(),
        energy_drift: (mean(&energies[energies.len() - tenth..]) - mean(&energies[..tenth]))
            / e_mean.abs(),
        peak_mib: peak_memory_mib(),
    })
}

fn main() {
    let wall = Instant::now();
    let o = parse_args();
    println!(
        "Lennard-Jones cluster, one build for every n: {}",
        Cluster::GENERATED
    );
    println!(
        "m = ε = σ = 1, spacing {SPACING}, speed {SPEED}, h = {}, {} steps (t = {}); rayon threads: {}; step times the median of {} runs",
        o.h,
        o.steps,
        o.steps as f64 * o.h,
        dirac::runtime::ensemble::rayon::current_num_threads(),
        o.repeats
    );
    println!(
        "{:>5} {:>6} {:>8} {:>5} {:>9} {:>17} {:>6} {:>8} {:>9} {:>9} {:>9} {:>7} {:>26} {:>7} {:>9} {:>10} {:>8}",
        "n",
        "3n",
        "nnz",
        "par",
        "step ms",
        "(range)",
        "corr",
        "fact/st",
        "R+J ms",
        "R+J ser",
        "factor ms",
        "fact %",
        "max|Δμ| (x, y, z)",
        "/εΣ|p|",
        "E spread",
        "E drift",
        "peak MiB"
    );
    let mut rows = Vec::new();
    let mut failed = false;
    for &n in &o.sizes {
        match measure(n, &o) {
            Ok(r) => {
                let (lo, hi) = range(&r.step_ms);
                println!(
                    "{:>5} {:>6} {:>8} {:>5} {:>9.3} {:>17} {:>6.2} {:>8.4} {:>9.3} {:>9.3} {:>9.2} {:>6.1}% {:>8.1e} {:>8.1e} {:>8.1e} {:>7.1} {:>9.1e} {:>+10.1e} {:>8}",
                    r.n,
                    3 * r.n,
                    r.nnz,
                    if r.parallel { "yes" } else { "no" },
                    r.step_ms(),
                    format!("({lo:.3}–{hi:.3})"),
                    r.corrections,
                    r.factorizations as f64 / r.steps as f64,
                    r.assembly_ms,
                    r.serial_assembly_ms,
                    r.factor_ms,
                    100.0 * r.factor_share(),
                    r.mu_deviation[0],
                    r.mu_deviation[1],
                    r.mu_deviation[2],
                    r.mu_ulps(),
                    r.energy_spread,
                    r.energy_drift,
                    r.peak_mib.map_or("-".into(), |m| format!("{m:.1}"))
                );
                rows.push(r);
            }
            Err(e) => {
                println!("{n:>5} failed: {e}");
                failed = true;
            }
        }
    }
    if rows.is_empty() {
        eprintln!("cluster: no size completed its run");
        std::process::exit(1);
    }
    let dense = rows.iter().all(|r| r.nnz == 9 * r.n * r.n);
    println!(
        "Jacobian pattern dense (nnz = (3n)²) at every n: {}",
        if dense { "yes" } else { "NO" }
    );
    let slope = |f: &dyn Fn(&Row) -> f64| {
        loglog_slope(&rows.iter().map(|r| (r.n as f64, f(r))).collect::<Vec<_>>())
    };
    if let (Some(step), Some(assembly), Some(factor)) = (
        slope(&|r| r.step_ms()),
        slope(&|r| r.assembly_ms),
        slope(&|r| r.factor_ms),
    ) {
        println!(
            "log–log slopes against n over {:?}: step time {step:.2}, residual + Jacobian assembly {assembly:.2} (pairs: 2), one factorization {factor:.2} (dense LU: 3)",
            rows.iter().map(|r| r.n).collect::<Vec<_>>()
        );
    }
    // Every step keeps μ_{k+1} = μ_k up to the rounding of one sum: over S steps a random walk
    // of such roundings, about √S ε Σ|p|.
    let mu_bound = 10.0 * (o.steps as f64).sqrt();
    let mu_worst = rows.iter().map(Row::mu_ulps).fold(0.0, f64::max);
    let spread = rows.iter().map(|r| r.energy_spread).fold(0.0, f64::max);
    let seconds = wall.elapsed().as_secs_f64();
    let yes = |ok: bool| if ok { "met" } else { "NOT MET" };
    println!(
        "targets: every step converged: {}; μ exact to round-off (max |Δμ| ≤ 10 √S ε Σ|p| = {mu_bound:.0} ε Σ|p|; largest {mu_worst:.1}): {}; energy relative spread ≤ 1e-4 (largest {spread:.1e}): {}; whole example {seconds:.1} s ≤ 60 s: {}",
        yes(!failed),
        yes(mu_worst <= mu_bound),
        yes(spread <= 1e-4),
        yes(seconds <= 60.0)
    );
    if let Err(e) = strided(rows[0].n, &o) {
        println!("strided form failed: {e}");
        failed = true;
    }
    if failed {
        std::process::exit(1);
    }
}

/// The same cluster written with strided indices (`coordinates(x[3 * n])`, point `i` at
/// `x[3 i + d]`), run from the same state: its largest difference to the three-array form over
/// the run, and its step time against that form's (interleaved, medians).
fn strided(n: usize, o: &Options) -> Result<(), Box<dyn std::error::Error>> {
    let (m, eps, sigma) = (1.0, 1.0, 1.0);
    let arrays = ElementIntegrator::new(
        Cluster {
            m,
            eps,
            sigma,
            h: o.h,
            n,
        },
        NewtonOptions::default(),
    );
    let strided = ElementIntegrator::new(
        cluster::StridedCluster {
            m,
            eps,
            sigma,
            h: o.h,
            n,
        },
        NewtonOptions::default(),
    );
    let start = cluster::initial(
        &Cluster {
            m,
            eps,
            sigma,
            h: o.h,
            n,
        },
        SPACING,
        SPEED,
    );
    // Three arrays x[k], y[k], z[k] at k, n + k, 2n + k; strided at 3k + d.
    let permute = |v: &DVector<f64>| DVector::from_fn(3 * n, |a, _| v[(a % 3) * n + a / 3]);
    let strided_start = ElementState::new(permute(&start.q), permute(&start.p));
    let a = arrays.run(start.clone()).steps(o.steps).collect()?;
    let b = strided
        .run(strided_start.clone())
        .steps(o.steps)
        .collect()?;
    let gap = a
        .states
        .iter()
        .zip(&b.states)
        .map(|(x, y)| {
            (permute(&x.q) - &y.q)
                .amax()
                .max((permute(&x.p) - &y.p).amax())
        })
        .fold(0.0, f64::max);
    let (mut ratios, steps) = (Vec::new(), o.steps.min(50));
    for _ in 0..o.repeats.max(3) {
        let t0 = Instant::now();
        arrays
            .run(start.clone())
            .steps(steps)
            .observe(|_, _, _, _| ())
            .stream()?;
        let t_arrays = t0.elapsed().as_secs_f64();
        let t0 = Instant::now();
        strided
            .run(strided_start.clone())
            .steps(steps)
            .observe(|_, _, _, _| ())
            .stream()?;
        ratios.push(t0.elapsed().as_secs_f64() / t_arrays);
    }
    let (lo, hi) = range(&ratios);
    println!(
        "strided form (x[3 * n], {}): n = {n}, largest difference to the three arrays over {} steps {gap:.1e}; step time strided / arrays {:.2} ({lo:.2}–{hi:.2})",
        cluster::StridedCluster::GENERATED,
        o.steps,
        median(ratios.clone())
    );
    Ok(())
}
