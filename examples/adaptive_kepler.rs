//! Adaptive steps on Kepler's problem: work against precision for the fixed step and the adaptive
//! step (`time(t), adapt = |q| q.r * q.r.sqrt()`) of the same Lagrangian and rule, at eccentricities
//! 0.9 and 0.99, for the base step (order 2), its triple-jump composition (order 4) and Kahan
//! and Li's composition of order 6.
//!
//! For each method the example finds, by halving the step, the coarsest step whose error in the
//! orbit's phase after `--orbits` orbits is at most `--tolerance` (against the closed form from
//! Kepler's equation, at the physical time the run reached), and counts the force evaluations
//! that took (one per Newton iteration, each an evaluation of the step residual). It then runs
//! the adaptive step for `--long` orbits at `e = 0.9` and reports the energy error's mean over the
//! first and last tenths, and times a step of each kind.
//!
//! Run: `cargo run --release --example adaptive_kepler [-- --orbits 100 --tolerance-4 1e-6]`;
//! with `DEBUG_ADAPTIVE=1` in the environment every trial step and its error go to stderr.

use std::f64::consts::PI;
use std::time::Instant;

use dirac::prelude::*;

#[path = "common/cli.rs"]
mod cli;

use cli::{at_least, greater_than, Cli};

/// Kepler's problem in polar coordinates, the step following the free-fall time `r^{3/2}`
/// (written `r √r`: a square root is cheaper than a power).
#[reduced_lagrangian(shape(r), group(theta, t), time(t), adapt = |q| q.r * q.r.sqrt(), rule = midpoint)]
fn kepler(q: Config, v: Velocity, k: f64) -> f64 {
    0.5 * (v.r * v.r + q.r * q.r * v.theta * v.theta) + k / q.r
}

/// The same Lagrangian and rule in physical time.
#[reduced_lagrangian(shape(r), group(theta), rule = midpoint)]
fn kepler_fixed(q: Config, v: Velocity, k: f64) -> f64 {
    0.5 * (v.r * v.r + q.r * q.r * v.theta * v.theta) + k / q.r
}

const TAU: f64 = 2.0 * PI;

/// The phase `θ` of the orbit of eccentricity `e` (semi-major axis 1, period 2π) at time `t`
/// from periapsis, by Kepler's equation `E − e sin E = t` solved by Newton.
fn exact_phase(e: f64, t: f64) -> f64 {
    let m = t.rem_euclid(TAU);
    let mut big_e = PI;
    for _ in 0..200 {
        let d = (big_e - e * big_e.sin() - m) / (1.0 - e * big_e.cos());
        big_e -= d;
        if d.abs() < 1e-16 {
            break;
        }
    }
    let anomaly = 2.0
        * ((1.0 + e).sqrt() * (big_e / 2.0).sin()).atan2((1.0 - e).sqrt() * (big_e / 2.0).cos());
    anomaly.rem_euclid(TAU) + (t / TAU).floor() * TAU
}

fn options() -> NewtonOptions {
    NewtonOptions {
        abs_tol: 1e-14,
        rel_tol: 1e-14,
        ..NewtonOptions::default()
    }
}

/// The periapsis state's position and physical angular velocity.
fn periapsis(e: f64) -> (f64, f64) {
    let r0 = 1.0 - e;
    (r0, (1.0 - e * e).sqrt() / (r0 * r0))
}

/// An observer that adds each step's Newton iterations (one residual evaluation each) to `n`.
fn counter<S, R: AsRef<StepStats>>(n: &mut usize) -> impl FnMut(usize, f64, &S, Option<&R>) + '_ {
    move |_, _, _, r| *n += r.map_or(0, |r| r.as_ref().iterations)
}

