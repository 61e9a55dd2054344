//! Articulated rigid bodies from URDF, stepped through their system text: the 7-DoF KUKA iiwa
//! arm of `examples/data/iiwa14.urdf` (its text's size, the compile time, the step time, the
//! energy error and Newton's iterations), then chains of 5 to 40 links built in Rust, to show
//! how a step's cost grows with the number of joints.
//!
//! ```text
//! cargo run --release --manifest-path dirac-io/Cargo.toml --target-dir target -p dirac-jit \
//!     --example urdf_arm -- [--steps 10000] [--h 0.001] [--no-chains] [--machine]
//! ```
//!
//! `--h` changes the iiwa's step (seconds; the chains keep 1 ms). `--machine` adds two lines of JSON for the MuJoCo comparison (`benches/mujoco/run.sh`): the
//! iiwa's start (angles, rates, kinetic and potential energy, mass matrix), and the run's figures
//! (step time, Newton iterations, the energy's largest error and its drift: the mean of
//! `E − E₀` over the last tenth of the nodes less that over the first tenth; the last angles).
//!
//! A fixed-base tree is stepped in its joint angles with the midpoint rule: the step's
//! Jacobian is the dense `n × n` matrix `D1 D2 L_d`, so a Newton iteration assembles `O(n²)`
//! entries (each a straight line through the tree) and factors it in `O(n³)`; the chains show
//! the slope this gives at these sizes.

use std::time::{Duration, Instant};

use dirac_jit::{compile_model, Compiled};
use dirac_multibody::nalgebra::{Matrix3, Vector3};
use dirac_multibody::{Inertial, JointSpec, Model, Pose, TextOptions};
use dirac_runtime::prelude::*;

/// The command line's options.
struct Args {
    steps: usize,
    h: f64,
    chains: bool,
    machine: bool,
}

fn args() -> Args {
    let mut args = Args {
        steps: 10_000,
        h: 1e-3,
        chains: true,
        machine: false,
    };
    let mut it = std::env::args().skip(1);
    while let Some(a) = it.next() {
        match a.as_str() {
            "--steps" => {
                args.steps = it
                    .next()
                    .and_then(|s| s.parse().ok())
                    .expect("--steps takes a number")
            }
            "--h" => {
                args.h = it
                    .next()
                    .and_then(|s| s.parse().ok())
                    .filter(|h: &f64| h.is_finite() && *h > 0.0)
                    .expect("--h takes a positive number of seconds")
            }
            "--no-chains" => args.chains = false,
            "--machine" => args.machine = true,
            other => panic!("unknown argument {other}"),
        }
    }
    args
}

/// A chain of `n` rods hanging from the world, 0.5 m apart, hinged alternately about `y` and
/// `x` so that it swings in 3-D.
fn chain(n: usize) -> Model {
    let rod = Inertial::new(
        1.0,
        Vector3::new(0.0, 0.0, -0.25),
        Matrix3::from_diagonal(&Vector3::new(0.02, 0.02, 0.002)),
    );
    let mut b = Model::builder().frame("l0");
    for i in 1..=n {
        let axis = if i % 2 == 1 {
            Vector3::y()
        } else {
            Vector3::x()
        };
        let at = if i == 1 { 0.0 } else { -0.5 };
        b = b.body(format!("l{i}"), rod).joint(
            JointSpec::revolute(
                format!("j{i}"),
                format!("l{}", i - 1),
                format!("l{i}"),
                axis,
            )
            .at(Pose::from_translation(Vector3::new(0.0, 0.0, at))),
        );
    }
    b.build().expect("a chain is a tree")
}

/// What one run measured.
struct Measured {
    compile: Duration,
    per_step: Duration,
    /// The whole run's time, for a per-step figure finer than `per_step`'s nanoseconds.
    run: Duration,
    iterations: f64,
    energy_error: f64,
    /// The mean of `E − E₀` over the last tenth of the nodes less that over the first tenth.
    energy_drift: f64,
    /// The joint angles at the last node.
    q_end: Vec<f64>,
}

