//! Every stepper benchmark in one process, one table: the generated (+) stepper of the paper's two
//! systems against run-time AD (num-dual), a hand-coded stepper (charged particle), the unreduced
//! stepper from the same annotation and, when asked, CasADi's generated C (double spherical
//! pendulum), with the ratios.
//!
//! ```text
//! cargo run --release --example bench_table                       # dirac and num-dual only
//! cargo run --release --example bench_table -- --casadi           # also runs benches/casadi.sh
//! cargo run --release --example bench_table -- --casadi-eval-ns 265 --casadi-step-ns 1347
//! ```
//!
//! Options: `--batches B` (default 21), `--batch-ms T` (default 20), `--casadi-repeats R` (default
//! 5: how often CasADi's compiled driver is rerun, spread between our batches).
//!
//! Method: each row is a closure doing one pass over its inputs (evaluations: 64 points spread
//! along the paper's run, at the integrator's Newton guess; steps: the steps of the paper's run,
//! each from the trajectory's state and the integrator's own guess). A pass is repeated to fill a
//! batch of about T ms; the batches of all rows are interleaved (row 1, row 2, …, row 1, …) so
//! that load from other processes spreads over every row; each row reports the median, min and
//! max over its B batches of the time per operation. Ratios are of medians. Outputs go through
//! `std::hint::black_box`.
//!
//! `dirac generated` is `ReducedIntegrator::plus(sys, NewtonOptions::default())`, whichever path
//! the attribute chose for the system; where it emitted a momentum-level elimination, the general
//! path (Newton on all `N` unknowns, the algorithm of the num-dual and hand-coded steppers and of
//! CasADi's driver) and the eliminated path are also timed, forced.
//!
//! The correctness of every baseline against the generated code at these inputs is
//! `tests/bench_oracles.rs`.

#[path = "common/cli.rs"]
mod cli;
#[path = "../benches/common/mod.rs"]
mod common;
use cli::{at_least, greater_than, Check, Cli};
#[path = "common/stats.rs"]
mod stats;
use stats::{median, range};

use std::error::Error;
use std::hint::black_box;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use common::workload::{self, StepCase, Workload};
use common::{ad, hand};
use dirac::paper::{ChargedParticle, DoubleSphericalPendulum, DSP_STEPS};
use dirac::prelude::*;
use dirac::runtime::linalg::Lu;
use dirac::runtime::system::join;

/// Evaluation points per system.
const EVAL_POINTS: usize = 64;

// ---------------------------------------------------------------------------------------------
// Arguments.
// ---------------------------------------------------------------------------------------------

struct Args {
    batches: usize,
    batch: Duration,
    casadi: bool,
    casadi_repeats: usize,
    casadi_eval_ns: Option<f64>,
    casadi_step_ns: Option<f64>,
}

impl Args {
    /// The command line: `--help` lists it; a bad value stops the example with exit code 2.
    fn parse() -> Self {
        let mut cli = Cli::new(
            "bench_table",
            "every stepper benchmark of the paper's two systems in one process, one table",
        );
        let args = Self {
            batches: cli.value("--batches", "B", "timed batches per row", 21, at_least(1)),
            batch: Duration::from_secs_f64(
                cli.value(
                    "--batch-ms",
                    "T",
                    "milliseconds per batch",
                    20.0,
                    Check::new("a number of milliseconds > 0 and ≤ 60000", |&ms| {
                        ms > 0.0 && ms <= 6e4
                    }),
                ) / 1e3,
            ),
            casadi: cli.switch(
                "--casadi",
                "also time CasADi's generated C (benches/casadi.sh, needs casadi)",
            ),
            casadi_repeats: cli.value(
                "--casadi-repeats",
                "R",
                "reruns of CasADi's compiled driver, spread between the batches",
                5,
                at_least(1),
            ),
            casadi_eval_ns: cli.optional(
                "--casadi-eval-ns",
                "NS",
                "CasADi's ns per R+J evaluation, measured elsewhere (with --casadi-step-ns)",
                greater_than(0.0),
            ),
            casadi_step_ns: cli.optional(
                "--casadi-step-ns",
                "NS",
                "CasADi's ns per step, measured elsewhere (with --casadi-eval-ns)",
                greater_than(0.0),
            ),
        };
        if args.casadi_eval_ns.is_some() != args.casadi_step_ns.is_some() {
            cli.reject("give both --casadi-eval-ns and --casadi-step-ns, or neither");
        }
        cli.finish();
        args
    }
}

