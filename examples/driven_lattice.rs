//! A damped, driven Toda lattice sized at run time: a damping force on every particle and a
//! periodic drive on the first one, a control set before every step — forces and controls
//! written with loops like the Lagrangian, one build for every `n`.
//!
//! ```sh
//! cargo run --release --example driven_lattice -- [--n 1000] [--time 20] [--h 0.02] [--drive 0.5]
//! ```
//!
//! The energy balance: between step midpoints the energy at the midpoints (`E((q_k + q_{k+1})/2,
//! (q_{k+1} − q_k)/h)`, summed element by element) changes by the work the forces do, the power
//! injected by the drive minus that taken by the damping. Over a step the midpoint rule's forces
//! do `W_k = Σ_i F_i(q̄, v) Δq_i = u_k Δq_0 − c Σ_i Δq_i²/h`; the example accumulates the injected
//! and the dissipated work, compares the energy change with their sum (the half-step average
//! `(W_{k−1} + W_k)/2` between midpoints) and does so at `h` and `h/2`: the balance's residual
//! is a discretization error of order 2, so it falls by 4. It also checks the forced discrete
//! Noether balance of the translation: the total momentum changes by the drive's and the
//! damping's impulse, `u_k h − c Σ_i Δq_i`, to round-off at every step. A failed step ends the
//! example with its typed error and exit code 1.

use dirac::prelude::*;
use dirac::runtime::element::ElementIntegrator;

#[path = "common/cli.rs"]
mod cli;
use cli::{at_least, greater_than, Cli};

/// The periodic Toda lattice in positions measured from the equilibrium sites, damped on every
/// particle, driven on the first by the control `u`.
#[reduced_lagrangian(coordinates(x[n]), translate(x), rule = midpoint, controls(u),
    force = |dq| {
        let mut w = 0.0;
        for i in 0..n {
            w -= c * v.x[i] * dq.x[i];
        }
        w + u * dq.x[0]
    })]
fn driven_toda(q: Config, v: Velocity, c: f64, u: f64, n: usize) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        l += 0.5 * v.x[i] * v.x[i];
    }
    for i in 0..n - 1 {
        l -= (-(q.x[i + 1] - q.x[i])).exp();
    }
    l - (-(q.x[0] - q.x[n - 1])).exp()
}

/// What one run measured.
struct Balance {
    injected: f64,
    dissipated: f64,
    energy_change: f64,
    /// `|ΔE − Σ W|` between the first and the last midpoint.
    residual: f64,
    /// The largest `|Δμ_k − impulse_k|` over the steps.
    momentum: f64,
    steps: usize,
}

fn run(
    n: usize,
    time: f64,
    h: f64,
    c: f64,
    drive: f64,
) -> Result<Balance, Box<dyn std::error::Error>> {
    let omega = 1.3;
    let sys = DrivenToda { c, u: 0.0, h, n };
    let integ = ElementIntegrator::new(sys, NewtonOptions::default());
    let start = ElementState::new(
        DVector::from_fn(n, |i, _| {
            0.1 * (2.0 * std::f64::consts::PI * i as f64 / n as f64).sin()
        }),
        DVector::zeros(n),
    );
    let steps = (time / h).round() as usize;
    let traj = integ
        .run(start)
        .steps(steps)
        .feedback(|_, t: f64, _: &ElementState, u: &mut [f64]| {
            u[0] = drive * (omega * (t + 0.5 * h)).sin()
        })
        .collect()?;
    let (mut injected, mut dissipated, mut work, mut momentum) = (0.0, 0.0, Vec::new(), 0.0f64);
    for k in 0..steps {
        let (q0, q1) = (&traj.states[k].q, &traj.states[k + 1].q);
        let u = drive * (omega * (k as f64 * h + 0.5 * h)).sin();
        let dq = q1 - q0;
        let (w_in, w_out) = (u * dq[0], c * dq.norm_squared() / h);
        injected += w_in;
        dissipated += w_out;
        work.push(w_in - w_out);
        let mu = |s: &ElementState| integ.momentum_map(s).map(|m| m[0]);
        let change = mu(&traj.states[k + 1])? - mu(&traj.states[k])?;
        momentum = momentum.max((change - (u * h - c * dq.sum())).abs());
    }
    let energy = |k: usize| integ.energy(&traj.states[k].q, &traj.states[k + 1].q);
    let energy_change = energy(steps - 1)? - energy(0)?;
    // Between the midpoints of steps 0 and K − 1: half of W_0, W_1 … W_{K−2}, half of W_{K−1}.
    let between: f64 =
        0.5 * work[0] + work[1..steps - 1].iter().sum::<f64>() + 0.5 * work[steps - 1];
    Ok(Balance {
        injected,
        dissipated,
        energy_change,
        residual: (energy_change - between).abs(),
        momentum,
        steps,
    })
}

fn main() {
    let mut cli = Cli::new(
        "driven_lattice",
        "a damped, driven Toda lattice sized at run time: the energy balance against the injected power",
    );
    let n: usize = cli.value("--n", "N", "particles", 1000, at_least(3));
    let time: f64 = cli.value("--time", "T", "duration", 20.0, greater_than(0.0));
    let h: f64 = cli.value(
        "--h",
        "H",
        "time step (also run at H/2)",
        0.02,
        greater_than(0.0),
    );
    let drive: f64 = cli.value("--drive", "A", "drive amplitude", 0.5, greater_than(0.0));
    let c: f64 = cli.value(
        "--damping",
        "C",
        "damping coefficient",
        0.05,
        greater_than(0.0),
    );
    cli.finish();
    println!("damped, driven Toda lattice: {}", DrivenToda::GENERATED);
    let mut residuals = Vec::new();
    for step in [h, h / 2.0] {
        match run(n, time, step, c, drive) {
            Ok(b) => {
                println!(
                    "n = {n}, h = {step}, {} steps: injected {:.6e}, dissipated {:.6e}, energy change {:.6e}; balance residual {:.3e} ({:.2e} of the injected work); momentum balance to {:.1e} per step",
                    b.steps,
                    b.injected,
                    b.dissipated,
                    b.energy_change,
                    b.residual,
                    b.residual / b.injected.abs(),
                    b.momentum
                );
                residuals.push(b.residual);
            }
            Err(e) => {
                eprintln!("driven_lattice: {e}");
                std::process::exit(1);
            }
        }
    }
    println!(
        "the balance residual falls by {:.2} when h halves (order 2: 4)",
        residuals[0] / residuals[1]
    );
}
