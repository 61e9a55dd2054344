//! Gauss–Legendre variational integrators of any even order: the observed order against closed
//! forms (the harmonic oscillator, Kepler's equation) and a tight Runge–Kutta reference (the
//! pendulum), momenta of the translations bit for bit, unreduced and reduced, the reduced (+) and
//! (−) sides as the same equations, symplecticity of the step map, adaptive steps at high order,
//! forces, and the typed errors.

mod common;

use dirac::runtime::nalgebra::Vector2;

use dirac::prelude::*;

/// The harmonic oscillator, `q̈ = −q`.
#[reduced_lagrangian(shape(x), group(), rule = midpoint)]
fn oscillator(q: Config, v: Velocity) -> f64 {
    0.5 * v.x * v.x - 0.5 * q.x * q.x
}

/// Kepler's problem in polar coordinates (`k = 1`), stepped in physical time.
#[reduced_lagrangian(shape(r), group(theta), rule = midpoint)]
fn kepler(q: Config, v: Velocity, k: f64) -> f64 {
    0.5 * (v.r * v.r + q.r * q.r * v.theta * v.theta) + k / q.r
}

/// Kepler's problem with steps following `r^{3/2}` (the Poincaré time transformation).
#[reduced_lagrangian(shape(r), group(theta, t), time(t), adapt = |q| q.r.powf(1.5), rule = midpoint)]
fn kepler_adaptive(q: Config, v: Velocity, k: f64) -> f64 {
    0.5 * (v.r * v.r + q.r * q.r * v.theta * v.theta) + k / q.r
}

/// The pendulum, `θ̈ = −sin θ`, damped by `−c θ̇`.
#[reduced_lagrangian(shape(th), group(), rule = midpoint, force = |dq| -c * v.th * dq.th)]
fn damped_pendulum(q: Config, v: Velocity, c: f64) -> f64 {
    0.5 * v.th * v.th + q.th.cos()
}

/// Kepler's problem with its domain declared.
#[reduced_lagrangian(shape(r), group(theta), rule = midpoint, domain(r > 0.0))]
fn kepler_in_domain(q: Config, v: Velocity, k: f64) -> f64 {
    0.5 * (v.r * v.r + q.r * q.r * v.theta * v.theta) + k / q.r
}

/// Kepler's problem in cylindrical coordinates, its reduced momenta read through a connection
/// (`w = p_x + Bᵀ μ`, eq. (3.6)).
#[reduced_lagrangian(shape(r, z), group(theta), connection = [[0.4, -0.3]], rule = midpoint)]
fn cylinder(q: Config, v: Velocity, k: f64) -> f64 {
    0.5 * (v.r * v.r + v.z * v.z + q.r * q.r * v.theta * v.theta)
        + k / (q.r * q.r + q.z * q.z).sqrt()
}

const TAU: f64 = 2.0 * std::f64::consts::PI;

/// The final state of `steps` steps of size `h` of the `stages`-stage method from `start`.
fn run<L, const S: usize, const K: usize, const N: usize>(
    sys: L,
    stages: usize,
    start: UnreducedState<N>,
    steps: usize,
) -> UnreducedTrajectory<N>
where
    L: DiscreteLagrangian<S, K, N> + StageDerivatives<N>,
{
    let integrator = GaussIntegrator::new(sys, stages, tight()).unwrap();
    integrator.run(start).steps(steps).collect().unwrap()
}

/// Newton to round-off, so that the errors measured are the method's down to 1e-13.
fn tight() -> NewtonOptions {
    NewtonOptions {
        abs_tol: 1e-14,
        rel_tol: 1e-14,
        ..NewtonOptions::default()
    }
}

/// `log2(e(h) / e(h/2))` from the errors at `h, h/2, h/4, …`, the last pair.
fn orders(errors: &[f64]) -> Vec<f64> {
    errors.windows(2).map(|w| (w[0] / w[1]).log2()).collect()
}

