//! The integrator on systems beyond the paper's: a nonzero connection matrix, two group
//! coordinates, and the failure paths.

use dirac::prelude::*;
use dirac::runtime::system::join;

mod common;
use common::{ParticleWithConnection, PlanarRotor};

/// A Lagrangian whose shape equation does not involve x_{k+1}: the step Jacobian is singular.
#[reduced_lagrangian(shape(x), group(theta))]
fn degenerate(q0: Config, q1: Config, h: f64) -> f64 {
    0.5 / h * (q1.theta - q0.theta).powi(2) + q0.x * q0.x
}

fn central_gradient<const N: usize>(
    f: impl Fn(&SVector<f64, N>) -> f64,
    at: &SVector<f64, N>,
) -> SVector<f64, N> {
    SVector::from_fn(|i, _| {
        let step = 1e-5 * (1.0 + at[i].abs());
        let (mut a, mut b) = (*at, *at);
        a[i] += step;
        b[i] -= step;
        (f(&a) - f(&b)) / (2.0 * step)
    })
}

/// Mapped back with the trivialization (3.7) and the group reconstruction, every reduced step is
/// a step of the unreduced (+) discrete Lagrange–Dirac equations (Definition 2.7):
/// `p_k = −D1 L_d(q_k, q_{k+1})` and `p_{k+1} = D2 L_d(q_k, q_{k+1})`, checked against central
/// differences of the user's own function (tolerance 1e-7: the difference quotient's error).
fn assert_steps_satisfy_unreduced_equations<L, const S: usize, const K: usize, const N: usize>(
    sys: &L,
    traj: &Trajectory<S, K>,
) where
    L: DiscreteLagrangian<S, K, N>,
{
    for (k, pair) in traj.states.windows(2).enumerate() {
        let c0 = sys.untrivialize(&pair[0]);
        let c1 = sys.untrivialize(&pair[1]);
        let d1 = central_gradient(|q| sys.lagrangian(q, &c1.q), &c0.q);
        let d2 = central_gradient(|q| sys.lagrangian(&c0.q, q), &c1.q);
        let scale = 1.0 + c0.p.amax().max(c1.p.amax());
        assert!(
            (c0.p + d1).amax() < 1e-7 * scale,
            "step {k}: p_k = {} but −D1 L_d = {}",
            c0.p,
            -d1
        );
        assert!(
            (c1.p - d2).amax() < 1e-7 * scale,
            "step {k}: p_k+1 = {} but D2 L_d = {}",
            c1.p,
            d2
        );
    }
}

#[test]
fn reduced_steps_with_a_connection_solve_the_unreduced_equations() {
    let sys = ParticleWithConnection {
        h: 0.1,
        m: 1.3,
        b0: 0.8,
        b: 0.45,
    };
    let canonical = UnreducedState {
        q: SVector::from([0.2, -0.1, 0.3, 0.7]),
        p: SVector::from([0.9, 0.2, -0.4, 1.1]),
    };
    let initial = sys.trivialize(&canonical);
    // w = p_x + Bᵀ μ (eq. (3.6)) and the round trip through (3.7).
    let b = sys.connection();
    assert_eq!(b, SMatrix::<f64, 1, 3>::new(0.3, -0.7, 0.45));
    assert!((initial.w - (SVector::from([0.9, 0.2, -0.4]) + b.transpose() * 1.1)).amax() < 1e-15);
    assert!((sys.untrivialize(&initial).p - canonical.p).amax() < 1e-15);
    assert_eq!(sys.momentum_map(&canonical)[0], 1.1);
    let traj = ReducedIntegrator::plus(sys, NewtonOptions::default())
        .run(initial)
        .steps(50)
        .collect()
        .unwrap();
    assert_steps_satisfy_unreduced_equations(&sys, &traj);
}

