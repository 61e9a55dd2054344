//! The baselines of the stepper benchmarks (`benches/steppers.rs`, `examples/bench_table.rs`)
//! compute what the generated code computes, so their timings compare equal work: num-dual's
//! residual and Jacobian, the hand-coded charged particle, and the unreduced stepper, each against
//! the generated (+) stepper at the benchmarks' own inputs (states on the paper's runs). No timing
//! here.

#[path = "../benches/common/mod.rs"]
mod common;

use common::workload::{self, StepCase, Workload};
use common::{ad, hand};
use dirac::paper::ChargedParticle;
use dirac::prelude::*;
use dirac::runtime::system::join;

/// `max |a − b| / scale` over the entries.
fn scaled_error<const R: usize, const C: usize>(
    a: &SMatrix<f64, R, C>,
    b: &SMatrix<f64, R, C>,
    scale: f64,
) -> f64 {
    (a - b).amax() / scale
}

/// Largest scaled disagreement of a residual+Jacobian implementation with the generated one over
/// `cases`. `R` is a sum of derivative terms that nearly cancel (it is small near the solution),
/// so both `R` and `∂R/∂z` are compared relative to the size of the Jacobian, `max(1, ‖J‖max)`:
/// round-off in either implementation is a few ulps of the largest term, not of the result.
fn worst_disagreement<L, const S: usize, const K: usize, const N: usize>(
    sys: &L,
    cases: &[StepCase<S, K, N>],
    other: impl Fn(
        &SVector<f64, S>,
        &SVector<f64, S>,
        &SVector<f64, K>,
        &SVector<f64, N>,
    ) -> (SVector<f64, N>, SMatrix<f64, N, N>),
) -> f64
where
    L: Reduced<Plus, S, K, N, Linear = dirac::runtime::Lu<N>>,
{
    let mut worst = 0f64;
    for case in cases {
        let s = &case.state;
        // At the guess (where Newton starts) and at the solution (where it ends).
        for z in [&case.guess, &case.solution] {
            let (r, j) = sys.residual_jacobian(&s.x, &s.w, &s.mu, z);
            let (r_other, j_other) = other(&s.x, &s.w, &s.mu, z);
            let scale = 1f64.max(j.amax());
            let e = scaled_error(&r, &r_other, scale).max(scaled_error(&j, &j_other, scale));
            assert!(
                e.is_finite(),
                "non-finite disagreement at step {}: generated ({r}, {j}), other ({r_other}, {j_other})",
                case.k
            );
            worst = worst.max(e);
        }
    }
    worst
}

/// Forward-mode AD and the generated straight-line code round differently; on these systems the
/// differences are a few ulps of the largest term.
const DERIVATIVE_TOL: f64 = 1e-13;

#[test]
fn num_dual_residual_and_jacobian_match_the_generated_ones() {
    let cp = workload::charged_particle();
    let dsp = workload::double_spherical_pendulum();
    let dsp_cases = dsp.spread(100);
    let checks = [
        (
            "charged particle, hessian",
            worst_disagreement(&cp.system, &cp.cases, |x, w, mu, z| {
                ad::residual_jacobian::<_, 3, 1, 4, 7>(&cp.system, x, w, mu, z)
            }),
        ),
        (
            "charged particle, partial_hessian",
            worst_disagreement(&cp.system, &cp.cases, |x, w, mu, z| {
                ad::residual_jacobian_partial::<_, 3, 1, 4>(&cp.system, x, w, mu, z)
            }),
        ),
        (
            "double spherical pendulum, hessian",
            worst_disagreement(&dsp.system, &dsp_cases, |x, w, mu, z| {
                ad::residual_jacobian::<_, 3, 1, 4, 7>(&dsp.system, x, w, mu, z)
            }),
        ),
        (
            "double spherical pendulum, partial_hessian",
            worst_disagreement(&dsp.system, &dsp_cases, |x, w, mu, z| {
                ad::residual_jacobian_partial::<_, 3, 1, 4>(&dsp.system, x, w, mu, z)
            }),
        ),
    ];
    for (what, worst) in checks {
        println!("{what}: worst scaled disagreement {worst:.2e}");
        assert!(worst <= DERIVATIVE_TOL, "{what}: {worst:e}");
    }
}