#[test]
fn the_rule_integrates_polynomials_of_degree_2s_minus_1_exactly_and_is_symplectic() {
    for s in 1..=12 {
        let rule = GaussRule::new(s).unwrap();
        for degree in 0..2 * s {
            let quad: f64 = (0..s)
                .map(|i| rule.b()[i] * rule.c()[i].powi(degree as i32))
                .sum();
            assert!(
                (quad - 1.0 / (degree as f64 + 1.0)).abs() < 1e-14,
                "s {s} degree {degree}"
            );
        }
        // Collocation: Σ_j a_ij c_j^m = c_i^{m+1}/(m+1) for m < s.
        for i in 0..s {
            for m in 0..s {
                let lhs: f64 = (0..s)
                    .map(|j| rule.a(i, j) * rule.c()[j].powi(m as i32))
                    .sum();
                let rhs = rule.c()[i].powi(m as i32 + 1) / (m as f64 + 1.0);
                assert!((lhs - rhs).abs() < 1e-13, "s {s} i {i} m {m}: {lhs} {rhs}");
            }
        }
        // b_i a_ij + b_j a_ji = b_i b_j: the method is its own symplectic partner.
        for i in 0..s {
            for j in 0..s {
                let (b, a) = (rule.b(), |i, j| rule.a(i, j));
                assert!((b[i] * a(i, j) + b[j] * a(j, i) - b[i] * b[j]).abs() < 1e-15);
            }
        }
    }
    assert!(
        GaussRule::new(0).is_none()
            && GaussRule::new(dirac::runtime::gauss::MAX_STAGES + 1).is_none()
    );
}

#[test]
fn the_oscillator_is_of_order_2s_against_its_closed_form() {
    for (s, h0, ratio) in [
        (1, 0.2, 2.0),
        (2, 0.4, 2.0),
        (3, 0.8, 2.0),
        (4, 1.0, 2.0),
        (5, 1.4, 1.5),
        (6, 1.6, 1.4f64),
    ] {
        let t = 8.0;
        let errors: Vec<f64> = (0..3)
            .map(|j| {
                let h = t / (t / (h0 / ratio.powi(j))).round();
                let steps = (t / h).round() as usize;
                let traj = run(
                    Oscillator { h },
                    s,
                    UnreducedState::new([1.0], [0.0]),
                    steps,
                );
                let last = traj.states.last().unwrap();
                ((last.q[0] - t.cos()).abs()).max((last.p[0] + t.sin()).abs())
            })
            .collect();
        let hs: Vec<f64> = (0..3)
            .map(|j| t / (t / (h0 / ratio.powi(j))).round())
            .collect();
        let observed: Vec<f64> = errors
            .windows(2)
            .zip(hs.windows(2))
            .map(|(e, h)| (e[0] / e[1]).ln() / (h[0] / h[1]).ln())
            .collect();
        eprintln!("oscillator s = {s}: errors {errors:?}, orders {observed:?}");
        for o in observed {
            assert!((o - 2.0 * s as f64).abs() < 0.1, "s = {s}: order {o}");
        }
    }
}

/// The orbit of eccentricity `e` (semi-major axis 1, `k = 1`) at time `t` from periapsis:
/// `(r, θ)` by Kepler's equation.
fn exact(e: f64, t: f64) -> (f64, f64) {
    let big_e = common::eccentric_anomaly(e, t);
    let r = 1.0 - e * big_e.cos();
    let anomaly = 2.0
        * ((1.0 + e).sqrt() * (big_e / 2.0).sin()).atan2((1.0 - e).sqrt() * (big_e / 2.0).cos());
    (r, anomaly.rem_euclid(TAU) + (t / TAU).floor() * TAU)
}

/// Position and velocity at periapsis, `(r, θ)` and `(ṙ, θ̇)`.
fn periapsis(e: f64) -> ([f64; 2], [f64; 2]) {
    let r0 = 1.0 - e;
    ([r0, 0.0], [0.0, (1.0 - e * e).sqrt() / (r0 * r0)])
}