// ---------------------------------------------------------------------------------------------
// CasADi.
// ---------------------------------------------------------------------------------------------

/// One CasADi configuration: the shared script generates the C, compiles it and runs it once; the
/// compiled driver is then rerun between our batches, so its timings see the same machine load.
struct Casadi {
    label: String,
    /// The compiled driver and its directory (removed on drop); `None` for numbers given on the
    /// command line.
    binary: Option<(PathBuf, PathBuf)>,
    /// ns per residual+Jacobian evaluation, one per driver run.
    evals: Vec<f64>,
    /// ns per step of the paper's run, one per driver run.
    steps: Vec<f64>,
    iterations: Option<f64>,
    /// The script's report (generation and first run).
    report: String,
}

impl Drop for Casadi {
    fn drop(&mut self) {
        if let Some((_, dir)) = &self.binary {
            let _ = std::fs::remove_dir_all(dir);
        }
    }
}

/// The number right after `prefix` in `text`.
fn number_after(text: &str, prefix: &str) -> Option<f64> {
    let rest = &text[text.find(prefix)? + prefix.len()..];
    rest.split_whitespace()
        .next()?
        .trim_end_matches(',')
        .parse()
        .ok()
}

/// ns per evaluation, ns per step and Newton iterations per step from the driver's report.
fn parse_casadi(report: &str) -> Result<(f64, f64, Option<f64>), Box<dyn Error>> {
    let line = |what: &str| {
        report
            .lines()
            .find(|l| l.starts_with("casadi-c: ") && l.contains(what))
            .ok_or_else(|| format!("no `casadi-c: … {what}` in the CasADi report:\n{report}"))
    };
    let (eval, step) = (
        line("per residual+Jacobian evaluation")?,
        line("ns per step")?,
    );
    Ok((
        number_after(eval, "casadi-c: ").ok_or("unreadable evaluation time")?,
        number_after(step, "casadi-c: ").ok_or("unreadable step time")?,
        number_after(step, "ns per step, "),
    ))
}

/// Output of a command that must succeed.
fn output(cmd: &mut Command) -> Result<String, Box<dyn Error>> {
    let out = cmd.output()?;
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    if !out.status.success() {
        return Err(format!(
            "{cmd:?} failed ({}):\n{stdout}{}",
            out.status,
            String::from_utf8_lossy(&out.stderr)
        )
        .into());
    }
    Ok(stdout)
}

impl Casadi {
    /// Runs `benches/casadi.sh` with `flags`, keeping the compiled driver in a temporary directory.
    fn build(label: &str, flags: &[&str]) -> Result<Self, Box<dyn Error>> {
        let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("benches/casadi.sh");
        let dir = std::env::temp_dir().join(format!(
            "dirac-bench-casadi-{}-{}",
            std::process::id(),
            flags.join("")
        ));
        std::fs::create_dir_all(&dir)?;
        let mut casadi = Self {
            label: label.into(),
            binary: Some((dir.join("dsp_bench"), dir.clone())),
            evals: Vec::new(),
            steps: Vec::new(),
            iterations: None,
            report: String::new(),
        };
        casadi.report = output(
            Command::new("bash")
                .arg(&script)
                .args(flags)
                .env("CASADI_BENCH_DIR", &dir),
        )?;
        casadi.iterations = parse_casadi(&casadi.report)?.2;
        Ok(casadi)
    }

    /// Numbers given on the command line.
    fn given(eval_ns: f64, step_ns: f64) -> Self {
        Self {
            label: "CasADi C (given)".into(),
            binary: None,
            evals: vec![eval_ns],
            steps: vec![step_ns],
            iterations: None,
            report: String::new(),
        }
    }

    /// Median, min and max ns per evaluation (`eval`) or per step over the driver's runs.
    fn stats(&self, eval: bool) -> (f64, f64, f64) {
        let v = if eval {
            self.evals.clone()
        } else {
            self.steps.clone()
        };
        let (lo, hi) = range(&v);
        (median(v), lo, hi)
    }