#[test]
fn num_dual_residual_and_momentum_match_the_generated_ones() {
    fn check<L, const S: usize, const K: usize, const N: usize>(
        w: &Workload<L, S, K, N>,
        cases: &[StepCase<S, K, N>],
    ) where
        L: Reduced<Plus, S, K, N, Linear = dirac::runtime::Lu<N>> + ad::DualLagrangian<N>,
    {
        for case in cases {
            let s = &case.state;
            let z = &case.solution;
            let j = w.system.residual_jacobian(&s.x, &s.w, &s.mu, z).1;
            let scale = 1f64.max(j.amax());
            let r = w.system.residual(&s.x, &s.w, &s.mu, z);
            let r_ad = ad::residual::<L, S, K, N>(&w.system, &s.x, &s.w, &s.mu, z);
            let p = w.system.momentum(&s.x, z);
            let p_ad = ad::momentum::<L, S, K, N>(&w.system, &s.x, z);
            assert!(
                scaled_error(&r, &r_ad, scale) <= DERIVATIVE_TOL,
                "{}: residual at step {}: {r} vs {r_ad}",
                w.name,
                case.k
            );
            assert!(
                scaled_error(&p, &p_ad, scale) <= DERIVATIVE_TOL,
                "{}: momentum at step {}: {p} vs {p_ad}",
                w.name,
                case.k
            );
        }
    }
    let cp = workload::charged_particle();
    check(&cp, &cp.cases);
    let dsp = workload::double_spherical_pendulum();
    check(&dsp, &dsp.spread(100));
}

#[test]
fn hand_coded_residual_and_jacobian_match_the_generated_ones() {
    let cp = workload::charged_particle();
    let p = cp.system;
    let worst = worst_disagreement(&p, &cp.cases, |x, w, mu, z| {
        hand::residual_jacobian(&p, x, w, mu, z)
    });
    println!("hand-coded: worst scaled disagreement {worst:.2e}");
    assert!(worst <= DERIVATIVE_TOL, "{worst:e}");
    for case in &cp.cases {
        let s = &case.state;
        for z in [&case.guess, &case.solution] {
            let r = hand::residual(&p, &s.x, &s.w, &s.mu, z);
            assert_eq!(r, hand::residual_jacobian(&p, &s.x, &s.w, &s.mu, z).0);
            let jacobian = Reduced::<Plus, 3, 1, 4>::residual_jacobian(&p, &s.x, &s.w, &s.mu, z).1;
            let scale = 1f64.max(jacobian.amax());
            let m = Reduced::<Plus, 3, 1, 4>::momentum(&p, &s.x, z);
            assert!(scaled_error(&hand::momentum(&p, &s.x, z), &m, scale) <= DERIVATIVE_TOL);
        }
    }
}

/// The cases replay the integrator: stepping from a case's state and guess gives back, bit for
/// bit, the trajectory's next state — so the benchmarks time the steps of the paper's run.
#[test]
fn the_cases_are_the_integrators_own_steps() {
    fn check<L, const S: usize, const K: usize, const N: usize>(w: &Workload<L, S, K, N>)
    where
        L: Reduced<Plus, S, K, N> + Copy,
    {
        let integ = ReducedIntegrator::plus(w.system, NewtonOptions::default());
        for case in &w.cases {
            let (
                next,
                ReducedStep {
                    group_unknown: g_plus,
                    stats,
                },
            ) = integ.step_from(case.k, &case.state, &case.guess).unwrap();
            assert_eq!(next, w.trajectory.states[case.k + 1], "step {}", case.k);
            assert_eq!(g_plus, w.trajectory.group_unknowns[case.k]);
            assert_eq!(stats.iterations, case.iterations);
        }
    }
    check(&workload::charged_particle());
    check(&workload::double_spherical_pendulum());
}

