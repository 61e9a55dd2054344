//! Adaptive steps on rotation groups: `time(t), adapt = |q| g` with rotation and direction
//! coordinates — a rigid body on an eccentric orbit and a spherical pendulum — against Kepler's
//! equation and tight Runge–Kutta solves, with their conserved momenta, reversibility and typed
//! errors.

mod common;

use common::{eccentric_anomaly, rk4};
use dirac::lie::cayley;
use dirac::prelude::*;

/// A rigid body on a Kepler orbit in the plane (the orbit and the attitude uncoupled), its step
/// following `r^{3/2}`: the attitude must still be stepped in physical time.
#[reduced_lagrangian(shape(x, y), rotation(r), group(t), rule = trapezoid, symmetry(r),
    time(t), adapt = |q| (q.x * q.x + q.y * q.y).powf(0.75))]
fn orbiting(q: Config, v: Velocity, k: f64, j1: f64, j2: f64, j3: f64) -> f64 {
    0.5 * (v.x * v.x + v.y * v.y)
        + k / (q.x * q.x + q.y * q.y).sqrt()
        + 0.5 * (j1 * v.r.x * v.r.x + j2 * v.r.y * v.r.y + j3 * v.r.z * v.r.z)
}

/// The spherical pendulum of unit length in unit gravity, its steps shorter near the bottom
/// where it is fastest.
#[reduced_lagrangian(direction(n), group(t), rule = trapezoid, symmetry(n, axis = z),
    time(t), adapt = |q| 1.5 + q.n.z)]
fn swinging(q: Config, v: Velocity, g: f64) -> f64 {
    0.5 * v.n.dot(&v.n) - g * q.n.z
}

/// The same pendulum with a damping force `−c ṅ`.
#[reduced_lagrangian(direction(n), group(t), rule = trapezoid, time(t), adapt = |q| 1.5 + q.n.z,
    force = |dq| -c * v.n.dot(&dq.n))]
fn damped_swing(q: Config, v: Velocity, g: f64, c: f64) -> f64 {
    0.5 * v.n.dot(&v.n) - g * q.n.z
}

const TAU: f64 = 2.0 * std::f64::consts::PI;
const J: [f64; 3] = [1.0, 2.0, 3.0];

fn tight() -> NewtonOptions {
    NewtonOptions {
        abs_tol: 1e-14,
        rel_tol: 1e-14,
        ..NewtonOptions::default()
    }
}

fn orbiting_system(h: f64) -> Orbiting {
    Orbiting {
        h,
        k: 1.0,
        j1: J[0],
        j2: J[1],
        j3: J[2],
    }
}

/// The state at periapsis of the orbit of eccentricity `e` (semi-major axis 1, period 2π), the
/// body spinning about a generic axis, on the energy level.
fn periapsis(sys: &Orbiting, e: f64) -> LieState<12, 6> {
    let r0 = 1.0 - e;
    let speed = ((1.0 + e) / r0).sqrt();
    sys.unreduced_state(
        &OrbitingConfig {
            x: r0,
            y: 0.0,
            r: cayley(&Vector3::new(0.2, -0.1, 0.4)),
            t: 0.0,
        },
        &OrbitingVelocity {
            x: 0.0,
            y: speed,
            r: Vector3::new(0.3, 0.5, -0.07),
            t: 1.0,
        },
    )
    .unwrap()
}

/// The orbit at time `t` from periapsis: `(x, y)` by Kepler's equation `E − e sin E = t`.
fn kepler(e: f64, t: f64) -> (f64, f64) {
    let big_e = eccentric_anomaly(e, t);
    (big_e.cos() - e, (1.0 - e * e).sqrt() * big_e.sin())
}

/// The free rigid body `Π̇ = Π × J⁻¹Π`, `Ṙ = R (J⁻¹Π)^` over `t` by the classical Runge–Kutta
/// method with 20,000 steps per unit time.
fn free_body(r: Matrix3<f64>, pi: Vector3<f64>, t: f64) -> (Matrix3<f64>, Vector3<f64>) {
    let j = Vector3::from(J);
    // y = (R row by row, Π).
    let mut y0 = SVector::<f64, 12>::zeros();
    y0.fixed_rows_mut::<9>(0)
        .copy_from_slice(r.transpose().as_slice());
    y0.fixed_rows_mut::<3>(9).copy_from(&pi);
    let y = rk4(
        y0,
        |y| {
            let r = Matrix3::from_row_slice(&y.as_slice()[..9]);
            let pi = Vector3::new(y[9], y[10], y[11]);
            let omega = pi.component_div(&j);
            let mut dy = SVector::<f64, 12>::zeros();
            dy.fixed_rows_mut::<9>(0)
                .copy_from_slice((r * omega.cross_matrix()).transpose().as_slice());
            dy.fixed_rows_mut::<3>(9).copy_from(&pi.cross(&omega));
            dy
        },
        t,
        20_000.0,
    );
    (
        Matrix3::from_row_slice(&y.as_slice()[..9]),
        Vector3::new(y[9], y[10], y[11]),
    )
}

