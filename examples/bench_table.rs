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
//! 3; the median of R runs of the CasADi script, with and without `--cse`).
//!
//! Method: each row is a closure doing one pass over its inputs (evaluations: 64 points spread
//! along the paper's run, at the integrator's Newton guess; steps: the steps of the paper's run,
//! each from the trajectory's state and the integrator's own guess). A pass is repeated to fill a
//! batch of about T ms; the batches of all rows are interleaved (row 1, row 2, …, row 1, …) so
//! that load from other processes spreads over every row; each row reports the median, min and
//! max over its B batches of the time per operation. Ratios are of medians. Outputs go through
//! `std::hint::black_box`.
//!
//! The correctness of every baseline against the generated code at these inputs is
//! `tests/bench_oracles.rs`.

#[path = "../benches/common/mod.rs"]
mod common;

use std::error::Error;
use std::hint::black_box;
use std::path::Path;
use std::process::Command;
use std::time::{Duration, Instant};

use common::workload::{self, Workload};
use common::{ad, hand};
use dirac::paper::{ChargedParticle, DoubleSphericalPendulum, DSP_STEPS};
use dirac::prelude::*;
use dirac::runtime::lu::Lu;
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

const USAGE: &str = "usage: bench_table [--batches B] [--batch-ms T] [--casadi] \
                     [--casadi-repeats R] [--casadi-eval-ns N --casadi-step-ns M]";

impl Args {
    fn parse() -> Result<Self, Box<dyn Error>> {
        let mut args = Self {
            batches: 21,
            batch: Duration::from_millis(20),
            casadi: false,
            casadi_repeats: 3,
            casadi_eval_ns: None,
            casadi_step_ns: None,
        };
        let mut it = std::env::args().skip(1);
        while let Some(arg) = it.next() {
            let mut value = |name: &str| -> Result<f64, Box<dyn Error>> {
                let v = it.next().ok_or(format!("{name} needs a value; {USAGE}"))?;
                Ok(v.parse::<f64>()
                    .map_err(|e| format!("{name} {v}: {e}; {USAGE}"))?)
            };
            match arg.as_str() {
                "--batches" => args.batches = (value("--batches")? as usize).max(1),
                "--batch-ms" => args.batch = Duration::from_secs_f64(value("--batch-ms")? / 1e3),
                "--casadi" => args.casadi = true,
                "--casadi-repeats" => {
                    args.casadi_repeats = (value("--casadi-repeats")? as usize).max(1)
                }
                "--casadi-eval-ns" => args.casadi_eval_ns = Some(value("--casadi-eval-ns")?),
                "--casadi-step-ns" => args.casadi_step_ns = Some(value("--casadi-step-ns")?),
                other => return Err(format!("unknown argument `{other}`; {USAGE}").into()),
            }
        }
        Ok(args)
    }
}

// ---------------------------------------------------------------------------------------------
// CasADi.
// ---------------------------------------------------------------------------------------------

/// One CasADi configuration's numbers (medians over the script runs).
struct Casadi {
    label: String,
    eval_ns: f64,
    step_ns: f64,
    iterations: Option<f64>,
    /// The script's own report, from its last run.
    report: String,
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

/// Runs `benches/casadi.sh` `repeats` times with `flags` and takes the medians.
fn run_casadi(label: &str, flags: &[&str], repeats: usize) -> Result<Casadi, Box<dyn Error>> {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("benches/casadi.sh");
    let (mut evals, mut steps, mut iterations, mut report) = (vec![], vec![], None, String::new());
    for _ in 0..repeats {
        let out = Command::new("bash").arg(&script).args(flags).output()?;
        report = String::from_utf8_lossy(&out.stdout).into_owned();
        if !out.status.success() {
            return Err(format!(
                "{} {flags:?} failed ({}):\n{report}{}",
                script.display(),
                out.status,
                String::from_utf8_lossy(&out.stderr)
            )
            .into());
        }
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
        evals.push(number_after(eval, "casadi-c: ").ok_or("unreadable evaluation time")?);
        steps.push(number_after(step, "casadi-c: ").ok_or("unreadable step time")?);
        iterations = number_after(step, "ns per step, ");
    }
    Ok(Casadi {
        label: label.into(),
        eval_ns: median(&mut evals),
        step_ns: median(&mut steps),
        iterations,
        report,
    })
}

// ---------------------------------------------------------------------------------------------
// Timing.
// ---------------------------------------------------------------------------------------------

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

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

