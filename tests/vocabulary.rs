//! One vocabulary for every integrator: states built from arrays, nalgebra vectors or slices
//! alike; momentum maps and energies reached as methods of the integrator, for fixed and
//! run-time sizes and for constrained runs, checked against closed forms computed here; the
//! derivative of a step as one type.

// The constructors are called with borrowed arguments on purpose: accepting them is the point.
#![allow(clippy::needless_borrows_for_generic_args)]

use dirac::nalgebra::{DVector, SVector};
use dirac::prelude::*;
use dirac::runtime::{DiscreteLagrangian, ReducedConstrainedIntegrator};

/// A particle on a line with a spring (`x`) and free along `z`: `E = |p|²/2m + x²/2`.
#[reduced_lagrangian(shape(x), group(z), rule = midpoint)]
fn slider(q: Config, v: Velocity, m: f64) -> f64 {
    0.5 * m * (v.x * v.x + v.z * v.z) - 0.5 * q.x * q.x
}

/// A bead on a vertical cylinder of radius `r`, with a spring in `x`: translating `z` is a
/// symmetry the constraint respects. `E = |p|²/2m + (x − 0.3)²/2`.
#[reduced_lagrangian(shape(x, y), group(z), rule = midpoint,
    constraints = |q| [q.x * q.x + q.y * q.y - r * r])]
fn bead(q: Config, v: Velocity, m: f64, r: f64) -> f64 {
    0.5 * m * (v.x * v.x + v.y * v.y + v.z * v.z) - 0.5 * (q.x - 0.3) * (q.x - 0.3)
}

/// A chain of `n` unit masses with unit springs, sized at run time; translating every `x[i]`
/// is a symmetry with momentum map `Σ p_i`.
#[reduced_lagrangian(coordinates(x[n]), translate(x), rule = midpoint)]
fn chain(q: Config, v: Velocity, n: usize) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        l += 0.5 * v.x[i] * v.x[i];
    }
    for i in 0..n - 1 {
        l -= 0.5 * (q.x[i + 1] - q.x[i]) * (q.x[i + 1] - q.x[i]);
    }
    l
}

/// A ring of `n` particles with gyroscopic coupling, sized at run time: the momentum
/// `p_i = m v_i + b (q_{i−1} − q_{i+1})` depends on the positions, and the energy
/// `E = Σ ½ m v_i² + Σ ½ (q_{i+1} − q_i)²` does not see the coupling.
#[reduced_lagrangian(coordinates(x[n]), rule = midpoint)]
fn ring(q: Config, v: Velocity, m: f64, b: f64, n: usize) -> f64 {
    let mut l = 0.0;
    for i in 0..n {
        let j = (i + 1) % n;
        l += 0.5 * m * v.x[i] * v.x[i] + b * (q.x[i] * v.x[j] - q.x[j] * v.x[i])
            - 0.5 * (q.x[j] - q.x[i]).powi(2);
    }
    l
}

/// A smooth schedule of step sizes between `h/2` and `3h/2`.
fn smooth<S>(h: f64) -> impl FnMut(usize, f64, &S) -> f64 + Clone {
    move |_, t, _| h * (1.0 + 0.5 * (3.0 * t).sin())
}

fn close(a: f64, b: f64, what: &str) {
    assert!(
        (a - b).abs() <= 1e-12 * (1.0 + b.abs()),
        "{what}: {a} vs {b}"
    );
}