#[test]
fn the_shape_trajectory_does_not_depend_on_the_connection() {
    let canonical = UnreducedState {
        q: SVector::from([0.2, -0.1, 0.3, 0.7]),
        p: SVector::from([0.9, 0.2, -0.4, 1.1]),
    };
    let with_b = ParticleWithConnection {
        h: 0.1,
        m: 1.3,
        b0: 0.8,
        b: 0.45,
    };
    let without_b = dirac::paper::ChargedParticle {
        h: 0.1,
        m: 1.3,
        b0: 0.8,
    };
    let a = ReducedIntegrator::plus(with_b, NewtonOptions::default())
        .run(with_b.trivialize(&canonical))
        .steps(50)
        .collect()
        .unwrap();
    let b = ReducedIntegrator::plus(without_b, NewtonOptions::default())
        .run(without_b.trivialize(&canonical))
        .steps(50)
        .collect()
        .unwrap();
    for (sa, sb) in a.states.iter().zip(&b.states) {
        assert!((sa.x - sb.x).amax() < 1e-12, "{} vs {}", sa.x, sb.x);
        assert!((sa.g - sb.g).amax() < 1e-12, "{} vs {}", sa.g, sb.g);
        // Only the reduced shape momenta differ, by Bᵀ μ.
        let shift = with_b.connection().transpose() * sa.mu;
        assert!((sa.w - shift - sb.w).amax() < 1e-12);
    }
}

#[test]
fn two_group_coordinates() {
    let sys = PlanarRotor {
        h: 0.05,
        m: 2.0,
        k: 3.0,
    };
    let initial = ReducedState::new([0.4], [0.1], [0.5, -0.3], [1.0, 2.0]);
    let traj = ReducedIntegrator::plus(sys, NewtonOptions::default())
        .run(initial)
        .steps(400)
        .collect()
        .unwrap();
    assert!(traj.states.iter().all(|s| s.mu == initial.mu));
    assert_steps_satisfy_unreduced_equations(&sys, &traj);
    // The group coordinates drift: the reconstruction is exercised.
    assert!((traj.last().g - initial.g).amax() > 0.1);
}

/// A potential `V = √(1 − x)`, defined only for `x ≤ 1`, pushes the particle into the edge of the
/// domain within a few steps, where the step equations become NaN.
#[reduced_lagrangian(shape(x), group(theta))]
fn runaway(q0: Config, q1: Config, h: f64) -> f64 {
    let v = (q1.x - q0.x) / h;
    let w = (q1.theta - q0.theta) / h;
    h * (0.5 * v * v + 0.5 * w * w - (1.0 - q0.x).sqrt())
}

#[test]
fn a_failed_step_keeps_the_trajectory_computed_so_far() {
    let sys = Runaway { h: 0.1 };
    let initial = ReducedState::new([0.0], [1.0], [0.5], [0.0]);
    let err = ReducedIntegrator::plus(sys, NewtonOptions::default())
        .run(initial)
        .steps(100)
        .collect()
        .unwrap_err();
    let failed_at = err.source.step();
    assert!(failed_at > 3, "{err}");
    assert!(matches!(err.source, StepError::NonFinite { .. }), "{err}");
    assert_eq!(err.trajectory.step_count(), failed_at);
    assert_eq!(err.requested, 100);
    assert!(
        err.trajectory.last().x[0] > 1.0,
        "the last kept state is past the domain edge"
    );
    // The kept prefix is exactly what a shorter, successful run computes.
    let prefix = ReducedIntegrator::plus(sys, NewtonOptions::default())
        .run(initial)
        .steps(failed_at)
        .collect()
        .unwrap();
    assert_eq!(err.trajectory, prefix);
    assert!(
        err.to_string().contains(&format!("step {failed_at}")),
        "{err}"
    );
}

#[test]
fn newton_non_convergence_is_a_typed_error_with_the_residual() {
    // The first step of the N = 10 run starts from a poor guess and needs two corrections.
    let options = NewtonOptions {
        max_iterations: 1,
        ..NewtonOptions::default()
    };
    let sys = dirac::paper::ChargedParticle::paper(10);
    let initial = dirac::paper::ChargedParticle::paper_initial_state();
    // The general path: with the group unknown eliminated the charged particle's step equations
    // are linear and one correction always suffices.
    let err = ReducedIntegrator::plus(sys, options)
        .with_elimination(false)
        .run(initial)
        .steps(10)
        .collect()
        .unwrap_err();
    assert!(
        matches!(err.source, StepError::NotConverged { step: 0, iterations: 1, residual } if residual > 1e-6),
        "{err}"
    );
    assert!(err.source.residual() > 1e-6);
    assert_eq!(err.trajectory.step_count(), 0);
}

#[test]
fn a_singular_jacobian_is_a_typed_error() {
    let sys = Degenerate { h: 0.1 };
    let err = ReducedIntegrator::plus(sys, NewtonOptions::default())
        .run(ReducedState::new([0.5], [0.3], [1.0], [0.0]))
        .steps(5)
        .collect()
        .unwrap_err();
    assert!(
        matches!(err.source, StepError::SingularJacobian { step: 0, residual } if residual > 0.0),
        "{err}"
    );
    assert_eq!(err.trajectory.step_count(), 0);
}