    /// Reruns the compiled driver (20 runs of the paper's 10⁴ steps, as the script does).
    fn rerun(&mut self) -> Result<(), Box<dyn Error>> {
        if let Some((binary, _)) = &self.binary {
            let (eval, step, _) = parse_casadi(&output(Command::new(binary).arg("20"))?)?;
            self.evals.push(eval);
            self.steps.push(step);
        }
        Ok(())
    }
}

// ---------------------------------------------------------------------------------------------
// Timing.
// ---------------------------------------------------------------------------------------------

/// One row of the table.
struct Row<'a> {
    system: &'static str,
    quantity: &'static str,
    name: &'static str,
    /// Operations (evaluations or steps) in one pass.
    ops: usize,
    pass: Box<dyn FnMut() + 'a>,
    /// Newton corrections per step, where that applies.
    iterations: Option<f64>,
    passes_per_batch: usize,
    /// ns per operation, one per batch.
    samples: Vec<f64>,
}

struct Bench<'a> {
    rows: Vec<Row<'a>>,
}

const CP: &str = "charged particle";
const DSP: &str = "double sph. pendulum";
/// The generated stepper as `ReducedIntegrator::plus(sys, NewtonOptions::default())` runs it.
const GEN: &str = "dirac generated";
/// The generated stepper forced onto the general path (Newton on all `N` unknowns).
const GENERAL: &str = "dirac, general path";
/// The generated stepper forced onto the eliminated path (Newton on the `S` shape unknowns).
const ELIMINATED: &str = "dirac, eliminated path";
/// The generated stepper under the CasADi driver's protocol (see [`casadi_protocol_run`]).
const PROTOCOL: &str = "dirac, CasADi protocol";

impl<'a> Bench<'a> {
    fn add(
        &mut self,
        system: &'static str,
        quantity: &'static str,
        name: &'static str,
        ops: usize,
        iterations: Option<f64>,
        pass: impl FnMut() + 'a,
    ) {
        self.rows.push(Row {
            system,
            quantity,
            name,
            ops,
            pass: Box::new(pass),
            iterations,
            passes_per_batch: 1,
            samples: Vec::new(),
        });
    }

    /// Sets each row's passes per batch to fill about `batch`; also warms caches and predictors.
    fn calibrate(&mut self, batch: Duration) {
        for row in &mut self.rows {
            let start = Instant::now();
            let mut passes = 0;
            while start.elapsed() < batch / 4 || passes < 2 {
                (row.pass)();
                passes += 1;
            }
            let per_pass = start.elapsed().as_secs_f64() / passes as f64;
            row.passes_per_batch = ((batch.as_secs_f64() / per_pass).ceil() as usize).max(1);
        }
    }

    /// One batch of every row, in turn.
    fn batch(&mut self) {
        for row in &mut self.rows {
            let start = Instant::now();
            for _ in 0..row.passes_per_batch {
                (row.pass)();
            }
            let ns = start.elapsed().as_secs_f64() * 1e9;
            row.samples
                .push(ns / (row.passes_per_batch * row.ops) as f64);
        }
    }

    /// Median ns per operation of a row.
    fn median(&self, system: &str, quantity: &str, name: &str) -> Option<f64> {
        let row = self
            .rows
            .iter()
            .find(|r| r.system == system && r.quantity == quantity && r.name == name)?;
        Some(median(row.samples.clone()))
    }
}

// ---------------------------------------------------------------------------------------------
// The rows.
// ---------------------------------------------------------------------------------------------

type Case = StepCase<3, 1, 4>;

/// Adds an evaluation row: `f` at every point, one pass.
fn eval_row<'a, T>(
    bench: &mut Bench<'a>,
    system: &'static str,
    name: &'static str,
    points: Vec<Case>,
    f: impl Fn(&Case) -> T + 'a,
) {
    bench.add(system, "eval R+J", name, points.len(), None, move || {
        for p in &points {
            black_box(f(black_box(p)));
        }
    });
}

/// Adds a step row: `f` takes the step of every case and returns its result with the Newton
/// corrections it took; a first pass, untimed, counts them.
fn step_row<'a, T>(
    bench: &mut Bench<'a>,
    system: &'static str,
    name: &'static str,
    cases: &'a [Case],
    f: impl Fn(&Case) -> (T, usize) + 'a,
) {
    let iterations = cases.iter().map(|c| f(c).1).sum::<usize>() as f64 / cases.len() as f64;
    bench.add(
        system,
        "step",
        name,
        cases.len(),
        Some(iterations),
        move || {
            for c in cases {
                black_box(f(black_box(c)));
            }
        },
    );
}