#[test]
fn states_from_arrays_vectors_and_slices_are_the_same_state() {
    let (q, p) = ([0.1, -0.2, 0.3], [1.0, 2.0, -3.0]);
    let a = UnreducedState::new(q, p);
    assert_eq!(a, UnreducedState::new(&q, &p));
    assert_eq!(a, UnreducedState::new(SVector::from(q), SVector::from(p)));
    assert_eq!(a, UnreducedState::new(&SVector::from(q), p));
    assert_eq!((a.q[2], a.p[1]), (0.3, 2.0));
    let r = ReducedState::new([0.5, 0.25], [1.0, -1.0], [2.0], [0.125]);
    assert_eq!(
        r,
        ReducedState::new(
            SVector::from([0.5, 0.25]),
            &SVector::from([1.0, -1.0]),
            SVector::from([2.0]),
            &[0.125]
        )
    );
    let e = ElementState::new(vec![1.0, 2.0], [3.0, 4.0]);
    assert_eq!(e, ElementState::new(&[1.0, 2.0][..], &[3.0, 4.0]));
    assert_eq!(
        e,
        ElementState::new(DVector::from_vec(vec![1.0, 2.0]), &e.p)
    );
    let sys = Slider { h: 0.1, m: 2.0 };
    assert_eq!(
        sys.reduced_state::<1, 1>([0.5, 0.0], [1.0, 2.0]),
        sys.reduced_state::<1, 1>(SVector::from([0.5, 0.0]), &SVector::from([1.0, 2.0]))
    );
    // The order of q and v is the system's SHAPE followed by its GROUP.
    assert_eq!((Slider::SHAPE, Slider::GROUP), (["x"], ["z"]));
    let c = sys.unreduced_state([0.5, 0.0], [1.0, 2.0]).unwrap();
    assert_eq!((c.p[0], c.p[1]), (2.0, 4.0));
    // A state from a position and velocity is a `Result`: what is not finite is a typed error,
    // never a state that carries a NaN into a run.
    assert!(matches!(
        sys.unreduced_state([f64::NAN, 0.0], [1.0, 2.0]),
        Err(StepError::NonFinite { step: 0, .. })
    ));
    assert!(matches!(
        sys.reduced_state::<1, 1>([0.5, 0.0], [f64::INFINITY, 2.0]),
        Err(StepError::NonFinite { step: 0, .. })
    ));
    // Every integrator's momentum map is a `Result`, as the run-time-sized ones' are.
    let mut off = sys.reduced_state::<1, 1>([0.5, 0.0], [1.0, 2.0]).unwrap();
    let reduced = ReducedIntegrator::plus(sys, NewtonOptions::default());
    assert_eq!(reduced.momentum_map(&off), Ok(off.mu));
    off.mu[0] = f64::NAN;
    assert!(matches!(
        reduced.momentum_map(&off),
        Err(StepError::NonFinite { .. })
    ));
    let unreduced = UnreducedIntegrator::new(sys, NewtonOptions::default());
    assert!(matches!(
        unreduced.momentum_map(&sys.untrivialize(&off)),
        Err(StepError::NonFinite { .. })
    ));
}

#[test]
fn reduced_and_unreduced_integrators_give_momentum_maps_and_energies() {
    let (h, m) = (0.1, 2.0);
    let sys = Slider { h, m };
    let energy =
        |q: &SVector<f64, 2>, p: &SVector<f64, 2>| p.norm_squared() / (2.0 * m) + 0.5 * q[0] * q[0];
    let s0 = sys.reduced_state::<1, 1>([0.5, 0.0], [0.3, 0.7]).unwrap();
    let reduced = ReducedIntegrator::plus(sys, NewtonOptions::default());
    let unreduced = UnreducedIntegrator::new(sys, NewtonOptions::default());
    let traj = reduced
        .run(s0)
        .end_time(3.05)
        .schedule(smooth(h))
        .collect()
        .unwrap();
    let utraj = unreduced
        .run(sys.untrivialize(&s0))
        .end_time(3.05)
        .schedule(smooth(h))
        .collect()
        .unwrap();
    let (re, ue) = (
        reduced.energies(&traj).unwrap(),
        unreduced.energies(&utraj).unwrap(),
    );
    assert_eq!(
        (re.nodes.len(), re.midpoints.len()),
        (traj.states.len(), traj.step_count())
    );
    for (k, s) in traj.states.iter().enumerate() {
        let c = sys.untrivialize(s);
        assert_eq!(
            reduced.momentum_map(s).unwrap()[0].to_bits(),
            s0.mu[0].to_bits()
        );
        close(
            unreduced.momentum_map(&c).unwrap()[0],
            c.p[1],
            "unreduced μ",
        );
        close(re.nodes[k], energy(&c.q, &c.p), "reduced node energy");
        let u = &utraj.states[k];
        close(ue.nodes[k], energy(&u.q, &u.p), "unreduced node energy");
    }
    // Midpoint energies use each step's own size t_{k+1} − t_k (the schedule varies it).
    for k in 0..traj.step_count() {
        let (a, b) = (
            sys.untrivialize(&traj.states[k]),
            sys.untrivialize(&traj.states[k + 1]),
        );
        let hk = traj.times[k + 1] - traj.times[k];
        let (qm, v) = (0.5 * (a.q + b.q), (b.q - a.q) / hk);
        close(
            re.midpoints[k],
            0.5 * m * v.norm_squared() + 0.5 * qm[0] * qm[0],
            "midpoint",
        );
    }
    assert!(
        traj.step_sizes[0] != traj.step_sizes[5],
        "the schedule varies the step"
    );
}