#[test]
fn bad_input_is_rejected_before_stepping() {
    let good = dirac::paper::ChargedParticle::paper(10);
    let initial = dirac::paper::ChargedParticle::paper_initial_state();
    let mut nan_state = initial;
    nan_state.w[1] = f64::NAN;
    let err = ReducedIntegrator::plus(good, NewtonOptions::default())
        .run(nan_state)
        .steps(3)
        .collect()
        .unwrap_err();
    assert!(
        matches!(err.source, StepError::NonFinite { step: 0, .. }),
        "{err}"
    );

    for h in [0.0, -0.1, f64::INFINITY, f64::NAN] {
        let sys = dirac::paper::ChargedParticle { h, ..good };
        let err = ReducedIntegrator::plus(sys, NewtonOptions::default())
            .run(initial)
            .steps(3)
            .collect()
            .unwrap_err();
        assert!(
            matches!(err.source, StepError::InvalidTimeStep { .. }),
            "h = {h}: {err}"
        );
    }
    let sys = dirac::paper::ChargedParticle {
        m: f64::NAN,
        ..good
    };
    let err = ReducedIntegrator::plus(sys, NewtonOptions::default())
        .run(initial)
        .steps(3)
        .collect()
        .unwrap_err();
    assert!(
        matches!(
            err.source,
            StepError::NonFinite {
                what: "the parameters",
                ..
            }
        ),
        "{err}"
    );
}

#[test]
fn discrete_energy_along_a_trajectory_is_the_generalized_energy() {
    // On solutions q_k^+ = q_{k+1}, so E_{d+}(q_k, q_k^+, q_{k+1}, p_{k+1}) = L_d(q_k, q_{k+1}) (5.7).
    let sys = dirac::paper::ChargedParticle::paper(100);
    let traj = ReducedIntegrator::plus(sys, NewtonOptions::default())
        .run(dirac::paper::ChargedParticle::paper_initial_state())
        .steps(20)
        .collect()
        .unwrap();
    let energies = dirac::trajectory_energies(&sys, &traj);
    assert_eq!(energies.len(), 20);
    for (k, pair) in traj.states.windows(2).enumerate() {
        let q0 = join::<3, 1, 4>(&pair[0].x, &pair[0].g);
        let q1 = join::<3, 1, 4>(&pair[1].x, &pair[1].g);
        let p1 = sys.untrivialize(&pair[1]).p;
        let e = sys.generalized_energy_plus(&q0, &q1, &q1, &p1);
        assert_eq!(e, energies[k]);
        // Off the constraint the pairing term contributes.
        let shifted = q1 + SVector::from([0.1, 0.0, 0.0, 0.0]);
        let e_off = sys.generalized_energy_plus(&q0, &q1, &shifted, &p1);
        assert!((e_off - e - 0.1 * p1[0]).abs() < 1e-12);
    }
}

#[test]
fn the_user_function_stays_callable() {
    let q0 = ChargedParticleConfigAlias {
        x: 0.0,
        y: 0.0,
        z: 0.0,
        theta: 0.0,
    };
    let q1 = ChargedParticleConfigAlias {
        x: 0.1,
        y: 0.0,
        z: 0.0,
        theta: 0.2,
    };
    let l = dirac::paper::charged_particle(q0, q1, 0.1, 1.0, 1.0);
    assert!((l - (0.5 / 0.1 * 0.01 + 0.5 / 0.1 * 0.04)).abs() < 1e-15);
    let sys = dirac::paper::ChargedParticle {
        h: 0.1,
        m: 1.0,
        b0: 1.0,
    };
    assert_eq!(sys.lagrangian(&q0.to_vector(), &q1.to_vector()), l);
    assert_eq!(ChargedParticleConfigAlias::from_vector(&q1.to_vector()), q1);
}

use dirac::paper::ChargedParticleConfig as ChargedParticleConfigAlias;