#[test]
fn kepler_is_of_order_2s_against_keplers_equation_and_keeps_its_angular_momentum_bit_for_bit() {
    let e = 0.5;
    for (s, n0) in [(1, 400.0), (2, 100.0), (3, 100.0), (4, 80.0)] {
        // Steps per orbit n0, 1.5 n0, 2.25 n0.
        let errors: Vec<f64> = (0..3)
            .map(|j| {
                let h = TAU / (n0 * 1.5f64.powi(j));
                let sys = Kepler { h, k: 1.0 };
                let (q, v) = periapsis(e);
                let start = sys.unreduced_state(q, v).unwrap();
                let steps = (TAU / h).round() as usize;
                let traj = run(sys, s, start, steps);
                for state in &traj.states {
                    assert_eq!(state.p[1].to_bits(), start.p[1].to_bits(), "p_θ, s = {s}");
                }
                let last = traj.states.last().unwrap();
                let (r, theta) = exact(e, traj.times.last().copied().unwrap());
                (last.q[0] - r).abs().max((last.q[1] - theta).abs())
            })
            .collect();
        let observed: Vec<f64> = errors
            .windows(2)
            .map(|w| (w[0] / w[1]).ln() / 1.5f64.ln())
            .collect();
        eprintln!("kepler s = {s}: errors {errors:?}, orders {observed:?}");
        for o in observed {
            assert!((o - 2.0 * s as f64).abs() < 0.15, "s = {s}: order {o}");
        }
    }
}

#[test]
fn the_damped_pendulum_is_of_order_2s_against_a_tight_runge_kutta_solve() {
    let c = 0.3;
    let (q0, t) = (2.0, 4.0);
    let reference = common::rk4(
        Vector2::new(q0, 0.0),
        |y| Vector2::new(y[1], -y[0].sin() - c * y[1]),
        t,
        4e4,
    );
    for (s, h0) in [(1, 0.05), (2, 0.2), (3, 0.4), (4, 0.8)] {
        let errors: Vec<f64> = (0..3)
            .map(|j| {
                let h = h0 / f64::from(1 << j);
                let sys = DampedPendulum { h, c };
                let start = sys.unreduced_state([q0], [0.0]).unwrap();
                let traj = run(sys, s, start, (t / h).round() as usize);
                let last = traj.states.last().unwrap();
                // p = θ̇ for this Lagrangian.
                (last.q[0] - reference[0])
                    .abs()
                    .max((last.p[0] - reference[1]).abs())
            })
            .collect();
        let observed = orders(&errors);
        eprintln!("damped pendulum s = {s}: errors {errors:?}, orders {observed:?}");
        for o in observed {
            assert!((o - 2.0 * s as f64).abs() < 0.15, "s = {s}: order {o}");
        }
    }
}

#[test]
fn the_step_map_is_symplectic_and_its_jacobian_matches_central_differences() {
    let sys = Kepler { h: 0.3, k: 1.0 };
    let (q, v) = periapsis(0.6);
    let start = sys.unreduced_state(q, v).unwrap();
    for s in [1, 2, 3, 5] {
        let integrator = GaussIntegrator::new(sys, s, NewtonOptions::default()).unwrap();
        let m = integrator.step_jacobian(0, 0.3, &start).unwrap();
        let defect = m.symplecticity_defect();
        assert!(defect <= 1e-12, "s = {s}: symplecticity defect {defect:e}");
        // Column by column against central differences of the step.
        let step = |x: [f64; 4]| {
            let st = UnreducedState::new([x[0], x[1]], [x[2], x[3]]);
            let next = integrator.run(st).steps(1).collect().unwrap();
            let last = next.states[1];
            [last.q[0], last.q[1], last.p[0], last.p[1]]
        };
        let x0 = [start.q[0], start.q[1], start.p[0], start.p[1]];
        for col in 0..4 {
            let d = 1e-6;
            let (mut up, mut down) = (x0, x0);
            up[col] += d;
            down[col] -= d;
            let (a, b) = (step(up), step(down));
            for row in 0..4 {
                let fd = (a[row] - b[row]) / (2.0 * d);
                let exact = m.state[(row, col)];
                assert!(
                    (fd - exact).abs() <= 1e-6 * (1.0 + exact.abs()),
                    "s = {s}: ({row}, {col}) {exact} against {fd}"
                );
            }
        }
    }
}