#[test]
fn constrained_integrators_give_momentum_maps_and_energies_on_both_forms() {
    let sys = Bead {
        h: 0.02,
        m: 1.2,
        r: 0.8,
    };
    let energy = |q: &SVector<f64, 3>, p: &SVector<f64, 3>| {
        p.norm_squared() / 2.4 + 0.5 * (q[0] - 0.3).powi(2)
    };
    let c0 = UnreducedState::new([0.8, 0.0, 0.0], [0.0, 0.5, 0.7]);
    let unreduced = ConstrainedIntegrator::new(sys, NewtonOptions::default());
    let reduced = ReducedConstrainedIntegrator::plus(sys, NewtonOptions::default());
    let ut = unreduced.run(c0).steps(200).collect().unwrap();
    let rt = reduced
        .run(sys.trivialize(&c0))
        .steps(200)
        .collect()
        .unwrap();
    let (ue, re) = (
        unreduced.energies(&ut).unwrap(),
        reduced.energies(&rt).unwrap(),
    );
    for k in 0..=200 {
        let (u, r) = (&ut.states[k], sys.untrivialize(&rt.states[k]));
        close(
            ue.nodes[k],
            energy(&u.q, &u.p),
            "unreduced constrained node energy",
        );
        close(
            re.nodes[k],
            energy(&r.q, &r.p),
            "reduced constrained node energy",
        );
        close(unreduced.momentum_map(u).unwrap()[0], 0.7, "unreduced p_z");
        assert_eq!(
            reduced.momentum_map(&rt.states[k]).unwrap()[0].to_bits(),
            0.7f64.to_bits()
        );
    }
    // Both forms integrate the same equations: their energies agree to round-off.
    close(ue.midpoints[199], re.midpoints[199], "forms agree");
}

#[test]
fn element_integrators_give_momentum_maps_and_midpoint_energies() {
    let n = 12;
    let sys = Chain { h: 0.05, n };
    let q: Vec<f64> = (0..n).map(|i| i as f64 + 0.1 * (i as f64).sin()).collect();
    let p: Vec<f64> = (0..n).map(|i| 0.2 * (0.7 * i as f64).cos()).collect();
    let s0 = ElementState::new(&q[..], &p[..]);
    let integ = ElementIntegrator::new(sys, NewtonOptions::default());
    let traj = integ
        .run(s0.clone())
        .end_time(2.0)
        .schedule(smooth(0.05))
        .collect()
        .unwrap();
    let mu0: f64 = p.iter().sum();
    for s in &traj.states {
        close(integ.momentum_map(s).unwrap()[0], mu0, "Σ p");
    }
    let mids = integ.midpoint_energies(&traj).unwrap();
    assert_eq!(mids.len(), traj.step_count());
    for (k, e) in mids.iter().enumerate() {
        let (a, b) = (&traj.states[k].q, &traj.states[k + 1].q);
        let hk = traj.times[k + 1] - traj.times[k];
        let qm = 0.5 * (a + b);
        let v = (b - a) / hk;
        let kinetic = 0.5 * v.norm_squared();
        let potential: f64 = (0..n - 1).map(|i| 0.5 * (qm[i + 1] - qm[i]).powi(2)).sum();
        close(*e, kinetic + potential, "element midpoint energy");
    }
    // Node energies through the inverse Legendre map (unit masses: v = p).
    let energies = integ.energies(&traj).unwrap();
    assert_eq!(energies.midpoints, mids);
    for (k, s) in traj.states.iter().enumerate() {
        let potential: f64 = (0..n - 1)
            .map(|i| 0.5 * (s.q[i + 1] - s.q[i]).powi(2))
            .sum();
        close(
            energies.nodes[k],
            0.5 * s.p.norm_squared() + potential,
            "element node energy",
        );
    }
    assert_eq!(integ.system().n, n);
    assert_eq!(integ.solver(), StepSolver::Auto);
}