/// The largest error of the position, the attitude and the body momentum after `span/ε` steps
/// of `method` at `e = 0.9`, against the closed-form orbit and the tight solve of the attitude
/// at the physical time reached.
fn orbiting_error(eps: f64, span: f64, method: CompositionMethod) -> f64 {
    let sys = orbiting_system(eps);
    let s0 = periapsis(&sys, 0.9);
    let integ = LieIntegrator::new(sys, tight());
    let n = (span / eps).round() as usize;
    let last = *Composition::new(integ, method)
        .run(s0)
        .steps(n)
        .collect()
        .unwrap()
        .last();
    let (q, p) = (sys.config(&last), sys.momenta(&last));
    let (x, y) = kepler(0.9, q.t);
    let start = sys.config(&s0);
    let (r, pi) = free_body(start.r, sys.momenta(&s0).r, q.t);
    (q.x - x)
        .abs()
        .max((q.y - y).abs())
        .max((q.r - r).amax())
        .max((p.r - pi).amax())
}

#[test]
fn a_body_on_an_eccentric_orbit_has_order_two_and_four_in_the_fictitious_step() {
    for (method, steps) in [
        (CompositionMethod::BASE, [0.04, 0.02, 0.01]),
        (CompositionMethod::TRIPLE_JUMP, [0.08, 0.04, 0.02]),
    ] {
        let e: Vec<f64> = steps
            .iter()
            .map(|&eps| orbiting_error(eps, 4.0, method))
            .collect();
        for w in e.windows(2) {
            let observed = (w[0] / w[1]).log2();
            assert!(
                (observed - f64::from(method.order)).abs() < 0.3,
                "order {observed} (expected {}) from {e:?}",
                method.order
            );
        }
    }
}

#[test]
fn the_energy_level_and_the_spatial_momentum_are_kept_and_reduced_equals_unreduced() {
    let sys = orbiting_system(0.05);
    let s0 = periapsis(&sys, 0.9);
    let unreduced = LieIntegrator::new(sys, tight());
    let reduced = ReducedLieIntegrator::new(sys, tight());
    let a = unreduced.run(s0).steps(2000).collect().unwrap();
    let b = reduced
        .run(reduced.reduce(&s0))
        .steps(2000)
        .collect()
        .unwrap();
    let last = sys.config(a.last());
    assert!(last.t > 2.0 * TAU, "the run covered t = {}", last.t);
    let pt = s0.p[5];
    let energy = |s: &LieState<12, 6>| {
        let (q, p) = (sys.config(s), sys.momenta(s));
        let kinetic = 0.5 * (p.x * p.x + p.y * p.y)
            + 0.5 * (0..3).map(|i| p.r[i] * p.r[i] / J[i]).sum::<f64>();
        kinetic - 1.0 / (q.x * q.x + q.y * q.y).sqrt()
    };
    assert!((energy(&s0) + pt).abs() < 1e-14, "p_t = −E at the start");
    let pi0 = reduced.momentum_map(&s0).unwrap();
    let mut worst_energy: f64 = 0.0;
    for (s, r) in a.states.iter().zip(&b.states) {
        assert_eq!(s.p[5], pt, "p_t of the unreduced run, bit for bit");
        assert_eq!(r.p[5], pt, "p_t of the reduced run, bit for bit");
        assert_eq!(r.mu, pi0, "π of the reduced run, bit for bit");
        let drift = (reduced.momentum_map(s).unwrap() - pi0).amax();
        assert!(drift < 1e-13, "π of the unreduced run drifts by {drift:e}");
        let gap = (s.q - r.q).amax().max((s.p - r.p).amax());
        assert!(gap < 1e-9, "reduced and unreduced differ by {gap:e}");
        worst_energy = worst_energy.max((energy(s) + pt).abs());
    }
    // The energy oscillates about −p_t (the step's own error at periapsis), without drift.
    assert!(worst_energy < 1e-2, "{worst_energy:e}");
}

