//! Adaptive steps: `time(t), adapt = |q| g` — the Poincaré time transformation stepped at a
//! fixed fictitious step — against Kepler's closed form, with its conserved momenta, its
//! reversibility and its typed errors.

mod common;

use dirac::prelude::*;
use dirac::runtime::adaptive;

/// Kepler's problem in the plane in polar coordinates, its step following `r^{3/2}`.
#[reduced_lagrangian(shape(r), group(theta, t), time(t), adapt = |q| q.r.powf(1.5), rule = midpoint)]
fn kepler(q: Config, v: Velocity, k: f64) -> f64 {
    0.5 * (v.r * v.r + q.r * q.r * v.theta * v.theta) + k / q.r
}

/// The same Lagrangian stepped in physical time.
#[reduced_lagrangian(shape(r), group(theta), rule = midpoint)]
fn kepler_fixed(q: Config, v: Velocity, k: f64) -> f64 {
    0.5 * (v.r * v.r + q.r * q.r * v.theta * v.theta) + k / q.r
}

/// A particle on a line in a uniform field whose monitor is `1 + c x`, `c` a control.
#[reduced_lagrangian(shape(x), group(t), time(t), adapt = |q| 1.0 + c * q.x, controls(c), rule = midpoint)]
fn drifting(q: Config, v: Velocity, m: f64, c: f64) -> f64 {
    0.5 * m * v.x * v.x - 0.1 * q.x
}

/// A particle on a line whose monitor is the square root of its position.
#[reduced_lagrangian(shape(x), group(t), time(t), adapt = |q| q.x.sqrt(), rule = midpoint)]
fn rooted(q: Config, v: Velocity, m: f64) -> f64 {
    0.5 * m * v.x * v.x - 0.1 * q.x
}

/// A damped oscillator, `ẍ = −x − c ẋ`, with a monitor that shortens steps away from rest.
#[reduced_lagrangian(shape(x), group(t), time(t), adapt = |q| 1.0 / (1.0 + q.x * q.x), rule = midpoint, force = |dq| -c * v.x * dq.x)]
fn damped(q: Config, v: Velocity, c: f64) -> f64 {
    0.5 * v.x * v.x - 0.5 * q.x * q.x
}

const TAU: f64 = 2.0 * std::f64::consts::PI;

/// The orbit of eccentricity `e` (semi-major axis 1, `k = 1`, period 2π) at time `t` from
/// periapsis at `t = 0`: `(r, θ)` by Kepler's equation `E − e sin E = t mod 2π`, solved by Newton.
fn exact(e: f64, t: f64) -> (f64, f64) {
    let big_e = common::eccentric_anomaly(e, t);
    let r = 1.0 - e * big_e.cos();
    let anomaly = 2.0
        * ((1.0 + e).sqrt() * (big_e / 2.0).sin()).atan2((1.0 - e).sqrt() * (big_e / 2.0).cos());
    (r, anomaly.rem_euclid(TAU) + (t / TAU).floor() * TAU)
}

/// The reduced initial state at periapsis, on the energy level.
fn periapsis(sys: &Kepler, e: f64) -> ReducedState<1, 2> {
    let r0 = 1.0 - e;
    let omega = (1.0 - e * e).sqrt() / (r0 * r0);
    sys.reduced_state([r0, 0.0, 0.0], [0.0, omega, 1.0])
        .unwrap()
}

/// The physical energy `p_r²/2 + p_θ²/(2 r²) − k/r` of a reduced state.
fn energy(s: &ReducedState<1, 2>) -> f64 {
    let (r, pr, ptheta) = (s.x[0], s.w[0], s.mu[0]);
    0.5 * pr * pr + 0.5 * ptheta * ptheta / (r * r) - 1.0 / r
}

fn tight() -> NewtonOptions {
    NewtonOptions {
        abs_tol: 1e-14,
        rel_tol: 1e-14,
        ..NewtonOptions::default()
    }
}

/// The largest of the errors in `r` and `θ` after `span/ε` steps of `method` (the base step
/// for [`CompositionMethod::BASE`]), against the closed form at the physical time reached.
fn kepler_error(e: f64, eps: f64, span: f64, method: CompositionMethod) -> f64 {
    let sys = Kepler { h: eps, k: 1.0 };
    let integ = ReducedIntegrator::plus(sys, tight());
    let s0 = periapsis(&sys, e);
    let n = (span / eps).round() as usize;
    let last = *Composition::new(integ, method)
        .run(s0)
        .steps(n)
        .collect()
        .unwrap()
        .last();
    let (r, theta) = exact(e, last.g[1]);
    (last.x[0] - r).abs().max((last.g[0] - theta).abs())
}