#[test]
fn the_derivative_of_a_step_is_one_type() {
    let sys = Slider { h: 0.1, m: 2.0 };
    let integ = UnreducedIntegrator::new(sys, NewtonOptions::default());
    let a = sys.unreduced_state([0.5, 0.0], [0.3, 0.7]).unwrap();
    let (b, _) = integ.step_from(0, &a, &a.q).unwrap();
    let (c, _) = integ.step_from(1, &b, &b.q).unwrap();
    let m1: Sensitivity = integ.step_jacobian(0, &a, &b).unwrap();
    let m2 = integ.step_jacobian(1, &b, &c).unwrap();
    assert_eq!((m1.state.shape(), m1.control.ncols()), ((4, 4), 0));
    let both = m2.compose(&m1).unwrap();
    // Steps of different sizes do not compose: a typed error, not a panic in the product.
    let other = Sensitivity::from_blocks(
        &m1.dq_dq().view((0, 0), (1, 1)),
        &m1.dq_dp().view((0, 0), (1, 1)),
        &m1.dp_dq().view((0, 0), (1, 1)),
        &m1.dp_dp().view((0, 0), (1, 1)),
    );
    assert!(matches!(
        m2.compose(&other),
        Err(StepError::InvalidSize { .. })
    ));
    assert!(both.symplecticity_defect() < 1e-12);
    assert_eq!(both.state, &m2.state * &m1.state);
    // Blocks read back what from_blocks puts in.
    let rebuilt = Sensitivity::from_blocks(&m1.dq_dq(), &m1.dq_dp(), &m1.dp_dq(), &m1.dp_dp());
    assert_eq!(rebuilt, m1);
}

#[test]
fn element_node_energies_invert_a_position_dependent_legendre_map() {
    let (n, m, b) = (9, 1.5, 0.4);
    let sys = Ring { h: 0.04, m, b, n };
    let q: Vec<f64> = (0..n).map(|i| 0.3 * (1.3 * i as f64).sin()).collect();
    let p: Vec<f64> = (0..n).map(|i| 0.5 * (0.9 * i as f64).cos()).collect();
    let integ = ElementIntegrator::new(sys, NewtonOptions::default());
    let traj = integ
        .run(ElementState::new(q, p))
        .steps(50)
        .collect()
        .unwrap();
    let energies = integ.energies(&traj).unwrap();
    for (k, s) in traj.states.iter().enumerate() {
        let (q, p) = (&s.q, &s.p);
        let v: Vec<f64> = (0..n)
            .map(|i| (p[i] - b * (q[(i + n - 1) % n] - q[(i + 1) % n])) / m)
            .collect();
        let kinetic: f64 = v.iter().map(|v| 0.5 * m * v * v).sum();
        let potential: f64 = (0..n).map(|i| 0.5 * (q[(i + 1) % n] - q[i]).powi(2)).sum();
        close(energies.nodes[k], kinetic + potential, "ring node energy");
    }
    // The midpoint rule keeps the energy within O(h²) without drift: the nodes agree with
    // each other to that order.
    let (lo, hi) = energies
        .nodes
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &e| (a.min(e), b.max(e)));
    assert!(hi - lo < 1e-2 * hi.abs(), "{lo} .. {hi}");
}
