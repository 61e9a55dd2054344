//! Four bodies in space under softened gravity, written in the bodies' own positions, with the
//! translation of the centre of mass declared per axis (K = 3): the reduced integrator conserves
//! the total linear momentum exactly.
//!
//! ```sh
//! cargo run --release --example n_body
//! ```
//!
//! `L = Σ_i ½ m_i |ṙ_i|² + Σ_{i<j} G m_i m_j / sqrt(|r_i − r_j|² + ε²)`, midpoint rule. The
//! attribute takes the bodies' coordinates `x[4], y[4], z[4]` and `translate(x), translate(y),
//! translate(z)`; it builds the adapted coordinates (group: body 0's position; shape: the other
//! bodies relative to it) and the conversions of positions and momenta.

use dirac::prelude::*;

#[path = "common/cli.rs"]
mod cli;

/// Softened gravity between four bodies; masses are parameters.
#[reduced_lagrangian(
    coordinates(x[4], y[4], z[4]),
    translate(x),
    translate(y),
    translate(z),
    rule = midpoint
)]
#[allow(clippy::too_many_arguments)]
fn four_bodies(q: Config, v: Velocity, m0: f64, m1: f64, m2: f64, m3: f64, eps: f64) -> f64 {
    let m = [m0, m1, m2, m3];
    let mut l = 0.0;
    for i in 0..4 {
        l += 0.5 * m[i] * (v.x[i] * v.x[i] + v.y[i] * v.y[i] + v.z[i] * v.z[i]);
    }
    for i in 0..4 {
        for j in i + 1..4 {
            let (dx, dy, dz) = (q.x[i] - q.x[j], q.y[i] - q.y[j], q.z[i] - q.z[j]);
            l += m[i] * m[j] / (dx * dx + dy * dy + dz * dz + eps * eps).sqrt();
        }
    }
    l
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // No options: `--help` says so, and any argument stops the example with exit code 2.
    cli::Cli::new(
        "n_body",
        "four bodies in space, one declared translation per axis: total momentum exact",
    )
    .finish();
    let sys = FourBodies {
        m0: 1.0,
        m1: 0.3,
        m2: 0.2,
        m3: 0.1,
        eps: 0.05,
        h: 0.002,
    };
    let masses = [sys.m0, sys.m1, sys.m2, sys.m3];
    // Positions (x[0..4], y[0..4], z[0..4]) and velocities of a bound, non-planar configuration.
    let q = SVector::<f64, 12>::from([
        0.0, 1.0, -1.2, 0.3, // x
        0.0, 0.1, 0.4, -1.5, // y
        0.0, 0.2, -0.1, 0.3, // z
    ]);
    let v = SVector::<f64, 12>::from([
        0.0, 0.1, -0.2, 0.6, // ẋ
        0.0, 0.8, -0.7, -0.1, // ẏ
        0.0, 0.1, 0.2, -0.3, // ż
    ]);
    let p = SVector::<f64, 12>::from_fn(|i, _| masses[i % 4] * v[i]);
    let start = sys.trivialize(&FourBodies::adapted_state(&q, &p));
    println!(
        "four bodies, softened gravity (ε = {}), h = {}, midpoint rule; group coordinates {:?}",
        sys.eps,
        sys.h,
        <FourBodies as DiscreteLagrangian<9, 3, 12>>::GROUP
    );
    let total =
        |p: &SVector<f64, 12>| [0, 1, 2].map(|axis| (0..4).map(|i| p[4 * axis + i]).sum::<f64>());
    println!("  total momentum from the bodies' momenta: {:?}", total(&p));
    println!(
        "  μ of the reduced state (= the total momentum):   {:?}",
        start.mu.as_slice()
    );

    let steps = 50_000;
    let integ = ReducedIntegrator::plus(sys, NewtonOptions::default());
    let traj = integ.clone().run(start).steps(steps).collect()?;
    let mu_deviation = traj
        .states
        .iter()
        .map(|s| (s.mu - start.mu).amax())
        .fold(0.0, f64::max);
    let energies = dirac::reduced_continuous_energies(&sys, &traj)?;
    let (lo, hi) = energies
        .midpoints
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &e| {
            (a.min(e), b.max(e))
        });
    let end = FourBodies::from_adapted_state(&sys.untrivialize(traj.last()));
    println!(
        "  {steps} steps (T = {}): mean Newton iterations {:.3}",
        traj.times[steps],
        traj.mean_iterations()
    );
    println!("  max |μ_k − μ_0| over the run: {mu_deviation:e} (exact)");
    println!(
        "  total momentum of the bodies at the end (from their momenta): {:?}",
        total(&end.p)
    );
    println!(
        "  energy at the midpoints: {:.6} … {:.6} (spread {:.2e} relative)",
        lo,
        hi,
        (hi - lo) / lo.abs().max(hi.abs())
    );
    // The unreduced integrator from the same annotation carries the momentum only to round-off.
    let unreduced = UnreducedIntegrator::new(sys, NewtonOptions::default())
        .run(FourBodies::adapted_state(&q, &p))
        .steps(steps)
        .collect()?;
    let drift = unreduced
        .states
        .iter()
        .map(|s| (sys.momentum_map(s) - start.mu).amax())
        .fold(0.0, f64::max);
    println!("  unreduced integrator, same steps: max |J − J_0| = {drift:e}");
    Ok(())
}