#[test]
fn a_step_back_returns_to_the_start_the_method_being_self_adjoint() {
    let sys = Kepler { h: 0.2, k: 1.0 };
    let (q, v) = periapsis(0.7);
    let start = sys.unreduced_state(q, v).unwrap();
    for s in [1, 2, 4, 6] {
        let integrator = GaussIntegrator::new(sys, s, tight()).unwrap();
        let mut state = start;
        for (k, h) in [(0, 0.2), (1, -0.2)] {
            let mut ws = integrator.workspace();
            state = integrator
                .step_with(&mut ws, StepAt::new(k, h), &state)
                .unwrap()
                .0;
        }
        let gap = (state.q - start.q).amax().max((state.p - start.p).amax());
        assert!(gap < 1e-13, "s = {s}: {gap:e}");
    }
}

#[test]
fn adaptive_kepler_at_e_0_9_is_of_order_2s_in_the_fictitious_step() {
    let e: f64 = 0.9;
    let r0 = 1.0 - e;
    let omega = (1.0 - e * e).sqrt() / (r0 * r0);
    for (s, eps0, ratio) in [(2, 0.1, 2.0), (3, 0.2, 2.0), (4, 0.25, 1.4f64)] {
        let errors: Vec<f64> = (0..3)
            .map(|j| {
                let eps = eps0 / ratio.powi(j);
                let sys = KeplerAdaptive { h: eps, k: 1.0 };
                let start = sys
                    .unreduced_state([r0, 0.0, 0.0], [0.0, omega, 1.0])
                    .unwrap();
                let traj = run(sys, s, start, (8.0 / eps).round() as usize);
                for state in &traj.states {
                    assert_eq!(state.p[1].to_bits(), start.p[1].to_bits(), "p_θ, s = {s}");
                }
                let last = traj.states.last().unwrap();
                let (r, theta) = exact(e, last.q[2]);
                (last.q[0] - r).abs().max((last.q[1] - theta).abs())
            })
            .collect();
        let observed: Vec<f64> = errors
            .windows(2)
            .map(|w| (w[0] / w[1]).ln() / ratio.ln())
            .collect();
        eprintln!("adaptive kepler s = {s}: errors {errors:?}, orders {observed:?}");
        for o in observed {
            assert!((o - 2.0 * s as f64).abs() < 0.25, "s = {s}: order {o}");
        }
    }
}

#[test]
fn bad_input_is_a_typed_error_with_the_trajectory_kept() {
    let sys = Kepler { h: 0.1, k: 1.0 };
    let Err(StepError::InvalidSize { reason }) =
        GaussIntegrator::new(sys, 0, NewtonOptions::default())
    else {
        panic!("zero stages accepted")
    };
    assert!(reason.contains("1 to 16 stages"), "{reason}");
    // A coarse step leaves the declared domain r > 0: a typed error, the states before it kept.
    let integrator = GaussIntegrator::new(
        KeplerInDomain { h: 0.4, k: 1.0 },
        2,
        NewtonOptions::default(),
    )
    .unwrap();
    let start = KeplerInDomain { h: 0.4, k: 1.0 }
        .unreduced_state([1.0, 0.0], [0.0, 0.2])
        .unwrap();
    let failure = integrator.run(start).steps(1000).collect().unwrap_err();
    let step = failure.source.step();
    assert!(
        matches!(failure.source, StepError::OutOfDomain { .. })
            && step > 0
            && failure.trajectory.states.len() == step + 1,
        "{:?}",
        failure.source
    );
    assert!(failure.trajectory.states.iter().all(|s| s.q[0] > 0.0));
}

#[test]
fn one_stage_is_the_midpoint_rules_step() {
    // With s = 1 the Galerkin discrete Lagrangian is the midpoint rule's, so the step is the
    // one the attribute's rule = midpoint takes (the same equations, solved differently).
    let sys = DampedPendulum { h: 0.1, c: 0.2 };
    let start = sys.unreduced_state([1.2], [0.3]).unwrap();
    let gauss = GaussIntegrator::new(sys, 1, tight()).unwrap();
    let midpoint = UnreducedIntegrator::new(sys, tight());
    let a = gauss.run(start).steps(200).collect().unwrap();
    let b = midpoint.run(start).steps(200).collect().unwrap();
    for (x, y) in a.states.iter().zip(&b.states) {
        let gap = (x.q - y.q).amax().max((x.p - y.p).amax());
        assert!(gap < 1e-13, "{gap:e}");
    }
}

