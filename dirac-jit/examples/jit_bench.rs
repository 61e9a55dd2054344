//! Systems given at run time against the same systems compiled in: how long the text takes to
//! become machine code, and a step's time against the attribute's, interleaved in one run.
//!
//! ```text
//! cargo run --release --manifest-path dirac-jit/Cargo.toml --example jit_bench -- [--rounds 7] [--steps 20000]
//! ```
//!
//! The double spherical pendulum and the charged particle of the paper (§7), from the text of
//! the facade's own sources; the 200-particle Toda lattice of the examples (sparse backend); and
//! the scaling benchmark's 32-link chain on a cart, in its angles and in maximal coordinates with
//! one constraint per link (compile times); the heavy top on `SO(3)` and the pendulum on
//! `S² × S²` (systems on rotation groups); the Toda lattice sized at run time, at n = 1000
//! (an element-wise system). Each round compiles the text once and runs both integrators for
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

/// Seconds per step of a streamed reduced (+) run of `sys` from `start`, over `steps` steps.
fn stream_time<L, const S: usize, const K: usize, const N: usize>(
    sys: &L,
    start: ReducedState<S, K>,
    steps: usize,
) -> f64
where
    L: Reduced<Plus, S, K, N> + Clone,
{
    let t = Instant::now();
    let s = ReducedIntegrator::plus(sys.clone(), NewtonOptions::default())
        .run(start)
        .steps(steps)
        .stream();
    std::hint::black_box(s.expect("the run completes"));
    t.elapsed().as_secs_f64() / steps as f64
}

/// Per round: the compile time, the seconds per step given at run time and compiled in, and
/// their ratio.
struct Rounds {
    compile: Vec<f64>,
    jit_t: Vec<f64>,
    aot_t: Vec<f64>,
    ratio: Vec<f64>,
}

/// `rounds` rounds, each compiling `text`, instantiating it with `instantiate` and timing its
/// steps from `start` and those of the compiled-in `aot`, the one given at run time first in
/// even rounds.
fn against_compiled_in<J, L, const S: usize, const K: usize, const N: usize>(
    text: &str,
    rounds: usize,
    instantiate: impl Fn(&std::sync::Arc<dirac_jit::Code>) -> Result<J, dirac_jit::Error>,
    aot: &L,
    start: ReducedState<S, K>,
    steps: usize,
) -> Result<Rounds, dirac_jit::Error>
where
    J: Reduced<Plus, S, K, N> + Clone,
    L: Reduced<Plus, S, K, N> + Clone,
{
    Rounds::interleaved(
        rounds,
        || {
            let code = dirac_jit::compile(text)?;
            Ok((code.compile_time().as_secs_f64(), instantiate(&code)?))
        },
        |jit| stream_time(jit, start, steps),
        || stream_time(aot, start, steps),
    )
}

impl Rounds {
    /// `rounds` rounds, each compiling a text (`compile` returns the compile time and the
    /// system given at run time) and timing its steps (`jit`) and the compiled-in system's
    /// (`aot`), the one given at run time first in even rounds.
    fn interleaved<T, E>(
        rounds: usize,
        mut compile: impl FnMut() -> Result<(f64, T), E>,
        jit: impl Fn(&T) -> f64,
        aot: impl Fn() -> f64,
    ) -> Result<Rounds, E> {
        let mut r = Rounds {
            compile: vec![],
            jit_t: vec![],
            aot_t: vec![],
            ratio: vec![],
        };
        for round in 0..rounds {
            let (seconds, system) = compile()?;
            r.compile.push(seconds);
            let (j, a) = if round.is_multiple_of(2) {
                let j = jit(&system);
                (j, aot())
            } else {
                let a = aot();
                (jit(&system), a)
            };
            r.jit_t.push(j);
            r.aot_t.push(a);
            r.ratio.push(j / a);
        }
        Ok(r)
    }
}

/// The medians of [`Rounds`], with the fastest compilation and the spread of the ratios.
struct Summary {
    compile: f64,
    compile_min: f64,
    jit: f64,
    aot: f64,
    ratio: f64,
    ratio_min: f64,
    ratio_max: f64,
}

impl Rounds {
    fn summary(mut self) -> Summary {
        let (ratio_min, ratio_max) = range(&self.ratio);
        Summary {
            compile_min: range(&self.compile).0,
            compile: median(&mut self.compile),
            jit: median(&mut self.jit_t),
            aot: median(&mut self.aot_t),
            ratio: median(&mut self.ratio),
            ratio_min,
            ratio_max,
        }
    }
}