#[test]
fn kepler_at_e_0_9_has_order_two_four_and_six_in_the_fictitious_step() {
    for (method, steps) in [
        (CompositionMethod::BASE, [0.04, 0.02, 0.01]),
        (CompositionMethod::TRIPLE_JUMP, [0.08, 0.04, 0.02]),
        (CompositionMethod::KAHAN_LI_6, [0.16, 0.08, 0.04]),
    ] {
        let order = f64::from(method.order);
        let e: Vec<f64> = steps
            .iter()
            .map(|&eps| kepler_error(0.9, eps, 8.0, method))
            .collect();
        for w in e.windows(2) {
            let observed = (w[0] / w[1]).log2();
            assert!(
                (observed - order).abs() < 0.25,
                "order {observed} (expected {order}) from errors {e:?}"
            );
        }
    }
}

#[test]
fn the_angular_momentum_and_the_energy_level_are_kept_bit_for_bit() {
    let sys = Kepler { h: 0.05, k: 1.0 };
    let integ = ReducedIntegrator::plus(sys, NewtonOptions::default());
    let s0 = periapsis(&sys, 0.9);
    // p_t = −E at the level the run starts on: E = −1/(2a) = −1/2.
    assert!((s0.mu[1] - 0.5).abs() < 1e-15, "{}", s0.mu[1]);
    let (e0, steps) = (energy(&s0), 20_000);
    let (mut first, mut last_tenth): (Vec<f64>, Vec<f64>) = (Vec::new(), Vec::new());
    let mut t_last = 0.0;
    integ
        .run(s0)
        .steps(steps)
        .observe(|k, _, s: &ReducedState<1, 2>, _| {
            assert_eq!(s.mu, s0.mu, "step {k}");
            let de = energy(s) - e0;
            if k < steps / 10 {
                first.push(de);
            } else if k >= steps - steps / 10 {
                last_tenth.push(de);
            }
            assert!(s.g[1] > t_last || k == 0, "time runs forward");
            t_last = s.g[1];
        })
        .stream()
        .unwrap();
    // Over ≈ 40 orbits: the energy error oscillates with no drift.
    let spread = |v: &[f64]| {
        let (lo, hi) = v
            .iter()
            .fold((f64::MAX, f64::MIN), |(a, b), &x| (a.min(x), b.max(x)));
        (lo, hi)
    };
    let (lo, hi) = spread(&first);
    let mean = last_tenth.iter().sum::<f64>() / last_tenth.len() as f64;
    assert!(
        lo <= mean && mean <= hi,
        "mean of the last tenth {mean:e} outside the first tenth's [{lo:e}, {hi:e}]"
    );
    assert!(hi - lo < 1e-2, "energy error spread {:e}", hi - lo);
    assert!(t_last > 40.0 * TAU, "physical time reached {t_last}");
}

#[test]
fn reduced_unreduced_and_both_sides_agree() {
    let sys = Kepler { h: 0.05, k: 1.0 };
    let s0 = periapsis(&sys, 0.7);
    let plus = ReducedIntegrator::plus(sys, tight());
    let minus = ReducedIntegrator::minus(sys, tight());
    let unreduced = UnreducedIntegrator::new(sys, tight());
    let a = plus.run(s0).steps(400).collect().unwrap();
    let b = minus.run(s0).steps(400).collect().unwrap();
    let c = unreduced
        .run(sys.untrivialize(&s0))
        .steps(400)
        .collect()
        .unwrap();
    for k in 0..=400 {
        let (a, b, c) = (&a.states[k], &b.states[k], sys.trivialize(&c.states[k]));
        let gap = (a.x - b.x)
            .amax()
            .max((a.g - b.g).amax())
            .max((a.x - c.x).amax())
            .max((a.g - c.g).amax());
        assert!(gap < 1e-9, "step {k}: {gap:e}");
    }
}

