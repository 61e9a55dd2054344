//! A degenerate Lagrangian through the continuous front end: two point vortices,
//! `L = −½ Σ Γ_j r_j² θ̇_j − H` (linear in the velocities), midpoint rule, reduced by rotations.
//! Prints the error against the exact rigid rotation and the observed order, and the angular
//! impulse μ, which the reduced integrator keeps exactly.
//!
//! ```sh
//! cargo run --release --example point_vortices
//! ```

use dirac::prelude::*;
use std::f64::consts::PI;

#[path = "common/cli.rs"]
mod cli;

/// Two point vortices in polar coordinates: `θ1 = vt` (translated by rotations), `θ2 = vt + phi`.
#[reduced_lagrangian(shape(r1, r2, phi), group(vt), rule = midpoint)]
fn vortex_pair(q: Config, v: Velocity, gamma1: f64, gamma2: f64) -> f64 {
    let d2 = q.r1 * q.r1 + q.r2 * q.r2 - 2.0 * q.r1 * q.r2 * q.phi.cos();
    let impulse_rate = gamma1 * q.r1 * q.r1 * v.vt + gamma2 * q.r2 * q.r2 * (v.vt + v.phi);
    -0.5 * impulse_rate + gamma1 * gamma2 / (4.0 * std::f64::consts::PI) * d2.ln()
}

fn positions(x: &SVector<f64, 3>, vt: f64) -> [(f64, f64); 2] {
    [
        (x[0] * vt.cos(), x[0] * vt.sin()),
        (x[1] * (vt + x[2]).cos(), x[1] * (vt + x[2]).sin()),
    ]
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // No options: `--help` says so, and any argument stops the example with exit code 2.
    cli::Cli::new(
        "point_vortices",
        "two point vortices, a degenerate Lagrangian, reduced by rotations",
    )
    .finish();
    let (g1, g2, t) = (1.0, 2.0, 5.0);
    let q = SVector::from([1.0, 0.8, 2.0, 0.3]);
    let z0 = positions(&q.fixed_rows::<3>(0).into(), q[3]);
    // Exact: rigid rotation about the centre of vorticity at Ω = (Γ1 + Γ2)/(2π d²).
    let c = (
        (g1 * z0[0].0 + g2 * z0[1].0) / (g1 + g2),
        (g1 * z0[0].1 + g2 * z0[1].1) / (g1 + g2),
    );
    let d2 = (z0[0].0 - z0[1].0).powi(2) + (z0[0].1 - z0[1].1).powi(2);
    let a = (g1 + g2) / (2.0 * PI * d2) * t;
    let exact = z0.map(|(x, y)| {
        let (dx, dy) = (x - c.0, y - c.1);
        (
            c.0 + a.cos() * dx - a.sin() * dy,
            c.1 + a.sin() * dx + a.cos() * dy,
        )
    });
    println!(
        "{:>6} {:>12} {:>6} {:>24}",
        "N", "error", "order", "max |μ_k − μ_0|"
    );
    let mut last: Option<f64> = None;
    for steps in [50, 100, 200, 400, 800] {
        let sys = VortexPair {
            gamma1: g1,
            gamma2: g2,
            h: t / f64::from(steps),
        };
        // Momenta from positions alone: p = ∂L/∂v does not depend on v (degenerate L).
        let initial: ReducedState<3, 1> = sys.reduced_state(q, SVector::zeros())?;
        let traj = ReducedIntegrator::plus(sys, NewtonOptions::default())
            .run(initial)
            .steps(steps as usize)
            .collect()?;
        let z = positions(&traj.last().x, traj.last().g[0]);
        let err = (0..2)
            .map(|j| (z[j].0 - exact[j].0).hypot(z[j].1 - exact[j].1))
            .fold(0.0, f64::max);
        let drift = traj
            .states
            .iter()
            .map(|s| (s.mu[0] - initial.mu[0]).abs())
            .fold(0.0, f64::max);
        let order = last.map_or(String::from("-"), |e| format!("{:.3}", (e / err).log2()));
        println!("{steps:>6} {err:>12.4e} {order:>6} {drift:>24e}");
        last = Some(err);
    }
    Ok(())
}
