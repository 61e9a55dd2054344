//! The paper's double spherical pendulum in Cartesian coordinates: the two bobs in
//! R³ and two length constraints, with no singular chart anywhere.
//!
//! 1. From the paper's initial state (§7.2), the bob positions at `T` against the atlas run of
//!    the paper's coordinates (§6, §7.2), for two time steps: the two discretizations approach
//!    each other as `h²`.
//! 2. The angular momentum about the vertical: the rotation is a symmetry of the Lagrangian and
//!    the constraints (not a translation of these coordinates, so it is not reduced), and the
//!    constrained discrete Noether theorem conserves its momentum map up to the step residual.
//! 3. The constraint residual `|φ(q)|/l²` at every step of a run of `--steps` steps (default
//!    10⁶, `T = 10⁴`).
//! 4. What a constrained step costs: against the same six coordinates with the two rods replaced
//!    by stiff springs (no constraints), interleaved repeats.
//!
//! Run: `cargo run --release --example cartesian_dsp [-- --steps 1000000]`.

use std::time::Instant;

use dirac::paper::atlas::PAPER;
use dirac::paper::DoubleSphericalPendulum;
use dirac::prelude::*;

#[path = "common/cli.rs"]
mod cli;
use cli::{at_least, Cli};

#[path = "common/cartesian_dsp.rs"]
mod cartesian;
use cartesian::{cartesian_initial, sys_residual};

/// The same six coordinates with stiff springs (stiffness `k`) in place of the rods: the
/// unconstrained step of the same size, for the cost comparison.
#[reduced_lagrangian(shape(x1, y1, z1, x2, y2, z2), group(), rule = midpoint)]
#[allow(clippy::too_many_arguments)]
fn spring_dsp(q: Config, v: Velocity, m1: f64, m2: f64, l1: f64, l2: f64, g: f64, k: f64) -> f64 {
    let d1 = (q.x1 * q.x1 + q.y1 * q.y1 + q.z1 * q.z1).sqrt() - l1;
    let (dx, dy, dz) = (q.x2 - q.x1, q.y2 - q.y1, q.z2 - q.z1);
    let d2 = (dx * dx + dy * dy + dz * dz).sqrt() - l2;
    0.5 * m1 * (v.x1 * v.x1 + v.y1 * v.y1 + v.z1 * v.z1)
        + 0.5 * m2 * (v.x2 * v.x2 + v.y2 * v.y2 + v.z2 * v.z2)
        - g * (m1 * q.z1 + m2 * q.z2)
        - 0.5 * k * (d1 * d1 + d2 * d2)
}

/// `L_z = Σ (x p_y − y p_x)`.
fn angular_momentum(s: &UnreducedState<6>) -> f64 {
    s.q[0] * s.p[1] - s.q[1] * s.p[0] + s.q[3] * s.p[4] - s.q[4] * s.p[3]
}