#[test]
fn forward_then_backward_returns_to_the_start() {
    let sys = Kepler { h: 0.05, k: 1.0 };
    let s0 = periapsis(&sys, 0.9);
    let forward = ReducedIntegrator::plus(sys, tight());
    let backward = ReducedIntegrator::plus(Kepler { h: -0.05, k: 1.0 }, tight());
    let (mut ws_f, mut ws_b) = (forward.workspace(), backward.workspace());
    let steps = 300;
    let mut s = s0;
    for k in 0..steps {
        s = forward.step_in(&mut ws_f, k, &s).unwrap().0;
    }
    assert!(s.g[1] > 2.0, "the run covered physical time {}", s.g[1]);
    for k in 0..steps {
        s = backward.step_in(&mut ws_b, k, &s).unwrap().0;
    }
    let gap = (s.x - s0.x)
        .amax()
        .max((s.w - s0.w).amax())
        .max((s.g - s0.g).amax());
    assert!(gap < 1e-12 * steps as f64, "{gap:e}");
}

#[test]
fn adaptive_steps_beat_the_fixed_step_at_high_eccentricity() {
    // One orbit at e = 0.9: the adaptive run, stopped once its physical time passes the
    // period, against fixed steps of the same Lagrangian with four times as many steps.
    let e = 0.9;
    let sys = Kepler { h: 0.05, k: 1.0 };
    let traj = ReducedIntegrator::plus(sys, tight())
        .run(periapsis(&sys, e))
        .steps(1_000_000)
        .stop(|_, _, s: &ReducedState<1, 2>| s.g[1] >= TAU)
        .collect()
        .unwrap();
    let last = traj.last();
    let (r, theta) = exact(e, last.g[1]);
    let adaptive_error = (last.x[0] - r).abs().max((last.g[0] - theta).abs());
    let n = 4 * traj.step_count();
    let fixed = KeplerFixed {
        h: TAU / n as f64,
        k: 1.0,
    };
    let r0 = 1.0 - e;
    let omega = (1.0 - e * e).sqrt() / (r0 * r0);
    let s0 = fixed.reduced_state([r0, 0.0], [0.0, omega]).unwrap();
    let end = *ReducedIntegrator::plus(fixed, tight())
        .run(s0)
        .steps(n)
        .collect()
        .unwrap()
        .last();
    let (r, theta) = exact(e, TAU);
    let fixed_error = (end.x[0] - r).abs().max((end.g[0] - theta).abs());
    assert!(
        fixed_error > 3.0 * adaptive_error,
        "{} adaptive steps: {adaptive_error:e}; {n} fixed steps: {fixed_error:e}",
        traj.step_count()
    );
}

#[test]
fn a_monitor_that_is_not_positive_is_a_typed_error_with_its_step() {
    // At the initial state: 1 + c x = −0.5.
    let sys = Drifting {
        h: 0.1,
        m: 1.0,
        c: 3.0,
    };
    let err = sys.reduced_state([-0.5, 0.0], [1.0, 1.0]).unwrap_err();
    assert!(
        matches!(err, StepError::InvalidMonitor { step: 0, .. }),
        "{err}"
    );
    // In the middle of a run: a control law sets c so that the monitor turns negative.
    let sys = Drifting {
        h: 0.1,
        m: 1.0,
        c: 0.0,
    };
    let s0 = sys.reduced_state([1.0, 0.0], [1.0, 1.0]).unwrap();
    let err = ReducedIntegrator::plus(sys, NewtonOptions::default())
        .run(s0)
        .steps(10)
        .feedback(|k, _, _: &ReducedState<1, 1>, u: &mut [f64]| {
            u[0] = if k < 4 { 0.0 } else { -2.0 }
        })
        .collect()
        .unwrap_err();
    assert!(
        matches!(err.source, StepError::InvalidMonitor { step: 4, value } if value < 0.0),
        "{}",
        err.source
    );
    assert_eq!(
        err.trajectory.states.len(),
        5,
        "the states before the failed step are kept"
    );
    // A monitor that is not finite: √x for x < 0, as the run starts.
    let sys = Rooted { h: 0.1, m: 1.0 };
    let mut s0 = sys.reduced_state([1.0, 0.0], [1.0, 1.0]).unwrap();
    s0.x[0] = -1.0;
    let err = ReducedIntegrator::plus(sys, NewtonOptions::default())
        .run(s0)
        .steps(5)
        .collect()
        .unwrap_err();
    assert!(
        matches!(err.source, StepError::InvalidMonitor { step: 0, value } if value.is_nan()),
        "{}",
        err.source
    );
}