/// The smallest and largest of `v`.
fn range(v: &[f64]) -> (f64, f64) {
    (
        v.iter().copied().fold(f64::INFINITY, f64::min),
        v.iter().copied().fold(0.0, f64::max),
    )
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let rounds = arg("--rounds", 7);
    let steps = arg("--steps", 20_000);
    let opts = NewtonOptions::default();
    println!("{rounds} rounds of {steps} steps; medians, with the min–max of per-round ratios");
    // The double spherical pendulum.
    let text = function(PAPER, "double_spherical_pendulum");
    let aot = DoubleSphericalPendulum::paper();
    let r = against_compiled_in(
        &text,
        rounds,
        |code| code.instantiate::<3, 1, 4>(&aot.parameter_values()),
        &aot,
        DoubleSphericalPendulum::paper_initial_state(),
        steps,
    )?
    .summary();
    println!(
        "double spherical pendulum: text → machine code {:.1} ms (min {:.1}); step {:.2} µs given at run time, {:.2} µs compiled in: ratio {:.2} ({:.2}–{:.2})",
        r.compile * 1e3,
        r.compile_min * 1e3,
        r.jit * 1e6,
        r.aot * 1e6,
        r.ratio,
        r.ratio_min,
        r.ratio_max,
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
    let j = stream_time(&jit, start, steps);
    let a = stream_time(&aot, start, steps);
    println!(
        "charged particle: text → machine code {:.1} ms; step {:.3} µs given at run time, {:.3} µs compiled in (one round: ratio {:.2})",
        median(&mut compile) * 1e3,
        j * 1e6,
        a * 1e6,
        j / a
    );
    lattice(rounds, steps / 20)?;
    chain(rounds)?;
    rotations(rounds, steps)?;
    elements(rounds, steps / 100)?;
    Ok(())
}

/// The examples' Toda lattice sized at run time.
#[path = "../../examples/common/toda_n.rs"]
mod toda_n;

const TODA_N: &str = include_str!("../../examples/common/toda_n.rs");

/// Seconds per step of a streamed element-wise run.
fn element_time<L: dirac::runtime::element::ElementLagrangian>(
    sys: &L,
    start: &dirac::runtime::element::ElementState,
    steps: usize,
) -> f64 {
    let t = Instant::now();
    let s = dirac::runtime::element::ElementIntegrator::new(sys.clone(), NewtonOptions::default())
        .run(start.clone())
        .steps(steps)
        .stream();
    std::hint::black_box(s.expect("the run completes"));
    t.elapsed().as_secs_f64() / steps as f64
}

/// The Toda lattice sized at run time: compile time, and its steps at n = 1000 against the
/// compiled-in lattice's, interleaved.
fn elements(rounds: usize, steps: usize) -> Result<(), Box<dyn std::error::Error>> {
    let text = function(TODA_N, "toda_n");
    let aot = toda_n::TodaN {
        m: 1.0,
        d: 1.0,
        h: 0.05,
        n: 1000,
    };
    let start = toda_n::initial(&aot, 0.1, 0.2, 0.05);
    let r = Rounds::interleaved(
        rounds,
        || {
            let code = dirac_jit::compile_element(&text)?;
            let jit = code.instantiate(&[1.0, 1.0, 0.05], &[1000])?;
            Ok::<_, dirac_jit::Error>((code.compile_time().as_secs_f64(), jit))
        },
        |jit| element_time(jit, &start, steps),
        || element_time(&aot, &start, steps),
    )?
    .summary();
    println!(
        "Toda lattice sized at run time (n = 1000): text → machine code {:.1} ms (min {:.1}); step {:.1} µs given at run time, {:.1} µs compiled in: ratio {:.2} ({:.2}–{:.2})",
        r.compile * 1e3,
        r.compile_min * 1e3,
        r.jit * 1e6,
        r.aot * 1e6,
        r.ratio,
        r.ratio_min,
        r.ratio_max,
    );
    Ok(())
}

const ROTATIONS: &str = include_str!("../../src/systems/rotations.rs");

/// Seconds per step of a streamed run of the Lie group variational integrator.
fn lie_time<L: LieLagrangian<P, N>, const P: usize, const N: usize>(
    sys: &L,
    start: LieState<P, N>,
    steps: usize,
) -> f64 {
    let t = Instant::now();
    let s = LieIntegrator::new(sys.clone(), NewtonOptions::default())
        .run(start)
        .steps(steps)
        .stream();
    std::hint::black_box(s.expect("the run completes"));
    t.elapsed().as_secs_f64() / steps as f64
}

/// Seconds per step of a streamed run of the Lie group variational integrator on a system at
/// the sizes its text declares (`Dyn`).
fn dyn_lie_time(
    sys: &dirac_jit::DynJitLie,
    start: &dirac::runtime::lie::DynLieState,
    steps: usize,
) -> f64 {
    let t = Instant::now();
    let s = dirac::runtime::lie::LieIntegratorOf::new(sys.clone(), NewtonOptions::default())
        .run(start.clone())
        .steps(steps)
        .stream();
    std::hint::black_box(s.expect("the run completes"));
    t.elapsed().as_secs_f64() / steps as f64
}

/// A system on rotation groups: `rounds` compilations of its text, and its steps against the
/// compiled-in system's, interleaved: at fixed sizes (the instances the front ends dispatch
/// small systems to), then at the sizes the text declares (`Dyn`, what they run any other size
/// at).
fn lie_rounds<L: LieLagrangian<P, N>, const P: usize, const N: usize>(
    name: &str,
    rounds: usize,
    steps: usize,
    aot: &L,
    start: LieState<P, N>,
) -> Result<(), Box<dyn std::error::Error>> {
    let text = function(ROTATIONS, name);
    let r = Rounds::interleaved(
        rounds,
        || {
            let code = dirac_jit::compile_lie(&text)?;
            let jit = code.instantiate::<P, N>(&aot.parameter_values())?;
            Ok::<_, dirac_jit::Error>((code.compile_time().as_secs_f64(), jit))
        },
        |jit| lie_time(jit, start, steps),
        || lie_time(aot, start, steps),
    )?
    .summary();
    println!(
        "{name} (rotation groups): text → machine code {:.1} ms (min {:.1}); step {:.2} µs given at run time, {:.2} µs compiled in: ratio {:.2} ({:.2}–{:.2})",
        r.compile * 1e3,
        r.compile_min * 1e3,
        r.jit * 1e6,
        r.aot * 1e6,
        r.ratio,
        r.ratio_min,
        r.ratio_max,
    );
    let dyn_start = dirac::runtime::lie::DynLieState {
        q: dirac::runtime::nalgebra::DVector::from_column_slice(start.q.as_slice()),
        p: dirac::runtime::nalgebra::DVector::from_column_slice(start.p.as_slice()),
    };
    let r = Rounds::interleaved(
        rounds,
        || {
            let code = dirac_jit::compile_lie(&text)?;
            let jit = code.instantiate_dyn(&aot.parameter_values())?;
            Ok::<_, dirac_jit::Error>((code.compile_time().as_secs_f64(), jit))
        },
        |jit| dyn_lie_time(jit, &dyn_start, steps),
        || lie_time(aot, start, steps),
    )?
    .summary();
    println!(
        "{name} (rotation groups) at run-time sizes: step {:.2} µs given at run time, {:.2} µs compiled in: ratio {:.2} ({:.2}–{:.2})",
        r.jit * 1e6,
        r.aot * 1e6,
        r.ratio,
        r.ratio_min,
        r.ratio_max,
    );
    Ok(())
}

/// The heavy top on `SO(3)` and the paper's pendulum on `S² × S²`, from the facade's sources.
fn rotations(rounds: usize, steps: usize) -> Result<(), Box<dyn std::error::Error>> {
    use dirac::runtime::lie::cayley;
    use dirac::systems::rotations::{DspOnSpheres, HeavyTop, HeavyTopConfig, HeavyTopMomentum};
    let top = HeavyTop {
        h: 0.01,
        j1: 1.0,
        j2: 1.0,
        j3: 0.5,
        mgl: 2.0,
    };
    let start = top.state(
        &HeavyTopConfig {
            r: cayley(&Vector3::new(0.4, -0.1, 0.2)),
        },
        &HeavyTopMomentum {
            r: Vector3::new(0.2, -0.1, 3.0),
        },
    );
    lie_rounds("heavy_top", rounds, steps, &top, start)?;
    let dsp = DspOnSpheres::paper(0.01);
    lie_rounds(
        "dsp_on_spheres",
        rounds,
        steps,
        &dsp,
        dsp.paper_initial_state(),
    )
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
    let r = against_compiled_in(
        &text,
        rounds,
        |code| code.instantiate_sparse::<199, 1, 200>(&[1.0, 1.0, 0.05]),
        &aot,
        toda::initial(&aot, 0.1, 0.3, 0.05),
        steps,
    )?
    .summary();
    println!(
        "200-particle Toda lattice (sparse backend): text → machine code {:.0} ms; step {:.1} µs given at run time, {:.1} µs compiled in: ratio {:.2} ({:.2}–{:.2})",
        r.compile * 1e3,
        r.jit * 1e6,
        r.aot * 1e6,
        r.ratio,
        r.ratio_min,
        r.ratio_max,
    );
    Ok(())
}

/// The scaling benchmark's chain (`benches/scaling/chain.rs.in`) at 32 links: pendulum links
/// hanging from a cart on a rail, in the links' angles (the cart's position the symmetry),
/// midpoint rule, a dense 33 × 33 step Jacobian. Then the same 32 links in maximal coordinates
/// (the example `maximal_chain`: every link's end point a coordinate, one length constraint per
/// link), whose constrained solves have 97 unknowns on the sparse backend. Compile times over
/// `rounds` compilations, and a short run of each.
fn chain(rounds: usize) -> Result<(), Box<dyn std::error::Error>> {
    let links = 32;
    let angles = include_str!("../../benches/scaling/chain.rs.in")
        .replace("@NU@", &(links + 1).to_string())
        .replace("@N@", &links.to_string());
    let maximal = format!(
        "#[reduced_lagrangian(shape(c, x[{links}], y[{links}]), group(), rule = midpoint,
             constraints = |q| {{
                 let mut phi = [0.0; {links}];
                 phi[0] = (q.x[0] - q.c) * (q.x[0] - q.c) + q.y[0] * q.y[0] - l * l;
                 for i in 1..{links} {{
                     let (dx, dy) = (q.x[i] - q.x[i - 1], q.y[i] - q.y[i - 1]);
                     phi[i] = dx * dx + dy * dy - l * l;
                 }}
                 phi
             }})]
         fn chain(q: Config, v: Velocity, mc: f64, m: f64, l: f64, gr: f64) -> f64 {{
             let mut t = 0.5 * mc * v.c * v.c;
             let mut u = 0.0;
             for i in 0..{links} {{
                 t += 0.5 * m * (v.x[i] * v.x[i] + v.y[i] * v.y[i]);
                 u += m * gr * q.y[i];
             }}
             t - u
         }}"
    );
    let compile_times = |text: &str| -> Result<_, dirac_jit::Error> {
        let mut times = vec![];
        let mut last = None;
        for _ in 0..rounds {
            let code = dirac_jit::compile(text)?;
            times.push(code.compile_time().as_secs_f64() * 1e3);
            last = Some(code);
        }
        let spread = (
            median(&mut times.clone()),
            times.iter().copied().fold(f64::INFINITY, f64::min),
            times.iter().copied().fold(0.0, f64::max),
        );
        Ok((last.expect("at least one round"), spread))
    };
    // θ_i = 0.3 sin(i + 1) from the vertical, the cart at 0, at rest (the benchmark's state).
    let theta = |i: usize| 0.3 * ((i + 1) as f64).sin();
    let steps = 200;

    let (code, (median_ms, min_ms, max_ms)) = compile_times(&angles)?;
    let nnz = code
        .system()
        .plus
        .stepper
        .pattern
        .as_ref()
        .map_or(0, |p| p.row_idx.len());
    let sys = code.instantiate_sparse_named::<32, 1, 33>(&[
        ("mc", 1.0),
        ("m", 1.0),
        ("l", 1.0),
        ("gr", 9.81),
        ("h", 0.01),
    ])?;
    let start = ReducedState::new(
        std::array::from_fn::<f64, 32, _>(theta),
        [0.0; 32],
        [0.0],
        [0.0],
    );
    let t = Instant::now();
    let traj = ReducedIntegrator::plus(sys, NewtonOptions::default())
        .run(start)
        .steps(steps)
        .collect()
        .map_err(|e| e.to_string())?;
    let step = t.elapsed().as_secs_f64() / steps as f64;
    println!(
        "{links}-link chain on a cart, angles (33 coordinates, {nnz} Jacobian nonzeros): text → machine code {median_ms:.0} ms (min {min_ms:.0}, max {max_ms:.0}); step {:.1} µs, μ kept: {}",
        step * 1e6,
        traj.last().mu == start.mu
    );

    let (code, (median_ms, min_ms, max_ms)) = compile_times(&maximal)?;
    let constrained = code.system().constrained.as_ref().expect("constraints");
    let nnz = constrained
        .unreduced
        .position
        .pattern
        .as_ref()
        .map_or(0, |p| p.row_idx.len());
    let sys =
        code.instantiate_constrained_sparse::<65, 0, 65, 32, 97>(&[1.0, 1.0, 1.0, 9.81, 0.01])?;
    let mut q = SVector::<f64, 65>::zeros();
    let (mut x, mut y) = (0.0, 0.0);
    for i in 0..links {
        x += theta(i).sin();
        y -= theta(i).cos();
        q[1 + i] = x;
        q[1 + links + i] = y;
    }
    let t = Instant::now();
    let traj = ConstrainedIntegrator::new(sys, NewtonOptions::default())
        .run(UnreducedState {
            q,
            p: SVector::zeros(),
        })
        .steps(steps)
        .collect()
        .map_err(|e| e.to_string())?;
    let step = t.elapsed().as_secs_f64() / steps as f64;
    println!(
        "{links}-link chain, maximal coordinates (65 coordinates, 32 constraints, 97 unknowns, {nnz} nonzeros): text → machine code {median_ms:.0} ms (min {min_ms:.0}, max {max_ms:.0}); step {:.1} µs, largest |φ| {:.1e}",
        step * 1e6,
        traj.max_constraint_residual()
    );
    Ok(())
}
