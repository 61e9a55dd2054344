//! Forces and controls: the forced discrete Lagrange–Dirac equations, reduced and unreduced,
//! the forced discrete Noether balance, and the sensitivities of a step.

use dirac::prelude::*;
use dirac::runtime::DiscreteLagrangian;
use nalgebra::{DMatrix, SVector};

#[path = "../examples/common/forced.rs"]
mod forced;
use forced::{exact as driven_exact, Oscillator, Turntable};

/// The same turntable without forces.
#[reduced_lagrangian(shape(x), group(phi), rule = midpoint)]
fn free_turntable(q: Config, v: Velocity, i0: f64, m: f64, l: f64) -> f64 {
    let r = l * q.x.sin();
    0.5 * i0 * v.phi * v.phi
        + 0.5 * m * (l * l * v.x * v.x + r * r * v.phi * v.phi)
        + 9.81 * m * l * q.x.cos()
}

/// A damped chain of 20 particles with a pushed end (sparse backend: N = 20 > 16).
#[reduced_lagrangian(coordinates(x[20]), translate(x), rule = midpoint, controls(push),
    force = |dq| {
        let mut w = push * dq.x[0];
        for i in 0..20 { w -= c * v.x[i] * dq.x[i]; }
        w
    })]
fn chain(q: Config, v: Velocity, c: f64, push: f64) -> f64 {
    let mut t = 0.0;
    for i in 0..20 {
        t += 0.5 * v.x[i] * v.x[i];
    }
    let mut u = 0.0;
    for i in 0..19 {
        let d = q.x[i + 1] - q.x[i] - 1.0;
        u += 0.5 * d * d + 0.1 * d * d * d * d;
    }
    t - u
}

fn options() -> NewtonOptions {
    NewtonOptions::default()
}

#[test]
fn zero_forces_give_the_unforced_trajectory_bit_for_bit() {
    let (h, i0, m, l) = (0.01, 0.7, 1.3, 0.9);
    let forced = Turntable {
        h,
        i0,
        m,
        l,
        c: 0.0,
        tau: 0.0,
    };
    let free = FreeTurntable { h, i0, m, l };
    let s0 = ReducedState {
        x: SVector::from([0.4]),
        w: SVector::from([0.2]),
        mu: SVector::from([0.3]),
        g: SVector::from([0.0]),
    };
    let a = ReducedIntegrator::plus(forced, options())
        .run(s0)
        .steps(500)
        .collect()
        .unwrap();
    let b = ReducedIntegrator::plus(free, options())
        .run(s0)
        .steps(500)
        .collect()
        .unwrap();
    assert_eq!(a.states, b.states);
    let a = ReducedIntegrator::minus(forced, options())
        .run(s0)
        .steps(500)
        .collect()
        .unwrap();
    let b = ReducedIntegrator::minus(free, options())
        .run(s0)
        .steps(500)
        .collect()
        .unwrap();
    assert_eq!(a.states, b.states);
}

#[test]
fn a_group_force_changes_mu_by_exactly_its_impulse() {
    // Midpoint: f^- + f^+ = h τ in the group direction, every step.
    let (h, tau) = (0.01, 0.25);
    let sys = Turntable {
        h,
        i0: 0.7,
        m: 1.3,
        l: 0.9,
        c: 0.1,
        tau,
    };
    let s0 = ReducedState {
        x: SVector::from([0.4]),
        w: SVector::from([0.0]),
        mu: SVector::from([0.3]),
        g: SVector::from([0.0]),
    };
    let steps = 100_000;
    let mut worst = 0.0_f64;
    let mut previous = s0.mu[0];
    ReducedIntegrator::plus(sys, options())
        .run(s0)
        .steps(steps)
        .observe(|k, _, s, _| {
            if k > 0 {
                worst = worst.max((s.mu[0] - previous - h * tau).abs());
            }
            previous = s.mu[0];
        })
        .stream()
        .unwrap();
    assert!(worst <= 1e-15 * (1.0 + previous.abs()), "{worst:e}");
    let last = previous;
    let expected = s0.mu[0] + steps as f64 * h * tau;
    assert!(
        (last - expected).abs() <= 1e-9 * expected.abs(),
        "{last} {expected}"
    );
}