#[test]
fn a_step_chosen_from_a_tolerance_reaches_it() {
    // Kepler at e = 0.9 over a fictitious span of 8 (a little more than one orbit): the step the
    // pilot at ε0 = 0.1 and 0.05 picks, then the run at that step against the closed form.
    let span = 8.0;
    for (method, tolerance) in [
        (CompositionMethod::BASE, 1e-4),
        (CompositionMethod::TRIPLE_JUMP, 1e-6),
    ] {
        let eps = adaptive::step_for_tolerance(method.order, 0.1, tolerance, |eps| {
            let sys = Kepler { h: eps, k: 1.0 };
            let n = (span / eps).round() as usize;
            let last = *Composition::new(ReducedIntegrator::plus(sys, tight()), method)
                .run(periapsis(&sys, 0.9))
                .steps(n)
                .collect()?
                .last();
            Ok::<_, Box<IntegrationError<_>>>(DVector::from_vec(vec![last.x[0], last.g[0]]))
        })
        .unwrap();
        let error = kepler_error(0.9, eps, span, method);
        assert!(
            error <= tolerance && error > tolerance / 30.0,
            "{}: ε = {eps}, error {error:e} for the tolerance {tolerance:e}",
            method.name
        );
    }
}

/// `x(t)` of the damped oscillator from `x(0) = 1`, `ẋ(0) = 0`.
fn damped_exact(c: f64, t: f64) -> f64 {
    let (gamma, omega) = (0.5 * c, (1.0 - 0.25 * c * c).sqrt());
    (-gamma * t).exp() * ((omega * t).cos() + gamma / omega * (omega * t).sin())
}

#[test]
fn a_damping_force_with_adaptive_steps_has_order_two_and_balances_the_energy() {
    let c = 0.3;
    let errors: Vec<f64> = [0.04, 0.02, 0.01]
        .iter()
        .map(|&eps| {
            let sys = Damped { h: eps, c };
            let s0 = sys.reduced_state([1.0, 0.0], [0.0, 1.0]).unwrap();
            let traj = ReducedIntegrator::plus(sys, tight())
                .run(s0)
                .steps((10.0 / eps) as usize)
                .collect()
                .unwrap();
            // −p_t follows the physical energy ½ẋ² + ½x² as the force drains it.
            for s in &traj.states {
                let energy = 0.5 * s.w[0] * s.w[0] + 0.5 * s.x[0] * s.x[0];
                assert!(
                    (energy + s.mu[0]).abs() < 20.0 * eps * eps,
                    "{energy} {}",
                    s.mu[0]
                );
            }
            let last = traj.last();
            (last.x[0] - damped_exact(c, last.g[0])).abs()
        })
        .collect();
    for w in errors.windows(2) {
        let observed = (w[0] / w[1]).log2();
        assert!(
            (observed - 2.0).abs() < 0.25,
            "order {observed} from {errors:?}"
        );
    }
}

#[test]
fn a_run_lands_on_a_physical_end_time_exactly() {
    let (e, end) = (0.9, 10.0);
    let errors: Vec<f64> = [0.04, 0.02, 0.01]
        .iter()
        .map(|&eps| {
            let sys = Kepler { h: eps, k: 1.0 };
            let integ = ReducedIntegrator::plus(sys, tight());
            let traj = integ
                .run(periapsis(&sys, e))
                .steps(1_000_000)
                .stop(|_, _, s: &ReducedState<1, 2>| s.g[1] >= end)
                .collect()
                .unwrap();
            // Take the step that crossed `end` again, landing on it.
            let k = traj.step_count() - 1;
            let before = traj.states[k];
            let last = adaptive::land_at(end, before.g[1], eps, |h| {
                let (s, _) =
                    ReducedIntegrator::plus(Kepler { h, k: 1.0 }, tight()).step(k, &before)?;
                Ok((s.g[1], s))
            })
            .unwrap();
            assert!(
                (last.g[1] - end).abs() <= 4.0 * f64::EPSILON * end,
                "{}",
                last.g[1]
            );
            assert_eq!(
                last.mu, before.mu,
                "the landing step is a step of the same integrator"
            );
            let (r, theta) = exact(e, end);
            (last.x[0] - r).abs().max((last.g[0] - theta).abs())
        })
        .collect();
    for w in errors.windows(2) {
        let observed = (w[0] / w[1]).log2();
        assert!(
            (observed - 2.0).abs() < 0.3,
            "order {observed} from {errors:?}"
        );
    }
    // An end time outside the step is a typed error.
    let err = adaptive::land_at(5.0, 6.0, 0.1, |_| Ok::<_, StepError>((7.0, ()))).unwrap_err();
    assert!(matches!(err, StepError::InvalidRun { .. }), "{err}");
}

