//! Gauss–Legendre variational integrators of any even order: the observed order against closed
//! forms (the harmonic oscillator, Kepler's equation) and a tight Runge–Kutta reference (the
//! pendulum), momenta of the translations bit for bit, symplecticity of the step map, adaptive
//! steps at high order, forces, and the typed errors.

mod common;

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
    let integrator = GaussIntegrator::new(sys, stages, NewtonOptions::default()).unwrap();
    integrator.run(start).steps(steps).collect().unwrap()
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
    for (s, h0) in [(1, 0.2), (2, 0.4), (3, 0.8), (4, 1.0)] {
        let t = 8.0;
        let errors: Vec<f64> = (0..3)
            .map(|j| {
                let h = h0 / f64::from(1 << j);
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
        let observed = orders(&errors);
        eprintln!("oscillator s = {s}: errors {errors:?}, orders {observed:?}");
        for o in observed {
            assert!((o - 2.0 * s as f64).abs() < 0.1, "s = {s}: order {o}");
        }
    }
}
