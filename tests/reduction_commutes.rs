//! Reduction commutes with integration, as a test: the reduced
//! (+) and (−) trajectories, mapped back with the trivialization (3.7) and the group
//! reconstruction, are the unreduced discrete Lagrange–Dirac trajectory (Definitions 2.7/2.8), for
//! `B = 0` and for nonzero connection matrices, with one and two group coordinates.

use dirac::paper::ChargedParticle;
use dirac::prelude::*;

mod common;
use common::{ParticleWithConnection, PlanarRotor};

/// `‖a − b‖∞ ≤ tol · max(‖b‖∞, 1e-300)`: relative agreement of two vectors.
fn assert_close<const N: usize>(a: &SVector<f64, N>, b: &SVector<f64, N>, tol: f64, what: &str) {
    let err = (a - b).amax();
    let scale = b.amax().max(1e-300);
    assert!(
        err <= tol * scale,
        "{what}: {a} vs {b} (relative error {:e})",
        err / scale
    );
}

/// Integrates `initial` with the reduced (+), reduced (−) and unreduced steppers and checks that
/// they describe the same physical trajectory `(q_k, p_k)` to `tol` (relative).
fn assert_reduction_commutes<L, const S: usize, const K: usize, const N: usize>(
    sys: L,
    initial: UnreducedState<N>,
    steps: usize,
    tol: f64,
) where
    L: Reduced<Plus, S, K, N> + Reduced<Minus, S, K, N> + Unreduced<S, K, N> + Copy,
{
    let options = NewtonOptions::default();
    let plus = ReducedIntegrator::plus(sys, options)
        .run(sys.trivialize(&initial))
        .steps(steps)
        .collect()
        .unwrap();
    let minus = ReducedIntegrator::minus(sys, options)
        .run(sys.trivialize(&initial))
        .steps(steps)
        .collect()
        .unwrap();
    let unreduced = UnreducedIntegrator::new(sys, options)
        .run(initial)
        .steps(steps)
        .collect()
        .unwrap();
    for k in 0..=steps {
        let u = unreduced.states[k];
        for (name, traj) in [("(+)", &plus), ("(−)", &minus)] {
            let c = sys.untrivialize(&traj.states[k]);
            assert_close(&c.q, &u.q, tol, &format!("{name} q at step {k}"));
            assert_close(&c.p, &u.p, tol, &format!("{name} p at step {k}"));
            // μ is the momentum map of the unreduced state, and it is conserved bit for bit.
            assert_eq!(traj.states[k].mu, traj.states[0].mu);
            assert_close(
                &traj.states[k].mu,
                &sys.momentum_map(&u),
                tol,
                "μ = J(q, p)",
            );
        }
    }
}

fn canonical<const N: usize>(q: [f64; N], p: [f64; N]) -> UnreducedState<N> {
    UnreducedState {
        q: SVector::from(q),
        p: SVector::from(p),
    }
}

#[test]
fn charged_particle_without_connection() {
    let sys = ChargedParticle::paper(100);
    let initial = sys.untrivialize(&ChargedParticle::paper_initial_state());
    assert_reduction_commutes(sys, initial, 100, 1e-10);
}

#[test]
fn charged_particle_with_a_connection() {
    let sys = ParticleWithConnection {
        h: 0.1,
        m: 1.3,
        b0: 0.8,
        b: 0.45,
    };
    assert_reduction_commutes(
        sys,
        canonical([0.2, -0.1, 0.3, 0.7], [0.9, 0.2, -0.4, 1.1]),
        200,
        1e-10,
    );
}

#[test]
fn two_group_coordinates() {
    let sys = PlanarRotor {
        h: 0.05,
        m: 2.0,
        k: 3.0,
    };
    assert_reduction_commutes(
        sys,
        canonical([0.4, 1.0, 2.0], [0.1, 0.5, -0.3]),
        400,
        1e-10,
    );
}

