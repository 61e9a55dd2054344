//! Holonomic constraints of systems sized at run time: a chain of rigid links in maximal
//! coordinates against the same chain unrolled at a fixed size, multipliers, exact momentum
//! maps and typed errors.

use dirac::prelude::*;
use dirac::runtime::element::{ElementConstrainedIntegrator, ElementState};

#[path = "../examples/common/link_chain.rs"]
mod link_chain;
use link_chain::{hanging, LinkChain as Chain};

/// The chain of `link_chain` at four links, unrolled.
#[reduced_lagrangian(shape(c, x[4], y[4]), group(), rule = midpoint,
    constraints = |q| {
        let mut phi = [0.0; 4];
        phi[0] = (q.x[0] - q.c) * (q.x[0] - q.c) + q.y[0] * q.y[0] - l * l;
        for i in 1..4 {
            let (dx, dy) = (q.x[i] - q.x[i - 1], q.y[i] - q.y[i - 1]);
            phi[i] = dx * dx + dy * dy - l * l;
        }
        phi
    })]
fn chain4(q: Config, v: Velocity, mc: f64, m: f64, l: f64, gr: f64) -> f64 {
    let mut t = 0.5 * mc * v.c * v.c;
    for i in 0..4 {
        t += 0.5 * m * (v.x[i] * v.x[i] + v.y[i] * v.y[i]) - m * gr * q.y[i];
    }
    t
}

fn tight() -> NewtonOptions {
    NewtonOptions {
        abs_tol: 1e-13,
        rel_tol: 1e-13,
        ..NewtonOptions::default()
    }
}

#[test]
fn a_run_time_sized_chain_is_the_unrolled_constrained_chain() {
    let (h, mc, m, l, gr) = (0.01, 1.0, 1.0, 1.0, 9.81);
    let el = Chain {
        h,
        mc,
        m,
        l,
        gr,
        n: 4,
    };
    let start = hanging(4, l);
    let integ = ElementConstrainedIntegrator::new(el, tight());
    let steps = 300;
    let traj = integ.run(start.clone()).steps(steps).collect().unwrap();
    let fixed = ConstrainedIntegrator::new(Chain4 { h, mc, m, l, gr }, tight());
    let s9 = |v: &DVector<f64>| SVector::<f64, 9>::from_column_slice(v.as_slice());
    let reference = fixed
        .run(UnreducedState::new(s9(&start.q), s9(&start.p)))
        .steps(steps)
        .collect()
        .unwrap();
    let mut worst: f64 = 0.0;
    for k in 0..=steps {
        let (a, b) = (&traj.states[k], &reference.states[k]);
        worst = worst
            .max((s9(&a.q) - b.q).amax())
            .max((s9(&a.p) - b.p).amax());
    }
    assert!(worst <= 1e-10, "states: {worst:e}");
    // The multipliers of every step, and the constraint on every step.
    let mut worst_multiplier: f64 = 0.0;
    for (a, b) in traj.records.iter().zip(&reference.records) {
        let lambda = SVector::<f64, 4>::from_column_slice(a.lambda.as_slice());
        let nu = SVector::<f64, 4>::from_column_slice(a.nu.as_slice());
        let scale = b.lambda.amax().max(b.nu.amax()).max(1.0);
        worst_multiplier = worst_multiplier
            .max((lambda - b.lambda).amax() / scale)
            .max((nu - b.nu).amax() / scale);
    }
    assert!(
        worst_multiplier <= 1e-9,
        "multipliers: {worst_multiplier:e}"
    );
    assert!(traj.max_constraint_residual() <= 1e-11);
    assert!(traj.records.iter().all(|s| s.lambda.amax() > 0.0));
    // The energy at the nodes, from the projected momenta, and at the midpoints: near its
    // initial value, as the unrolled chain's.
    let energies = integ.energies(&traj).unwrap();
    let reference_energies = fixed.energies(&reference).unwrap();
    assert_eq!(energies.nodes.len(), steps + 1);
    let e0 = energies.nodes[0];
    for (k, (e, r)) in energies
        .nodes
        .iter()
        .zip(&reference_energies.nodes)
        .enumerate()
    {
        assert!((e - r).abs() <= 1e-8 * e0.abs(), "node {k}: {e} vs {r}");
        assert!((e - e0).abs() <= 1e-2 * e0.abs(), "node {k}: {e} from {e0}");
    }
    // The chain swings: the state moved.
    assert!((&traj.last().q - &start.q).amax() > 0.05);
}