/// A spherical pendulum in spherical coordinates, midpoint rule: the S¹ action on the azimuth
/// `theta` is not free at the poles φ = 0, π (the paper's Remark 7.1), where the group block of
/// the step Jacobian, ∝ sin²φ, vanishes.
#[reduced_lagrangian(shape(phi), group(theta))]
fn spherical_pendulum(q0: Config, q1: Config, h: f64, l: f64, g: f64) -> f64 {
    let phi = 0.5 * (q0.phi + q1.phi);
    let (dphi, dtheta) = ((q1.phi - q0.phi) / h, (q1.theta - q0.theta) / h);
    h * (0.5 * l * l * (dphi * dphi + phi.sin().powi(2) * dtheta * dtheta) - g * l * phi.cos())
}

#[test]
fn conditioning_is_recorded_and_a_threshold_turns_it_into_an_error() {
    let sys = SphericalPendulum {
        h: 0.01,
        l: 1.0,
        g: 9.8,
    };
    let run = |phi0: f64, w0: f64, options: NewtonOptions, eliminate: bool| {
        ReducedIntegrator::plus(sys, options)
            .with_elimination(eliminate)
            .run(ReducedState::new([phi0], [w0], [0.0], [0.0]))
            .steps(50)
            .collect()
    };
    let pole = std::f64::consts::PI - 1e-9;
    for eliminate in [true, false] {
        // Away from the pole the steps are well conditioned, and every step records its estimate.
        let far = run(2.0, 0.1, NewtonOptions::default(), eliminate).unwrap();
        let (_, worst_far) = far.worst_rcond().unwrap();
        assert!(far.stats.iter().all(|s| s.rcond.is_some()));
        assert!(worst_far > 1e-6, "{worst_far:e}");
        // At rest at the pole (the stable bottom, so the motion stays there) the group block
        // ∝ sin²φ degenerates: the default threshold refuses the step instead of returning a
        // result with no correct digits, and says why — also when the group unknown is
        // eliminated in closed form, where the degeneracy is in the divisor, not in the shape
        // Jacobian.
        let err = run(pole, 0.0, NewtonOptions::default(), eliminate).unwrap_err();
        assert!(
            matches!(err.source, StepError::IllConditioned { step: 0, rcond, .. } if rcond < 1e-13),
            "eliminate = {eliminate}: {err}"
        );
        assert!(err.to_string().contains("ill-conditioned"), "{err}");
    }
    // With the check disabled the same run continues, and the statistics show why it should not.
    let options = NewtonOptions {
        min_rcond: 0.0,
        ..NewtonOptions::default()
    };
    let near = run(pole, 0.0, options, true).unwrap();
    assert!(near.worst_rcond().unwrap().1 < 1e-13);
}

/// An error chain prints each cause once: `IntegrationError`'s message names the step and what was
/// kept, and its cause, the `StepError`, comes from `source()` and is not repeated in the message.
#[test]
fn an_error_chain_prints_each_cause_once() {
    let sys = Runaway { h: 0.1 };
    let err = ReducedIntegrator::plus(sys, NewtonOptions::default())
        .run(ReducedState::new([0.0], [1.0], [0.5], [0.0]))
        .steps(100)
        .collect()
        .unwrap_err();
    let mut chain = Vec::new();
    let mut cause: Option<&dyn std::error::Error> = Some(&*err);
    while let Some(e) = cause {
        chain.push(e.to_string());
        cause = e.source();
    }
    assert_eq!(chain.len(), 2, "{chain:?}");
    assert_eq!(chain[1], err.source.to_string());
    let printed = chain.join("\ncaused by: ");
    assert_eq!(printed.matches(&chain[1]).count(), 1, "{printed}");
    assert!(
        chain[0].contains(&format!("step {}", err.source.step())),
        "{printed}"
    );
}

/// Each step records the residual tolerance it was accepted against: `abs_tol + rel_tol · ρ`
/// with `ρ = max(‖w_k‖∞, ‖μ_k‖∞)`, the momenta the step's residual balances.
#[test]
fn step_stats_record_the_tolerance_of_each_step() {
    let options = NewtonOptions {
        abs_tol: 1e-11,
        rel_tol: 1e-9,
        ..NewtonOptions::default()
    };
    let initial = dirac::paper::ChargedParticle::paper_initial_state();
    let traj = ReducedIntegrator::plus(dirac::paper::ChargedParticle::paper(50), options)
        .run(initial)
        .steps(50)
        .collect()
        .unwrap();
    for (k, (s, stats)) in traj.states.iter().zip(&traj.stats).enumerate() {
        let rho = s.w.amax().max(s.mu.amax());
        assert_eq!(
            stats.tolerance,
            options.abs_tol + options.rel_tol * rho,
            "step {k}"
        );
    }
}