/// Each reduced step equals one unreduced step taken from the same physical state with the
/// group coordinate re-centred at `g_k = 0` (the reduced space's identification (3.10)): there
/// the unreduced stepper loses no digits to a large absolute group coordinate.
#[test]
fn each_reduced_step_is_an_unreduced_step_at_g_zero() {
    let sys = ParticleWithConnection {
        h: 0.1,
        m: 1.3,
        b0: 0.8,
        b: 0.45,
    };
    let initial = sys.trivialize(&canonical([0.2, -0.1, 0.3, 0.7], [0.9, 0.2, -0.4, 1.1]));
    let options = NewtonOptions::default();
    let reduced = ReducedIntegrator::plus(sys, options)
        .run(initial)
        .steps(200)
        .collect()
        .unwrap();
    let unreduced = UnreducedIntegrator::new(sys, options);
    for (k, pair) in reduced.states.windows(2).enumerate() {
        let mut at_zero = pair[0];
        at_zero.g = SVector::zeros();
        let start = sys.untrivialize(&at_zero);
        let (next, _) = unreduced.step_from(k, &start, &start.q).unwrap();
        let mut expected = pair[1];
        expected.g -= pair[0].g;
        let expected = sys.untrivialize(&expected);
        assert_close(&next.q, &expected.q, 1e-12, &format!("q at step {k}"));
        assert_close(&next.p, &expected.p, 1e-12, &format!("p at step {k}"));
    }
}

/// The practical reason to reduce: the unreduced stepper evaluates `L_d` at absolute group
/// coordinates, and `θ1 − θ0` of two large numbers has few correct digits. The reduced
/// trajectory does not see `g` at all: shifting the initial group coordinate leaves its shape
/// trajectory bit for bit unchanged, while the unreduced one drifts.
#[test]
fn a_large_group_coordinate_costs_the_unreduced_stepper_digits() {
    let sys = ChargedParticle::paper(100);
    let options = NewtonOptions::default();
    let at = |theta0: f64| {
        let mut state = ChargedParticle::paper_initial_state();
        state.g[0] = theta0;
        state
    };
    let reduced_0 = ReducedIntegrator::plus(sys, options)
        .run(at(0.0))
        .steps(100)
        .collect()
        .unwrap();
    let reduced_far = ReducedIntegrator::plus(sys, options)
        .run(at(1e8))
        .steps(100)
        .collect()
        .unwrap();
    for (a, b) in reduced_0.states.iter().zip(&reduced_far.states) {
        assert_eq!(a.x, b.x);
        assert_eq!(a.w, b.w);
    }
    let final_error = |theta0: f64| {
        let traj = UnreducedIntegrator::new(sys, options)
            .run(sys.untrivialize(&at(theta0)))
            .steps(100)
            .collect()
            .unwrap();
        let q = traj.last().q;
        let x = reduced_0.last().x;
        (0..3).map(|i| (q[i] - x[i]).abs()).fold(0.0, f64::max)
    };
    let near = final_error(0.0);
    let far = final_error(1e8);
    assert!(near < 1e-12, "unreduced at θ0 = 0 differs by {near:e}");
    assert!(
        far > 1e3 * near.max(1e-15),
        "unreduced at θ0 = 1e8 differs by only {far:e}"
    );
}

