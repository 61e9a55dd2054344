//! The paper's two routes to the reduced equations — the reduced Dirac structure (§3–4) and the
//! reduced variational principle (§5) — checked against the stepper on every example system.

use dirac::paper::ChargedParticle;
use dirac::prelude::*;
use dirac::runtime::diagnostics::{
    dirac_membership_residuals, reduced_energy_minus, ReducedActionPlus,
};

mod common;
use common::{ParticleWithConnection, PlanarRotor};

/// Along (+) and (−) trajectories: every step lies in the reduced Dirac structure (Props. 3.8,
/// 4.3 and 3.10, 4.4) and the (+) reduced action is stationary (Theorem 5.2), to the accuracy the
/// stepper itself achieved: the membership residual of each step is within a few times the
/// Newton residual that step was accepted with (plus round-off of the compared values), and the
/// action gradient within a few times the largest.
fn assert_geometry<L, const S: usize, const K: usize, const N: usize>(
    sys: L,
    initial: ReducedState<S, K>,
    steps: usize,
) where
    L: Reduced<Plus, S, K, N> + Reduced<Minus, S, K, N> + Copy,
{
    for variant in [Variant::Plus, Variant::Minus] {
        let traj = match variant {
            Variant::Plus => ReducedIntegrator::plus(sys, NewtonOptions::default())
                .run(initial)
                .steps(steps)
                .collect(),
            Variant::Minus => ReducedIntegrator::minus(sys, NewtonOptions::default())
                .run(initial)
                .steps(steps)
                .collect(),
        }
        .unwrap();
        let membership = dirac_membership_residuals(&sys, &traj);
        assert_eq!(membership.len(), steps);
        for (k, (m, stats)) in membership.iter().zip(&traj.stats).enumerate() {
            let scale = traj.states[k]
                .w
                .amax()
                .max(traj.states[k + 1].w.amax())
                .max(traj.states[k].x.amax());
            let bound = 4.0 * stats.residual + 1e-14 * (1.0 + scale);
            assert!(
                *m <= bound,
                "{variant:?} step {k}: Dirac membership residual {m:e} > {bound:e}"
            );
        }
        if variant == Variant::Plus {
            let vars = ReducedActionPlus::from_trajectory(&traj).unwrap();
            let scale = traj
                .states
                .iter()
                .map(|s| s.w.amax().max(s.x.amax()))
                .fold(1.0, f64::max);
            let bound = 4.0 * traj.max_residual() + 1e-14 * scale;
            let gradient = vars.gradient(&sys).max_abs();
            assert!(
                gradient <= bound,
                "(+) action gradient {gradient:e} > {bound:e}"
            );
        }
    }
}

#[test]
fn charged_particle() {
    assert_geometry(
        ChargedParticle::paper(100),
        ChargedParticle::paper_initial_state(),
        100,
    );
}

#[test]
fn particle_with_connection() {
    let sys = ParticleWithConnection {
        h: 0.1,
        m: 1.3,
        b0: 0.8,
        b: 0.45,
    };
    assert_geometry(
        sys,
        ReducedState::new([0.2, -0.1, 0.3], [0.9, 0.2, -0.4], [1.1], [0.7]),
        200,
    );
}

#[test]
fn two_group_coordinates() {
    let sys = PlanarRotor {
        h: 0.05,
        m: 2.0,
        k: 3.0,
    };
    assert_geometry(
        sys,
        ReducedState::new([0.4], [0.1], [0.5, -0.3], [1.0, 2.0]),
        400,
    );
}

/// A small deterministic perturbation, different for every index.
fn wiggle(i: usize) -> f64 {
    ((i as f64 * 12.9898).sin() * 43758.5453).fract() * 0.01
}