/// Tolerance of the step comparisons: both Newton solves stop at `‖R‖∞ ≤ 1e-12 (1 + ρ)` or at a
/// correction below `1e-12 (1 + ‖z‖∞)`, and the roots they approach are the same to round-off.
const STEP_TOL: f64 = 1e-12;

/// `max |a − b| / max(1, |b|)` over the entries of two reduced states.
fn state_error(a: &ReducedState<3, 1>, b: &ReducedState<3, 1>) -> f64 {
    let v = |s: &ReducedState<3, 1>| {
        SVector::<f64, 8>::from_iterator(s.x.iter().chain(&s.w).chain(&s.mu).chain(&s.g).copied())
    };
    let (a, b) = (v(a), v(b));
    (a - b)
        .iter()
        .zip(b.iter())
        .map(|(d, b)| d.abs() / 1f64.max(b.abs()))
        .fold(0.0, f64::max)
}

#[test]
fn hand_coded_steps_reproduce_the_generated_stepper() {
    let cp = workload::charged_particle();
    let p = cp.system;
    let options = NewtonOptions::default();
    // What a user runs (its default path), and the general path, which solves the same N
    // unknowns with the same Newton iteration as the hand-coded step.
    let integ = ReducedIntegrator::plus(p, options);
    let general = ReducedIntegrator::plus(p, options).with_elimination(false);
    let (mut worst_newton, mut worst_closed) = (0f64, 0f64);
    for case in &cp.cases {
        let (
            next,
            ReducedStep {
                group_unknown: g_plus,
                ..
            },
        ) = integ.step_from(case.k, &case.state, &case.guess).unwrap();
        let (general_next, ReducedStep { stats, .. }) =
            general.step_from(case.k, &case.state, &case.guess).unwrap();
        let (hand_next, hand_g, iterations) =
            hand::newton_step(&p, &options, &case.state, &case.guess).unwrap();
        assert_eq!(iterations, stats.iterations, "step {}", case.k);
        worst_newton = worst_newton
            .max(state_error(&hand_next, &next))
            .max(state_error(&hand_next, &general_next))
            .max((hand_g[0] - g_plus[0]).abs());
        let (closed_next, closed_g) = hand::closed_form_step(&p, &case.state);
        worst_closed = worst_closed
            .max(state_error(&closed_next, &next))
            .max((closed_g - g_plus[0]).abs());
    }
    println!("hand-coded Newton step: {worst_newton:.2e}; closed form: {worst_closed:.2e}");
    assert!(worst_newton <= STEP_TOL, "{worst_newton:e}");
    assert!(worst_closed <= STEP_TOL, "{worst_closed:e}");
}