/// The paper's double spherical pendulum (§7.2, N = 10⁴): reduced (+), reduced (−) and
/// unreduced trajectories, compared relative to the largest magnitude q and p reach over the
/// run (|p| up to ≈1.3e6).
///
/// * Configurations agree to 1e-10 over the first 2,000 steps (measured ≈ 2e-11).
/// * Momenta agree to round-off, which here is ≈ 1e-10 and no better: the residual cannot drop
///   below ≈ 5e-7 (its terms are ~3e9 and rounded), the step Jacobian has rcond ≈ 1e-3, and
///   `p_{k+1} = D2 L_d` amplifies configuration errors by ∂p/∂q_{k+1} ≈ m l²/h ≈ 2e9. The
///   yardstick is how far a one-ulp change of the initial state moves the same integrator
///   (≈ 8e-11 over 2,000 steps): the steppers agree to within 3× that, and to within 30× it over
///   the whole run (each stepper — reduced (+)/(−) with the group unknown eliminated, unreduced —
///   rounds differently at every step, and those perturbations accumulate like the initial one), which passes within |sin φ2| ≈ 1.6e-3 of a pole (step ≈ 6,600) where the
///   sensitivity grows to ≈ 2e-9.
#[test]
fn double_spherical_pendulum_paper_run() {
    use dirac::paper::{DoubleSphericalPendulum, DSP_STEPS};
    let sys = DoubleSphericalPendulum::paper();
    let initial = DoubleSphericalPendulum::paper_initial_state();
    let options = NewtonOptions::default();
    let plus = ReducedIntegrator::plus(sys, options)
        .run(initial)
        .steps(DSP_STEPS)
        .collect()
        .unwrap();
    let minus = ReducedIntegrator::minus(sys, options)
        .run(initial)
        .steps(DSP_STEPS)
        .collect()
        .unwrap();
    let unreduced = UnreducedIntegrator::new(sys, options)
        .run(sys.untrivialize(&initial))
        .steps(DSP_STEPS)
        .collect()
        .unwrap();
    let mut nudged = initial;
    nudged.x[0] = f64::from_bits(initial.x[0].to_bits() + 1);
    let ulp = ReducedIntegrator::plus(sys, options)
        .run(nudged)
        .steps(DSP_STEPS)
        .collect()
        .unwrap();
    let scale_q = unreduced
        .states
        .iter()
        .map(|s| s.q.amax())
        .fold(0.0, f64::max);
    let scale_p = unreduced
        .states
        .iter()
        .map(|s| s.p.amax())
        .fold(0.0, f64::max);
    let rel_q = |a: &SVector<f64, 4>, b: &SVector<f64, 4>| (a - b).amax() / scale_q;
    let rel_p = |a: &SVector<f64, 4>, b: &SVector<f64, 4>| (a - b).amax() / scale_p;
    let mut worst_sensitivity = 0.0f64;
    for k in 0..=DSP_STEPS {
        let u = unreduced.states[k];
        let reference = sys.untrivialize(&plus.states[k]);
        let perturbed = sys.untrivialize(&ulp.states[k]);
        worst_sensitivity = worst_sensitivity
            .max(rel_q(&perturbed.q, &reference.q))
            .max(rel_p(&perturbed.p, &reference.p));
        let (tol_q, tol_p) = if k <= 2000 {
            (1e-10, 3.0 * worst_sensitivity.max(1e-11))
        } else {
            let t = 30.0 * worst_sensitivity.max(1e-11);
            (t, t)
        };
        for (name, c) in [
            ("(+)", reference),
            ("(−)", sys.untrivialize(&minus.states[k])),
        ] {
            let (eq, ep) = (rel_q(&c.q, &u.q), rel_p(&c.p, &u.p));
            assert!(eq <= tol_q, "{name} q at step {k}: {eq:e} > {tol_q:e}");
            assert!(ep <= tol_p, "{name} p at step {k}: {ep:e} > {tol_p:e}");
        }
    }
    // The closest approach to a pole, as documented above.
    let (k_pole, sin_pole) = (0..=DSP_STEPS)
        .map(|k| (k, plus.states[k].x[2].sin().abs()))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .unwrap();
    assert!(
        sin_pole < 3e-3 && k_pole > 2000,
        "closest approach |sin φ2| = {sin_pole:e} at step {k_pole}"
    );
}

/// A Lagrangian whose momentum equation is not affine in the group increment (a quartic term in
/// `θ1 − θ0`): the compiler must keep the general path.
#[reduced_lagrangian(shape(x), group(theta))]
fn quartic_rotor(q0: Config, q1: Config, h: f64) -> f64 {
    let (dx, dt) = ((q1.x - q0.x) / h, (q1.theta - q0.theta) / h);
    h * (0.5 * dx * dx + 0.5 * (1.0 + 0.1 * q0.x * q0.x) * dt * dt + 0.01 * dt.powi(4)
        - 0.5 * q0.x * q0.x)
}