/// The rows every system gets: the generated stepper (its default path and both paths forced),
/// num-dual (both Jacobians), unreduced, and the pieces of the generated general-path step.
fn system_rows<'a, L>(bench: &mut Bench<'a>, system: &'static str, w: &'a Workload<L, 3, 1, 4>)
where
    L: Reduced<Plus, 3, 1, 4, Linear = dirac::runtime::Lu<4>>
        + Unreduced<3, 1, 4, UnreducedLinear = dirac::runtime::Lu<4>>
        + ad::DualLagrangian<4>
        + Copy
        + 'a,
{
    let sys = w.system;
    let options = NewtonOptions::default();
    let points = w.spread(EVAL_POINTS);
    let cases = &w.cases[..];

    eval_row(bench, system, GEN, points.clone(), move |p| {
        let s = &p.state;
        sys.residual_jacobian(&s.x, &s.w, &s.mu, &p.guess)
    });
    if <L as Reduced<Plus, 3, 1, 4>>::ELIMINATES_GROUP {
        eval_row(
            bench,
            system,
            "dirac eliminated (S x S)",
            points.clone(),
            move |p| {
                let s = &p.state;
                let x1 = p.guess.fixed_rows::<3>(0).into_owned();
                sys.eliminated_residual_jacobian(&s.x, &s.w, &s.mu, &x1)
            },
        );
    }
    eval_row(
        bench,
        system,
        "num-dual hessian",
        points.clone(),
        move |p| {
            let s = &p.state;
            ad::residual_jacobian::<L, 3, 1, 4, 7>(&sys, &s.x, &s.w, &s.mu, &p.guess)
        },
    );
    eval_row(
        bench,
        system,
        "num-dual partial_hessian",
        points.clone(),
        move |p| {
            let s = &p.state;
            ad::residual_jacobian_partial::<L, 3, 1, 4>(&sys, &s.x, &s.w, &s.mu, &p.guess)
        },
    );
    eval_row(
        bench,
        system,
        "unreduced generated",
        points.clone(),
        move |p| {
            sys.unreduced_residual_jacobian(&p.canonical.q, &p.canonical.p, &p.canonical_guess)
        },
    );

    let integrators = [
        (GEN, ReducedIntegrator::plus(sys, options)),
        (
            GENERAL,
            ReducedIntegrator::plus(sys, options).with_elimination(false),
        ),
        (
            ELIMINATED,
            ReducedIntegrator::plus(sys, options).with_elimination(true),
        ),
    ];
    for (name, integ) in integrators {
        if name == ELIMINATED && !integ.eliminates_group() {
            continue;
        }
        step_row(bench, system, name, cases, move |c| {
            let r = integ
                .step_from(c.k, &c.state, &c.guess)
                .expect("the step succeeds");
            let it = r.1.stats.iterations;
            (r, it)
        });
    }
    for (name, how) in [
        ("num-dual hessian", ad::Jacobian::Hessian),
        ("num-dual partial_hessian", ad::Jacobian::PartialHessian),
    ] {
        step_row(bench, system, name, cases, move |c| {
            let r = ad::step::<L, 3, 1, 4, 7>(&sys, &options, how, &c.state, &c.guess)
                .expect("the step succeeds");
            let it = r.2;
            (r, it)
        });
    }
    let unreduced = UnreducedIntegrator::new(sys, options);
    step_row(bench, system, "unreduced generated", cases, move |c| {
        let r = unreduced
            .step_from(c.k, &c.canonical, &c.canonical_guess)
            .expect("the step succeeds");
        let it = r.1.iterations;
        (r, it)
    });

    // The pieces of a general-path step: Newton evaluates R once, then per correction R+J, a
    // factorization and solve and R again; it estimates the condition once; then w_{k+1}.
    let piece = |bench: &mut Bench<'a>, name, f: Box<dyn Fn(&Case) -> f64 + 'a>| {
        bench.add(system, "piece", name, points.len(), None, {
            let points = points.clone();
            move || {
                for p in &points {
                    black_box(f(black_box(p)));
                }
            }
        })
    };
    piece(
        bench,
        "generated R alone",
        Box::new(move |p| {
            let s = &p.state;
            sys.residual(&s.x, &s.w, &s.mu, &p.guess)[0]
        }),
    );
    piece(
        bench,
        "generated w_{k+1}",
        Box::new(move |p| sys.momentum(&p.state.x, &p.solution)[0]),
    );
    piece(
        bench,
        "generated R and w_{k+1}",
        Box::new(move |p| {
            let s = &p.state;
            sys.residual_momentum(&s.x, &s.w, &s.mu, &p.solution).1[0]
        }),
    );
    let jacobians: Vec<(SMatrix<f64, 4, 4>, SVector<f64, 4>)> = points
        .iter()
        .map(|p| {
            let s = &p.state;
            let (r, j) = sys.residual_jacobian(&s.x, &s.w, &s.mu, &p.guess);
            (j, r)
        })
        .collect();
    let nalgebra_jacobians = jacobians.clone();
    let factors: Vec<Lu<4>> = jacobians
        .iter()
        .map(|(j, _)| Lu::new(*j).expect("a regular Jacobian"))
        .collect();
    bench.add(
        system,
        "piece",
        "runtime LU + solve",
        points.len(),
        None,
        move || {
            for (j, r) in &jacobians {
                black_box(Lu::new(*black_box(j)).map(|lu| lu.solve(black_box(r))));
            }
        },
    );
    bench.add(
        system,
        "piece",
        "nalgebra lu() + solve",
        points.len(),
        None,
        move || {
            for (j, r) in &nalgebra_jacobians {
                black_box(black_box(*j).lu().solve(black_box(r)));
            }
        },
    );
    let bound_factors = factors.clone();
    bench.add(
        system,
        "piece",
        "runtime rcond lower bound",
        points.len(),
        None,
        move || {
            for f in &bound_factors {
                black_box(black_box(f).rcond_lower_bound());
            }
        },
    );
    bench.add(
        system,
        "piece",
        "runtime rcond estimate",
        points.len(),
        None,
        move || {
            for f in &factors {
                black_box(black_box(f).rcond());
            }
        },
    );
}

