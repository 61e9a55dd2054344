//! Systems given at run time against the same systems compiled in: how long the text takes to
//! become machine code, and a step's time against the attribute's, interleaved in one run.
//!
//! ```text
//! cargo run --release --manifest-path dirac-jit/Cargo.toml --example jit_bench -- [--rounds 7] [--steps 20000]
//! ```
//!
//! The double spherical pendulum and the charged particle of the paper (§7), from the text of
//! the facade's own sources; the 200-particle Toda lattice of the examples (sparse backend); and
//! a 32-link chain on a cart (compile time). Each round compiles the text once and runs both integrators for
//! `--steps` steps, alternating which goes first; the medians over rounds are printed with the
//! spread (min–max) of the per-round ratios.

use std::time::Instant;

use dirac::paper::{ChargedParticle, DoubleSphericalPendulum};
use dirac::prelude::*;

const PAPER: &str = include_str!("../../src/paper.rs");
const TODA: &str = include_str!("../../examples/common/toda.rs");

/// The compiled-in 200-particle Toda lattice of the examples.
#[path = "../../examples/common/toda.rs"]
mod toda;

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
    lattice(rounds, steps / 20)?;
    chain(rounds)?;
    Ok(())
}

/// The 200-particle Toda lattice of the examples, on the sparse backend: compile time, and the
/// step against the compiled-in lattice's, interleaved.
fn lattice(rounds: usize, steps: usize) -> Result<(), Box<dyn std::error::Error>> {
    let text = function(TODA, "toda");
    let aot = toda::Toda {
        m: 1.0,
        d: 1.0,
        h: 0.05,
    };
    let start = toda::initial(&aot, 0.1, 0.3, 0.05);
    let opts = NewtonOptions::default();
    let (mut compile, mut jit_t, mut aot_t, mut ratio) = (vec![], vec![], vec![], vec![]);
    for round in 0..rounds {
        let code = dirac_jit::compile(&text)?;
        compile.push(code.compile_time().as_secs_f64());
        let jit = code.instantiate_sparse::<199, 1, 200>(&[1.0, 1.0, 0.05])?;
        let run_jit = || {
            time(steps, || {
                let s = ReducedIntegrator::plus(jit.clone(), opts)
                    .run(start)
                    .steps(steps)
                    .stream();
                std::hint::black_box(s.expect("the run completes"));
            })
        };
        let run_aot = || {
            time(steps, || {
                let s = ReducedIntegrator::plus(aot, opts)
                    .run(start)
                    .steps(steps)
                    .stream();
                std::hint::black_box(s.expect("the run completes"));
            })
        };
        let (j, a) = if round % 2 == 0 {
            let j = run_jit();
            (j, run_aot())
        } else {
            let a = run_aot();
            (run_jit(), a)
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
        "200-particle Toda lattice (sparse backend): text → machine code {:.0} ms; step {:.1} µs given at run time, {:.1} µs compiled in: ratio {:.2} ({lo:.2}–{hi:.2})",
        median(&mut compile) * 1e3,
        median(&mut jit_t) * 1e6,
        median(&mut aot_t) * 1e6,
        median(&mut ratio),
    );
    Ok(())
}

/// A planar chain of 32 pendulum links hanging from a cart on a rail, in the links' angles
/// (the cart's position the symmetry), midpoint rule: a dense 33 × 33 step Jacobian. Compile
/// time, and a short run.
fn chain(rounds: usize) -> Result<(), Box<dyn std::error::Error>> {
    let links = 32;
    let text = format!(
        "#[reduced_lagrangian(shape(th[{links}]), group(x), rule = midpoint)]
         fn chain(q: Config, v: Velocity, mc: f64, m: f64, l: f64, gr: f64) -> f64 {{
             let mut lag = 0.5 * mc * v.x * v.x;
             let (mut vx, mut vy, mut y) = (v.x, 0.0, 0.0);
             for i in 0..{links} {{
                 vx += l * q.th[i].cos() * v.th[i];
                 vy += l * q.th[i].sin() * v.th[i];
                 y -= l * q.th[i].cos();
                 lag += 0.5 * m * (vx * vx + vy * vy) - m * gr * y;
             }}
             lag
         }}"
    );
    let mut compile = vec![];
    let mut last = None;
    for _ in 0..rounds {
        let code = dirac_jit::compile(&text)?;
        compile.push(code.compile_time().as_secs_f64());
        last = Some(code);
    }
    let code = last.expect("at least one round");
    let pattern = code.system().plus.stepper.pattern.as_ref();
    let nnz = pattern.map_or(0, |p| p.row_idx.len());
    let sys = code.instantiate_sparse::<32, 1, 33>(&[1.0, 0.1, 0.1, 9.81, 0.002])?;
    let mut x = [0.0; 32];
    x[0] = 0.2;
    let start = ReducedState::new(x, [0.0; 32], [0.0], [0.0]);
    let steps = 200;
    let t = Instant::now();
    let traj = ReducedIntegrator::plus(sys, NewtonOptions::default())
        .run(start)
        .steps(steps)
        .collect()
        .map_err(|e| e.to_string())?;
    let step = t.elapsed().as_secs_f64() / steps as f64;
    println!(
        "{links}-link chain on a cart (33 coordinates, {nnz} Jacobian nonzeros): text → machine code {:.0} ms (min {:.0}, max {:.0}); step {:.1} µs, μ kept: {}",
        median(&mut compile.clone()) * 1e3,
        compile.iter().copied().fold(f64::INFINITY, f64::min) * 1e3,
        compile.iter().copied().fold(0.0, f64::max) * 1e3,
        step * 1e6,
        traj.last().mu == start.mu
    );
    Ok(())
}