/// Momentum-level elimination (the group unknowns solved in closed form, Newton on the shape
/// unknowns only) is detected at compile time exactly when the momentum equations are affine in
/// the group unknowns, and gives the same trajectory as the general path to round-off.
#[test]
fn eliminated_and_general_paths_agree() {
    fn compare<L, const S: usize, const K: usize, const N: usize>(
        sys: L,
        initial: ReducedState<S, K>,
        steps: usize,
    ) where
        L: Reduced<Plus, S, K, N> + Reduced<Minus, S, K, N> + Copy,
    {
        compare_side::<Plus, L, S, K, N>(sys, initial, steps);
        compare_side::<Minus, L, S, K, N>(sys, initial, steps);
    }
    fn compare_side<D, L, const S: usize, const K: usize, const N: usize>(
        sys: L,
        initial: ReducedState<S, K>,
        steps: usize,
    ) where
        D: Side,
        L: Reduced<D, S, K, N> + Copy,
    {
        assert!(L::ELIMINATES_GROUP);
        let minus = D::VARIANT == Variant::Minus;
        let make = |eliminate| {
            ReducedIntegrator::<L, D, S, K, N>::new(sys, NewtonOptions::default())
                .with_elimination(eliminate)
        };
        assert!(make(true).eliminates_group() && !make(false).eliminates_group());
        let fast = make(true).run(initial).steps(steps).collect().unwrap();
        let general = make(false).run(initial).steps(steps).collect().unwrap();
        // Round-off yardstick: how far a one-ulp change of the initial state moves the
        // general path (≈ 1e-16 for the small systems; ≈ 8e-11 of |w| for the double
        // spherical pendulum over 2,000 steps, whose momenta carry a ~1e-10 round-off floor).
        let mut nudged = initial;
        nudged.x[0] = f64::from_bits(initial.x[0].to_bits() + 1);
        let ulp = make(false).run(nudged).steps(steps).collect().unwrap();
        let scale_x = general
            .states
            .iter()
            .map(|s| s.x.amax().max(s.g.amax()))
            .fold(1e-300, f64::max);
        let scale_w = general
            .states
            .iter()
            .map(|s| s.w.amax())
            .fold(1e-300, f64::max);
        let spread = |f: &dyn Fn(&ReducedState<S, K>, &ReducedState<S, K>) -> f64| {
            ulp.states
                .iter()
                .zip(&general.states)
                .map(|(a, b)| f(a, b))
                .fold(0.0, f64::max)
        };
        let tol_x = 1e-10f64
            .max(3.0 * spread(&|a, b| (a.x - b.x).amax().max((a.g - b.g).amax())) / scale_x);
        let tol_w = 1e-10f64.max(3.0 * spread(&|a, b| (a.w - b.w).amax()) / scale_w);
        for (k, (a, b)) in fast.states.iter().zip(&general.states).enumerate() {
            let (ex, eg, ew) = (
                (a.x - b.x).amax() / scale_x,
                (a.g - b.g).amax() / scale_x,
                (a.w - b.w).amax() / scale_w,
            );
            assert!(
                ex <= tol_x && eg <= tol_x,
                "minus = {minus}, step {k}: x {ex:e}, g {eg:e} > {tol_x:e}"
            );
            assert!(
                ew <= tol_w,
                "minus = {minus}, step {k}: w {ew:e} > {tol_w:e}"
            );
            assert_eq!(a.mu, b.mu);
        }
    }
    compare(
        ChargedParticle::paper(100),
        ChargedParticle::paper_initial_state(),
        100,
    );
    let with_b = ParticleWithConnection {
        h: 0.1,
        m: 1.3,
        b0: 0.8,
        b: 0.45,
    };
    compare(
        with_b,
        ReducedState::new([0.2, -0.1, 0.3], [0.9, 0.2, -0.4], [1.1], [0.7]),
        200,
    );
    let rotor = PlanarRotor {
        h: 0.05,
        m: 2.0,
        k: 3.0,
    };
    compare(
        rotor,
        ReducedState::new([0.4], [0.1], [0.5, -0.3], [1.0, 2.0]),
        400,
    );
    // The double spherical pendulum's momentum equation is affine too, but its closed form costs
    // more code than the general path, so it is not the default there.
    let dsp = dirac::paper::DoubleSphericalPendulum::paper();
    const {
        assert!(
            !<dirac::paper::DoubleSphericalPendulum as Reduced<Plus, 3, 1, 4>>::ELIMINATION_PAYS
        )
    };
    assert!(!ReducedIntegrator::plus(dsp, NewtonOptions::default()).eliminates_group());
    compare(
        dsp,
        dirac::paper::DoubleSphericalPendulum::paper_initial_state(),
        2000,
    );

    // Not affine: no elimination, the general path runs either way.
    const {
        assert!(
            !<QuarticRotor as Reduced<Plus, 1, 1, 2>>::ELIMINATES_GROUP
                && !<QuarticRotor as Reduced<Minus, 1, 1, 2>>::ELIMINATES_GROUP
        )
    };
    let sys = QuarticRotor { h: 0.05 };
    let integ = ReducedIntegrator::plus(sys, NewtonOptions::default());
    assert!(!integ.eliminates_group());
    let traj = ReducedIntegrator::plus(sys, NewtonOptions::default())
        .run(ReducedState::new([0.3], [0.2], [0.4], [0.0]))
        .steps(100)
        .collect()
        .unwrap();
    assert_eq!(traj.step_count(), 100);
}
