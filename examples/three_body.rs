//! Close encounters of three bodies in the plane: Burrau's Pythagorean problem (masses 3, 4, 5 at
//! rest at the vertices of a 3-4-5 triangle, `G = 1`), whose bodies pass within 10⁻³ of each
//! other. The adaptive step follows the free-fall time of the closest pair,
//! `g = (Σ 1/r_ij³)^{−1/2}`; the fixed step of the same Lagrangian takes as many steps over the
//! same time. Reports the physical energy error, the shortest and longest physical steps, and the
//! smallest pair distance each run saw.
//!
//! Run: `cargo run --release --example three_body [-- --time 20 --eps 0.0005]`.

use dirac::prelude::*;

#[path = "common/cli.rs"]
mod cli;

use cli::{greater_than, Cli};

const MASSES: [f64; 3] = [3.0, 4.0, 5.0];

/// Three bodies in the plane with adaptive steps.
#[reduced_lagrangian(shape(x1, y1, x2, y2, x3, y3), group(t), time(t),
    adapt = |q| 1.0 / (1.0 / ((q.x1 - q.x2) * (q.x1 - q.x2) + (q.y1 - q.y2) * (q.y1 - q.y2)).powf(1.5)
        + 1.0 / ((q.x1 - q.x3) * (q.x1 - q.x3) + (q.y1 - q.y3) * (q.y1 - q.y3)).powf(1.5)
        + 1.0 / ((q.x2 - q.x3) * (q.x2 - q.x3) + (q.y2 - q.y3) * (q.y2 - q.y3)).powf(1.5)).sqrt(),
    rule = midpoint)]
#[allow(clippy::too_many_arguments)]
fn three_bodies(q: Config, v: Velocity, m1: f64, m2: f64, m3: f64) -> f64 {
    let kinetic = 0.5 * m1 * (v.x1 * v.x1 + v.y1 * v.y1)
        + 0.5 * m2 * (v.x2 * v.x2 + v.y2 * v.y2)
        + 0.5 * m3 * (v.x3 * v.x3 + v.y3 * v.y3);
    let r12 = ((q.x1 - q.x2) * (q.x1 - q.x2) + (q.y1 - q.y2) * (q.y1 - q.y2)).sqrt();
    let r13 = ((q.x1 - q.x3) * (q.x1 - q.x3) + (q.y1 - q.y3) * (q.y1 - q.y3)).sqrt();
    let r23 = ((q.x2 - q.x3) * (q.x2 - q.x3) + (q.y2 - q.y3) * (q.y2 - q.y3)).sqrt();
    kinetic + m1 * m2 / r12 + m1 * m3 / r13 + m2 * m3 / r23
}

/// The same bodies in physical time.
#[reduced_lagrangian(shape(x1, y1, x2, y2, x3, y3), group(), rule = midpoint)]
#[allow(clippy::too_many_arguments)]
fn three_bodies_fixed(q: Config, v: Velocity, m1: f64, m2: f64, m3: f64) -> f64 {
    let kinetic = 0.5 * m1 * (v.x1 * v.x1 + v.y1 * v.y1)
        + 0.5 * m2 * (v.x2 * v.x2 + v.y2 * v.y2)
        + 0.5 * m3 * (v.x3 * v.x3 + v.y3 * v.y3);
    let r12 = ((q.x1 - q.x2) * (q.x1 - q.x2) + (q.y1 - q.y2) * (q.y1 - q.y2)).sqrt();
    let r13 = ((q.x1 - q.x3) * (q.x1 - q.x3) + (q.y1 - q.y3) * (q.y1 - q.y3)).sqrt();
    let r23 = ((q.x2 - q.x3) * (q.x2 - q.x3) + (q.y2 - q.y3) * (q.y2 - q.y3)).sqrt();
    kinetic + m1 * m2 / r12 + m1 * m3 / r13 + m2 * m3 / r23
}

