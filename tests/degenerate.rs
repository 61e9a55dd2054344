//! Degenerate Lagrangians, linear in the velocities, through the same
//! annotation: point vortices (converging at the midpoint rule's order 2, angular impulse μ
//! exact) and a massless charged particle whose left-point discrete Legendre map is singular
//! (a typed error, not a panic).

use dirac::prelude::*;
use dirac::{midpoint_energies, reduced_continuous_energies, ContinuousLagrangian, LegendreError};
use std::f64::consts::PI;

/// Two point vortices of strengths `gamma1`, `gamma2` in the plane, in polar coordinates
/// `z_j = r_j e^{iθ_j}` with `θ1 = ϑ` (the group coordinate, translated by rotations) and
/// `θ2 = ϑ + φ`. Kirchhoff's equations `Γ_j ẋ_j = ∂H/∂y_j`, `Γ_j ẏ_j = −∂H/∂x_j` with
/// `H = −Γ1Γ2/(4π) ln |z1 − z2|²` are the Euler–Lagrange equations of
/// `L = −½ Σ Γ_j r_j² θ̇_j − H`, linear in the velocities.
#[reduced_lagrangian(shape(r1, r2, phi), group(vt), rule = midpoint)]
fn vortex_pair(q: Config, v: Velocity, gamma1: f64, gamma2: f64) -> f64 {
    let d2 = q.r1 * q.r1 + q.r2 * q.r2 - 2.0 * q.r1 * q.r2 * q.phi.cos();
    let impulse_rate = gamma1 * q.r1 * q.r1 * v.vt + gamma2 * q.r2 * q.r2 * (v.vt + v.phi);
    -0.5 * impulse_rate + gamma1 * gamma2 / (4.0 * std::f64::consts::PI) * d2.ln()
}

/// A charged particle of zero mass in the plane, in the uniform field `b` (Landau gauge
/// `A = (−b y, 0)`) and the potential `V = ½ k (x² + y²)`: `L = −b y ẋ − V`, the guiding-centre
/// limit. The left-point rule makes `D1 L_d(q0, q1)` independent of `x1`, `y1` in its first row.
#[reduced_lagrangian(shape(x, y), group(), rule = left)]
fn massless_particle(q: Config, v: Velocity, b: f64, k: f64) -> f64 {
    -b * q.y * v.x - 0.5 * k * (q.x * q.x + q.y * q.y)
}

/// The same with the midpoint rule: the discrete Legendre map is regular.
#[reduced_lagrangian(shape(x, y), group(), rule = midpoint, name = MasslessMidpoint)]
fn massless_particle_midpoint(q: Config, v: Velocity, b: f64, k: f64) -> f64 {
    -b * q.y * v.x - 0.5 * k * (q.x * q.x + q.y * q.y)
}

const GAMMA: (f64, f64) = (1.0, 2.0);

/// Both vortices rotate rigidly about the centre of vorticity `c = (Γ1 z1 + Γ2 z2)/(Γ1 + Γ2)`
/// at `Ω = (Γ1 + Γ2)/(2π d²)`, `d = |z1 − z2|` (constant): the exact positions at `t`.
fn exact(z: [(f64, f64); 2], t: f64) -> [(f64, f64); 2] {
    let (g1, g2) = GAMMA;
    let c = (
        (g1 * z[0].0 + g2 * z[1].0) / (g1 + g2),
        (g1 * z[0].1 + g2 * z[1].1) / (g1 + g2),
    );
    let d2 = (z[0].0 - z[1].0).powi(2) + (z[0].1 - z[1].1).powi(2);
    let a = (g1 + g2) / (2.0 * PI * d2) * t;
    z.map(|(x, y)| {
        let (dx, dy) = (x - c.0, y - c.1);
        (
            c.0 + a.cos() * dx - a.sin() * dy,
            c.1 + a.sin() * dx + a.cos() * dy,
        )
    })
}

fn positions(x: &SVector<f64, 3>, vt: f64) -> [(f64, f64); 2] {
    let (r1, r2, phi) = (x[0], x[1], x[2]);
    [
        (r1 * vt.cos(), r1 * vt.sin()),
        (r2 * (vt + phi).cos(), r2 * (vt + phi).sin()),
    ]
}

/// Off-centre initial positions (the centre of vorticity is not the origin, so `r1`, `r2`, `φ`
/// all vary), momenta from the Legendre map `p = ∂L/∂v (q)` (independent of `v`: the primary
/// constraint of the degenerate Lagrangian).
fn run(steps: usize, t: f64) -> (Trajectory<3, 1>, f64) {
    let sys = VortexPair {
        gamma1: GAMMA.0,
        gamma2: GAMMA.1,
        h: t / steps as f64,
    };
    let q = SVector::from([1.0, 0.8, 2.0, 0.3]);
    let initial: ReducedState<3, 1> = sys.reduced_state(q, SVector::zeros()).unwrap();
    let traj = ReducedIntegrator::plus(sys, NewtonOptions::default())
        .run(initial)
        .steps(steps)
        .collect()
        .unwrap();
    let z0 = positions(&initial.x, initial.g[0]);
    let z_ref = exact(z0, t);
    let z = positions(&traj.last().x, traj.last().g[0]);
    let err = (0..2)
        .map(|j| (z[j].0 - z_ref[j].0).hypot(z[j].1 - z_ref[j].1))
        .fold(0.0, f64::max);
    (traj, err)
}