fn main() {
    let mut cli = Cli::new(
        "cartesian_dsp",
        "the paper's double spherical pendulum in Cartesian coordinates with two rod constraints",
    );
    let steps = cli.value(
        "--steps",
        "S",
        "steps of the long constraint-residual run (h = 0.01)",
        1_000_000,
        at_least(1),
    );
    cli.finish();
    let t_end: f64 = 100.0;
    println!("Double spherical pendulum in Cartesian coordinates, from the paper's initial state (§7.2):");
    println!("1. Bob 2 at T = {t_end} against the atlas run of the paper's coordinates (§6):");
    println!(
        "   {:>8} {:>22} {:>24}",
        "h", "|r2 cartesian - r2 atlas|", "max |phi|/l^2 over the run"
    );
    let mut previous: Option<f64> = None;
    for h in [0.01_f64, 0.005, 0.0025] {
        let n = (t_end / h).round() as usize;
        let (sys, c0) = cartesian_initial(h);
        let summary = ConstrainedIntegrator::new(sys, NewtonOptions::default())
            .run(c0)
            .steps(n)
            .observe(|_, _, _, _| {})
            .stream()
            .expect("the Cartesian pendulum integrates");
        let paper = DoubleSphericalPendulum {
            h,
            ..DoubleSphericalPendulum::paper()
        };
        let atlas = paper
            .atlas(NewtonOptions::default())
            .run((PAPER, DoubleSphericalPendulum::paper_initial_state()))
            .steps(n)
            .observe(|_, _, _, _| {})
            .stream()
            .expect("the atlas integrates");
        let (chart, state) = atlas.last;
        let (_, r2) = paper.charts().bob_positions(chart, &state);
        let c = &summary.last.q;
        let d = ((c[3] - r2[0]).powi(2) + (c[4] - r2[1]).powi(2) + (c[5] - r2[2]).powi(2)).sqrt();
        let phi = sys_residual(&sys, &summary.last);
        let ratio = previous.map_or(String::new(), |p| format!("  (ratio {:.2})", p / d));
        println!("   {h:>8} {d:>22.6e} {phi:>24.2e}{ratio}");
        previous = Some(d);
    }

    let (sys, c0) = cartesian_initial(0.01);
    let l0 = angular_momentum(&c0);
    // The scale of L_z's terms, |q| |p|: L_z itself is 0 at the paper's state (μ0 = 0).
    let scale = c0.q.amax() * c0.p.amax();
    let (mut worst_phi, mut worst_l) = (0.0_f64, 0.0_f64);
    // Steps solved to round-off, so the momentum map's drift shows the integrator, not the
    // Newton tolerance.
    let tight = NewtonOptions {
        abs_tol: 1e-13,
        rel_tol: 1e-15,
        ..NewtonOptions::default()
    };
    let start = Instant::now();
    let summary = ConstrainedIntegrator::new(sys, tight)
        .run(c0)
        .steps(steps)
        .observe(|_, _, s, _| {
            worst_phi = worst_phi.max(sys_residual(&sys, s));
            worst_l = worst_l.max((angular_momentum(s) - l0).abs());
        })
        .stream()
        .expect("the long run integrates");
    let seconds = start.elapsed().as_secs_f64();
    println!("2. Angular momentum about the vertical over {steps} steps (h = 0.01), steps solved to round-off: L_z(0) = {l0:.3e}, largest drift {worst_l:.2e} = {:.1e} of |q||p| = {scale:.2e} (largest step residual {:.1e})",
        worst_l / scale, summary.max_residual);
    println!("3. Constraint residual over the same run: max |phi|/l^2 = {worst_phi:.2e}; {:.2} µs per step, {:.2} Newton corrections per step (both solves)",
        seconds * 1e6 / steps as f64, summary.mean_iterations());

    // 4. Cost: the constrained step against the unconstrained one with the same coordinates.
    let springs = SpringDsp {
        h: 0.01,
        m1: sys.m1,
        m2: sys.m2,
        l1: sys.l1,
        l2: sys.l2,
        g: sys.g,
        k: 1e5,
    };
    let n = 20_000;
    let mut ratios = Vec::new();
    let (mut t_c, mut t_s) = (Vec::new(), Vec::new());
    for _ in 0..5 {
        let start = Instant::now();
        let a = ConstrainedIntegrator::new(sys, NewtonOptions::default())
            .run(c0)
            .steps(n)
            .observe(|_, _, _, _| {})
            .stream()
            .expect("constrained");
        let tc = start.elapsed().as_secs_f64() * 1e6 / n as f64;
        let start = Instant::now();
        let b = UnreducedIntegrator::new(springs, NewtonOptions::default())
            .run(c0)
            .steps(n)
            .observe(|_, _, _, _| {})
            .stream()
            .expect("springs");
        let ts = start.elapsed().as_secs_f64() * 1e6 / n as f64;
        std::hint::black_box((a.last, b.last));
        ratios.push(tc / ts);
        t_c.push(tc);
        t_s.push(ts);
    }
    ratios.sort_by(f64::total_cmp);
    t_c.sort_by(f64::total_cmp);
    t_s.sort_by(f64::total_cmp);
    println!(
        "4. Constrained step {:.3} µs against the spring step {:.3} µs (6 coordinates each): ratio median {:.2}, range [{:.2}, {:.2}] (target ≤ 2)",
        t_c[2], t_s[2], ratios[2], ratios[0], ratios[4]
    );
}