#[test]
fn a_step_that_goes_back_in_time_is_a_typed_error() {
    // A fictitious step far too large for the periapsis of e = 0.99: the step equations' root
    // that Newton finds has Δt < 0.
    let sys = Kepler { h: 0.15, k: 1.0 };
    let err = ReducedIntegrator::plus(sys, NewtonOptions::default())
        .run(periapsis(&sys, 0.99))
        .steps(2000)
        .collect()
        .unwrap_err();
    assert!(
        matches!(err.source, StepError::TimeReversed { dt, .. } if dt <= 0.0),
        "{}",
        err.source
    );
}

/// A pendulum of unit length in Cartesian coordinates, held by a rod (a holonomic constraint),
/// its steps shorter where it swings fast (near the bottom, `y = −1`).
#[reduced_lagrangian(shape(x, y), group(t), time(t), adapt = |q| 1.5 + q.y, rule = midpoint,
    constraints = |q| [q.x * q.x + q.y * q.y - 1.0])]
fn rod(q: Config, v: Velocity, g: f64) -> f64 {
    0.5 * (v.x * v.x + v.y * v.y) - g * q.y
}

/// The pendulum angle from the bottom, `θ'' = −g sin θ`, by the classical Runge–Kutta method with
/// 20,000 steps per unit time, from `θ(0) = θ0` at rest.
fn pendulum_angle(g: f64, theta0: f64, t: f64) -> f64 {
    let n = (20_000.0 * t).ceil() as usize;
    let dt = t / n as f64;
    let f = |th: f64, om: f64| (om, -g * th.sin());
    let (mut th, mut om) = (theta0, 0.0);
    for _ in 0..n {
        let (a1, b1) = f(th, om);
        let (a2, b2) = f(th + 0.5 * dt * a1, om + 0.5 * dt * b1);
        let (a3, b3) = f(th + 0.5 * dt * a2, om + 0.5 * dt * b2);
        let (a4, b4) = f(th + dt * a3, om + dt * b3);
        th += dt / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4);
        om += dt / 6.0 * (b1 + 2.0 * b2 + 2.0 * b3 + b4);
    }
    th
}

#[test]
fn a_constrained_pendulum_with_adaptive_steps_keeps_its_rod_and_its_energy_level() {
    let (g, theta0): (f64, f64) = (9.81, 1.2);
    let errors: Vec<f64> = [0.02, 0.01, 0.005]
        .iter()
        .map(|&eps| {
            let sys = Rod { h: eps, g };
            let q0 = [theta0.sin(), -theta0.cos(), 0.0];
            let s0 = sys.reduced_state(q0, [0.0, 0.0, 1.0]).unwrap();
            let traj = ReducedConstrainedIntegrator::plus(sys, tight())
                .run(s0)
                .steps((3.0 / eps) as usize)
                .collect()
                .unwrap();
            for s in &traj.states {
                let (x, y) = (s.x[0], s.x[1]);
                assert!(
                    (x * x + y * y - 1.0).abs() < 1e-12,
                    "off the rod by {:e}",
                    x * x + y * y - 1.0
                );
                assert_eq!(
                    s.mu, s0.mu,
                    "p_t = −E is the momentum of the time translation"
                );
            }
            let last = traj.last();
            let theta = last.x[0].atan2(-last.x[1]);
            (theta - pendulum_angle(g, theta0, last.g[0])).abs()
        })
        .collect();
    for w in errors.windows(2) {
        let observed = (w[0] / w[1]).log2();
        assert!(
            (observed - 2.0).abs() < 0.3,
            "order {observed} from {errors:?}"
        );
    }
}

/// A knife edge (a skate) in the plane: it moves only along its heading `θ`, a nonholonomic
/// constraint, with steps shorter while it heads along `x`.
#[reduced_lagrangian(shape(theta), group(x, y, t), time(t), adapt = |q| 1.5 + q.theta.cos(), rule = midpoint,
    nonholonomic = |q, v| [q.theta.sin() * v.x - q.theta.cos() * v.y])]