#[test]
fn the_unreduced_forced_step_balances_the_group_momentum() {
    let (h, tau) = (0.01, -0.4);
    let sys = Turntable {
        h,
        i0: 0.7,
        m: 1.3,
        l: 0.9,
        c: 0.1,
        tau,
    };
    let s0 = ReducedState {
        x: SVector::from([0.4]),
        w: SVector::from([0.1]),
        mu: SVector::from([0.3]),
        g: SVector::from([0.0]),
    };
    let c0 = sys.untrivialize(&s0);
    let steps = 100_000;
    let mut worst = 0.0_f64;
    let mut previous = c0.p[1];
    // The unreduced step carries p_g through Newton's residual, so the balance holds to the
    // residual tolerance: tightened here to round-off level.
    let tight = NewtonOptions {
        abs_tol: 1e-15,
        rel_tol: 1e-15,
        ..options()
    };
    // A torque that changes sign (a feedback-free law of the step index) keeps the motion
    // bounded over the 10⁵ steps.
    let torque = |k: usize| 0.4 * (0.003 * k as f64).sin();
    let summary = UnreducedIntegrator::new(sys, tight)
        .run(c0)
        .steps(steps)
        .feedback(|k: usize, _, _: &UnreducedState<2>, u: &mut [f64]| u[0] = torque(k))
        .observe(|k, _, s, _| {
            if k > 0 {
                worst = worst.max(((s.p[1] - previous) - h * torque(k - 1)).abs());
            }
            previous = s.p[1];
        })
        .stream()
        .unwrap();
    // p_g is computed by the unreduced momentum update D2 L_d + f^+, which equals
    // p_{g,k} + f^- + f^+ − R_g: the balance holds up to the accepted step residual (the reduced
    // stepper applies it explicitly, to round-off).
    assert!(
        worst <= summary.max_residual + 1e-14,
        "{worst:e} > {:e}",
        summary.max_residual
    );
    // Reduced and unreduced agree.
    let red = ReducedIntegrator::plus(sys, options())
        .run(s0)
        .steps(2000)
        .collect()
        .unwrap();
    let unr = UnreducedIntegrator::new(sys, options())
        .run(c0)
        .steps(2000)
        .collect()
        .unwrap();
    let a = sys.untrivialize(red.last());
    let b = unr.last();
    assert!(
        (a.q - b.q).amax() < 1e-9 && (a.p - b.p).amax() < 1e-9,
        "{a:?} {b:?}"
    );
}

#[test]
fn the_damped_driven_oscillator_converges_at_order_two() {
    let (m, k, c, a0, omega, x0, t_end) = (1.0, 4.0, 0.3, 0.5, 1.3, 1.0, 5.0);
    let error = |n: usize| {
        let h = t_end / n as f64;
        let sys = Oscillator { h, m, k, c, a: 0.0 };
        let integ = UnreducedIntegrator::new(sys, options());
        let s0 = UnreducedState {
            q: SVector::from([x0]),
            p: SVector::from([0.0]),
        };
        // The drive at the step's midpoint, where the midpoint rule evaluates the force.
        let traj = integ
            .run(s0)
            .steps(n)
            .feedback(|k: usize, _, _: &UnreducedState<1>, u: &mut [f64]| {
                u[0] = a0 * (omega * (k as f64 + 0.5) * h).cos();
            })
            .collect()
            .unwrap();
        (traj.last().q[0] - driven_exact(m, k, c, a0, omega, x0, t_end)).abs()
    };
    let (e1, e2) = (error(200), error(400));
    let order = (e1 / e2).log2();
    assert!((order - 2.0).abs() < 0.1, "order {order} ({e1:e}, {e2:e})");
}