/// Compiles the model and runs `steps` steps of `h` from the angles `q0` and rates `v0`
/// (`N` joints; the dense backend up to 16, the sparse one above).
macro_rules! measure {
    ($model:expr, $n:literal, $instantiate:ident, $h:expr, $steps:expr, $q0:expr, $v0:expr) => {{
        let started = Instant::now();
        let code = compile_model(&$model, &TextOptions::default()).expect("the model compiles");
        let compile = started.elapsed();
        let Compiled::Flat(flat) = &code.compiled else {
            unreachable!("a fixed base")
        };
        let sys = flat
            .$instantiate::<$n, 0, $n>(&[$h])
            .expect("the dimensions");
        let start = sys
            .unreduced_state::<$n, 0>($q0, $v0)
            .expect("a finite start");
        let integ = UnreducedIntegrator::new(sys, NewtonOptions::default());
        let started = Instant::now();
        let traj = integ.run(start).steps($steps).collect().expect("the steps");
        let run = started.elapsed();
        let per_step = run / $steps as u32;
        let energies = integ.energies(&traj).expect("a regular Lagrangian").nodes;
        let e0 = energies[0];
        let energy_error = energies.iter().map(|e| (e - e0).abs()).fold(0.0, f64::max);
        let tenth = (energies.len() / 10).max(1);
        let mean = |es: &[f64]| es.iter().map(|e| e - e0).sum::<f64>() / es.len() as f64;
        let energy_drift = mean(&energies[energies.len() - tenth..]) - mean(&energies[..tenth]);
        let iterations =
            traj.stats.iter().map(|s| s.iterations as f64).sum::<f64>() / traj.stats.len() as f64;
        (
            code,
            Measured {
                compile,
                per_step,
                run,
                iterations,
                energy_error,
                energy_drift,
                q_end: traj
                    .states
                    .last()
                    .expect("a start")
                    .q
                    .iter()
                    .copied()
                    .collect(),
            },
        )
    }};
}

fn main() {
    let Args {
        steps,
        h,
        chains,
        machine,
    } = args();
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/data/iiwa14.urdf");
    let iiwa = Model::from_urdf_file(path).expect("the iiwa URDF reads");
    let q0 = [0.3, 0.5, -0.2, -1.2, 0.4, 0.7, -0.1];
    let v0 = [0.5, -0.4, 0.8, 0.6, -1.0, 0.9, 1.5];
    let (code, m) = measure!(iiwa, 7, instantiate, h, steps, q0, v0);
    let config = iiwa
        .configuration_from_scalars(&q0)
        .expect("a configuration");
    let kinetic = iiwa.kinetic_energy(&config, &v0).expect("a velocity");
    let potential = iiwa.potential_energy(&config).expect("a configuration");
    let energy = kinetic + potential;
    println!(
        "iiwa14 (7 revolute joints, h = {} ms, {steps} steps from a swing under gravity):",
        h * 1e3
    );
    println!(
        "  text {} bytes in {} lines; compiled in {:.0} ms",
        code.text.text.len(),
        code.text.text.lines().count(),
        m.compile.as_secs_f64() * 1e3
    );
    println!(
        "  {:.2} us per step, {:.2} Newton iterations per step; largest energy error {:.2e} J \
         (E = {energy:.2} J)",
        m.per_step.as_secs_f64() * 1e6,
        m.iterations,
        m.energy_error
    );
    if machine {
        let mass = iiwa.mass_matrix(&config).expect("a configuration");
        let rows: Vec<String> = mass
            .row_iter()
            .map(|r| format!("{:?}", r.iter().collect::<Vec<_>>()))
            .collect();
        println!(
            "{{\"start\": {{\"q\": {q0:?}, \"v\": {v0:?}, \"kinetic\": {kinetic:?}, \
             \"potential\": {potential:?}, \"mass_matrix\": [{}]}}}}",
            rows.join(", ")
        );
        println!(
            "{{\"run\": {{\"steps\": {steps}, \"h\": {h:?}, \"us_per_step\": {:?}, \"iterations\": {:?}, \
             \"energy_error\": {:?}, \"energy_drift\": {:?}, \"q_end\": {:?}}}}}",
            m.run.as_secs_f64() * 1e6 / steps as f64,
            m.iterations,
            m.energy_error,
            m.energy_drift,
            m.q_end
        );
    }
    if !chains {
        return;
    }
    println!("chains of n links (h = 1 ms, 1000 steps from a bent rest):");
    println!("  n    text bytes  compile ms  us/step  iterations");
    let mut points = Vec::new();
    macro_rules! row {
        ($n:literal, $instantiate:ident) => {{
            let q0: [f64; $n] = std::array::from_fn(|i| 0.3 * ((i as f64) * 1.7).sin());
            let (code, m) = measure!(chain($n), $n, $instantiate, 1e-3, 1000, q0, [0.0; $n]);
            println!(
                "  {:<4} {:>10}  {:>10.0}  {:>7.1}  {:>10.2}",
                $n,
                code.text.text.len(),
                m.compile.as_secs_f64() * 1e3,
                m.per_step.as_secs_f64() * 1e6,
                m.iterations
            );
            points.push(($n as f64, m.per_step.as_secs_f64()));
        }};
    }
    row!(5, instantiate);
    row!(10, instantiate);
    row!(20, instantiate_sparse);
    row!(40, instantiate_sparse);
    for pair in points.windows(2) {
        let slope = (pair[1].1 / pair[0].1).ln() / (pair[1].0 / pair[0].0).ln();
        println!(
            "  slope of the step time from n = {} to {}: {slope:.2}",
            pair[0].0, pair[1].0
        );
    }
}
