//! The paper's double spherical pendulum in Cartesian coordinates (issue 20): the two bobs in
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
use dirac::paper::{DoubleSphericalPendulum, DoubleSphericalPendulumContinuous};
use dirac::prelude::*;
use dirac::runtime::ContinuousLagrangian;

/// Two bobs at `r1 = (x1, y1, z1)`, `r2`, hanging from the origin on rods of lengths `l1`, `l2`
/// (`z` up), midpoint rule.
#[reduced_lagrangian(shape(x1, y1, z1, x2, y2, z2), group(), rule = midpoint,
    constraints = |q| [
        q.x1 * q.x1 + q.y1 * q.y1 + q.z1 * q.z1 - l1 * l1,
        (q.x2 - q.x1) * (q.x2 - q.x1) + (q.y2 - q.y1) * (q.y2 - q.y1) + (q.z2 - q.z1) * (q.z2 - q.z1) - l2 * l2,
    ])]
#[allow(clippy::too_many_arguments)]
fn cartesian_dsp(q: Config, v: Velocity, m1: f64, m2: f64, l1: f64, l2: f64, g: f64) -> f64 {
    0.5 * m1 * (v.x1 * v.x1 + v.y1 * v.y1 + v.z1 * v.z1)
        + 0.5 * m2 * (v.x2 * v.x2 + v.y2 * v.y2 + v.z2 * v.z2)
        - g * (m1 * q.z1 + m2 * q.z2)
}

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

fn arg(name: &str, default: usize) -> usize {
    let args: Vec<String> = std::env::args().collect();
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1))
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// The paper's initial state in Cartesian positions and momenta.
fn cartesian_initial(h: f64) -> (CartesianDsp, CanonicalState<6>) {
    let paper = DoubleSphericalPendulum::paper();
    let continuous = DoubleSphericalPendulumContinuous::paper();
    let s0 = DoubleSphericalPendulum::paper_initial_state();
    let c0 = continuous.untrivialize(&s0);
    let v = continuous
        .velocity(0, &c0.q, &c0.p, SVector::zeros())
        .expect("the paper's state is regular");
    // q = (φ1, ϑ2, φ2, ϑ1) with the azimuths θ1 = ϑ1 − ϑ2, θ2 = ϑ1 + ϑ2 (src/paper.rs).
    let (phi1, vt2, phi2, vt1) = (c0.q[0], c0.q[1], c0.q[2], c0.q[3]);
    let (dphi1, dvt2, dphi2, dvt1) = (v[0], v[1], v[2], v[3]);
    let (th1, th2, dth1, dth2) = (vt1 - vt2, vt1 + vt2, dvt1 - dvt2, dvt1 + dvt2);
    let (s1, c1, s2, c2) = (phi1.sin(), phi1.cos(), phi2.sin(), phi2.cos());
    let (st1, ct1, st2, ct2) = (th1.sin(), th1.cos(), th2.sin(), th2.cos());
    let (l1, l2) = (paper.l1, paper.l2);
    let v1 = [
        l1 * (c1 * ct1 * dphi1 - s1 * st1 * dth1),
        l1 * (c1 * st1 * dphi1 + s1 * ct1 * dth1),
        -l1 * s1 * dphi1,
    ];
    let u2 = [
        l2 * (c2 * ct2 * dphi2 - s2 * st2 * dth2),
        l2 * (c2 * st2 * dphi2 + s2 * ct2 * dth2),
        -l2 * s2 * dphi2,
    ];
    let (r1, r2) = paper.bob_positions(&c0.q);
    let sys = CartesianDsp {
        h,
        m1: paper.m1,
        m2: paper.m2,
        l1,
        l2,
        g: paper.g,
    };
    let p = [
        sys.m1 * v1[0],
        sys.m1 * v1[1],
        sys.m1 * v1[2],
        sys.m2 * (v1[0] + u2[0]),
        sys.m2 * (v1[1] + u2[1]),
        sys.m2 * (v1[2] + u2[2]),
    ];
    let q = [r1[0], r1[1], r1[2], r2[0], r2[1], r2[2]];
    (sys, CanonicalState::new(q, p))
}

/// `L_z = Σ (x p_y − y p_x)`.
fn angular_momentum(s: &CanonicalState<6>) -> f64 {
    s.q[0] * s.p[1] - s.q[1] * s.p[0] + s.q[3] * s.p[4] - s.q[4] * s.p[3]
}

fn main() {
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
            .run(c0, n, |_, _, _| {})
            .expect("the Cartesian pendulum integrates");
        let paper = DoubleSphericalPendulum {
            h,
            ..DoubleSphericalPendulum::paper()
        };
        let atlas = paper
            .atlas(NewtonOptions::default())
            .run(
                (PAPER, DoubleSphericalPendulum::paper_initial_state()),
                n,
                |_, _, _| {},
            )
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

    let steps = arg("--steps", 1_000_000);
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
        .run(c0, steps, |_, s, _| {
            worst_phi = worst_phi.max(sys_residual(&sys, s));
            worst_l = worst_l.max((angular_momentum(s) - l0).abs());
        })
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
            .run(c0, n, |_, _, _| {})
            .expect("constrained");
        let tc = start.elapsed().as_secs_f64() * 1e6 / n as f64;
        let start = Instant::now();
        let b = UnreducedIntegrator::plus(springs, NewtonOptions::default())
            .run(c0, n, |_, _, _| {})
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

/// `max_j |φ_j(q)| / l_j²`.
fn sys_residual(sys: &CartesianDsp, s: &CanonicalState<6>) -> f64 {
    use dirac::runtime::Constrained;
    let phi = sys.constraint(&s.q);
    (phi[0] / (sys.l1 * sys.l1))
        .abs()
        .max((phi[1] / (sys.l2 * sys.l2)).abs())
}