#[test]
fn a_long_chain_keeps_its_links_and_a_start_off_the_constraints_is_a_typed_error() {
    let (h, l) = (0.01, 1.0);
    let n = 500;
    let sys = Chain {
        h,
        mc: 1.0,
        m: 1.0,
        l,
        gr: 9.81,
        n,
    };
    let integ = ElementConstrainedIntegrator::new(sys, NewtonOptions::default());
    let start = hanging(n, l);
    let phi = integ.constraint(&start.q).unwrap();
    assert_eq!(phi.len(), n);
    assert!(phi.amax() < 1e-12);
    let traj = integ.run(start.clone()).steps(50).collect().unwrap();
    assert!(
        traj.max_constraint_residual() <= 1e-8,
        "{:e}",
        traj.max_constraint_residual()
    );
    // The projected velocities are tangent: A(q_{k+1}) v = 0 with v from the momenta,
    // v_c = p_c / mc, v_i = p_i / m.
    let last = traj.last();
    let v = &last.p; // unit masses
    let (x, y) = (last.q.rows(1, n), last.q.rows(1 + n, n));
    let (vx, vy) = (v.rows(1, n), v.rows(1 + n, n));
    let mut worst: f64 = 0.0;
    for i in 1..n {
        let rate = 2.0
            * ((x[i] - x[i - 1]) * (vx[i] - vx[i - 1]) + (y[i] - y[i - 1]) * (vy[i] - vy[i - 1]));
        worst = worst.max(rate.abs());
    }
    assert!(worst <= 1e-8, "d φ/dt = {worst:e}");
    // Off the constraints.
    let mut off = start;
    off.q[3] += 0.1;
    let err = integ.run(off).steps(1).collect().unwrap_err();
    assert!(
        matches!(err.source, StepError::ConstraintViolated { .. }),
        "{}",
        err.source
    );
}

/// A free chain in the plane: no gravity, translations in `x` and `y` declared.
#[reduced_lagrangian(coordinates(x[n], y[n]), translate(x), translate(y), rule = midpoint,
    constraints = |q| {
        let mut phi = vec![0.0; n - 1];
        for i in 0..n - 1 {
            let (dx, dy) = (q.x[i + 1] - q.x[i], q.y[i + 1] - q.y[i]);
            phi[i] = dx * dx + dy * dy - l * l;
        }
        phi
    })]
fn free_chain(q: Config, v: Velocity, m: f64, l: f64, n: usize) -> f64 {
    let mut t = 0.0;
    for i in 0..n {
        t += 0.5 * m * (v.x[i] * v.x[i] + v.y[i] * v.y[i]);
    }
    t
}

