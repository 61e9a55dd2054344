//! The periodic Toda lattice with `n` on the command line: one build of one element-wise
//! system serves every size (`examples/common/toda_n.rs`, `coordinates(x[n])`).
//!
//! ```sh
//! cargo run --release --example toda_n -- [--n 100,1000,10000,100000] [--seconds 0.5] [--repeats 3]
//! ```
//!
//! For every `n`: the time per step of `ElementIntegrator` (median of `--repeats` runs of about
//! `--seconds` each, interleaved with the same number of steps of the hand-written `O(n)`
//! bordered-tridiagonal Newton step of `benches/common/toda_hand.rs` — the same discrete
//! equations in adapted coordinates, the physical-limit baseline, up to n = 20,000: above, its
//! residual test on the border equation does not converge in 50 corrections), their ratio, the
//! step of the same lattice with a damping force over the undamped step (`forced×`), the Newton
//! corrections and Jacobian factorizations per step, the momentum map's largest deviation (exact: round-off), the spread of
//! the energy at the step midpoints, one residual + Jacobian assembly serial and on all of
//! rayon's threads (their ratio is the parallel speed-up; the results are the same bit for bit)
//! and the process's peak memory so far (`VmHWM`, sizes run in increasing order). Then the
//! log–log slope of the step time against `n` over the sizes ≥ 1000, and the targets, each met or not.

use std::time::Instant;

use dirac::prelude::*;
use dirac::runtime::element::{ElementIntegrator, ElementWorkspace};

#[path = "common/stats.rs"]
mod stats;
use stats::{loglog_slope, median, peak_memory_mib, range};

#[path = "common/cli.rs"]
mod cli;
use cli::{at_least, greater_than, Cli};

#[path = "common/toda_n.rs"]
mod toda_n;
use toda_n::{initial, DampedTodaN, TodaN};

#[path = "../benches/common/toda_hand.rs"]
#[allow(dead_code)]
mod toda_hand;
use toda_hand::{TodaHand, TodaParams, TodaState};

struct Options {
    sizes: Vec<usize>,
    seconds: f64,
    repeats: usize,
    solver: StepSolver,
}

/// The command line: `--help` lists it; a bad value stops the example with exit code 2.
fn parse_args() -> Options {
    let mut cli = Cli::new(
        "toda_n",
        "the periodic Toda lattice, one build for every n, against a hand-written O(n) step",
    );
    let o = Options {
        sizes: cli.list(
            "--n",
            "N1,N2,..",
            "lattice sizes, run in the order given",
            &[100, 1000, 10_000, 100_000],
            at_least(3),
        ),
        seconds: cli.value(
            "--seconds",
            "S",
            "wall time of one timed run",
            0.5,
            greater_than(0.0),
        ),
        repeats: cli.value("--repeats", "R", "timed runs per size", 3, at_least(1)),
        solver: cli.choice(
            "--solver",
            "the step Jacobian's solver",
            "auto",
            &[
                ("auto", StepSolver::Auto),
                ("banded", StepSolver::Banded),
                ("direct", StepSolver::Direct),
            ],
        ),
    };
    cli.finish();
    o
}

/// One row of the table.
struct Row {
    n: usize,
    step_us: f64,
    hand_us: f64,
    ratios: Vec<f64>,
    /// The damped lattice's step over the undamped one's, per repeat.
    forced: Vec<f64>,
    corrections: f64,
    factorizations: f64,
    mu_deviation: f64,
    energy_spread: f64,
    rj_serial_us: f64,
    rj_parallel_us: f64,
    peak_mib: Option<f64>,
}

/// Median seconds of one `residual_jacobian` of `integ` at `state` (and a nearby `z`).
fn time_rj(
    integ: &ElementIntegrator<TodaN>,
    ws: &mut ElementWorkspace,
    state: &ElementState,
) -> Result<f64, StepError> {
    let n = state.q.len();
    let z = &state.q + &state.p * integ.system().h;
    let (mut r, mut j) = (DVector::zeros(n), Vec::new());
    integ.residual_jacobian(ws, &state.q, &state.p, &z, &mut r, &mut j)?;
    let reps = (2_000_000 / n).clamp(3, 2000);
    let mut samples = Vec::new();
    for _ in 0..5 {
        let t0 = Instant::now();
        for _ in 0..reps {
            integ.residual_jacobian(ws, &state.q, &state.p, &z, &mut r, &mut j)?;
            std::hint::black_box(&r);
        }
        samples.push(t0.elapsed().as_secs_f64() / reps as f64);
    }
    Ok(median(samples))
}

