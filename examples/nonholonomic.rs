//! Nonholonomic constraints: the discrete Lagrange–d'Alembert step with the discrete
//! constraint imposed at the step's midpoint, `A((q_k + q_{k+1})/2) (q_{k+1} − q_k)/h = 0`
//! (McLachlan & Perlmutter), constraint forces `A(q_k)ᵀ λ_k`, and momenta projected so that
//! their velocities satisfy the constraint.
//!
//! 1. The vertical rolling disk, whose heading and spin rates are constant: the error against
//!    the closed-form solution for halved time steps (observed order 2).
//! 2. The Chaplygin sleigh (a knife edge at distance `a` behind the centre of mass): its
//!    rotation dies out while its forward speed grows to `u∞ = √(2E/m)` — the known qualitative
//!    solution of `m u̇ = m a ω²`, `(I + m a²) ω̇ = −m a u ω` — with its energy and its constraint
//!    printed along the way.
//!
//! Run: `cargo run --release --example nonholonomic`.

use dirac::prelude::*;

#[path = "common/cli.rs"]
mod cli;

/// The vertical rolling disk: heading `phi`, contact point `(x, y)`, rolling angle `psi`.
#[reduced_lagrangian(shape(phi), group(x, y, psi), rule = midpoint,
    nonholonomic = |q, v| [v.x - r * q.phi.cos() * v.psi, v.y - r * q.phi.sin() * v.psi])]
fn rolling_disk(_q: Config, v: Velocity, m: f64, i: f64, j: f64, r: f64) -> f64 {
    0.5 * m * (v.x * v.x + v.y * v.y) + 0.5 * i * v.phi * v.phi + 0.5 * j * v.psi * v.psi
}

/// The Chaplygin sleigh: centre of mass `(x, y)`, heading `theta`; the knife edge at distance
/// `a` behind the centre of mass cannot slip sideways.
#[reduced_lagrangian(shape(theta), group(x, y), rule = midpoint,
    nonholonomic = |q, v| [-q.theta.sin() * v.x + q.theta.cos() * v.y - a * v.theta])]
fn sleigh(_q: Config, v: Velocity, m: f64, i: f64, a: f64) -> f64 {
    0.5 * m * (v.x * v.x + v.y * v.y) + 0.5 * i * v.theta * v.theta
}

fn main() {
    // No options: `--help` says so, and any argument stops the example with exit code 2.
    cli::Cli::new(
        "nonholonomic",
        "nonholonomic constraints: the rolling disk and the Chaplygin sleigh",
    )
    .finish();
    let options = NewtonOptions {
        abs_tol: 1e-14,
        rel_tol: 1e-14,
        ..NewtonOptions::default()
    };
    // 1. The rolling disk: φ = ω t, ψ = Ω t, x = (rΩ/ω) sin φ, y = (rΩ/ω)(1 − cos φ).
    let (omega, spin, t_end) = (0.7, 2.0, 10.0);
    println!("1. Vertical rolling disk (m = 1, I = 0.25, J = 0.5, r = 0.5), heading rate {omega}, spin {spin}, T = {t_end}:");
    println!(
        "   {:>8} {:>10} {:>16} {:>8}",
        "steps", "h", "max |q_N - q(T)|", "order"
    );
    let mut previous: Option<f64> = None;
    for n in [100, 200, 400, 800, 1600] {
        let sys = RollingDisk {
            h: t_end / n as f64,
            m: 1.0,
            i: 0.25,
            j: 0.5,
            r: 0.5,
        };
        let start = UnreducedState::new(
            [0.0; 4],
            [sys.i * omega, sys.m * sys.r * spin, 0.0, sys.j * spin],
        );
        let traj = ReducedConstrainedIntegrator::plus(sys, options)
            .run(sys.trivialize(&start))
            .steps(n)
            .collect()
            .expect("the disk rolls");
        let end = sys.untrivialize(traj.last()).q;
        let phi = omega * t_end;
        let radius = sys.r * spin / omega;
        let exact = [
            phi,
            radius * phi.sin(),
            radius * (1.0 - phi.cos()),
            spin * t_end,
        ];
        let error = (0..4)
            .map(|i| (end[i] - exact[i]).abs())
            .fold(0.0, f64::max);
        let order = previous.map_or(String::new(), |e| format!("{:.3}", (e / error).log2()));
        println!(
            "   {n:>8} {:>10.5} {error:>16.3e} {order:>8}",
            t_end / n as f64
        );
        previous = Some(error);
    }

    // 2. The Chaplygin sleigh.
    let sys = Sleigh {
        h: 0.01,
        m: 1.0,
        i: 0.2,
        a: 0.5,
    };
    let (u0, w0) = (0.2, 2.0);
    // Velocities satisfying the constraint at θ = 0: ẋ = u0, ẏ = a ω0, θ̇ = ω0.
    let start = UnreducedState::new([0.0; 3], [sys.i * w0, sys.m * u0, sys.m * sys.a * w0]);
    let energy = |s: &UnreducedState<3>| {
        0.5 * (s.p[1] * s.p[1] + s.p[2] * s.p[2]) / sys.m + 0.5 * s.p[0] * s.p[0] / sys.i
    };
    let e0 = energy(&start);
    let u_inf = (2.0 * e0 / sys.m).sqrt();
    let steps = 3000;
    let traj = ConstrainedIntegrator::new(sys, options)
        .run(start)
        .steps(steps)
        .collect()
        .expect("the sleigh slides");
    println!("\n2. Chaplygin sleigh (m = 1, I = 0.2, a = 0.5, h = 0.01) from u = {u0}, ω = {w0}: u∞ = √(2E/m) = {u_inf:.6}");
    println!(
        "   {:>6} {:>12} {:>12} {:>14} {:>16}",
        "t", "ω", "u", "E/E0 − 1", "constraint"
    );
    let (mut e_min, mut e_max) = (0.0_f64, 0.0_f64);
    for (k, s) in traj.states.iter().enumerate() {
        let de = energy(s) / e0 - 1.0;
        e_min = e_min.min(de);
        e_max = e_max.max(de);
        if k % 300 == 0 {
            let (theta, v) = (s.q[0], [s.p[1] / sys.m, s.p[2] / sys.m]);
            let u = theta.cos() * v[0] + theta.sin() * v[1];
            let w = s.p[0] / sys.i;
            let c = -theta.sin() * v[0] + theta.cos() * v[1] - sys.a * w;
            println!(
                "   {:>6.1} {w:>12.4e} {u:>12.6} {de:>14.3e} {c:>16.2e}",
                k as f64 * sys.h
            );
        }
    }
    println!(
        "   energy over the run within [{e_min:.2e}, {e_max:.2e}] of E0; largest discrete-constraint residual {:.1e}",
        traj.max_constraint_residual()
    );
}
