//! Systems given at run time against the same systems compiled in: how long the text takes to
//! become machine code, and a step's time against the attribute's, interleaved in one run.
//!
//! ```text
//! cargo run --release --manifest-path dirac-jit/Cargo.toml --example jit_bench -- [--rounds 7] [--steps 20000]
//! ```
//!
//! The double spherical pendulum and the charged particle of the paper (§7), from the text of
//! the facade's own sources. Each round compiles the text once and runs both integrators for
//! `--steps` steps, alternating which goes first; the medians over rounds are printed with the
//! spread (min–max) of the per-round ratios.

use std::time::Instant;

use dirac::paper::{ChargedParticle, DoubleSphericalPendulum};
use dirac::prelude::*;

const PAPER: &str = include_str!("../../src/paper.rs");

fn function(source: &str, name: &str) -> String {
    let start = source
        .find(&format!("pub fn {name}("))
        .expect("the function is in the source");
    // Back to the attribute line above the function (and its `#[allow]`, if any).
    let attr = source[..start]
        .rfind("#[reduced_lagrangian")
        .expect("the function has the attribute");
    // The body ends at the first line that is a lone `}` after the signature.
    let end = start + source[start..].find("\n}\n").expect("the body ends") + 2;
    source[attr..end].to_owned()
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn arg(name: &str, default: usize) -> usize {
    let args: Vec<String> = std::env::args().collect();
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1))
        .map_or(default, |v| v.parse().expect("a number"))
}

/// Seconds per step of `run`, over `steps` steps.
fn time(steps: usize, run: impl FnOnce()) -> f64 {
    let t = Instant::now();
    run();
    t.elapsed().as_secs_f64() / steps as f64
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let rounds = arg("--rounds", 7);
    let steps = arg("--steps", 20_000);
    let opts = NewtonOptions::default();
    println!("{rounds} rounds of {steps} steps; medians, with the min–max of per-round ratios");
    // The double spherical pendulum.
    let text = function(PAPER, "double_spherical_pendulum");
    let (mut compile, mut jit_t, mut aot_t, mut ratio) = (vec![], vec![], vec![], vec![]);
    for round in 0..rounds {
        let code = dirac_jit::compile(&text)?;
        compile.push(code.compile_time().as_secs_f64());
        let aot = DoubleSphericalPendulum::paper();
        let jit = code.instantiate::<3, 1, 4>(&aot.parameter_values())?;
        let start = DoubleSphericalPendulum::paper_initial_state();
        let run_jit = || {
            let s = ReducedIntegrator::plus(jit.clone(), opts)
                .run(start)
                .steps(steps)
                .stream();
            std::hint::black_box(s.expect("the run completes"));
        };
        let run_aot = || {
            let s = ReducedIntegrator::plus(aot, opts)
                .run(start)
                .steps(steps)
                .stream();
            std::hint::black_box(s.expect("the run completes"));
        };
        let (j, a) = if round % 2 == 0 {
            let j = time(steps, run_jit);
            (j, time(steps, run_aot))
        } else {
            let a = time(steps, run_aot);
            (time(steps, run_jit), a)
        };
        jit_t.push(j);
        aot_t.push(a);
        ratio.push(j / a);
    }
    let (lo, hi) = (
        ratio.iter().copied().fold(f64::INFINITY, f64::min),
        ratio.iter().copied().fold(0.0, f64::max),
    );
    println!(
        "double spherical pendulum: text → machine code {:.1} ms (min {:.1}); step {:.2} µs given at run time, {:.2} µs compiled in: ratio {:.2} ({lo:.2}–{hi:.2})",
        median(&mut compile.clone()) * 1e3,
        compile.iter().copied().fold(f64::INFINITY, f64::min) * 1e3,
        median(&mut jit_t) * 1e6,
        median(&mut aot_t) * 1e6,
        median(&mut ratio),
    );
    // A collected run of 10⁴ steps of the text's system, what a Python `run` wraps
    // (dirac-py/examples/overhead.py times that).
    let code = dirac_jit::compile(&text)?;
    let aot = DoubleSphericalPendulum::paper();
    let jit = code.instantiate::<3, 1, 4>(&aot.parameter_values())?;
    let start = DoubleSphericalPendulum::paper_initial_state();
    let mut collected: Vec<f64> = (0..rounds.max(15))
        .map(|_| {
            let t = Instant::now();
            let traj = ReducedIntegrator::plus(jit.clone(), opts)
                .run(start)
                .steps(10_000)
                .collect()
                .expect("the run completes");
            std::hint::black_box(traj);
            t.elapsed().as_secs_f64()
        })
        .collect();
    let (lo, hi) = (
        collected.iter().copied().fold(f64::INFINITY, f64::min),
        collected.iter().copied().fold(0.0, f64::max),
    );
    println!(
        "double spherical pendulum given at run time, 10⁴ steps collected: median {:.2} ms (min {:.2}, max {:.2})",
        median(&mut collected) * 1e3,
        lo * 1e3,
        hi * 1e3
    );
    // The charged particle: compile time only (its step is a few hundred nanoseconds).
    let text = function(PAPER, "charged_particle");
    let mut compile: Vec<f64> = (0..rounds)
        .map(|_| {
            dirac_jit::compile(&text)
                .map(|c| c.compile_time().as_secs_f64())
                .expect("the text compiles")
        })
        .collect();
    let aot = ChargedParticle::paper(200);
    let code = dirac_jit::compile(&text)?;
    let jit = code.instantiate::<3, 1, 4>(&aot.parameter_values())?;
    let start = ChargedParticle::paper_initial_state();
    let j = time(steps, || {
        let s = ReducedIntegrator::plus(jit, opts)
            .run(start)
            .steps(steps)
            .stream();
        std::hint::black_box(s.expect("the run completes"));
    });
    let a = time(steps, || {
        let s = ReducedIntegrator::plus(aot, opts)
            .run(start)
            .steps(steps)
            .stream();
        std::hint::black_box(s.expect("the run completes"));
    });
    println!(
        "charged particle: text → machine code {:.1} ms; step {:.3} µs given at run time, {:.3} µs compiled in (one round: ratio {:.2})",
        median(&mut compile) * 1e3,
        j * 1e6,
        a * 1e6,
        j / a
    );
    Ok(())
}