#[test]
fn num_dual_steps_reproduce_the_generated_stepper() {
    fn check<L, const S: usize, const K: usize, const N: usize>(
        w: &Workload<L, S, K, N>,
        cases: &[StepCase<S, K, N>],
    ) -> f64
    where
        L: Reduced<Plus, S, K, N, Linear = dirac::runtime::Lu<N>> + ad::DualLagrangian<N> + Copy,
    {
        // The num-dual step solves all N unknowns, like the generated general path.
        let options = NewtonOptions::default();
        let integ = ReducedIntegrator::plus(w.system, options).with_elimination(false);
        let (mut worst, mut differing) = (0f64, 0);
        for case in cases {
            let (
                next,
                ReducedStep {
                    group_unknown: g_plus,
                    stats,
                },
            ) = integ.step_from(case.k, &case.state, &case.guess).unwrap();
            for how in [ad::Jacobian::Hessian, ad::Jacobian::PartialHessian] {
                let (ad_next, ad_g, iterations) =
                    ad::step::<L, S, K, N, 7>(&w.system, &options, how, &case.state, &case.guess)
                        .unwrap();
                // Where the step Jacobian is ill-conditioned (the pendulum's passages near the
                // pole, rcond ~ 1e-6) the two residuals' round-off can end Newton one correction
                // apart; elsewhere the iterations coincide.
                assert!(
                    iterations.abs_diff(stats.iterations) <= 1,
                    "{} step {}: {iterations} against {} corrections",
                    w.name,
                    case.k,
                    stats.iterations
                );
                differing += usize::from(iterations != stats.iterations);
                let z = join::<S, K, N>(&next.x, &g_plus);
                let z_ad = join::<S, K, N>(&ad_next.x, &ad_g);
                let scale = |v: &SVector<f64, N>| 1f64.max(v.amax());
                // w_{k+1} = ∂l/∂x1(z) moves by ‖∂w/∂z‖ ≈ ‖J‖ times the round-off in z, which
                // near the pole passages of the pendulum is far larger than ulps of w itself.
                let (s, zs) = (&case.state, &case.solution);
                let j = w.system.residual_jacobian(&s.x, &s.w, &s.mu, zs).1;
                worst = worst
                    .max((z - z_ad).amax() / scale(&z))
                    .max((next.w - ad_next.w).amax() / 1f64.max(next.w.amax()).max(j.amax()))
                    .max((next.g - ad_next.g).amax() / 1f64.max(next.g.amax()));
                assert_eq!(ad_next.mu, next.mu);
            }
        }
        assert!(
            differing * 20 <= 2 * cases.len(),
            "{}: {differing} of {} steps took a different number of corrections",
            w.name,
            2 * cases.len()
        );
        worst
    }
    let cp = workload::charged_particle();
    let worst = check(&cp, &cp.cases);
    println!("num-dual steps, charged particle: {worst:.2e}");
    assert!(worst <= STEP_TOL, "{worst:e}");
    let dsp = workload::double_spherical_pendulum();
    let worst = check(&dsp, &dsp.spread(50));
    println!("num-dual steps, double spherical pendulum: {worst:.2e}");
    assert!(worst <= STEP_TOL, "{worst:e}");
}

/// The unreduced stepper, from the same physical state, takes the same physical step:
/// `q_{k+1} = (x_{k+1}, g_k + g_k^+)` (B = 0). The unreduced equations carry the absolute group
/// coordinate, so agreement is to the tolerance of the reduction-commutes tests.
#[test]
fn the_unreduced_stepper_takes_the_same_steps() {
    fn check<L, const S: usize, const K: usize, const N: usize>(w: &Workload<L, S, K, N>) -> f64
    where
        L: Unreduced<S, K, N> + Copy,
    {
        let integ = UnreducedIntegrator::new(w.system, NewtonOptions::default());
        let mut worst = 0f64;
        for case in &w.cases {
            let (next, _) = integ
                .step_from(case.k, &case.canonical, &case.canonical_guess)
                .unwrap();
            let reduced = &w.trajectory.states[case.k + 1];
            let q = join::<S, K, N>(&reduced.x, &reduced.g);
            worst = worst.max((next.q - q).amax() / 1f64.max(q.amax()));
        }
        worst
    }
    let worst_cp = check(&workload::charged_particle());
    let worst_dsp = check(&workload::double_spherical_pendulum());
    println!("unreduced vs reduced step: charged particle {worst_cp:.2e}, DSP {worst_dsp:.2e}");
    assert!(worst_cp <= 1e-10 && worst_dsp <= 1e-10);
}

#[test]
fn the_charged_particle_workload_is_the_papers_run() {
    let cp = workload::charged_particle();
    assert_eq!(cp.system, ChargedParticle::paper(100));
    assert_eq!(cp.cases.len(), 99);
    assert_eq!(cp.cases[0].k, 1);
}