#[test]
fn a_control_sequence_equals_the_same_feedback_law() {
    let h = 0.01;
    let sys = Oscillator {
        h,
        m: 1.0,
        k: 4.0,
        c: 0.3,
        a: 0.0,
    };
    let integ = UnreducedIntegrator::new(sys, options());
    let s0 = UnreducedState {
        q: SVector::from([1.0]),
        p: SVector::from([0.0]),
    };
    let rows: Vec<[f64; 1]> = (0..100).map(|k| [(k as f64 * 0.1).sin()]).collect();
    let a = integ
        .run(s0)
        .steps(100)
        .controls(ControlSequence::rows(&rows))
        .collect()
        .unwrap();
    let b = integ
        .run(s0)
        .steps(100)
        .feedback(|k: usize, _, _: &UnreducedState<1>, u: &mut [f64]| u[0] = (k as f64 * 0.1).sin())
        .collect()
        .unwrap();
    assert_eq!(a.states, b.states);
    // A sequence shorter than the run ends it with a typed error that keeps the steps taken.
    let e = integ
        .run(s0)
        .steps(150)
        .controls(ControlSequence::rows(&rows))
        .collect()
        .unwrap_err();
    // The error gives the sequence's real row length and says where it ended.
    assert!(
        matches!(
            e.source,
            StepError::InvalidControls {
                step: 100,
                expected: 1,
                found: 1
            }
        ),
        "{:?}",
        e.source
    );
    let message = e.source.to_string();
    assert!(message.contains("ended after 100 row(s)"), "{message}");
    assert_eq!(e.trajectory.step_count(), 100);
    // A sequence whose rows have the wrong length: the error gives that length.
    let wide: Vec<f64> = rows.iter().flat_map(|r| [r[0], 0.0]).collect();
    let e = integ
        .run(s0)
        .steps(10)
        .controls(ControlSequence::flat(&wide, 2))
        .collect()
        .unwrap_err();
    assert!(
        matches!(
            e.source,
            StepError::InvalidControls {
                step: 0,
                expected: 1,
                found: 2
            }
        ),
        "{:?}",
        e.source
    );
    assert!(
        e.source.to_string().contains("2 control value(s) given"),
        "{}",
        e.source
    );
}

/// A step as a map of the flattened state and the controls.
type StepMap<'a> = &'a dyn Fn(&[f64], &[f64]) -> Vec<f64>;

/// Central differences of `f` (a state and control map) at `(s, u)`.
fn central(f: StepMap, s: &[f64], u: &[f64], eps: f64) -> (DMatrix<f64>, DMatrix<f64>) {
    let n_out = f(s, u).len();
    let column = |plus: Vec<f64>, minus: Vec<f64>| {
        nalgebra::DVector::from_iterator(
            n_out,
            plus.iter().zip(&minus).map(|(a, b)| (a - b) / (2.0 * eps)),
        )
    };
    let mut ds = DMatrix::zeros(n_out, s.len());
    for i in 0..s.len() {
        let (mut a, mut b) = (s.to_vec(), s.to_vec());
        a[i] += eps;
        b[i] -= eps;
        ds.set_column(i, &column(f(&a, u), f(&b, u)));
    }
    let mut du = DMatrix::zeros(n_out, u.len());
    for i in 0..u.len() {
        let (mut a, mut b) = (u.to_vec(), u.to_vec());
        a[i] += eps;
        b[i] -= eps;
        du.set_column(i, &column(f(s, &a), f(s, &b)));
    }
    (ds, du)
}

fn assert_close(exact: &DMatrix<f64>, fd: &DMatrix<f64>, what: &str) {
    let scale = exact.amax().max(1.0);
    let err = (exact - fd).amax();
    assert!(
        err <= 1e-6 * scale,
        "{what}: {err:e} (scale {scale:e})\n{exact}\n{fd}"
    );
}

fn reduced_vec<const S: usize, const K: usize>(s: &ReducedState<S, K>) -> Vec<f64> {
    s.x.iter()
        .chain(s.w.iter())
        .chain(s.mu.iter())
        .chain(s.g.iter())
        .copied()
        .collect()
}

fn reduced_from<const S: usize, const K: usize>(v: &[f64]) -> ReducedState<S, K> {
    ReducedState {
        x: SVector::from_column_slice(&v[..S]),
        w: SVector::from_column_slice(&v[S..2 * S]),
        mu: SVector::from_column_slice(&v[2 * S..2 * S + K]),
        g: SVector::from_column_slice(&v[2 * S + K..]),
    }
}

