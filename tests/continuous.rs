//! The continuous front end: a Lagrangian `L(q, v)` with `rule = ...` gives
//! the same integrator as the hand-written `L_d`, and the Legendre map, energy and initial states
//! from `(q, q̇)` it also emits.

use dirac::paper::{
    ChargedParticle, ChargedParticleContinuous, DoubleSphericalPendulum,
    DoubleSphericalPendulumContinuous,
};
use dirac::prelude::*;
use dirac::{continuous_energies, reduced_continuous_energies, ContinuousLagrangian};

/// The midpoint rule formed on the graph is the hand-written one node for node: the generated
/// code is identical (same operation counts) and so is every step, bit for bit, for the reduced
/// (+), (−) and unreduced steppers.
#[test]
fn double_spherical_pendulum_continuous_is_bit_for_bit_the_hand_written() {
    assert_eq!(
        DoubleSphericalPendulum::GENERATED,
        DoubleSphericalPendulumContinuous::GENERATED
    );
    let (hand, cont) = (
        DoubleSphericalPendulum::paper(),
        DoubleSphericalPendulumContinuous::paper(),
    );
    let initial = DoubleSphericalPendulum::paper_initial_state();
    for minus in [false, true] {
        let opts = NewtonOptions::default();
        let (a, b) = if minus {
            (
                ReducedIntegrator::minus(hand, opts)
                    .run(initial)
                    .steps(300)
                    .collect(),
                ReducedIntegrator::minus(cont, opts)
                    .run(initial)
                    .steps(300)
                    .collect(),
            )
        } else {
            (
                ReducedIntegrator::plus(hand, opts)
                    .run(initial)
                    .steps(300)
                    .collect(),
                ReducedIntegrator::plus(cont, opts)
                    .run(initial)
                    .steps(300)
                    .collect(),
            )
        };
        assert_eq!(a.unwrap().states, b.unwrap().states, "minus = {minus}");
    }
    let c0 = hand.untrivialize(&initial);
    let a = UnreducedIntegrator::new(hand, NewtonOptions::default())
        .run(c0)
        .steps(300)
        .collect();
    let b = UnreducedIntegrator::new(cont, NewtonOptions::default())
        .run(c0)
        .steps(300)
        .collect();
    assert_eq!(a.unwrap().states, b.unwrap().states);
    let (q0, q1) = (c0.q, c0.q + SVector::from([0.01, -0.02, 0.03, 0.04]));
    assert_eq!(
        hand.lagrangian(&q0, &q1).to_bits(),
        cont.lagrangian(&q0, &q1).to_bits()
    );
}

/// The left-point rule `h L(q0, Δq/h)` and the hand-written `½ m/h Δq² + …` are the same function
/// rounded differently (`Δq/h` is rounded before squaring), so from the same state and the same
/// Newton guess one step agrees to a few units of round-off of the state: measured normwise,
/// `|Δ(x, w)|∞ / (ε max(|(x, w)|∞, 1))`, printed below and bounded by 64. Over the Table 1 run
/// (N = 200) the error `|q(T) − q_N|` agrees to 1e-12 relative.
#[test]
fn charged_particle_continuous_agrees_to_round_off() {
    let (hand, cont) = (
        ChargedParticle::paper(200),
        ChargedParticleContinuous::paper(200),
    );
    let opts = NewtonOptions::default();
    let traj = ReducedIntegrator::plus(hand, opts)
        .run(ChargedParticle::paper_initial_state())
        .steps(200)
        .collect()
        .unwrap();
    let (hand_stepper, cont_stepper) = (
        ReducedIntegrator::plus(hand, opts),
        ReducedIntegrator::plus(cont, opts),
    );
    let (mut worst, mut identical) = (0.0_f64, 0);
    for (k, state) in traj.states.iter().enumerate() {
        // The same state and the same Newton guess, so only L_d differs.
        let guess = SVector::from([state.x[0], state.x[1], state.x[2], 0.0]);
        let (a, ..) = hand_stepper.step_from(k, state, &guess).unwrap();
        let (b, ..) = cont_stepper.step_from(k, state, &guess).unwrap();
        let scale = a.x.amax().max(a.w.amax()).max(1.0);
        let d = (a.x - b.x).amax().max((a.w - b.w).amax()) / (f64::EPSILON * scale);
        worst = worst.max(d);
        identical += usize::from(a == b);
        assert_eq!(a.mu, b.mu);
    }
    eprintln!(
        "charged particle, continuous vs hand-written, one step: max {worst} ε (normwise), {identical} of {} steps bit-for-bit",
        traj.states.len()
    );
    assert!(worst <= 64.0, "{worst} ε");
    let end = |t: &Trajectory<3, 1>| {
        let exact = ChargedParticle::exact_position(20.0);
        (t.last().x - SVector::from(exact)).norm()
    };
    let cont_traj = ReducedIntegrator::plus(cont, opts)
        .run(ChargedParticle::paper_initial_state())
        .steps(200)
        .collect()
        .unwrap();
    let (e_hand, e_cont) = (end(&traj), end(&cont_traj));
    eprintln!("Table 1, N = 200: hand-written {e_hand}, continuous {e_cont}");
    assert!(
        (e_hand - e_cont).abs() < 1e-12 * e_hand,
        "{e_hand} vs {e_cont}"
    );
}