#[allow(
    unused_variables,
    reason = "a free skate's Lagrangian does not read its configuration"
)]
fn skate(q: Config, v: Velocity, m: f64, j: f64) -> f64 {
    0.5 * m * (v.x * v.x + v.y * v.y) + 0.5 * j * v.theta * v.theta
}

#[test]
fn a_nonholonomic_skate_with_adaptive_steps_follows_its_circle() {
    // From the origin heading along x with speed 1 and turning rate 0.7: the circle
    // x = sin(ωt)/ω, y = (1 − cos(ωt))/ω, θ = ωt.
    let omega = 0.7;
    let errors: Vec<f64> = [0.04, 0.02, 0.01]
        .iter()
        .map(|&eps| {
            let sys = Skate {
                h: eps,
                m: 1.0,
                j: 0.5,
            };
            let s0 = sys
                .reduced_state([0.0, 0.0, 0.0, 0.0], [omega, 1.0, 0.0, 1.0])
                .unwrap();
            let traj = ReducedConstrainedIntegrator::plus(sys, tight())
                .run(s0)
                .steps((5.0 / eps) as usize)
                .collect()
                .unwrap();
            let last = traj.last();
            // The constraint's impulse reaches the group momenta through the step's residual:
            // p_t = −E is kept to round-off here, not bit for bit.
            assert!(
                (last.mu[2] - s0.mu[2]).abs() < 1e-12,
                "{} {}",
                last.mu[2],
                s0.mu[2]
            );
            let t = last.g[2];
            let (x, y) = ((omega * t).sin() / omega, (1.0 - (omega * t).cos()) / omega);
            (last.g[0] - x)
                .abs()
                .max((last.g[1] - y).abs())
                .max((last.x[0] - omega * t).abs())
        })
        .collect();
    for w in errors.windows(2) {
        let observed = (w[0] / w[1]).log2();
        assert!(
            (observed - 2.0).abs() < 0.3,
            "order {observed} from {errors:?}"
        );
    }
}

#[test]
fn the_run_api_keeps_physical_time_and_lands_on_an_end_time() {
    let (e, end) = (0.9, 10.0);
    let eps = 0.02;
    let sys = Kepler { h: eps, k: 1.0 };
    let integ = ReducedIntegrator::plus(sys, tight());
    let traj = integ
        .run(periapsis(&sys, e))
        .end_time(end)
        .collect()
        .unwrap();
    // The clock is physical time: each state's time coordinate; the steps are Δt_k in it, and
    // every step but the landing one has the fictitious size ε.
    for (k, s) in traj.states.iter().enumerate() {
        assert_eq!(traj.times[k], s.g[1], "time of state {k}");
    }
    let last = *traj.last();
    assert!(
        (last.g[1] - end).abs() <= 4.0 * f64::EPSILON * end,
        "{}",
        last.g[1]
    );
    let k = traj.step_count() - 1;
    let dt = |j: usize| traj.times[j + 1] - traj.times[j];
    let longest = (0..k).map(dt).fold(0.0, f64::max);
    assert!(dt(0) < 0.1 * longest, "short steps at periapsis");
    assert!(traj.step_sizes[..k].iter().all(|&s| s == eps));
    assert!(traj.step_sizes[k] > 0.0 && traj.step_sizes[k] <= eps);
    // The landing is `adaptive::land_at` on the step that passed the end.
    let before = traj.states[k];
    let landed = adaptive::land_at(end, before.g[1], eps, |h| {
        let (s, _) = ReducedIntegrator::plus(Kepler { h, k: 1.0 }, tight()).step(k, &before)?;
        Ok((s.g[1], s))
    })
    .unwrap();
    assert_eq!(landed, last);
    assert_eq!(last.mu, traj.states[0].mu, "momenta bit for bit");
    let (r, theta) = exact(e, end);
    assert!((last.x[0] - r).abs().max((last.g[0] - theta).abs()) < 1e-2);
    // A composition, and a run that starts later: the clock starts at the state's time.
    let mut later = periapsis(&sys, e);
    later.g[1] = 5.0;
    let mut seen = Vec::new();
    let summary = Composition::new(integ.clone(), CompositionMethod::TRIPLE_JUMP)
        .run(later)
        .end_time(5.0 + TAU)
        .observe(|_, t, s: &ReducedState<1, 2>, _| seen.push((t, s.g[1])))
        .stream()
        .unwrap();
    assert_eq!(seen[0], (5.0, 5.0));
    assert!(seen.iter().all(|(t, g)| t == g));
    assert!((summary.t - (5.0 + TAU)).abs() <= 4.0 * f64::EPSILON * (5.0 + TAU));
    assert_eq!(summary.t, summary.last.g[1]);
    // An end time before the state's time is a typed error.
    let err = integ.run(later).end_time(4.0).collect().unwrap_err();
    assert!(
        matches!(err.source, StepError::InvalidRun { .. }),
        "{}",
        err.source
    );
    // A start time: the state sets the clock, so another one is refused before any step, and
    // the state's own (as a resumed run passes it) is accepted.
    let err = integ
        .run(later)
        .start_time(1.0)
        .steps(3)
        .collect()
        .unwrap_err();
    match &err.source {
        StepError::InvalidRun { reason } => assert!(reason.contains("start_time"), "{reason}"),
        other => panic!("expected InvalidRun, got {other}"),
    }
    assert_eq!(err.trajectory.step_count(), 0);
    let resumed = integ.run(later).start_time(5.0).steps(3).collect().unwrap();
    assert_eq!(resumed.times[0], 5.0);
    assert_eq!(resumed.step_sizes, vec![eps; 3]);
}