/// The physical energy and the smallest pair distance at positions `x` and momenta `p`.
fn energy(x: &[f64], p: &[f64]) -> (f64, f64) {
    let mut e = 0.0;
    for i in 0..3 {
        e += 0.5 * (p[2 * i] * p[2 * i] + p[2 * i + 1] * p[2 * i + 1]) / MASSES[i];
    }
    let mut closest = f64::INFINITY;
    for i in 0..3 {
        for j in i + 1..3 {
            let r = (x[2 * i] - x[2 * j]).hypot(x[2 * i + 1] - x[2 * j + 1]);
            closest = closest.min(r);
            e -= MASSES[i] * MASSES[j] / r;
        }
    }
    (e, closest)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut cli = Cli::new(
        "three_body",
        "Burrau's three-body problem, adaptive against fixed steps",
    );
    let end: f64 = cli.value("--time", "T", "physical time", 20.0, greater_than(0.0));
    let eps: f64 = cli.value("--eps", "E", "fictitious step", 0.0005, greater_than(0.0));
    cli.finish();
    let start = [1.0, 3.0, -2.0, -1.0, 1.0, -1.0];
    let (e0, _) = energy(&start, &[0.0; 6]);
    let [m1, m2, m3] = MASSES;

    let sys = ThreeBodies { h: eps, m1, m2, m3 };
    let mut q0 = [0.0; 7];
    q0[..6].copy_from_slice(&start);
    let mut u0 = [0.0; 7];
    u0[6] = 1.0;
    let s0 = sys.reduced_state(q0, u0)?;
    let (mut worst, mut closest, mut dt_min, mut dt_max, mut t_prev) =
        (0.0_f64, f64::INFINITY, f64::INFINITY, 0.0_f64, 0.0);
    let run = ReducedIntegrator::plus(sys, NewtonOptions::default())
        .run(s0)
        .steps(100_000_000)
        .stop(|_, _, s: &ReducedState<6, 1>| s.g[0] >= end)
        .observe(|k, _, s: &ReducedState<6, 1>, _| {
            let (e, r) = energy(s.x.as_slice(), s.w.as_slice());
            worst = worst.max(((e - e0) / e0).abs());
            closest = closest.min(r);
            if k > 0 {
                dt_min = dt_min.min(s.g[0] - t_prev);
                dt_max = dt_max.max(s.g[0] - t_prev);
            }
            t_prev = s.g[0];
        })
        .stream();
    let steps = match &run {
        Ok(summary) => {
            println!(
                "adaptive ε = {eps}: t = {:.3} in {} steps; max |E − E0|/|E0| = {worst:.2e}; physical steps from {dt_min:.2e} to {dt_max:.2e}; closest approach {closest:.2e}; p_t = −E0 kept bit for bit: {}",
                summary.last.g[0],
                summary.step_count,
                summary.last.mu == s0.mu
            );
            summary.step_count
        }
        Err(e) => {
            println!(
                "adaptive ε = {eps}: stopped at t = {t_prev:.3}: {}",
                e.source
            );
            e.source.step()
        }
    };

    // The fixed step with as many steps over the same time.
    let fixed = ThreeBodiesFixed {
        h: end / steps as f64,
        m1,
        m2,
        m3,
    };
    let s0 = fixed.reduced_state(start, [0.0; 6])?;
    let (mut worst, mut closest, mut t_reached) = (0.0_f64, f64::INFINITY, 0.0);
    let run = ReducedIntegrator::plus(fixed, NewtonOptions::default())
        .run(s0)
        .steps(steps)
        .observe(|k, _, s: &ReducedState<6, 0>, _| {
            let (e, r) = energy(s.x.as_slice(), s.w.as_slice());
            worst = worst.max(((e - e0) / e0).abs());
            closest = closest.min(r);
            t_reached = k as f64 * fixed.h;
        })
        .stream();
    match run {
        Ok(_) => println!(
            "fixed h = {:.2e} ({steps} steps): max |E − E0|/|E0| = {worst:.2e}; closest approach {closest:.2e}",
            fixed.h
        ),
        Err(e) => println!(
            "fixed h = {:.2e}: stopped at t = {t_reached:.3} (max |E − E0|/|E0| = {worst:.2e} before): {}",
            fixed.h, e.source
        ),
    }
    Ok(())
}