/// The rows only the charged particle has: the hand-coded stepper.
fn hand_rows<'a>(bench: &mut Bench<'a>, w: &'a Workload<ChargedParticle, 3, 1, 4>) {
    let p = w.system;
    let options = NewtonOptions::default();
    eval_row(bench, CP, "hand-coded", w.spread(EVAL_POINTS), move |pt| {
        let s = &pt.state;
        hand::residual_jacobian(&p, &s.x, &s.w, &s.mu, &pt.guess)
    });
    step_row(bench, CP, "hand-coded Newton", &w.cases, move |c| {
        let r = hand::newton_step(&p, &options, &c.state, &c.guess).expect("the step succeeds");
        let it = r.2;
        (r, it)
    });
    step_row(bench, CP, "hand-coded closed form", &w.cases, move |c| {
        (hand::closed_form_step(&p, &c.state), 0)
    });
}

/// The paper's whole run with the generated stepper under the CasADi driver's protocol: Newton
/// from the previous configuration, `z0 = (x_k, 0)`, no extrapolation. Returns the final state and
/// the mean Newton corrections per step.
fn casadi_protocol_run(
    integ: &ReducedIntegrator<DoubleSphericalPendulum, Plus, 3, 1, 4>,
) -> (ReducedState<3, 1>, f64) {
    let mut state = DoubleSphericalPendulum::paper_initial_state();
    let mut iterations = 0;
    for k in 0..DSP_STEPS {
        let guess = join::<3, 1, 4>(&state.x, &SVector::zeros());
        let (next, ReducedStep { stats, .. }) = integ
            .step_from(k, black_box(&state), &guess)
            .expect("the paper's run succeeds");
        iterations += stats.iterations;
        state = next;
    }
    (state, iterations as f64 / DSP_STEPS as f64)
}

// ---------------------------------------------------------------------------------------------
// Output.
// ---------------------------------------------------------------------------------------------

fn ns(v: f64) -> String {
    if v >= 1e4 {
        format!("{:.0}", v)
    } else if v >= 100.0 {
        format!("{:.1}", v)
    } else {
        format!("{:.2}", v)
    }
}

const QUANTITIES: [&str; 3] = ["eval R+J", "step", "piece"];