/// Two bodies in the plane in their own coordinates, the symmetry declared on them: each
/// `translate(..)` moves both bodies, and physical time is translated alone.
#[reduced_lagrangian(coordinates(x[2], y[2], t), translate(x), translate(y), translate(t), time(t),
    adapt = |q| ((q.x[1] - q.x[0]).powi(2) + (q.y[1] - q.y[0]).powi(2)).powf(0.75), rule = midpoint)]
fn two_bodies(q: Config, v: Velocity, k: f64) -> f64 {
    let r = ((q.x[1] - q.x[0]).powi(2) + (q.y[1] - q.y[0]).powi(2)).sqrt();
    (v.x[0] * v.x[0] + v.x[1] * v.x[1] + v.y[0] * v.y[0] + v.y[1] * v.y[1]) + k / r
}

/// The two bodies (mass 2 each) at periapsis of their relative orbit of eccentricity `e` (the
/// relative motion is Kepler's with `k = 1`), drifting together with velocity `(0.3, −0.2)`.
fn two_bodies_start(sys: &TwoBodies, e: f64) -> ReducedState<2, 3> {
    use dirac::runtime::AdaptedCoordinates;
    let r0 = 1.0 - e;
    let speed = ((1.0 + e) / r0).sqrt();
    let q = SVector::<f64, 5>::from([-0.5 * r0, 0.5 * r0, 0.0, 0.0, 0.0]);
    let u = SVector::<f64, 5>::from([0.3, 0.3, -0.2 - 0.5 * speed, -0.2 + 0.5 * speed, 1.0]);
    sys.reduced_state(TwoBodies::to_adapted(&q), TwoBodies::to_adapted(&u))
        .unwrap()
}

#[test]
fn adaptive_steps_with_a_symmetry_declared_on_the_users_coordinates() {
    let errors: Vec<f64> = [0.04, 0.02, 0.01]
        .iter()
        .map(|&eps| {
            let sys = TwoBodies { h: eps, k: 1.0 };
            let s0 = two_bodies_start(&sys, 0.9);
            let traj = ReducedIntegrator::plus(sys, tight())
                .run(s0)
                .end_time(4.0)
                .collect()
                .unwrap();
            for s in &traj.states {
                assert_eq!(s.mu, s0.mu, "total momentum and p_t, bit for bit");
            }
            let last = traj.last();
            assert!((last.g[2] - 4.0).abs() < 1e-14, "{}", last.g[2]);
            // The relative position is the shape; the orbit is Kepler's.
            let big_e = common::eccentric_anomaly(0.9, 4.0);
            let (x, y) = (big_e.cos() - 0.9, (1.0 - 0.81_f64).sqrt() * big_e.sin());
            (last.x[0] - x).abs().max((last.x[1] - y).abs())
        })
        .collect();
    for w in errors.windows(2) {
        let observed = (w[0] / w[1]).log2();
        assert!(
            (observed - 2.0).abs() < 0.3,
            "order {observed} from {errors:?}"
        );
    }
}
