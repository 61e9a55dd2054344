//! What forces and sensitivities cost, against their targets, measured in one run with interleaved
//! repeats: the paper's double spherical pendulum (continuous form, midpoint rule) against the
//! same Lagrangian with a damping force on both polar angles, and one step's sensitivity against
//! one step.
//!
//! Run: `cargo run --release --example forced_bench [-- --steps 20000 --repeats 7]`.

use std::time::Instant;

use dirac::paper::DoubleSphericalPendulumContinuous;
use dirac::prelude::*;

#[path = "common/cli.rs"]
mod cli;
use cli::{at_least, Cli};
#[path = "common/stats.rs"]
mod stats;
use stats::median;

/// The paper's double spherical pendulum (the body of
/// `dirac::paper::double_spherical_pendulum_continuous`) with viscous damping `c` on the polar
/// angles: virtual work `−c (φ̇1 δφ1 + φ̇2 δφ2)`.
#[reduced_lagrangian(shape(phi1, vt2, phi2), group(vt1), rule = midpoint,
    force = |dq| -c * (v.phi1 * dq.phi1 + v.phi2 * dq.phi2))]
#[allow(clippy::too_many_arguments)]
fn damped_dsp(q: Config, v: Velocity, m1: f64, m2: f64, l1: f64, l2: f64, g: f64, c: f64) -> f64 {
    let (th1, th2) = (q.vt1 - q.vt2, q.vt1 + q.vt2);
    let (dth1, dth2) = (v.vt1 - v.vt2, v.vt1 + v.vt2);
    let (s1, c1, s2, c2) = (q.phi1.sin(), q.phi1.cos(), q.phi2.sin(), q.phi2.cos());
    let (st1, ct1, st2, ct2) = (th1.sin(), th1.cos(), th2.sin(), th2.cos());
    let v1 = [
        l1 * (c1 * ct1 * v.phi1 - s1 * st1 * dth1),
        l1 * (c1 * st1 * v.phi1 + s1 * ct1 * dth1),
        -l1 * s1 * v.phi1,
    ];
    let u2 = [
        l2 * (c2 * ct2 * v.phi2 - s2 * st2 * dth2),
        l2 * (c2 * st2 * v.phi2 + s2 * ct2 * dth2),
        -l2 * s2 * v.phi2,
    ];
    let v2 = [v1[0] + u2[0], v1[1] + u2[1], v1[2] + u2[2]];
    let kinetic = 0.5 * m1 * (v1[0] * v1[0] + v1[1] * v1[1] + v1[2] * v1[2])
        + 0.5 * m2 * (v2[0] * v2[0] + v2[1] * v2[1] + v2[2] * v2[2]);
    kinetic - g * (m1 * l1 * c1 + m2 * (l1 * c1 + l2 * c2))
}

fn main() {
    let mut cli = Cli::new(
        "forced_bench",
        "what forces and sensitivities cost on the paper's double spherical pendulum",
    );
    let steps: usize = cli.value("--steps", "S", "steps per timed run", 20_000, at_least(1));
    let repeats: usize = cli.value("--repeats", "R", "interleaved repeats", 7, at_least(1));
    cli.finish();
    let free = DoubleSphericalPendulumContinuous::paper();
    let damped = DampedDsp {
        h: free.h,
        m1: free.m1,
        m2: free.m2,
        l1: free.l1,
        l2: free.l2,
        g: free.g,
        // Light damping: the motion stays as lively as the paper's over the run.
        c: 1e3,
    };
    let s0 = dirac::paper::DoubleSphericalPendulum::paper_initial_state();
    let options = NewtonOptions::default();
    let free_integ = ReducedIntegrator::plus(free, options);
    let damped_integ = ReducedIntegrator::plus(damped, options);
    // Per-step time of a streamed run (no storage), in µs.
    let time_run = |run: &dyn Fn() -> usize| {
        let start = Instant::now();
        let n = run();
        start.elapsed().as_secs_f64() * 1e6 / n as f64
    };
    let (mut ratios, mut t_free, mut t_damped) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..repeats {
        let a = time_run(&|| {
            let s = free_integ
                .run(s0)
                .steps(steps)
                .observe(|_, _, _, _| {})
                .stream()
                .expect("free run");
            s.step_count
        });
        let b = time_run(&|| {
            let s = damped_integ
                .run(s0)
                .steps(steps)
                .observe(|_, _, _, _| {})
                .stream()
                .expect("damped run");
            s.step_count
        });
        ratios.push(b / a);
        t_free.push(a);
        t_damped.push(b);
    }
    let iterations = (
        free_integ
            .run(s0)
            .steps(steps)
            .observe(|_, _, _, _| {})
            .stream()
            .expect("free run")
            .mean_iterations(),
        damped_integ
            .run(s0)
            .steps(steps)
            .observe(|_, _, _, _| {})
            .stream()
            .expect("damped run")
            .mean_iterations(),
    );
    let spread = |v: &[f64]| {
        let (lo, hi) = v
            .iter()
            .fold((f64::INFINITY, 0.0_f64), |(l, h), x| (l.min(*x), h.max(*x)));
        format!("[{lo:.3}, {hi:.3}]")
    };
    println!("Double spherical pendulum (paper parameters, midpoint rule, h = {}), {steps} steps, {repeats} interleaved repeats:", free.h);
    println!(
        "  unforced step: {:.3} µs, damped step: {:.3} µs (mean Newton iterations {:.2} and {:.2})",
        median(t_free.clone()),
        median(t_damped.clone()),
        iterations.0,
        iterations.1
    );
    println!(
        "  forced / unforced step time: median {:.3}, range {} (target ≤ 1.2)",
        median(ratios.clone()),
        spread(&ratios)
    );

    // One step's sensitivity against one step: the trajectory's steps, then their sensitivities.
    let n = steps.min(5000);
    let traj = damped_integ
        .run(s0)
        .steps(n)
        .collect()
        .expect("damped trajectory");
    let (mut sens_ratios, mut t_sens) = (Vec::new(), Vec::new());
    for _ in 0..repeats {
        let step = time_run(&|| {
            damped_integ
                .run(s0)
                .steps(n)
                .observe(|_, _, _, _| {})
                .stream()
                .expect("run")
                .step_count
        });
        let sens = time_run(&|| {
            let mut checksum = 0.0;
            for k in 0..n {
                let record = ReducedStep {
                    group_unknown: traj.group_unknowns[k],
                    stats: traj.stats[k],
                };
                let s = damped_integ
                    .sensitivity(k, &traj.states[k], &traj.states[k + 1], &record, &[])
                    .expect("sensitivity");
                checksum += s.state[(0, 0)];
            }
            std::hint::black_box(checksum);
            n
        });
        sens_ratios.push(sens / step);
        t_sens.push(sens);
    }
    println!(
        "  one step's sensitivity (8 × 8 state Jacobian): {:.3} µs; sensitivity / step time: median {:.3}, range {} (target ≤ 3)",
        median(t_sens.clone()),
        median(sens_ratios.clone()),
        spread(&sens_ratios)
    );
}