fn check_reduced<L, D, const S: usize, const K: usize, const N: usize>(
    integ: &ReducedIntegrator<L, D, S, K, N>,
    s0: ReducedState<S, K>,
    u: &[f64],
) where
    D: dirac::runtime::Side,
    L: Reduced<D, S, K, N>,
{
    let (_, _, sens) = integ.step_sensitivity(0, &s0, u).unwrap();
    let step = |s: &[f64], u: &[f64]| {
        let (next, _) = integ
            .step_with(
                &mut integ.workspace(),
                StepAt::new(0, integ.time_step()).with_controls(u),
                &reduced_from::<S, K>(s),
            )
            .unwrap();
        reduced_vec(&next)
    };
    let (ds, du) = central(&step, &reduced_vec(&s0), u, 1e-6);
    assert_close(&sens.state, &ds, "reduced state");
    assert_close(&sens.control, &du, "reduced control");
}

fn check_unreduced<L, const S: usize, const K: usize, const N: usize>(
    integ: &UnreducedIntegrator<L, S, K, N>,
    s0: UnreducedState<N>,
    u: &[f64],
) where
    L: Unreduced<S, K, N>,
{
    let (_, _, sens) = integ.step_sensitivity(0, &s0, u).unwrap();
    let flat = |s: &UnreducedState<N>| s.q.iter().chain(s.p.iter()).copied().collect::<Vec<_>>();
    let step = |s: &[f64], u: &[f64]| {
        let state = UnreducedState {
            q: SVector::from_column_slice(&s[..N]),
            p: SVector::from_column_slice(&s[N..]),
        };
        let (next, _) = integ
            .step_with(
                &mut integ.workspace(),
                StepAt::new(0, integ.time_step()).with_controls(u),
                &state,
            )
            .unwrap();
        flat(&next)
    };
    let (ds, du) = central(&step, &flat(&s0), u, 1e-6);
    assert_close(&sens.state, &ds, "unreduced state");
    assert_close(&sens.control, &du, "unreduced control");
}

#[test]
fn sensitivities_match_central_differences_dense() {
    let sys = Turntable {
        h: 0.05,
        i0: 0.7,
        m: 1.3,
        l: 0.9,
        c: 0.2,
        tau: 0.3,
    };
    let s0 = ReducedState {
        x: SVector::from([0.4]),
        w: SVector::from([0.1]),
        mu: SVector::from([0.3]),
        g: SVector::from([0.2]),
    };
    check_reduced(&ReducedIntegrator::plus(sys, options()), s0, &[0.3]);
    check_reduced(&ReducedIntegrator::minus(sys, options()), s0, &[-0.2]);
    check_unreduced(
        &UnreducedIntegrator::new(sys, options()),
        sys.untrivialize(&s0),
        &[0.5],
    );
}

#[test]
fn sensitivities_match_central_differences_sparse() {
    let sys = Chain {
        h: 0.05,
        c: 0.2,
        push: 0.0,
    };
    let mut q = SVector::<f64, 20>::zeros();
    let mut p = SVector::<f64, 20>::zeros();
    for i in 0..20 {
        q[i] = 1.05 * i as f64 + 0.03 * (i as f64).sin();
        p[i] = 0.1 * (0.7 * i as f64).cos();
    }
    let c0 = UnreducedState { q, p };
    check_unreduced(&UnreducedIntegrator::new(sys, options()), c0, &[0.4]);
    let s0 = sys.trivialize(&c0);
    check_reduced(&ReducedIntegrator::plus(sys, options()), s0, &[0.4]);
}