/// `p = ∂L/∂v` and `E = ⟨p, v⟩ − L` against the closed forms of the charged particle:
/// `p = (m v + s A(q), s)` with `s = ⟨A, v⟩ + θ̇`, and `E = L` (L is quadratic in `v`); the
/// Jacobian `∂²L/∂v²` against central differences of the Legendre map (1e-7: the differences'
/// truncation error).
#[test]
fn legendre_map_and_energy_match_closed_forms() {
    let sys = ChargedParticleContinuous {
        m: 1.3,
        b0: 0.7,
        h: 0.1,
    };
    let q = SVector::from([0.3, -0.8, 0.5, 2.0]);
    let v = SVector::from([0.4, 1.1, -0.6, 0.9]);
    let a = [-0.5 * sys.b0 * q[1], 0.5 * sys.b0 * q[0]];
    let s = a[0] * v[0] + a[1] * v[1] + v[3];
    let p = sys.legendre(&q, &v);
    let expect = [
        sys.m * v[0] + s * a[0],
        sys.m * v[1] + s * a[1],
        sys.m * v[2],
        s,
    ];
    for i in 0..4 {
        assert!(
            (p[i] - expect[i]).abs() < 1e-14,
            "p[{i}] = {} vs {}",
            p[i],
            expect[i]
        );
    }
    let l = sys.continuous_lagrangian(&q, &v);
    assert!((l - (0.5 * sys.m * v.fixed_rows::<3>(0).norm_squared() + 0.5 * s * s)).abs() < 1e-14);
    assert!((sys.energy(&q, &v) - l).abs() < 1e-14);
    let (p2, jac) = sys.legendre_jacobian(&q, &v);
    assert_eq!(p, p2);
    let eps = 1e-6;
    for j in 0..4 {
        let mut e = SVector::<f64, 4>::zeros();
        e[j] = eps;
        let col = (sys.legendre(&q, &(v + e)) - sys.legendre(&q, &(v - e))) / (2.0 * eps);
        for i in 0..4 {
            assert!((jac[(i, j)] - col[i]).abs() < 1e-7, "({i}, {j})");
        }
    }
}

/// The paper's initial state of §7.1, `w0 = (1, 0, 1)`, `μ0 = 1` at `q = 0`, is the trivialized
/// (3.6) Legendre image of the velocity `q̇ = (1, 0, 1)`, `θ̇ = 1`.
#[test]
fn initial_state_from_positions_and_velocities() {
    let sys = ChargedParticleContinuous::paper(200);
    let state: ReducedState<3, 1> = sys
        .reduced_state(SVector::zeros(), SVector::from([1.0, 0.0, 1.0, 1.0]))
        .unwrap();
    assert_eq!(state, ChargedParticle::paper_initial_state());
    let c = sys
        .unreduced_state(SVector::zeros(), SVector::from([1.0, 0.0, 1.0, 1.0]))
        .unwrap();
    assert_eq!(sys.trivialize(&c), state);
}

/// The Legendre map inverted by Newton returns the velocity it was given (1e-12 relative).
#[test]
fn velocity_from_momentum_inverts_the_legendre_map() {
    let sys = DoubleSphericalPendulumContinuous::paper();
    let q = SVector::from([2.25, 2.0, 3.0, 0.3]);
    let v = SVector::from([0.01, -0.02, 0.015, 0.005]);
    let p = sys.legendre(&q, &v);
    let back = sys.velocity(0, &q, &p, SVector::zeros()).unwrap();
    assert!((back - v).amax() < 1e-12 * v.amax(), "{back} vs {v}");
}