/// The gradient diagnostic is the gradient of the action: compared with central differences at
/// a point off the solution (where it does not vanish), every component.
#[test]
fn the_action_gradient_is_the_gradient_of_the_action() {
    let sys = ParticleWithConnection {
        h: 0.1,
        m: 1.3,
        b0: 0.8,
        b: 0.45,
    };
    let initial = ReducedState::new([0.2, -0.1, 0.3], [0.9, 0.2, -0.4], [1.1], [0.7]);
    let traj = ReducedIntegrator::plus(sys, NewtonOptions::default())
        .run(initial)
        .steps(6)
        .collect()
        .unwrap();
    let mut vars = ReducedActionPlus::from_trajectory(&traj).unwrap();
    // Perturb every variable, so no component of the gradient vanishes by accident.
    let mut i = 0;
    for v in vars
        .x
        .iter_mut()
        .chain(vars.x_plus.iter_mut())
        .chain(vars.w.iter_mut())
    {
        for c in v.iter_mut() {
            *c += wiggle(i);
            i += 1;
        }
    }
    for v in vars
        .g
        .iter_mut()
        .chain(vars.g_plus.iter_mut())
        .chain(vars.mu.iter_mut())
    {
        for c in v.iter_mut() {
            *c += wiggle(i);
            i += 1;
        }
    }
    let grad = vars.gradient(&sys);
    let n = vars.x_plus.len();
    let fd = |set: &dyn Fn(&mut ReducedActionPlus<3, 1>, f64)| {
        let eps = 1e-6;
        let (mut a, mut b) = (vars.clone(), vars.clone());
        set(&mut a, eps);
        set(&mut b, -eps);
        (a.action(&sys) - b.action(&sys)) / (2.0 * eps)
    };
    let check = |analytic: f64, numeric: f64, what: String| {
        assert!(
            (analytic - numeric).abs() < 1e-6 * (1.0 + numeric.abs()),
            "{what}: {analytic} vs {numeric}"
        );
    };
    let mut nonzero = 0;
    for k in 1..n {
        for c in 0..3 {
            check(
                grad.x[k][c],
                fd(&|v, e| v.x[k][c] += e),
                format!("x[{k}][{c}]"),
            );
        }
        check(grad.g[k][0], fd(&|v, e| v.g[k][0] += e), format!("g[{k}]"));
    }
    for k in 0..n {
        for c in 0..3 {
            check(
                grad.x_plus[k][c],
                fd(&|v, e| v.x_plus[k][c] += e),
                format!("x+[{k}][{c}]"),
            );
            check(
                grad.w[k][c],
                fd(&|v, e| v.w[k][c] += e),
                format!("w[{k}][{c}]"),
            );
            nonzero += usize::from(grad.x_plus[k][c].abs() > 1e-6);
        }
        check(
            grad.g_plus[k][0],
            fd(&|v, e| v.g_plus[k][0] += e),
            format!("g+[{k}]"),
        );
        check(
            grad.mu[k][0],
            fd(&|v, e| v.mu[k][0] += e),
            format!("μ[{k}]"),
        );
    }
    assert!(nonzero > 10, "the perturbed point must be off the solution");
    assert!(grad.max_abs() > 1e-3);
}

