//! A pendulum chain of many links, stepped by the recursive step of a fixed-base tree
//! (`ArticulatedIntegrator`): rods 0.5 m long hinged alternately about `y` and `x`, so that the
//! chain swings in 3-D, let go from a bend at the top. No compilation: the model is data, and a
//! step costs `O(n)` — two passes over the tree per residual, GMRES corrections preconditioned
//! by the articulated-body solve of the mass term.
//!
//! ```text
//! cargo run --release --example pendulum_chain -- [--links 100] [--steps 2000]
//! cargo run --release --example pendulum_chain -- --scaling 10,30,100,300,1000 [--steps 500]
//! ```
//!
//! The first form runs one chain and checks what the step promises: the energy error stays
//! bounded (a variational integrator's, not a drift) and Newton takes at most three corrections
//! a step on average; it exits non-zero on a miss. The second prints, for each length, the time
//! per step, the corrections per step and the energy error, and the log–log slope of the time
//! per step in the number of links.

use std::time::Instant;

use dirac::multibody::nalgebra::{Matrix3, Vector3};
use dirac::multibody::{ArticulatedIntegrator, Inertial, JointSpec, Model, Pose};
use dirac::prelude::*;

#[path = "common/cli.rs"]
mod cli;

/// A chain of `n` rods, 1 kg and 0.5 m each, hinged alternately about `y` and `x`.
fn chain(n: usize) -> Model {
    let rod = Inertial::new(
        1.0,
        Vector3::new(0.0, 0.0, -0.25),
        Matrix3::from_diagonal(&Vector3::new(0.021, 0.021, 0.002)),
    );
    let mut b = Model::builder().frame("l0");
    for i in 1..=n {
        let axis = if i % 2 == 1 {
            Vector3::y()
        } else {
            Vector3::x()
        };
        let at = Pose::from_translation(Vector3::new(0.0, 0.0, if i == 1 { 0.0 } else { -0.5 }));
        b = b.body(format!("l{i}"), rod).joint(
            JointSpec::revolute(
                format!("j{i}"),
                format!("l{}", i - 1),
                format!("l{i}"),
                axis,
            )
            .at(at),
        );
    }
    b.build().expect("a chain is a tree")
}

/// What one run measured.
struct Measured {
    per_step_us: f64,
    corrections: f64,
    most: usize,
    energy_error: f64,
    energy_scale: f64,
}

/// `steps` steps of 1 ms of the `n`-link chain from its bend: the first joint at 0.8 rad, the
/// others at 0.02 rad, at rest.
fn run(n: usize, steps: usize) -> Result<Measured, Box<dyn std::error::Error>> {
    let model = chain(n);
    let integ = ArticulatedIntegrator::new(&model, 1e-3, NewtonOptions::default())?;
    let q: Vec<f64> = (0..n).map(|j| if j == 0 { 0.8 } else { 0.02 }).collect();
    let start = integ.state(&q, &vec![0.0; n])?;
    let e0 = integ.energy(&start)?;
    let started = Instant::now();
    let traj = integ.run(start).steps(steps).collect()?;
    let elapsed = started.elapsed().as_secs_f64();
    let every = (steps / 50).max(1);
    let mut energy_error: f64 = 0.0;
    for s in traj.states.iter().step_by(every) {
        energy_error = energy_error.max((integ.energy(s)? - e0).abs());
    }
    Ok(Measured {
        per_step_us: elapsed / steps as f64 * 1e6,
        corrections: traj.stats.mean_iterations(),
        most: traj.stats.iter().map(|s| s.iterations).max().unwrap_or(0),
        energy_error,
        // The chain's weight times its length: the scale of its energy.
        energy_scale: n as f64 * 9.81 * 0.5 * n as f64,
    })
}

/// The least-squares slope of `log y` in `log x`.
fn slope(points: &[(f64, f64)]) -> f64 {
    let m = points.len() as f64;
    let (sx, sy) = points
        .iter()
        .fold((0.0, 0.0), |(a, b), (x, y)| (a + x.ln(), b + y.ln()));
    let (mx, my) = (sx / m, sy / m);
    let (num, den) = points.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
        (a + (x.ln() - mx) * (y.ln() - my), b + (x.ln() - mx).powi(2))
    });
    num / den
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut cli = cli::Cli::new(
        "pendulum_chain",
        "a pendulum chain of many links by the recursive O(n) step",
    );
    let links = cli.value(
        "--links",
        "N",
        "links of the chain",
        100usize,
        cli::at_least(1),
    );
    let steps = cli.value(
        "--steps",
        "S",
        "steps of 1 ms",
        2000usize,
        cli::at_least(10),
    );
    let scaling: Vec<usize> = cli.list(
        "--scaling",
        "N1,N2,..",
        "lengths to time (instead of one run)",
        &[],
        cli::at_least(1),
    );
    cli.finish();
    if scaling.is_empty() {
        let m = run(links, steps)?;
        println!(
            "{links}-link chain, {steps} steps of 1 ms: {:.1} µs a step, {:.2} Newton corrections \
             a step (at most {}), largest energy error {:.2e} J ({:.1e} of its weight times its \
             length)",
            m.per_step_us,
            m.corrections,
            m.most,
            m.energy_error,
            m.energy_error / m.energy_scale
        );
        let mut missed = Vec::new();
        if m.corrections > 3.0 {
            missed.push(format!("mean Newton corrections {:.2} > 3", m.corrections));
        }
        if m.energy_error > 1e-6 * m.energy_scale {
            missed.push(format!("energy error {:.2e} J", m.energy_error));
        }
        if !missed.is_empty() {
            eprintln!("missed: {}", missed.join("; "));
            std::process::exit(1);
        }
        return Ok(());
    }
    println!("links   µs/step   corrections (most)   energy error (of weight × length)");
    let mut points = Vec::new();
    for &n in &scaling {
        let m = run(n, steps)?;
        println!(
            "{n:5}   {:8.1}   {:5.2} ({})            {:.1e}",
            m.per_step_us,
            m.corrections,
            m.most,
            m.energy_error / m.energy_scale
        );
        points.push((n as f64, m.per_step_us));
    }
    if points.len() > 1 {
        println!(
            "slope of the time per step in the number of links: {:.2}",
            slope(&points)
        );
    }
    Ok(())
}