    fn run(&mut self, batches: usize, batch: Duration) {
        // Calibration, which also warms caches and branch predictors.
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
        for _ in 0..batches {
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
    }

    /// Median ns per operation of a row.
    fn median(&self, system: &str, quantity: &str, name: &str) -> Option<f64> {
        let row = self
            .rows
            .iter()
            .find(|r| r.system == system && r.quantity == quantity && r.name == name)?;
        Some(median(&mut row.samples.clone()))
    }
}

// ---------------------------------------------------------------------------------------------
// The rows.
// ---------------------------------------------------------------------------------------------

/// The rows every system gets: generated, num-dual (both Jacobians), unreduced, and the pieces
/// of the generated stepper.
fn system_rows<'a, L>(bench: &mut Bench<'a>, system: &'static str, w: &'a Workload<L, 3, 1, 4>)
where
    L: ReducedPlus<3, 1, 4>
        + ReducedMinus<3, 1, 4>
        + Unreduced<3, 1, 4>
        + ad::DualLagrangian<4>
        + Copy
        + 'a,
{
    let sys = w.system;
    let options = NewtonOptions::default();
    let points = w.spread(EVAL_POINTS);
    let n = points.len();
    let cases = &w.cases[..];
    let it = Some(w.mean_iterations());

    let pts = points.clone();
    bench.add(system, "eval R+J", "dirac generated", n, None, move || {
        for p in &pts {
            let s = black_box(&p.state);
            black_box(sys.plus_residual_jacobian(&s.x, &s.w, &s.mu, black_box(&p.guess)));
        }
    });
    let pts = points.clone();
    bench.add(system, "eval R+J", "num-dual hessian", n, None, move || {
        for p in &pts {
            let s = black_box(&p.state);
            black_box(ad::residual_jacobian::<L, 3, 1, 4, 7>(
                &sys,
                &s.x,
                &s.w,
                &s.mu,
                black_box(&p.guess),
            ));
        }
    });
    let pts = points.clone();
    bench.add(
        system,
        "eval R+J",
        "num-dual partial_hessian",
        n,
        None,
        move || {
            for p in &pts {
                let s = black_box(&p.state);
                black_box(ad::residual_jacobian_partial::<L, 3, 1, 4>(
                    &sys,
                    &s.x,
                    &s.w,
                    &s.mu,
                    black_box(&p.guess),
                ));
            }
        },
    );
    let pts = points.clone();
    bench.add(
        system,
        "eval R+J",
        "unreduced generated",
        n,
        None,
        move || {
            for p in &pts {
                let s = black_box(&p.canonical);
                black_box(sys.unreduced_residual_jacobian(
                    &s.q,
                    &s.p,
                    black_box(&p.canonical_guess),
                ));
            }
        },
    );

    let integ = ReducedIntegrator::plus(sys, options);
    bench.add(
        system,
        "step",
        "dirac generated",
        cases.len(),
        it,
        move || {
            for c in cases {
                black_box(
                    integ
                        .step(c.k, black_box(&c.state), black_box(&c.guess))
                        .ok(),
                );
            }
        },
    );
    for (name, how) in [
        ("num-dual hessian", ad::Jacobian::Hessian),
        ("num-dual partial_hessian", ad::Jacobian::PartialHessian),
    ] {
        bench.add(system, "step", name, cases.len(), it, move || {
            for c in cases {
                let s = black_box(&c.state);
                black_box(
                    ad::step::<L, 3, 1, 4, 7>(&sys, &options, how, s, black_box(&c.guess)).ok(),
                );
            }
        });
    }
    let unreduced = UnreducedIntegrator::plus(sys, options);
    let unreduced_it = cases
        .iter()
        .map(|c| {
            let (_, stats) = unreduced
                .step(c.k, &c.canonical, &c.canonical_guess)
                .expect("the unreduced step succeeds");
            stats.iterations as f64
        })
        .sum::<f64>()
        / cases.len() as f64;
    bench.add(
        system,
        "step",
        "unreduced generated",
        cases.len(),
        Some(unreduced_it),
        move || {
            for c in cases {
                let s = black_box(&c.canonical);
                black_box(unreduced.step(c.k, s, black_box(&c.canonical_guess)).ok());
            }
        },
    );

    // The pieces of a generated step: Newton evaluates R+J and R once per correction (and R once
    // before the first), factors and solves, estimates the condition once, updates w.
    let pts = points.clone();
    bench.add(system, "piece", "generated R alone", n, None, move || {
        for p in &pts {
            let s = black_box(&p.state);
            black_box(sys.plus_residual(&s.x, &s.w, &s.mu, black_box(&p.guess)));
        }
    });
    let pts = points.clone();
    bench.add(system, "piece", "generated w_{k+1}", n, None, move || {
        for p in &pts {
            black_box(sys.plus_momentum(black_box(&p.state.x), black_box(&p.solution)));
        }
    });
    let jacobians: Vec<(SMatrix<f64, 4, 4>, SVector<f64, 4>)> = points
        .iter()
        .map(|p| {
            let s = &p.state;
            let (r, j) = sys.plus_residual_jacobian(&s.x, &s.w, &s.mu, &p.guess);
            (j, r)
        })
        .collect();
    let js = jacobians.clone();
    bench.add(system, "piece", "runtime LU + solve", n, None, move || {
        for (j, r) in &js {
            black_box(Lu::new(*black_box(j)).map(|lu| lu.solve(black_box(r))));
        }
    });
    let factors: Vec<Lu<4>> = jacobians
        .iter()
        .map(|(j, _)| Lu::new(*j).expect("a regular Jacobian"))
        .collect();
    bench.add(
        system,
        "piece",
        "runtime rcond estimate",
        n,
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
    let points = w.spread(EVAL_POINTS);
    let cases = &w.cases[..];
    bench.add(
        CP,
        "eval R+J",
        "hand-coded",
        points.len(),
        None,
        move || {
            for pt in &points {
                let s = black_box(&pt.state);
                black_box(hand::residual_jacobian(
                    &p,
                    &s.x,
                    &s.w,
                    &s.mu,
                    black_box(&pt.guess),
                ));
            }
        },
    );
    let it = Some(w.mean_iterations());
    bench.add(
        CP,
        "step",
        "hand-coded Newton",
        cases.len(),
        it,
        move || {
            for c in cases {
                black_box(
                    hand::newton_step(&p, &options, black_box(&c.state), black_box(&c.guess)).ok(),
                );
            }
        },
    );
    bench.add(
        CP,
        "step",
        "hand-coded closed form",
        cases.len(),
        Some(0.0),
        move || {
            for c in cases {
                black_box(hand::closed_form_step(&p, black_box(&c.state)));
            }
        },
    );
}

/// The paper's whole run with the generated stepper under the CasADi driver's protocol: Newton
/// from the previous configuration, `z0 = (x_k, 0)`, no extrapolation. Returns the final state and
/// the mean Newton corrections per step.
fn casadi_protocol_run(
    integ: &ReducedIntegrator<DoubleSphericalPendulum, 3, 1, 4>,
) -> (ReducedState<3, 1>, f64) {
    let mut state = DoubleSphericalPendulum::paper_initial_state();
    let mut iterations = 0;
    for k in 0..DSP_STEPS {
        let guess = join::<3, 1, 4>(&state.x, &SVector::zeros());
        let (next, _, stats) = integ
            .step(k, black_box(&state), &guess)
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

fn main() -> Result<(), Box<dyn Error>> {
    let args = Args::parse()?;
    if cfg!(debug_assertions) {
        eprintln!("warning: a debug build; run with --release for meaningful numbers");
    }

    let mut casadi = Vec::new();
    if args.casadi {
        eprintln!(
            "running benches/casadi.sh ({} times each) …",
            args.casadi_repeats
        );
        casadi.push(run_casadi("CasADi C, gcc -O3", &[], args.casadi_repeats)?);
        casadi.push(run_casadi(
            "CasADi C (cse), gcc -O3",
            &["--cse"],
            args.casadi_repeats,
        )?);
    }
    if let (Some(eval_ns), Some(step_ns)) = (args.casadi_eval_ns, args.casadi_step_ns) {
        casadi.push(Casadi {
            label: "CasADi C (given)".into(),
            eval_ns,
            step_ns,
            iterations: None,
            report: String::new(),
        });
    } else if args.casadi_eval_ns.is_some() || args.casadi_step_ns.is_some() {
        return Err(format!("give both --casadi-eval-ns and --casadi-step-ns; {USAGE}").into());
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
        "dirac, CasADi protocol",
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
    bench.run(args.batches, args.batch);
    let elapsed = start.elapsed();

    println!(
        "dirac stepper benchmarks: ns per operation, median [min, max] over {} batches of ~{} ms \
         ({:.1} s); {} threads available",
        args.batches,
        args.batch.as_millis(),
        elapsed.as_secs_f64(),
        std::thread::available_parallelism().map_or(0, |n| n.get())
    );
    println!(
        "  {}: {} steps timed, h = {}; {}: {} steps timed (every {}th of the run), h = {}",
        cp.name,
        cp.cases.len(),
        cp.system.h,
        dsp.name,
        dsp.cases.len(),
        workload::DSP_STRIDE,
        dsp.system.h
    );
    println!();
    println!(
        "{:<21} {:<9} {:<26} {:>10} {:>10} {:>10} {:>9}",
        "system", "what", "implementation", "median", "min", "max", "Newton it"
    );
    let mut last = ("", "");
    for row in &bench.rows {
        if (row.system, row.quantity) != last && last.0 != "" {
            println!();
        }
        last = (row.system, row.quantity);
        let mut s = row.samples.clone();
        s.sort_by(f64::total_cmp);
        println!(
            "{:<21} {:<9} {:<26} {:>10} {:>10} {:>10} {:>9}",
            row.system,
            row.quantity,
            row.name,
            ns(median(&mut s)),
            ns(s[0]),
            ns(s[s.len() - 1]),
            row.iterations.map_or(String::new(), |i| format!("{i:.3}"))
        );
    }
    if !casadi.is_empty() {
        println!();
        for c in &casadi {
            println!(
                "{:<21} {:<9} {:<26} {:>10}",
                DSP,
                "eval R+J",
                c.label,
                ns(c.eval_ns)
            );
            println!(
                "{:<21} {:<9} {:<26} {:>10} {:>10} {:>10} {:>9}",
                DSP,
                "step",
                c.label,
                ns(c.step_ns),
                "",
                "",
                c.iterations.map_or(String::new(), |i| format!("{i:.3}"))
            );
        }
    }

    // Ratios of medians.
    let m = |system: &str, quantity: &str, name: &str| bench.median(system, quantity, name);
    let ratio = |a: Option<f64>, b: Option<f64>| match (a, b) {
        (Some(a), Some(b)) => format!("{:.2}", a / b),
        _ => "-".into(),
    };
    println!();
    println!(
        "{:<44} {:>9} {:>9} {:>9} {:>9}",
        "ratios of medians", "CP eval", "CP step", "DSP eval", "DSP step"
    );
    let gen = "dirac generated";
    let line = |label: &str, num: &str, den: &str| {
        println!(
            "{:<44} {:>9} {:>9} {:>9} {:>9}",
            label,
            ratio(m(CP, "eval R+J", num), m(CP, "eval R+J", den)),
            ratio(m(CP, "step", num), m(CP, "step", den)),
            ratio(m(DSP, "eval R+J", num), m(DSP, "eval R+J", den)),
            ratio(m(DSP, "step", num), m(DSP, "step", den)),
        );
    };
    line("num-dual hessian / dirac", "num-dual hessian", gen);
    line(
        "num-dual partial_hessian / dirac",
        "num-dual partial_hessian",
        gen,
    );
    line("dirac / hand-coded (Newton)", gen, "hand-coded");
    println!(
        "{:<44} {:>9} {:>9} {:>9} {:>9}",
        "dirac / hand-coded closed form",
        "",
        ratio(m(CP, "step", gen), m(CP, "step", "hand-coded closed form")),
        "",
        ""
    );
    println!(
        "{:<44} {:>9} {:>9} {:>9} {:>9}",
        "dirac / hand-coded Newton",
        "",
        ratio(m(CP, "step", gen), m(CP, "step", "hand-coded Newton")),
        "",
        ""
    );
    line(
        "unreduced / reduced (both generated)",
        "unreduced generated",
        gen,
    );
    for c in &casadi {
        println!(
            "{:<44} {:>9} {:>9} {:>9} {:>9}",
            format!("dirac / {}", c.label),
            "",
            "",
            ratio(m(DSP, "eval R+J", gen), Some(c.eval_ns)),
            ratio(m(DSP, "step", "dirac, CasADi protocol"), Some(c.step_ns)),
        );
    }
    if !casadi.is_empty() {
        println!(
            "  (DSP step against CasADi: both whole runs of 10⁴ steps, Newton from the previous \
             configuration)"
        );
    }

    // What a generated step costs, piece by piece.
    println!();
    for (system, it) in [(CP, cp.mean_iterations()), (DSP, dsp.mean_iterations())] {
        let piece = |name| m(system, "piece", name).unwrap_or(f64::NAN);
        let (r, w, lu, rcond) = (
            piece("generated R alone"),
            piece("generated w_{k+1}"),
            piece("runtime LU + solve"),
            piece("runtime rcond estimate"),
        );
        let rj = m(system, "eval R+J", gen).unwrap_or(f64::NAN);
        let model = r + it * (rj + lu + r) + rcond + w;
        println!(
            "{system}: step ≈ R + it (R+J + LU + R) + rcond + w = {} + {it:.3} ({} + {} + {}) + {} + {} \
             = {} ns; measured {} ns",
            ns(r),
            ns(rj),
            ns(lu),
            ns(r),
            ns(rcond),
            ns(w),
            ns(model),
            ns(m(system, "step", gen).unwrap_or(f64::NAN)),
        );
    }

    println!();
    println!(
        "dirac under the CasADi protocol: final x = ({:.12}, {:.12}, {:.12}), vartheta1 = {:.12}",
        protocol_final.x[0], protocol_final.x[1], protocol_final.x[2], protocol_final.g[0]
    );
    for c in &casadi {
        if !c.report.is_empty() {
            println!("{} (last run of benches/casadi.sh):", c.label);
            for line in c.report.lines() {
                println!("  {line}");
            }
        }
    }
    Ok(())
}