/// The observed order of the midpoint rule against the exact rigid rotation at T = 5 (about a
/// quarter turn): log2 of successive error ratios at N = 50, 100, 200, 400 within [1.9, 2.1].
#[test]
fn vortex_pair_converges_at_order_two() {
    let errs: Vec<f64> = [50, 100, 200, 400].iter().map(|&n| run(n, 5.0).1).collect();
    let orders: Vec<f64> = errs.windows(2).map(|w| (w[0] / w[1]).log2()).collect();
    eprintln!("vortex pair errors {errs:?}, observed orders {orders:?}");
    for p in &orders {
        assert!((1.9..=2.1).contains(p), "order {p} from {errs:?}");
    }
}

/// The angular impulse `μ = −½ (Γ1 r1² + Γ2 r2²)` is one of the reduced equations: bit-for-bit
/// constant along the run, and equal to its value at the initial positions.
#[test]
fn angular_impulse_is_exact() {
    let (traj, _) = run(400, 5.0);
    let mu0 = traj.states[0].mu;
    let x0 = traj.states[0].x;
    let expect = -0.5 * (GAMMA.0 * x0[0] * x0[0] + GAMMA.1 * x0[1] * x0[1]);
    assert!((mu0[0] - expect).abs() < 1e-15);
    assert!(traj.states.iter().all(|s| s.mu == mu0));
}

/// `E = ⟨∂L/∂v, v⟩ − L = H` for a Lagrangian linear in `v`. At the nodes it needs the inverse
/// Legendre map, which does not exist: a typed error at node 0. At the midpoints it is defined
/// and stays within 1e-5 relative of its first value (H is conserved by the flow, and the
/// midpoint rule keeps it to O(h²)).
#[test]
fn energy_of_a_degenerate_lagrangian() {
    let (traj, _) = run(400, 5.0);
    let sys = VortexPair {
        gamma1: GAMMA.0,
        gamma2: GAMMA.1,
        h: traj.h,
    };
    assert_eq!(
        reduced_continuous_energies(&sys, &traj),
        Err(LegendreError::Singular { node: 0 })
    );
    let q: Vec<SVector<f64, 4>> = traj.states.iter().map(|s| sys.untrivialize(s).q).collect();
    let e = midpoint_energies(&sys, &q, traj.h);
    let spread = e.iter().map(|x| (x - e[0]).abs()).fold(0.0, f64::max) / e[0].abs();
    eprintln!("vortex pair midpoint energy spread {spread:e}");
    assert!(spread < 1e-5, "{spread:e}");
}

/// With the left-point rule, `p_k + D1 L_d(q_k, q_{k+1}) = 0` has a first row independent of
/// `q_{k+1}`: the step's Jacobian is singular and the integrator says so at step 0.
#[test]
fn singular_discrete_legendre_map_is_a_typed_error() {
    let sys = MasslessParticle {
        b: 1.0,
        k: 1.0,
        h: 0.01,
    };
    let q = SVector::from([0.5, 0.2]);
    let initial = sys.unreduced_state(q, SVector::zeros()).unwrap();
    let err = UnreducedIntegrator::new(sys, NewtonOptions::default())
        .run(initial)
        .steps(10)
        .collect()
        .unwrap_err();
    assert_eq!(err.trajectory.states.len(), 1, "the initial state is kept");
    assert!(
        matches!(
            err.source,
            StepError::SingularJacobian { step: 0, .. } | StepError::IllConditioned { step: 0, .. }
        ),
        "{err}"
    );
}

/// The midpoint rule of the same Lagrangian is regular: the guiding centre circles the origin
/// (`ẋ = −k y/b`, `ẏ = k x/b`: rotation at the rate k/b), keeping its radius to 1e-4.
#[test]
fn massless_particle_midpoint_rule_is_regular() {
    let sys = MasslessMidpoint {
        b: 1.0,
        k: 1.0,
        h: 0.01,
    };
    let q = SVector::from([0.5, 0.2]);
    let traj = UnreducedIntegrator::new(sys, NewtonOptions::default())
        .run(sys.unreduced_state(q, SVector::zeros()).unwrap())
        .steps(628)
        .collect()
        .unwrap();
    let r0 = q.norm();
    let worst = traj
        .states
        .iter()
        .map(|s| (s.q.norm() - r0).abs())
        .fold(0.0, f64::max);
    eprintln!("massless particle, midpoint: max |r − r0| = {worst:e}");
    assert!(worst < 1e-4 * r0, "{worst:e}");
}