fn measure(n: usize, o: &Options) -> Result<Row, Box<dyn std::error::Error>> {
    // Positions measured from the equilibrium sites (`d = 0`, the same dynamics as any `d`): in
    // absolute positions `x_i ≈ i d` the rounding of `x_{k+1} − x_k` alone exceeds the 10⁻¹²
    // residual tolerance at n = 10⁴ (ulp(10⁴) · m/h ≈ 4·10⁻¹¹), which the hand-written step,
    // testing the residual only, cannot meet.
    let sys = TodaN {
        m: 1.0,
        d: 0.0,
        h: 0.05,
        n,
    };
    let integ = ElementIntegrator::new(sys, NewtonOptions::default()).with_solver(o.solver);
    let start = initial(&sys, 0.1, 0.3, 0.0);
    let _ = &start;
    let mu0 = integ.momentum_map(&start)?[0];
    // Steps per timed run: about `--seconds`, from a short calibration run.
    let t0 = Instant::now();
    integ
        .run(start.clone())
        .steps(10)
        .observe(|_, _, _, _| ())
        .stream()?;
    let per_step = t0.elapsed().as_secs_f64() / 10.0;
    let steps = ((o.seconds / per_step) as usize).clamp(20, 200_000);
    let hand_params = TodaParams {
        n,
        m: sys.m,
        d: sys.d,
        h: sys.h,
    };
    let v: Vec<f64> = start.p.iter().map(|p| p / sys.m).collect();
    let hand_start = TodaState::from_positions_velocities(&hand_params, start.q.as_slice(), &v);
    let mut hand = TodaHand::new(hand_params);
    // One untimed run through the driver, observing every state: the momentum map's deviation
    // and the energy at the step midpoints.
    let (mut mu_deviation, mut e_min, mut e_max) = (0.0f64, f64::INFINITY, f64::NEG_INFINITY);
    let mut previous = start.q.clone();
    let summary = integ
        .run(start.clone())
        .steps(steps)
        .observe(|k, _, state, _| {
            if k > 0 {
                let e = integ.energy(&previous, &state.q).unwrap_or(f64::NAN);
                e_min = e_min.min(e);
                e_max = e_max.max(e);
                previous.copy_from(&state.q);
            }
            // The driver's states have the system's length: the map is never an error here (an
            // infinite deviation would show it).
            let mu = integ.momentum_map(state).map_or(f64::INFINITY, |mu| mu[0]);
            mu_deviation = mu_deviation.max((mu - mu0).abs());
        })
        .stream()?;
    let corrections = summary.mean_iterations();
    let factorizations = summary.factorizations as f64 / summary.step_count.max(1) as f64;
    // Timed: the steps alone (the workspace — pattern, ordering, symbolic factorization — is
    // built once per run, before), in the driver's way: two states swapped, nothing allocated.
    let (mut dirac_s, mut hand_s, mut forced) = (Vec::new(), Vec::new(), Vec::new());
    let mut hand_ok = n <= 20_000;
    // The same lattice with a weak damping force (Newton's work per step stays the same).
    let damped = ElementIntegrator::new(
        DampedTodaN {
            m: sys.m,
            d: sys.d,
            c: 1e-3,
            h: sys.h,
            n,
        },
        NewtonOptions::default(),
    )
    .with_solver(o.solver);
    for _ in 0..o.repeats {
        let mut ws = integ.workspace();
        let (mut state, mut next) = (start.clone(), start.clone());
        let t0 = Instant::now();
        for k in 0..steps {
            integ.step_into(
                &mut ws,
                StepAt::new(k, integ.time_step()),
                &state,
                &mut next,
            )?;
            std::mem::swap(&mut state, &mut next);
        }
        let unforced = t0.elapsed().as_secs_f64() / steps as f64;
        dirac_s.push(unforced);
        let mut ws = damped.workspace();
        let (mut state, mut next) = (start.clone(), start.clone());
        let t0 = Instant::now();
        for k in 0..steps {
            damped.step_into(
                &mut ws,
                StepAt::new(k, damped.time_step()),
                &state,
                &mut next,
            )?;
            std::mem::swap(&mut state, &mut next);
        }
        forced.push(t0.elapsed().as_secs_f64() / steps as f64 / unforced);
        if hand_ok {
            let mut s = hand_start.clone();
            hand.reset_history();
            let t0 = Instant::now();
            for _ in 0..steps {
                if hand.step(std::hint::black_box(&mut s)).is_err() {
                    hand_ok = false;
                    break;
                }
            }
            hand_s.push(t0.elapsed().as_secs_f64() / steps as f64);
        }
    }
    let step_us = 1e6 * median(dirac_s.clone());
    let (hand_us, ratios) = if hand_ok {
        (
            1e6 * median(hand_s.clone()),
            dirac_s.iter().zip(&hand_s).map(|(d, h)| d / h).collect(),
        )
    } else {
        (f64::NAN, Vec::new())
    };
    let serial = integ.clone().with_parallel(Parallel::Never);
    let parallel = integ.clone().with_parallel(Parallel::Always);
    let rj_serial_us = 1e6 * time_rj(&serial, &mut serial.workspace(), &start)?;
    let rj_parallel_us = 1e6 * time_rj(&parallel, &mut parallel.workspace(), &start)?;
    Ok(Row {
        n,
        step_us,
        hand_us,
        ratios,
        forced,
        corrections,
        factorizations,
        mu_deviation,
        energy_spread: (e_max - e_min) / e_max.abs(),
        rj_serial_us,
        rj_parallel_us,
        peak_mib: peak_memory_mib(),
    })
}