#[test]
fn the_momentum_maps_of_a_free_chain_are_exact_and_its_energy_is_bounded() {
    let (n, l) = (60, 0.5);
    let sys = FreeChain {
        h: 0.01,
        m: 1.0,
        l,
        n,
    };
    let integ = ElementConstrainedIntegrator::new(sys, NewtonOptions::default());
    // A zigzag at unit link length, with a spin and a drift.
    let mut q = DVector::zeros(2 * n);
    for i in 0..n {
        q[i] = l * i as f64 * 0.8;
        q[n + i] = if i % 2 == 0 { 0.0 } else { l * 0.6 };
    }
    let p = DVector::from_fn(2 * n, |i, _| {
        0.3 * ((i * 7) as f64).sin() + if i < n { 0.2 } else { 0.0 }
    });
    let start = ElementState::new(q, p);
    let mu0 = integ.momentum_map(&start).unwrap();
    let traj = integ.run(start).steps(400).collect().unwrap();
    for s in &traj.states {
        let mu = integ.momentum_map(s).unwrap();
        for (a, b) in mu.iter().zip(&mu0) {
            assert!((a - b).abs() <= 1e-13 * b.abs().max(1.0), "{a} vs {b}");
        }
    }
    assert!(traj.max_constraint_residual() <= 1e-9);
    // The kinetic energy of the constrained motion (unit masses: p = v) stays near its value.
    let energy = |s: &ElementState| 0.5 * s.p.norm_squared();
    let e: Vec<f64> = traj.states.iter().skip(1).map(energy).collect();
    let (lo, hi) = e
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &x| (a.min(x), b.max(x)));
    assert!((hi - lo) / hi <= 1e-2, "energy {lo} … {hi}");
}

/// A chain whose constraint vector has a row no assignment covers.
#[reduced_lagrangian(coordinates(x[n]), rule = midpoint,
    constraints = |q| {
        let mut phi = vec![0.0; n];
        for i in 0..n - 1 {
            phi[i] = q.x[i + 1] - q.x[i] - 1.0;
        }
        phi
    })]
fn gapped(q: Config, v: Velocity, m: f64, n: usize) -> f64 {
    let mut t = 0.0;
    for i in 0..n {
        t += 0.5 * m * v.x[i] * v.x[i];
    }
    t
}

#[test]
fn a_constraint_row_left_unassigned_is_a_typed_error() {
    let sys = Gapped {
        h: 0.1,
        m: 1.0,
        n: 5,
    };
    let integ = ElementConstrainedIntegrator::new(sys, NewtonOptions::default());
    let start = ElementState::new(DVector::from_fn(5, |i, _| i as f64), DVector::zeros(5));
    let err = integ.run(start).steps(1).collect().unwrap_err();
    let message = err.source.to_string();
    assert!(
        matches!(err.source, StepError::InvalidSize { .. }) && message.contains("row 4"),
        "{message}"
    );
}

/// The cart chain with a damping force on every end point and a control force `u` on the cart.
#[reduced_lagrangian(coordinates(c, x[n], y[n]), rule = midpoint, controls(u),
    force = |dq| {
        let mut w = u * dq.c;
        for i in 0..n {
            w -= b * (v.x[i] * dq.x[i] + v.y[i] * dq.y[i]);
        }
        w
    },
    constraints = |q| {
        let mut phi = vec![0.0; n];
        phi[0] = (q.x[0] - q.c) * (q.x[0] - q.c) + q.y[0] * q.y[0] - l * l;
        for i in 1..n {
            let (dx, dy) = (q.x[i] - q.x[i - 1], q.y[i] - q.y[i - 1]);
            phi[i] = dx * dx + dy * dy - l * l;
        }
        phi
    })]
fn driven_chain(
    q: Config,
    v: Velocity,
    mc: f64,
    m: f64,
    l: f64,
    gr: f64,
    b: f64,
    u: f64,
    n: usize,
) -> f64 {
    let mut t = 0.5 * mc * v.c * v.c;
    for i in 0..n {
        t += 0.5 * m * (v.x[i] * v.x[i] + v.y[i] * v.y[i]) - m * gr * q.y[i];
    }
    t
}