#[test]
fn forward_then_backward_returns_to_the_start_and_both_sides_agree() {
    let s0 = periapsis(&orbiting_system(0.05), 0.9);
    let forward = LieIntegrator::new(orbiting_system(0.05), tight());
    let backward = LieIntegrator::new(orbiting_system(-0.05), tight());
    let minus = LieIntegrator::minus(orbiting_system(0.05), tight());
    let (mut ws_f, mut ws_b, mut ws_m) =
        (forward.workspace(), backward.workspace(), minus.workspace());
    let steps = 300;
    let mut s = s0;
    for k in 0..steps {
        let next = forward.step_in(&mut ws_f, k, &s).unwrap().0;
        let other = minus.step_in(&mut ws_m, k, &s).unwrap().0;
        let gap = (next.q - other.q).amax().max((next.p - other.p).amax());
        assert!(gap < 1e-12, "step {k}: (+) and (−) differ by {gap:e}");
        s = next;
    }
    assert!(s.q[11] > 2.0, "the run covered physical time {}", s.q[12]);
    for k in 0..steps {
        s = backward.step_in(&mut ws_b, k, &s).unwrap().0;
    }
    let gap = (s.q - s0.q).amax().max((s.p - s0.p).amax());
    assert!(gap < 1e-12 * steps as f64, "{gap:e}");
}

#[test]
fn a_monitor_that_is_not_positive_is_a_typed_error() {
    let sys = orbiting_system(0.05);
    let at_origin = OrbitingConfig {
        x: 0.0,
        y: 0.0,
        r: Matrix3::identity(),
        t: 0.0,
    };
    let err = sys
        .unreduced_state(&at_origin, &OrbitingVelocity::default())
        .unwrap_err();
    assert!(
        matches!(err, StepError::InvalidMonitor { step: 0, value } if value == 0.0),
        "{err}"
    );
    let s0 = sys.state(
        &at_origin,
        &OrbitingMomentum {
            x: 0.0,
            y: 1.0,
            r: Vector3::zeros(),
            t: 0.0,
        },
    );
    let err = LieIntegrator::new(sys, tight())
        .run(s0)
        .steps(10)
        .collect()
        .unwrap_err();
    assert!(
        matches!(err.source, StepError::InvalidMonitor { step: 0, .. }),
        "{}",
        err.source
    );
}

/// The spherical pendulum `r̈ = −g e_z − c ṙ + λ r`, `λ = g z − |ṙ|²` (unit length, `g = 1`;
/// the damping is tangent), over `t` by the classical Runge–Kutta method with 20,000 steps per
/// unit time.
fn pendulum(r: Vector3<f64>, v: Vector3<f64>, c: f64, t: f64) -> Vector3<f64> {
    let mut y0 = SVector::<f64, 6>::zeros();
    y0.fixed_rows_mut::<3>(0).copy_from(&r);
    y0.fixed_rows_mut::<3>(3).copy_from(&v);
    let y = rk4(
        y0,
        |y| {
            let (r, v) = (y.fixed_rows::<3>(0), y.fixed_rows::<3>(3));
            let lambda = r.z - v.norm_squared();
            let a = Vector3::new(0.0, 0.0, -1.0) - v * c + r * lambda;
            let mut dy = SVector::<f64, 6>::zeros();
            dy.fixed_rows_mut::<3>(0).copy_from(&v);
            dy.fixed_rows_mut::<3>(3).copy_from(&a);
            dy
        },
        t,
        20_000.0,
    );
    y.fixed_rows::<3>(0).into_owned()
}

/// The pendulum's start: tilted by 1.2 rad from the bottom, moving sideways.
fn pendulum_start() -> (Vector3<f64>, Vector3<f64>) {
    let (s, c) = 1.2_f64.sin_cos();
    (Vector3::new(s, 0.0, -c), Vector3::new(0.0, 0.8, 0.0))
}