/// Lemma 5.4's e_{d−} follows the (−) action (2.12), whose momenta have the opposite sign to
/// Definition 2.8: along a trajectory of the (−) stepper, Σ_k e_{d−} evaluated with
/// (−w_k, −μ_k) is stationary in every interior variable (central differences, tolerance 1e-6
/// relative), and with (w_k, μ_k) it is not.
#[test]
fn the_printed_minus_energy_is_stationary_with_negated_momenta() {
    let sys = ParticleWithConnection {
        h: 0.1,
        m: 1.3,
        b0: 0.8,
        b: 0.45,
    };
    let initial = ReducedState::new([0.2, -0.1, 0.3], [0.9, 0.2, -0.4], [1.1], [0.7]);
    let traj = ReducedIntegrator::minus(sys, NewtonOptions::default())
        .run(initial)
        .steps(6)
        .collect()
        .unwrap();
    let n = traj.step_count();
    // Variables: per step k, (x_{k+1}^−, g_{k+1}^−, w_k, μ_k); configurations (x_k, g_k).
    // Flattened: [x (n+1)*3 | g (n+1) | x⁻ n*3 | g⁻ n | w n*3 | μ n].
    let sign_action = |v: &[f64], sign: f64| -> f64 {
        let vec3 = |o: usize| SVector::<f64, 3>::new(v[o], v[o + 1], v[o + 2]);
        let vec1 = |o: usize| SVector::<f64, 1>::new(v[o]);
        let (ox, og, oxm, ogm, ow, omu) = (
            0,
            3 * (n + 1),
            4 * (n + 1),
            4 * (n + 1) + 3 * n,
            4 * (n + 1) + 4 * n,
            4 * (n + 1) + 7 * n,
        );
        (0..n)
            .map(|k| {
                let g_rel = vec1(og + k) - vec1(og + k + 1);
                reduced_energy_minus(
                    &sys,
                    &vec3(oxm + 3 * k),
                    &vec1(ogm + k),
                    &vec3(ox + 3 * (k + 1)),
                    &(sign * vec3(ow + 3 * k)),
                    &(sign * vec1(omu + k)),
                    &vec3(ox + 3 * k),
                    &g_rel,
                )
            })
            .sum()
    };
    let mut v: Vec<f64> = Vec::new();
    traj.states.iter().for_each(|s| v.extend(s.x.iter()));
    traj.states.iter().for_each(|s| v.push(s.g[0]));
    traj.states[..n].iter().for_each(|s| v.extend(s.x.iter()));
    traj.group_unknowns.iter().for_each(|g| v.push(g[0]));
    traj.states[..n].iter().for_each(|s| v.extend(s.w.iter()));
    traj.states[..n].iter().for_each(|s| v.push(s.mu[0]));
    let endpoints = [
        0,
        1,
        2,
        3 * n,
        3 * n + 1,
        3 * n + 2,
        3 * (n + 1),
        3 * (n + 1) + n,
    ];
    let fd_max = |sign: f64| {
        (0..v.len())
            .filter(|i| !endpoints.contains(i))
            .map(|i| {
                let eps = 1e-6;
                let (mut a, mut b) = (v.clone(), v.clone());
                a[i] += eps;
                b[i] -= eps;
                ((sign_action(&a, sign) - sign_action(&b, sign)) / (2.0 * eps)).abs()
            })
            .fold(0.0, f64::max)
    };
    let negated = fd_max(-1.0);
    let as_is = fd_max(1.0);
    assert!(
        negated < 1e-6,
        "Σ e_d− with (−w, −μ) has gradient {negated:e}"
    );
    assert!(
        as_is > 1e-2,
        "Σ e_d− with (w, μ) has gradient only {as_is:e}"
    );
}

#[test]
fn double_spherical_pendulum() {
    use dirac::paper::DoubleSphericalPendulum;
    let sys = DoubleSphericalPendulum::paper();
    assert_geometry(sys, DoubleSphericalPendulum::paper_initial_state(), 2000);
}

/// The (+) action's variables of a trajectory of the (−) stepper (Theorem 5.2 is the (+)
/// principle), or of a trajectory without states: a typed error, not a panic.
#[test]
fn the_plus_action_of_a_minus_trajectory_is_a_typed_error() {
    let sys = ChargedParticle::paper(100);
    let initial = ChargedParticle::paper_initial_state();
    let minus = ReducedIntegrator::minus(sys, NewtonOptions::default())
        .run(initial)
        .steps(3)
        .collect()
        .unwrap();
    let mut empty = ReducedIntegrator::plus(sys, NewtonOptions::default())
        .run(initial)
        .steps(3)
        .collect()
        .unwrap();
    empty.states.clear();
    for traj in [&minus, &empty] {
        let got =
            std::panic::catch_unwind(|| format!("{:?}", ReducedActionPlus::from_trajectory(traj)))
                .unwrap_or_else(|_| "a panic".to_string());
        assert!(got.starts_with("Err("), "{got}");
    }
}