/// The continuous energy along the paper's double-spherical-pendulum run: at nodes (from the
/// discrete momenta through the inverse Legendre map) and at midpoints it stays within 1e-4
/// relative of its initial value over 2,000 steps — the bounded O(h²) oscillation of a
/// variational integrator — and the nodes of the reduced and unreduced runs give the same values.
#[test]
fn continuous_energy_along_a_trajectory() {
    let sys = DoubleSphericalPendulumContinuous::paper();
    let initial = DoubleSphericalPendulum::paper_initial_state();
    let reduced = ReducedIntegrator::plus(sys, NewtonOptions::default())
        .run(initial)
        .steps(2000)
        .collect()
        .unwrap();
    let e = reduced_continuous_energies(&sys, &reduced).unwrap();
    assert_eq!(e.nodes.len(), 2001);
    assert_eq!(e.midpoints.len(), 2000);
    let e0 = e.nodes[0];
    let spread = |v: &[f64]| v.iter().map(|x| (x - e0).abs()).fold(0.0, f64::max) / e0.abs();
    let (nodes, mids) = (spread(&e.nodes), spread(&e.midpoints));
    eprintln!("DSP continuous energy: node spread {nodes:e}, midpoint spread {mids:e} (E0 = {e0})");
    assert!(nodes < 1e-4 && mids < 1e-4, "{nodes:e} {mids:e}");
    let unreduced = UnreducedIntegrator::new(sys, NewtonOptions::default())
        .run(sys.untrivialize(&initial))
        .steps(2000)
        .collect()
        .unwrap();
    let u = continuous_energies(&sys, &unreduced).unwrap();
    let diff = e
        .nodes
        .iter()
        .zip(&u.nodes)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(diff < 1e-9 * e0.abs(), "{diff:e}");
}

/// A particle in the plane under `V = −k/r`, polar coordinates, reduced by rotations.
#[reduced_lagrangian(shape(r), group(theta), rule = trapezoid, name = TrapezoidContinuous)]
fn central_trapezoid(q: Config, v: Velocity, m: f64, k: f64) -> f64 {
    0.5 * m * (v.r * v.r + q.r * q.r * v.theta * v.theta) + k / q.r
}

/// The trapezoidal rule of [`central_trapezoid`], written out by hand.
#[reduced_lagrangian(shape(r), group(theta), name = TrapezoidByHand)]
fn central_trapezoid_by_hand(q0: Config, q1: Config, h: f64, m: f64, k: f64) -> f64 {
    let (vr, vt) = ((q1.r - q0.r) / h, (q1.theta - q0.theta) / h);
    let l0 = 0.5 * m * (vr * vr + q0.r * q0.r * vt * vt) + k / q0.r;
    let l1 = 0.5 * m * (vr * vr + q1.r * q1.r * vt * vt) + k / q1.r;
    0.5 * h * (l0 + l1)
}

#[reduced_lagrangian(shape(r), group(theta), rule = right, name = RightContinuous)]
fn central_right(q: Config, v: Velocity, m: f64, k: f64) -> f64 {
    0.5 * m * (v.r * v.r + q.r * q.r * v.theta * v.theta) + k / q.r
}

/// The right-point rule of [`central_right`], written out by hand.
#[reduced_lagrangian(shape(r), group(theta), name = RightByHand)]
fn central_right_by_hand(q0: Config, q1: Config, h: f64, m: f64, k: f64) -> f64 {
    let (vr, vt) = ((q1.r - q0.r) / h, (q1.theta - q0.theta) / h);
    h * (0.5 * m * (vr * vr + q1.r * q1.r * vt * vt) + k / q1.r)
}

/// The trapezoidal and right-point rules formed on the graph are the hand-written ones node for
/// node: the same generated code and the same steps, bit for bit, over 500 steps of an
/// eccentric orbit.
#[test]
fn trapezoid_and_right_rules_are_bit_for_bit_the_hand_written() {
    assert_eq!(TrapezoidContinuous::GENERATED, TrapezoidByHand::GENERATED);
    assert_eq!(RightContinuous::GENERATED, RightByHand::GENERATED);
    let (m, k, h) = (1.0, 1.0, 0.01);
    let initial = ReducedState::new([1.0], [0.0], [0.8], [0.0]);
    let opts = NewtonOptions::default();
    let a = ReducedIntegrator::plus(TrapezoidContinuous { m, k, h }, opts)
        .run(initial)
        .steps(500)
        .collect();
    let b = ReducedIntegrator::plus(TrapezoidByHand { h, m, k }, opts)
        .run(initial)
        .steps(500)
        .collect();
    assert_eq!(a.unwrap().states, b.unwrap().states);
    let a = ReducedIntegrator::plus(RightContinuous { m, k, h }, opts)
        .run(initial)
        .steps(500)
        .collect();
    let b = ReducedIntegrator::plus(RightByHand { h, m, k }, opts)
        .run(initial)
        .steps(500)
        .collect();
    assert_eq!(a.unwrap().states, b.unwrap().states);
    assert!(TrapezoidContinuous::RULE.starts_with("the trapezoidal rule"));
}