fn main() {
    let o = parse_args();
    println!(
        "periodic Toda lattice, one build for every n: {}",
        TodaN::GENERATED
    );
    println!(
        "rayon threads: {}; each time the median of {} interleaved runs; step solver {:?}",
        dirac::runtime::ensemble::rayon::current_num_threads(),
        o.repeats,
        o.solver
    );
    println!(
        "{:>7} {:>11} {:>11} {:>20} {:>18} {:>6} {:>7} {:>9} {:>10} {:>11} {:>11} {:>6} {:>8}",
        "n",
        "step µs",
        "hand µs",
        "ratio (range)",
        "forced× (range)",
        "corr",
        "fact",
        "max|Δμ|",
        "E spread",
        "R+J ser µs",
        "R+J par µs",
        "par×",
        "peak MiB"
    );
    let mut rows = Vec::new();
    for &n in &o.sizes {
        match measure(n, &o) {
            Ok(r) => {
                let ratio = if r.ratios.is_empty() {
                    "-".to_string()
                } else {
                    let (lo, hi) = range(&r.ratios);
                    format!("{:.2} ({lo:.2}–{hi:.2})", median(r.ratios.clone()))
                };
                let (lo, hi) = range(&r.forced);
                let forced = format!("{:.2} ({lo:.2}–{hi:.2})", median(r.forced.clone()));
                println!(
                    "{:>7} {:>11.2} {:>11.2} {:>20} {:>18} {:>6.2} {:>7.4} {:>9.1e} {:>10.1e} {:>11.1} {:>11.1} {:>6.2} {:>8}",
                    r.n,
                    r.step_us,
                    r.hand_us,
                    ratio,
                    forced,
                    r.corrections,
                    r.factorizations,
                    r.mu_deviation,
                    r.energy_spread,
                    r.rj_serial_us,
                    r.rj_parallel_us,
                    r.rj_serial_us / r.rj_parallel_us,
                    r.peak_mib.map_or("-".into(), |m| format!("{m:.1}"))
                );
                rows.push(r);
            }
            Err(e) => println!("{n:>7} failed: {e}"),
        }
    }
    // log–log slope of the step time over n ≥ 1000 (least squares).
    let pts: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| r.n >= 1000)
        .map(|r| (r.n as f64, r.step_us))
        .collect();
    if let Some(slope) = loglog_slope(&pts) {
        println!("log–log slope of the step time over n ≥ 1000: {slope:.3} (target 1 ± 0.1)");
    }
    if let Some(r) = rows.iter().find(|r| r.n == 100_000) {
        println!(
            "n = 100000: peak memory {} MiB (target ≤ 200 MB); parallel assembly {:.2}× on {} threads (target ≥ 1.7 on 2)",
            r.peak_mib.map_or("-".into(), |m| format!("{m:.1}")),
            r.rj_serial_us / r.rj_parallel_us,
            dirac::runtime::ensemble::rayon::current_num_threads()
        );
    }
}