/// The table: every row, grouped by system and quantity, CasADi's numbers beside ours.
fn print_table<L1, L2>(
    bench: &Bench<'_>,
    casadi: &[Casadi],
    args: &Args,
    elapsed: Duration,
    cp: &Workload<L1, 3, 1, 4>,
    dsp: &Workload<L2, 3, 1, 4>,
) where
    L1: Reduced<Plus, 3, 1, 4> + Copy,
    L2: Reduced<Plus, 3, 1, 4> + Copy,
{
    let path = |eliminates: bool| {
        if eliminates {
            "eliminated (Newton on x_{k+1}, g_k^+ in closed form)"
        } else {
            "general (Newton on z = (x_{k+1}, g_k^+))"
        }
    };
    let options = NewtonOptions::default();
    let cp_path = path(ReducedIntegrator::plus(cp.system, options).eliminates_group());
    let dsp_path = path(ReducedIntegrator::plus(dsp.system, options).eliminates_group());
    println!(
        "dirac stepper benchmarks: ns per operation, median [min, max] over {} interleaved batches \
         of ~{} ms ({:.1} s); {} threads available",
        args.batches,
        args.batch.as_millis(),
        elapsed.as_secs_f64(),
        std::thread::available_parallelism().map_or(0, |n| n.get())
    );
    if let Some(c) = casadi.first() {
        println!(
            "  CasADi rows: median [min, max] over {} reruns of its compiled driver between our \
             batches (each the mean of 2·10⁶ evaluations and 20 runs of 10⁴ steps)",
            c.evals.len()
        );
    }
    println!(
        "  {}: {} steps, h = {}\n  {}: {} steps (every {}th), h = {}",
        cp.name,
        cp.cases.len(),
        cp.system.time_step(),
        dsp.name,
        dsp.cases.len(),
        workload::DSP_STRIDE,
        dsp.system.time_step()
    );
    println!(
        "  `{GEN}` = ReducedIntegrator::plus(sys, NewtonOptions::default()); its default path: \
         charged particle {cp_path}, double spherical pendulum {dsp_path}"
    );
    println!(
        "  eval: {EVAL_POINTS} points along the run at the Newton guess; step: Newton included, \
         from the run's states and the integrator's guesses; piece: parts of a generated step"
    );
    println!();
    let header = [
        "system",
        "what",
        "implementation",
        "median",
        "min",
        "max",
        "Newton it",
    ];
    let print = |c: [&str; 7]| {
        println!(
            "{:<21} {:<9} {:<26} {:>10} {:>10} {:>10} {:>9}",
            c[0], c[1], c[2], c[3], c[4], c[5], c[6]
        )
    };
    print(header);
    let it = |i: Option<f64>| i.map_or(String::new(), |i| format!("{i:.3}"));
    for system in [CP, DSP] {
        for quantity in QUANTITIES {
            println!();
            for row in bench
                .rows
                .iter()
                .filter(|r| r.system == system && r.quantity == quantity)
            {
                let (lo, hi) = range(&row.samples);
                print([
                    row.system,
                    row.quantity,
                    row.name,
                    &ns(median(row.samples.clone())),
                    &ns(lo),
                    &ns(hi),
                    &it(row.iterations),
                ]);
            }
            if system != DSP {
                continue;
            }
            for c in casadi {
                let (eval, it_c) = match quantity {
                    "eval R+J" => (true, String::new()),
                    "step" => (false, it(c.iterations)),
                    _ => continue,
                };
                let (mid, lo, hi) = c.stats(eval);
                print([
                    system,
                    quantity,
                    &c.label,
                    &ns(mid),
                    &ns(lo),
                    &ns(hi),
                    &it_c,
                ]);
            }
        }
    }
}