/// Phase error and force evaluations of `orbits` orbits by fixed steps, `n` per orbit.
fn fixed_run(e: f64, n: usize, orbits: usize, method: CompositionMethod) -> (f64, usize) {
    let sys = KeplerFixed {
        h: TAU / n as f64,
        k: 1.0,
    };
    let (r0, omega) = periapsis(e);
    let s0 = sys
        .reduced_state([r0, 0.0], [0.0, omega])
        .expect("a finite state");
    let mut evaluations = 0;
    let integ = ReducedIntegrator::plus(sys, options());
    let summary = if method.order > 2 {
        Composition::new(integ, method)
            .run(s0)
            .steps(n * orbits)
            .observe(counter(&mut evaluations))
            .stream()
    } else {
        integ
            .run(s0)
            .steps(n * orbits)
            .observe(counter(&mut evaluations))
            .stream()
    };
    let last = summary.map(|s| s.last).ok();
    let error = last.map_or(f64::INFINITY, |s| {
        (s.g[0] - exact_phase(e, TAU * orbits as f64)).abs()
    });
    (error, evaluations)
}

/// Phase error, force evaluations and steps of the adaptive step `eps` until the physical time
/// passes `orbits` periods.
fn adaptive_run(e: f64, eps: f64, orbits: usize, method: CompositionMethod) -> (f64, usize, usize) {
    let sys = Kepler { h: eps, k: 1.0 };
    let (r0, omega) = periapsis(e);
    let s0 = sys
        .reduced_state([r0, 0.0, 0.0], [0.0, omega, 1.0])
        .expect("the monitor is positive at periapsis");
    let end = TAU * orbits as f64;
    let mut evaluations = 0;
    let stop = |_: usize, _: f64, s: &ReducedState<1, 2>| s.g[1] >= end;
    let integ = ReducedIntegrator::plus(sys, options());
    let summary = if method.order > 2 {
        Composition::new(integ, method)
            .run(s0)
            .steps(usize::MAX / 2)
            .stop(stop)
            .observe(counter(&mut evaluations))
            .stream()
    } else {
        integ
            .run(s0)
            .steps(usize::MAX / 2)
            .stop(stop)
            .observe(counter(&mut evaluations))
            .stream()
    };
    match summary {
        Ok(s) => (
            (s.last.g[0] - exact_phase(e, s.last.g[1])).abs(),
            evaluations,
            s.step_count,
        ),
        Err(_) => (f64::INFINITY, evaluations, 0),
    }
}