#[test]
fn a_composition_of_the_forced_midpoint_step_reaches_order_four() {
    // The midpoint rule's forced step is self-adjoint (its forces are (h/2) F at the midpoint,
    // symmetric under (q0, q1, h) → (q1, q0, −h)), so the triple jump of its stages, each with
    // its own forces at γ_i h, has order 4 on the damped oscillator.
    let (m, k, c, x0, t_end) = (1.0, 4.0, 0.3, 1.0, 5.0);
    let tight = NewtonOptions {
        abs_tol: 1e-15,
        rel_tol: 1e-15,
        ..options()
    };
    let error = |n: usize| {
        let sys = Oscillator {
            h: t_end / n as f64,
            m,
            k,
            c,
            a: 0.0,
        };
        let s0 = UnreducedState {
            q: SVector::from([x0]),
            p: SVector::from([0.0]),
        };
        let traj = Composition::new(
            UnreducedIntegrator::new(sys, tight),
            CompositionMethod::TRIPLE_JUMP,
        )
        .run(s0)
        .steps(n)
        .collect()
        .unwrap();
        (traj.last().q[0] - driven_exact(m, k, c, 0.0, 1.0, x0, t_end)).abs()
    };
    let (e1, e2) = (error(50), error(100));
    let order = (e1 / e2).log2();
    assert!((order - 4.0).abs() < 0.2, "order {order} ({e1:e}, {e2:e})");
}

#[test]
fn the_atlas_and_a_composition_pass_the_controls_to_their_charts_and_stages() {
    let sys = Turntable {
        h: 0.01,
        i0: 0.7,
        m: 1.3,
        l: 0.9,
        c: 0.1,
        tau: 0.0,
    };
    let s0 = ReducedState::new([0.4], [0.0], [0.3], [0.0]);
    let law = |k: usize| 0.3 * (0.01 * k as f64).cos();
    let plain = ReducedIntegrator::plus(sys, options())
        .run(s0)
        .steps(300)
        .feedback(|k: usize, _, _: &ReducedState<1, 1>, u: &mut [f64]| u[0] = law(k))
        .collect()
        .unwrap();
    // A one-chart atlas steps exactly as its chart.
    let atlas = dirac::runtime::atlas::AtlasIntegrator::new()
        .chart("table", ReducedIntegrator::plus(sys, options()));
    let through_atlas = atlas
        .run((0, s0))
        .steps(300)
        .feedback(|k: usize, _, _: &(usize, ReducedState<1, 1>), u: &mut [f64]| u[0] = law(k))
        .collect()
        .unwrap();
    assert_eq!(through_atlas.states, plain.states);
    // Every stage of a composition takes the macro step's controls: the impulse over a macro
    // step is Σ γ_i h τ_k = h τ_k.
    let composed = Composition::new(
        ReducedIntegrator::plus(sys, options()),
        CompositionMethod::TRIPLE_JUMP,
    )
    .run(s0)
    .steps(300)
    .feedback(|k: usize, _, _: &ReducedState<1, 1>, u: &mut [f64]| u[0] = law(k))
    .collect()
    .unwrap();
    for (k, pair) in composed.states.windows(2).enumerate() {
        let impulse = 0.01 * law(k);
        assert!((pair[1].mu[0] - pair[0].mu[0] - impulse).abs() < 1e-14);
    }
}

#[test]
fn the_eliminated_and_the_general_forced_steps_agree() {
    let sys = Turntable {
        h: 0.01,
        i0: 0.7,
        m: 1.3,
        l: 0.9,
        c: 0.1,
        tau: 0.2,
    };
    const { assert!(<Turntable as Reduced<dirac::runtime::Plus, 1, 1, 2>>::ELIMINATES_GROUP) };
    let s0 = ReducedState::new([0.4], [0.1], [0.3], [0.0]);
    let tight = NewtonOptions {
        abs_tol: 1e-15,
        rel_tol: 1e-15,
        ..options()
    };
    let run = |eliminate: bool| {
        ReducedIntegrator::plus(sys, tight)
            .with_elimination(eliminate)
            .run(s0)
            .steps(500)
            .collect()
            .unwrap()
    };
    let (a, b) = (run(true), run(false));
    // Round-off grows along the trajectory (the pendulum is chaotic); over 500 steps it stays
    // at the level of a few hundred ulps.
    for (x, y) in a.states.iter().zip(&b.states) {
        assert!((x.x - y.x).amax() < 1e-12 && (x.w - y.w).amax() < 1e-12);
        assert!((x.mu - y.mu).amax() < 1e-12 && (x.g - y.g).amax() < 1e-12);
    }
}