fn pendulum_error(eps: f64) -> f64 {
    let sys = Swinging { h: eps, g: 1.0 };
    let (n0, v0) = pendulum_start();
    let s0 = sys
        .unreduced_state(
            &SwingingConfig { n: n0, t: 0.0 },
            &SwingingVelocity { n: v0, t: 1.0 },
        )
        .unwrap();
    let integ = ReducedLieIntegrator::new(sys, tight());
    let r0 = integ.reduce(&s0);
    let traj = integ
        .run(r0)
        .steps((3.0 / eps).round() as usize)
        .collect()
        .unwrap();
    for s in &traj.states {
        assert_eq!(
            s.mu, r0.mu,
            "the angular momentum about the vertical, bit for bit"
        );
        assert_eq!(s.p[2], s0.p[2], "p_t, bit for bit");
    }
    let q = sys.config(&traj.last().unreduced());
    (q.n - pendulum(n0, v0, 0.0, q.t)).amax()
}

#[test]
fn a_spherical_pendulum_with_adaptive_steps_has_order_two_and_keeps_its_momenta() {
    let e: Vec<f64> = [0.04, 0.02, 0.01]
        .iter()
        .map(|&eps| pendulum_error(eps))
        .collect();
    for w in e.windows(2) {
        let observed = (w[0] / w[1]).log2();
        assert!((observed - 2.0).abs() < 0.3, "order {observed} from {e:?}");
    }
}

/// The error of the damped pendulum after `3/ε` steps against the tight solve, and the largest
/// gap between `−p_t` and the physical energy along the run (the time translation's forced
/// balance: `p_t` changes by the work of the damping).
fn damped_error(eps: f64) -> (f64, f64, f64) {
    let sys = DampedSwing {
        h: eps,
        g: 1.0,
        c: 0.3,
    };
    let (n0, v0) = pendulum_start();
    let s0 = sys
        .unreduced_state(
            &DampedSwingConfig { n: n0, t: 0.0 },
            &DampedSwingVelocity { n: v0, t: 1.0 },
        )
        .unwrap();
    let traj = LieIntegrator::new(sys, tight())
        .run(s0)
        .steps((3.0 / eps).round() as usize)
        .collect()
        .unwrap();
    let energy = |s: &LieState<10, 3>| {
        let (q, p) = (sys.config(s), sys.momenta(s));
        0.5 * p.n.norm_squared() + q.n.z
    };
    let gap = traj
        .states
        .iter()
        .map(|s| (energy(s) + s.p[2]).abs())
        .fold(0.0, f64::max);
    let q = sys.config(traj.last());
    let lost = energy(&s0) - energy(traj.last());
    ((q.n - pendulum(n0, v0, 0.3, q.t)).amax(), gap, lost)
}

#[test]
fn a_damped_pendulum_with_adaptive_steps_has_order_two_and_balances_its_energy() {
    let runs: Vec<(f64, f64, f64)> = [0.04, 0.02, 0.01]
        .iter()
        .map(|&eps| damped_error(eps))
        .collect();
    let e: Vec<f64> = runs.iter().map(|r| r.0).collect();
    for w in e.windows(2) {
        let observed = (w[0] / w[1]).log2();
        assert!((observed - 2.0).abs() < 0.3, "order {observed} from {e:?}");
    }
    // The damping removes energy, and −p_t follows the energy down to the step's error.
    for &(_, gap, lost) in &runs {
        assert!(lost > 0.1, "the damping removed {lost}");
        assert!(
            gap < 1e-2 * lost,
            "−p_t and the energy differ by {gap:e} (lost {lost})"
        );
    }
    assert!(
        runs[2].1 < runs[0].1 / 8.0,
        "the gap shrinks with the step: {runs:?}"
    );
}

#[test]
fn a_run_on_rotation_groups_lands_on_a_physical_end_time() {
    let sys = orbiting_system(0.04);
    let s0 = periapsis(&sys, 0.9);
    let integ = ReducedLieIntegrator::new(sys, tight());
    let traj = integ
        .run(integ.reduce(&s0))
        .end_time(3.0)
        .collect()
        .unwrap();
    for (k, s) in traj.states.iter().enumerate() {
        assert_eq!(traj.times[k], s.q[11], "time of state {k}");
    }
    let last = traj.last().unreduced();
    let q = sys.config(&last);
    assert!((q.t - 3.0).abs() <= 4.0 * f64::EPSILON * 3.0, "{}", q.t);
    let (x, y) = kepler(0.9, 3.0);
    let (r, pi) = free_body(sys.config(&s0).r, sys.momenta(&s0).r, 3.0);
    let error = (q.x - x)
        .abs()
        .max((q.y - y).abs())
        .max((q.r - r).amax())
        .max((sys.momenta(&last).r - pi).amax());
    assert!(error < 1e-2, "{error:e}");
    assert_eq!(traj.last().mu, traj.states[0].mu);
}