/// Ratios of medians: num-dual / dirac, dirac / hand-coded, unreduced / reduced, dirac / CasADi.
fn print_ratios(bench: &Bench<'_>, casadi: &[Casadi]) {
    let m = |system: &str, quantity: &str, name: &str| bench.median(system, quantity, name);
    let r = |a: Option<f64>, b: Option<f64>| match (a, b) {
        (Some(a), Some(b)) => format!("{:.2}", a / b),
        _ => String::new(),
    };
    let print = |label: &str, c: [String; 4]| {
        println!(
            "{:<46} {:>9} {:>9} {:>9} {:>9}",
            label, c[0], c[1], c[2], c[3]
        )
    };
    // `num` / `den` in each column: evaluations compare `*_eval` rows, steps `*_step` rows.
    let cols = |num_eval: &str, den_eval: &str, num_step: &str, den_step: &str| {
        [
            r(m(CP, "eval R+J", num_eval), m(CP, "eval R+J", den_eval)),
            r(m(CP, "step", num_step), m(CP, "step", den_step)),
            r(m(DSP, "eval R+J", num_eval), m(DSP, "eval R+J", den_eval)),
            r(m(DSP, "step", num_step), m(DSP, "step", den_step)),
        ]
    };
    println!();
    print(
        "ratios of medians",
        ["CP eval", "CP step", "DSP eval", "DSP step"].map(String::from),
    );
    for nd in ["num-dual hessian", "num-dual partial_hessian"] {
        print(&format!("{nd} / dirac"), cols(nd, GEN, nd, GEN));
        print(
            &format!("{nd} / dirac general path"),
            cols("", "", nd, GENERAL),
        );
    }
    print(
        "dirac / hand-coded (general path, same Newton)",
        [
            r(m(CP, "eval R+J", GEN), m(CP, "eval R+J", "hand-coded")),
            r(m(CP, "step", GENERAL), m(CP, "step", "hand-coded Newton")),
            String::new(),
            String::new(),
        ],
    );
    print(
        "dirac / hand-coded closed form (no Newton)",
        [
            String::new(),
            r(m(CP, "step", GEN), m(CP, "step", "hand-coded closed form")),
            String::new(),
            String::new(),
        ],
    );
    print(
        "unreduced / reduced (both generated)",
        cols("unreduced generated", GEN, "unreduced generated", GEN),
    );
    print(
        "unreduced / reduced general path",
        cols("", "", "unreduced generated", GENERAL),
    );
    print(
        "general path / eliminated path",
        cols("", "", GENERAL, ELIMINATED),
    );
    for c in casadi {
        print(
            &format!("dirac / {}", c.label),
            [
                String::new(),
                String::new(),
                r(m(DSP, "eval R+J", GEN), Some(c.stats(true).0)),
                r(m(DSP, "step", PROTOCOL), Some(c.stats(false).0)),
            ],
        );
    }
    if !casadi.is_empty() {
        println!(
            "  (DSP step / CasADi: both the whole run of 10⁴ steps, Newton from the previous \
             configuration, each with its own convergence test)"
        );
    }
}

/// What a general-path step costs, piece by piece: Newton evaluates `R` and `J` at the guess and
/// at every iterate it corrects again, factors and solves per correction, tests the accepted
/// iterate with `R` and `w_{k+1}` together, and checks the conditioning with the cheap bound.
fn print_pieces(bench: &Bench<'_>) {
    println!();
    for system in [CP, DSP] {
        let m = |quantity, name| bench.median(system, quantity, name).unwrap_or(f64::NAN);
        let it = bench
            .rows
            .iter()
            .find(|r| r.system == system && r.quantity == "step" && r.name == GENERAL)
            .and_then(|r| r.iterations)
            .unwrap_or(f64::NAN);
        let (rw, lu, bound, rj) = (
            m("piece", "generated R and w_{k+1}"),
            m("piece", "runtime LU + solve"),
            m("piece", "runtime rcond lower bound"),
            m("eval R+J", GEN),
        );
        let model = it * (rj + lu) + rw + bound;
        println!(
            "{system}, general path: step ~ it (R+J + LU) + (R and w) + rcond bound = {it:.3} ({} \
             + {}) + {} + {} = {} ns; measured {} ns",
            ns(rj),
            ns(lu),
            ns(rw),
            ns(bound),
            ns(model),
            ns(m("step", GENERAL)),
        );
    }
}

