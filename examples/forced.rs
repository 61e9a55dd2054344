//! Forces and controls, on two systems with known answers:
//!
//! 1. A damped, driven oscillator `m ẍ + c ẋ + k x = a0 cos ωt`, midpoint rule, the drive a
//!    control set by a feedback-free law of the step index: the error against the closed-form
//!    solution at `T` for halved time steps (observed order 2), and the mean decay rate of the
//!    energy of the undriven oscillator against `c/m`.
//! 2. A turntable (a rotor, angle `phi`, the group coordinate) carrying a damped pendulum, driven
//!    by a torque on its axis: the table's momentum `μ` changes over every step by exactly the
//!    applied discrete impulse `h τ_k` (the forced discrete Noether balance), printed with its
//!    largest defect, while the pendulum's damping leaves `μ` alone.
//!
//! Run: `cargo run --release --example forced`.

use dirac::prelude::*;

#[path = "common/forced.rs"]
mod forced;
use forced::{exact, Oscillator, Turntable};

#[path = "common/cli.rs"]
mod cli;

fn main() {
    // No options: `--help` says so, and any argument stops the example with exit code 2.
    cli::Cli::new(
        "forced",
        "forces and controls on a damped, driven oscillator and a driven turntable",
    )
    .finish();
    let options = NewtonOptions::default();
    let (m, k, c, a0, omega, x0, t_end) = (1.0, 4.0, 0.3, 0.5, 1.3, 1.0, 10.0);
    println!("1. Damped, driven oscillator m x'' + c x' + k x = a0 cos(w t): m = {m}, k = {k}, c = {c}, a0 = {a0}, w = {omega}, x(0) = {x0}, T = {t_end}");
    println!(
        "   {:>8} {:>12} {:>14} {:>8}",
        "steps", "h", "|x_N - x(T)|", "order"
    );
    let mut previous: Option<f64> = None;
    for n in [100, 200, 400, 800, 1600] {
        let h = t_end / n as f64;
        let sys = Oscillator { h, m, k, c, a: 0.0 };
        let s0 = UnreducedState {
            q: SVector::from([x0]),
            p: SVector::from([0.0]),
        };
        // The drive at the step's midpoint, where the midpoint rule evaluates the force.
        let drive = |k: usize, _: f64, _: &UnreducedState<1>, u: &mut [f64]| {
            u[0] = a0 * (omega * (k as f64 + 0.5) * h).cos()
        };
        let traj = UnreducedIntegrator::new(sys, options)
            .run(s0)
            .steps(n)
            .feedback(drive)
            .collect()
            .expect("the oscillator integrates");
        let error = (traj.last().q[0] - exact(m, k, c, a0, omega, x0, t_end)).abs();
        let order = previous.map_or(String::new(), |e| format!("{:.3}", (e / error).log2()));
        println!("   {n:>8} {h:>12.5} {error:>14.3e} {order:>8}");
        previous = Some(error);
    }
    // Energy decay without the drive: E = ½ m v² + ½ k x² decays on average like e^{−(c/m) t}.
    let h = 0.001;
    let sys = Oscillator { h, m, k, c, a: 0.0 };
    let n = (t_end / h) as usize;
    let s0 = UnreducedState {
        q: SVector::from([x0]),
        p: SVector::from([0.0]),
    };
    let traj = UnreducedIntegrator::new(sys, options)
        .run(s0)
        .steps(n)
        .collect()
        .expect("the oscillator integrates");
    let energy = |s: &UnreducedState<1>| 0.5 * s.p[0] * s.p[0] / m + 0.5 * k * s.q[0] * s.q[0];
    // Over whole periods of the damped motion the oscillation of the decay averages out.
    let period = 2.0 * std::f64::consts::PI / (k / m - (c / (2.0 * m)).powi(2)).sqrt();
    let whole = ((t_end / period).floor() * period / h).round() as usize;
    let rate = -(energy(&traj.states[whole]) / energy(&traj.states[0])).ln() / (whole as f64 * h);
    println!(
        "   energy decay rate without drive over {:.0} periods (h = {h}): {rate:.5} (c/m = {:.5})",
        (t_end / period).floor(),
        c / m
    );

    // 2. The turntable: μ (the table's angular momentum) changes by exactly h τ_k per step.
    let h = 0.01;
    let sys = Turntable {
        h,
        i0: 0.7,
        m: 1.3,
        l: 0.9,
        c: 0.1,
        tau: 0.0,
    };
    let steps = 100_000;
    let torque = |k: usize| 0.4 * (0.003 * k as f64).sin() + 0.05;
    let s0 = ReducedState::new([0.4], [0.0], [0.3], [0.0]);
    let mut worst = 0.0_f64;
    let mut applied = 0.0;
    let mut previous = s0.mu[0];
    let summary = ReducedIntegrator::plus(sys, options)
        .run(s0)
        .steps(steps)
        .feedback(|k: usize, _, _: &ReducedState<1, 1>, u: &mut [f64]| u[0] = torque(k))
        .observe(|k, _, s, _| {
            if k > 0 {
                let impulse = h * torque(k - 1);
                applied += impulse;
                worst = worst.max((s.mu[0] - previous - impulse).abs());
            }
            previous = s.mu[0];
        })
        .stream()
        .expect("the turntable integrates");
    println!("\n2. Turntable with a damped pendulum and a torque tau_k on its axis, {steps} steps of h = {h}:");
    println!(
        "   mu_N - mu_0 = {:.15}, sum of the applied impulses h tau_k = {applied:.15}",
        summary.last.mu[0] - s0.mu[0]
    );
    println!(
        "   largest per-step defect |mu_(k+1) - mu_k - h tau_k| = {worst:.1e} (mean Newton iterations {:.2})",
        summary.mean_iterations()
    );
}