#[test]
fn the_double_spherical_pendulum_is_of_order_2s_against_a_tight_runge_kutta_solve() {
    use dirac::paper::DoubleSphericalPendulumContinuous as Dsp;
    use dirac::runtime::nalgebra::{SVector, Vector4};
    let sys = Dsp::paper();
    // The paper's start, unreduced: q = (φ1, ϑ2, φ2, ϑ1), p = (w, μ) (B = 0).
    let start = UnreducedState::new([2.25, 2.0, 3.0, 0.0], [0.0, 1.0, 1.0, 0.0]);
    let v0 = sys
        .velocity(0, &start.q, &start.p, SVector::zeros())
        .unwrap();
    // The Euler–Lagrange equations from the stage derivatives: ∂p/∂v q̈ = f − ∂p/∂q q̇.
    let rate = |y: &SVector<f64, 8>| {
        let (q, v) = (
            Vector4::new(y[0], y[1], y[2], y[3]),
            Vector4::new(y[4], y[5], y[6], y[7]),
        );
        let j = sys.stage_jacobian(&q, &v);
        let a = j.p_v.lu().solve(&(j.f - j.p_q * v)).unwrap();
        SVector::<f64, 8>::from_iterator(v.iter().chain(a.iter()).copied())
    };
    let y0 = SVector::<f64, 8>::from_iterator(start.q.iter().chain(v0.iter()).copied());
    // Whole numbers of steps over the span, in the range where the error is C h^{2s} (the
    // higher the order, the longer the span that takes: at s = 4 over 5 time units the error
    // is at 1e-12 before the steps are small enough for its leading term to dominate).
    // RK4 at 2500 steps per time unit, compensated: its error is below 1e-15 (measured against
    // twice as many steps), under every error asserted here.
    let (at_5, at_20) = (
        common::rk4(y0, rate, 5.0, 2.5e3),
        common::rk4(y0, rate, 20.0, 2.5e3),
    );
    for (s, t, ns) in [
        (1, 5.0, [100.0, 150.0, 225.0]),
        (2, 5.0, [48.0, 72.0, 108.0]),
        (3, 5.0, [16.0, 24.0, 36.0]),
        (4, 20.0, [243.0, 304.0, 380.0]),
    ] {
        let reference = if t == 5.0 { at_5 } else { at_20 };
        let (q_ref, v_ref) = (
            Vector4::new(reference[0], reference[1], reference[2], reference[3]),
            Vector4::new(reference[4], reference[5], reference[6], reference[7]),
        );
        let p_ref = sys.legendre(&q_ref, &v_ref);
        let errors: Vec<f64> = ns
            .iter()
            .map(|&n| {
                let traj = run(Dsp { h: t / n, ..sys }, s, start, n as usize);
                let last = traj.states.last().unwrap();
                (last.q - q_ref)
                    .amax()
                    .max((last.p - p_ref).amax() / p_ref.amax())
            })
            .collect();
        let observed: Vec<f64> = errors
            .windows(2)
            .zip(ns.windows(2))
            .map(|(e, n)| (e[0] / e[1]).ln() / (n[1] / n[0]).ln())
            .collect();
        eprintln!("double spherical pendulum s = {s}: errors {errors:?}, orders {observed:?}");
        for o in observed {
            assert!((o - 2.0 * s as f64).abs() < 0.1, "s = {s}: order {o}");
        }
    }
}