/// The speed targets, each as measured in this run (ratios of medians), met or not.
fn print_targets(bench: &Bench<'_>, casadi: &[Casadi]) {
    let m = |system: &str, quantity: &str, name: &str| bench.median(system, quantity, name);
    let iterations = |system: &str, name: &str| {
        bench
            .rows
            .iter()
            .find(|r| r.system == system && r.quantity == "step" && r.name == name)
            .and_then(|r| r.iterations)
    };
    let line = |label: String, value: Option<f64>, target: f64| match value {
        Some(v) => println!(
            "{label:<62} {v:>7.2}   target <= {target:<4} {}",
            if v <= target { "met" } else { "NOT met" }
        ),
        None => println!(
            "{label:<62} {:>7}   target <= {target:<4} (not measured)",
            "-"
        ),
    };
    let ratio = |a: Option<f64>, b: Option<f64>| a.zip(b).map(|(a, b)| a / b);
    println!();
    println!("speed targets, ratios of medians in this run");
    for c in casadi {
        line(
            format!("DSP step, CasADi protocol: dirac / {}", c.label),
            ratio(m(DSP, "step", PROTOCOL), Some(c.stats(false).0)),
            0.6,
        );
    }
    let it = iterations(DSP, GEN);
    line(
        "DSP step / (Newton it. x R+J evaluation), dirac generated".into(),
        ratio(
            m(DSP, "step", GEN),
            it.zip(m(DSP, "eval R+J", GEN)).map(|(i, e)| i * e),
        ),
        1.5,
    );
    for c in casadi {
        line(
            format!("DSP R+J evaluation: dirac / {}", c.label),
            ratio(m(DSP, "eval R+J", GEN), Some(c.stats(true).0)),
            0.7,
        );
    }
    line(
        "CP step: dirac generated / hand-coded closed form".into(),
        ratio(m(CP, "step", GEN), m(CP, "step", "hand-coded closed form")),
        5.0,
    );
    line(
        "DSP mean Newton iterations per step, dirac generated".into(),
        it,
        1.8,
    );
}

fn main() -> Result<(), Box<dyn Error>> {
    let args = Args::parse();
    if cfg!(debug_assertions) {
        eprintln!("warning: a debug build; run with --release for meaningful numbers");
    }

    let mut casadi = Vec::new();
    if args.casadi {
        eprintln!(
            "generating and compiling CasADi's C (benches/casadi.sh, with and without --cse) …"
        );
        casadi.push(Casadi::build("CasADi C, gcc -O3", &[])?);
        casadi.push(Casadi::build("CasADi C (cse), gcc -O3", &["--cse"])?);
    }
    if let (Some(eval_ns), Some(step_ns)) = (args.casadi_eval_ns, args.casadi_step_ns) {
        casadi.push(Casadi::given(eval_ns, step_ns));
    }

    let cp = workload::charged_particle();
    let dsp = workload::double_spherical_pendulum();
    let options = NewtonOptions::default();
    let dsp_integ = ReducedIntegrator::plus(dsp.system, options);
    let (protocol_final, protocol_it) = casadi_protocol_run(&dsp_integ);

    let mut bench = Bench { rows: Vec::new() };
    system_rows(&mut bench, CP, &cp);
    hand_rows(&mut bench, &cp);
    system_rows(&mut bench, DSP, &dsp);
    let integ = &dsp_integ;
    bench.add(
        DSP,
        "step",
        PROTOCOL,
        DSP_STEPS,
        Some(protocol_it),
        move || {
            black_box(casadi_protocol_run(integ));
        },
    );
    eprintln!(
        "timing {} rows, {} interleaved batches of ~{} ms …",
        bench.rows.len(),
        args.batches,
        args.batch.as_millis()
    );
    let start = Instant::now();
    bench.calibrate(args.batch);
    for b in 0..args.batches {
        bench.batch();
        // The CasADi driver runs `casadi_repeats` times, spread evenly between the batches.
        let (r, n) = (args.casadi_repeats, args.batches);
        if (b + 1) * r / n > b * r / n {
            for c in &mut casadi {
                c.rerun()?;
            }
        }
    }
    let elapsed = start.elapsed();

    print_table(&bench, &casadi, &args, elapsed, &cp, &dsp);
    print_ratios(&bench, &casadi);
    print_pieces(&bench);
    print_targets(&bench, &casadi);
    println!();
    println!(
        "dirac under the CasADi protocol: final x = ({:.12}, {:.12}, {:.12}), vartheta1 = {:.12}",
        protocol_final.x[0], protocol_final.x[1], protocol_final.x[2], protocol_final.g[0]
    );
    for c in &casadi {
        if !c.report.is_empty() {
            println!(
                "{}: benches/casadi.sh (generation, compilation, first run):",
                c.label
            );
            for line in c.report.lines() {
                println!("  {line}");
            }
        }
    }
    Ok(())
}