/// The same, unrolled at four links.
#[reduced_lagrangian(shape(c, x[4], y[4]), group(), rule = midpoint, controls(u),
    force = |dq| {
        let mut w = u * dq.c;
        for i in 0..4 {
            w -= b * (v.x[i] * dq.x[i] + v.y[i] * dq.y[i]);
        }
        w
    },
    constraints = |q| {
        let mut phi = [0.0; 4];
        phi[0] = (q.x[0] - q.c) * (q.x[0] - q.c) + q.y[0] * q.y[0] - l * l;
        for i in 1..4 {
            let (dx, dy) = (q.x[i] - q.x[i - 1], q.y[i] - q.y[i - 1]);
            phi[i] = dx * dx + dy * dy - l * l;
        }
        phi
    })]
fn driven_chain4(q: Config, v: Velocity, mc: f64, m: f64, l: f64, gr: f64, b: f64, u: f64) -> f64 {
    let mut t = 0.5 * mc * v.c * v.c;
    for i in 0..4 {
        t += 0.5 * m * (v.x[i] * v.x[i] + v.y[i] * v.y[i]) - m * gr * q.y[i];
    }
    t
}

#[test]
fn forces_and_feedback_controls_with_constraints_are_the_unrolled_step() {
    let (h, mc, m, l, gr, b) = (0.01, 1.0, 1.0, 1.0, 9.81, 0.3);
    let el = DrivenChain {
        h,
        mc,
        m,
        l,
        gr,
        b,
        u: 0.0,
        n: 4,
    };
    let un = DrivenChain4 {
        h,
        mc,
        m,
        l,
        gr,
        b,
        u: 0.0,
    };
    let start = hanging(4, l);
    // A feedback law pushing the cart against its displacement and the first link's swing.
    let law = |c: f64, x0: f64| -4.0 * c - 2.0 * (x0 - c) + 1.0;
    let steps = 300;
    let traj = ElementConstrainedIntegrator::new(el, tight())
        .run(start.clone())
        .steps(steps)
        .feedback(|_, _, s: &ElementState, u: &mut [f64]| u[0] = law(s.q[0], s.q[1]))
        .collect()
        .unwrap();
    let s9 = |v: &DVector<f64>| SVector::<f64, 9>::from_column_slice(v.as_slice());
    let reference = ConstrainedIntegrator::new(un, tight())
        .run(UnreducedState::new(s9(&start.q), s9(&start.p)))
        .steps(steps)
        .feedback(|_, _, s: &UnreducedState<9>, u: &mut [f64]| u[0] = law(s.q[0], s.q[1]))
        .collect()
        .unwrap();
    let worst = traj
        .states
        .iter()
        .zip(&reference.states)
        .map(|(a, b)| (s9(&a.q) - b.q).amax().max((s9(&a.p) - b.p).amax()))
        .fold(0.0, f64::max);
    assert!(worst <= 1e-10, "{worst:e}");
    assert!(traj.max_constraint_residual() <= 1e-11);
    // The control moved the cart.
    assert!(traj.last().q[0].abs() > 0.01);
}

#[test]
fn the_minus_side_with_constraints_computes_the_plus_trajectory() {
    let sys = Chain {
        h: 0.01,
        mc: 1.0,
        m: 1.0,
        l: 1.0,
        gr: 9.81,
        n: 30,
    };
    let start = hanging(30, 1.0);
    let plus = ElementConstrainedIntegrator::new(sys, tight());
    let minus = ElementConstrainedIntegrator::minus(sys, tight());
    assert_eq!(minus.variant(), Variant::Minus);
    let a = plus.run(start.clone()).steps(200).collect().unwrap();
    let b = minus.run(start).steps(200).collect().unwrap();
    let mut worst: f64 = 0.0;
    for (x, y) in a.states.iter().zip(&b.states) {
        worst = worst.max((&x.q - &y.q).amax()).max((&x.p - &y.p).amax());
    }
    for (x, y) in a.records.iter().zip(&b.records) {
        worst = worst.max((&x.lambda - &y.lambda).amax() / x.lambda.amax().max(1.0));
    }
    assert!(worst <= 1e-9, "{worst:e}");
    assert!(b.max_constraint_residual() <= 1e-11);
}