#[test]
fn reduced_steps_keep_mu_bit_for_bit_and_their_plus_and_minus_sides_are_the_same_equations() {
    let sys = Cylinder { h: 0.05, k: 1.0 };
    let start = sys.trivialize(
        &sys.unreduced_state([1.0, 0.3, 0.0], [0.1, -0.2, 0.9])
            .unwrap(),
    );
    let b = sys.connection();
    for s in [1, 3] {
        let plus = ReducedGaussIntegrator::plus(sys, s, tight()).unwrap();
        let minus = ReducedGaussIntegrator::minus(sys, s, tight()).unwrap();
        let (a, m) = (
            plus.run(start).steps(300).collect().unwrap(),
            minus.run(start).steps(300).collect().unwrap(),
        );
        assert_eq!((a.variant, m.variant), (Variant::Plus, Variant::Minus));
        for (k, (x, y)) in a.states.iter().zip(&m.states).enumerate() {
            assert_eq!(
                x.mu[0].to_bits(),
                start.mu[0].to_bits(),
                "μ, s = {s}, state {k}"
            );
            // The same equations (§2.3.2): the same states, bit for bit.
            assert_eq!(x, y, "s = {s}, state {k}");
        }
        for k in 0..300 {
            let (u, v) = (a.group_unknowns[k][0], m.group_unknowns[k][0]);
            assert_eq!(u, -v, "u_+ = −u_−, step {k}");
            // The reconstruction line of eq. (4.6): g_{k+1} = g_k + u + B (x_{k+1} − x_k).
            let (x0, x1) = (&a.states[k], &a.states[k + 1]);
            let g = x0.g[0] + u + (b * (x1.x - x0.x))[0];
            assert!((g - x1.g[0]).abs() <= 1e-14 * (1.0 + g.abs()), "step {k}");
        }
        // The unreduced integrator, trivialized: the same motion to rounding.
        let unreduced = GaussIntegrator::new(sys, s, tight()).unwrap();
        let u = unreduced
            .run(sys.untrivialize(&start))
            .steps(300)
            .collect()
            .unwrap();
        for (x, y) in a.states.iter().zip(&u.states) {
            let y = sys.trivialize(y);
            let gap = (x.x - y.x)
                .amax()
                .max((x.w - y.w).amax())
                .max((x.g - y.g).amax());
            assert!(gap < 1e-12, "s = {s}: {gap:e}");
        }
        if s == 1 {
            // One stage is the midpoint rule: the second-order reduced integrators of the
            // attribute's rule = midpoint (their own unknowns and Newton) on both sides.
            for other in [
                ReducedIntegrator::plus(sys, tight())
                    .run(start)
                    .steps(300)
                    .collect()
                    .unwrap(),
                ReducedIntegrator::minus(sys, tight())
                    .run(start)
                    .steps(300)
                    .collect()
                    .unwrap(),
            ] {
                for (x, y) in a.states.iter().zip(&other.states) {
                    let gap = (x.x - y.x)
                        .amax()
                        .max((x.w - y.w).amax())
                        .max((x.g - y.g).amax());
                    assert!(gap < 1e-12, "{:?}: {gap:e}", other.variant);
                    assert_eq!(x.mu, y.mu);
                }
            }
        }
    }
}

#[test]
fn the_double_spherical_pendulums_reduced_steps_keep_mu_bit_for_bit_at_order_6() {
    use dirac::paper::DoubleSphericalPendulumContinuous as Dsp;
    let sys = Dsp {
        h: 0.02,
        ..Dsp::paper()
    };
    // The paper's start, x = (φ1, ϑ2, φ2), w = (0, 1, 1) (B = 0), ϑ1 = 0, turning: μ = 0.5. Its
    // Lagrangian reads ϑ1 through cos(ϑ1 ∓ ϑ2), invariant only up to rounding: the momentum
    // line keeps μ whatever the rounding of ∂L/∂ϑ1.
    let start = ReducedState::new([2.25, 2.0, 3.0], [0.0, 1.0, 1.0], [0.5], [0.0]);
    let integrator = ReducedGaussIntegrator::plus(sys, 3, tight()).unwrap();
    let traj = integrator.run(start).steps(500).collect().unwrap();
    for state in &traj.states {
        assert_eq!(state.mu[0].to_bits(), start.mu[0].to_bits());
    }
    let energies = integrator.energies(&traj).unwrap();
    let e0 = energies.nodes[0];
    let drift = energies
        .nodes
        .iter()
        .map(|e| (e - e0).abs())
        .fold(0.0, f64::max);
    assert!(drift < 1e-8 * e0.abs().max(1.0), "energy {drift:e}");
}