fn main() {
    let mut cli = Cli::new(
        "adaptive_kepler",
        "work against precision of adaptive and fixed steps on Kepler's problem",
    );
    let orbits: usize = cli.value("--orbits", "N", "orbits of each run", 100, at_least(1));
    let tolerance_2: f64 = cli.value(
        "--tolerance-2",
        "TOL",
        "phase error the order-2 steps must reach",
        1e-4,
        greater_than(0.0),
    );
    let tolerance_4: f64 = cli.value(
        "--tolerance-4",
        "TOL",
        "phase error the order-4 compositions must reach",
        1e-6,
        greater_than(0.0),
    );
    let tolerance_6: f64 = cli.value(
        "--tolerance-6",
        "TOL",
        "phase error the order-6 compositions must reach",
        1e-6,
        greater_than(0.0),
    );
    let long: usize = cli.value(
        "--long",
        "N",
        "orbits of the long run at e = 0.9",
        100_000,
        at_least(10),
    );
    let max_per_orbit: usize = cli.value(
        "--max-per-orbit",
        "N",
        "largest fixed steps per orbit tried",
        1 << 18,
        at_least(64),
    );
    cli.finish();
    let debug = std::env::var_os("DEBUG_ADAPTIVE").is_some();

    for (method, label, tolerance) in [
        (CompositionMethod::BASE, "order 2", tolerance_2),
        (CompositionMethod::TRIPLE_JUMP, "order 4", tolerance_4),
        (CompositionMethod::KAHAN_LI_6, "order 6", tolerance_6),
    ] {
        println!(
            "{label}: phase error ≤ {tolerance:.0e} after {orbits} orbits — the coarsest step (halving) and its force evaluations"
        );
        for e in [0.9, 0.99] {
            let mut n = 64;
            let fixed = loop {
                let (err, evals) = fixed_run(e, n, orbits, method);
                if debug {
                    eprintln!("    fixed n = {n}: error {err:.3e}, {evals} evaluations");
                }
                if err <= tolerance {
                    break Ok((n, err, evals));
                }
                if n >= max_per_orbit {
                    break Err((n, err, evals));
                }
                n *= 2;
            };
            let mut eps = 0.4;
            let adaptive = loop {
                let (err, evals, steps) = adaptive_run(e, eps, orbits, method);
                if debug {
                    eprintln!("    adaptive ε = {eps}: error {err:.3e}, {steps} steps, {evals} evaluations");
                }
                if err <= tolerance {
                    break Some((eps, err, evals, steps));
                }
                if eps < 1e-4 {
                    break None;
                }
                eps /= 2.0;
            };
            match (fixed, adaptive) {
                (Ok((n, ef, vf)), Some((eps, ea, va, steps))) => println!(
                    "  e = {e}: fixed {n} steps/orbit, error {ef:.2e}, {vf} evaluations; adaptive ε = {eps}, {steps} steps, error {ea:.2e}, {va} evaluations; fixed / adaptive evaluations {:.1}",
                    vf as f64 / va as f64
                ),
                (Err((n, ef, vf)), Some((eps, ea, va, steps))) => println!(
                    "  e = {e}: fixed not within {n} steps/orbit (error {ef:.2e} with {vf} evaluations); adaptive ε = {eps}, {steps} steps, error {ea:.2e}, {va} evaluations; fixed / adaptive evaluations > {:.1}",
                    vf as f64 / va as f64
                ),
                (f, a) => println!("  e = {e}: fixed {f:?}, adaptive {a:?} (tolerance not reached)"),
            }
        }
    }

    // The long run: the energy error with no drift, the momenta bit for bit.
    let e = 0.9;
    let sys = Kepler { h: 0.05, k: 1.0 };
    let (r0, omega) = periapsis(e);
    let s0 = sys
        .reduced_state([r0, 0.0, 0.0], [0.0, omega, 1.0])
        .expect("the monitor is positive at periapsis");
    let energy = |s: &ReducedState<1, 2>| {
        let (r, pr, pt) = (s.x[0], s.w[0], s.mu[0]);
        0.5 * pr * pr + 0.5 * pt * pt / (r * r) - 1.0 / r
    };
    let (e0, end) = (energy(&s0), TAU * long as f64);
    let mut samples: Vec<(f64, f64)> = Vec::new();
    let mut changed = 0usize;
    let began = Instant::now();
    let summary = ReducedIntegrator::plus(sys, NewtonOptions::default())
        .run(s0)
        .steps(usize::MAX / 2)
        .stop(|_, _, s: &ReducedState<1, 2>| s.g[1] >= end)
        .observe(|_, _, s: &ReducedState<1, 2>, _| {
            changed += usize::from(s.mu != s0.mu);
            samples.push((s.g[1], energy(s) - e0));
        })
        .stream()
        .expect("the long run integrates");
    let seconds = began.elapsed().as_secs_f64();
    let tenth = |lo: f64, hi: f64| {
        let v: Vec<f64> = samples
            .iter()
            .filter(|(t, _)| *t >= lo * end && *t < hi * end)
            .map(|(_, d)| *d)
            .collect();
        let mean = v.iter().sum::<f64>() / v.len().max(1) as f64;
        let (min, max) = v
            .iter()
            .fold((f64::MAX, f64::MIN), |(a, b), &x| (a.min(x), b.max(x)));
        (mean, min, max)
    };
    let (m1, lo1, hi1) = tenth(0.0, 0.1);
    let (m2, lo2, hi2) = tenth(0.9, 1.01);
    println!(
        "Long run, e = 0.9, ε = 0.05, {long} orbits ({} steps, {seconds:.1} s): momenta changed at {changed} steps; energy error first tenth mean {m1:.3e} in [{lo1:.3e}, {hi1:.3e}], last tenth mean {m2:.3e} in [{lo2:.3e}, {hi2:.3e}]: {}",
        summary.step_count,
        if (lo1..=hi1).contains(&m2) { "no drift (the last mean lies in the first spread)" } else { "DRIFT" }
    );

    // Cost per step: the adaptive step (unknowns r, θ, t) against the fixed step (r, θ; by
    // default θ is eliminated in closed form, leaving Newton on r alone). The adaptive step moves
    // farther per step (its guess is extrapolated from farther back), so it takes more Newton
    // iterations: the cost per iteration compares the steps themselves.
    let timed = 200_000;
    let adaptive_sys = Kepler { h: 0.05, k: 1.0 };
    let adaptive0 = adaptive_sys
        .reduced_state([r0, 0.0, 0.0], [0.0, omega, 1.0])
        .expect("positive");
    let fixed_sys = KeplerFixed {
        h: TAU / 2000.0,
        k: 1.0,
    };
    let fixed0 = fixed_sys
        .reduced_state([r0, 0.0], [0.0, omega])
        .expect("a finite state");
    let adaptive_integ = ReducedIntegrator::plus(adaptive_sys, NewtonOptions::default());
    let general =
        ReducedIntegrator::plus(fixed_sys, NewtonOptions::default()).with_elimination(false);
    let eliminated = ReducedIntegrator::plus(fixed_sys, NewtonOptions::default());
    let per_step = |run: &dyn Fn() -> usize| {
        let began = Instant::now();
        let iterations = run();
        (
            began.elapsed().as_secs_f64() * 1e9 / timed as f64,
            iterations as f64 / timed as f64,
        )
    };
    let mut rows: [Vec<(f64, f64)>; 3] = Default::default();
    for _ in 0..5 {
        rows[0].push(per_step(&|| {
            let mut n = 0;
            let s = adaptive_integ
                .run(adaptive0)
                .steps(timed)
                .observe(counter(&mut n))
                .stream()
                .expect("runs");
            std::hint::black_box(&s.last);
            n
        }));
        rows[1].push(per_step(&|| {
            let mut n = 0;
            let s = general
                .run(fixed0)
                .steps(timed)
                .observe(counter(&mut n))
                .stream()
                .expect("runs");
            std::hint::black_box(&s.last);
            n
        }));
        rows[2].push(per_step(&|| {
            let mut n = 0;
            let s = eliminated
                .run(fixed0)
                .steps(timed)
                .observe(counter(&mut n))
                .stream()
                .expect("runs");
            std::hint::black_box(&s.last);
            n
        }));
    }
    let median = |v: &[(f64, f64)], f: &dyn Fn(&(f64, f64)) -> f64| {
        let mut x: Vec<f64> = v.iter().map(f).collect();
        x.sort_by(f64::total_cmp);
        x[x.len() / 2]
    };
    let ns = |i: usize| median(&rows[i], &|r| r.0);
    let it = |i: usize| median(&rows[i], &|r| r.1);
    let per_iteration = |i: usize| median(&rows[i], &|r| r.0 / r.1);
    println!(
        "Cost per step (median of 5 interleaved repeats of {timed} steps): adaptive {:.0} ns, {:.2} Newton iterations, {:.0} ns per iteration; fixed, Newton on (r, θ): {:.0} ns, {:.2}, {:.0}; fixed, θ eliminated: {:.0} ns, {:.2}, {:.0}. Ratio per step {:.2} and {:.2}, per iteration {:.2} and {:.2}",
        ns(0), it(0), per_iteration(0), ns(1), it(1), per_iteration(1), ns(2), it(2), per_iteration(2),
        ns(0) / ns(1), ns(0) / ns(2), per_iteration(0) / per_iteration(1), per_iteration(0) / per_iteration(2)
    );
}
