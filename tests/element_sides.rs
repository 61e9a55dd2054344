//! Run-time-sized systems on both sides: the (−) equations against the (+) ones, with
//! translations, forces, controls and compositions; the step's sensitivities; the solve chosen by
//! the pattern.

use dirac::nalgebra::DMatrix;
use dirac::prelude::*;
use dirac::runtime::element::{ElementIntegrator, ElementLagrangian};

#[path = "../examples/common/toda_n.rs"]
mod toda_n;
use toda_n::{initial, DampedTodaN, TodaN};

mod element_systems;
use element_systems::DrivenChain;

fn tight() -> NewtonOptions {
    NewtonOptions {
        abs_tol: 1e-14,
        rel_tol: 1e-14,
        ..NewtonOptions::default()
    }
}

/// The largest difference between two trajectories' states, relative to their size.
fn gap(a: &ElementTrajectory, b: &ElementTrajectory) -> f64 {
    assert_eq!(a.states.len(), b.states.len());
    a.states
        .iter()
        .zip(&b.states)
        .map(|(x, y)| {
            let scale = x.q.amax().max(x.p.amax()).max(1.0);
            (&x.q - &y.q).amax().max((&x.p - &y.p).amax()) / scale
        })
        .fold(0.0, f64::max)
}

#[test]
fn the_minus_side_computes_the_plus_trajectory_with_translations_and_forces() {
    let (m, d, h) = (1.3, 0.9, 0.05);
    let toda = TodaN { m, d, h, n: 40 };
    let start = initial(&toda, 0.3, 0.5, 0.1);
    let plus = ElementIntegrator::new(toda, tight());
    let minus = ElementIntegrator::minus(toda, tight());
    assert_eq!(minus.variant(), Variant::Minus);
    let a = plus.run(start.clone()).steps(400).collect().unwrap();
    let b = minus.run(start.clone()).steps(400).collect().unwrap();
    assert_eq!((a.variant, b.variant), (Variant::Plus, Variant::Minus));
    let g = gap(&a, &b);
    assert!(g <= 1e-12, "Toda: {g:e}");
    // The momentum map is exact on the (−) side too.
    let mu0 = minus.momentum_map(&start).unwrap()[0];
    for s in &b.states {
        let mu = minus.momentum_map(s).unwrap()[0];
        assert!(
            (mu - mu0).abs() <= 1e-13 * mu0.abs().max(1.0),
            "{mu} vs {mu0}"
        );
    }
    // With a damping force: the same trajectory, and the forced Noether balance.
    let damped = DampedTodaN {
        m,
        d,
        c: 0.2,
        h,
        n: 40,
    };
    let plus = ElementIntegrator::new(damped, tight());
    let minus = ElementIntegrator::minus(damped, tight());
    let a = plus.run(start.clone()).steps(400).collect().unwrap();
    let b = minus.run(start.clone()).steps(400).collect().unwrap();
    let g = gap(&a, &b);
    assert!(g <= 1e-12, "damped Toda: {g:e}");
    for k in 0..400 {
        let mu = |s: &ElementState| minus.momentum_map(s).unwrap()[0];
        let impulse = -0.2 * (&b.states[k + 1].q - &b.states[k].q).sum();
        let balance = mu(&b.states[k + 1]) - mu(&b.states[k]) - impulse;
        assert!(balance.abs() <= 1e-14, "step {k}: {balance:e}");
    }
}

#[test]
fn the_minus_side_computes_the_plus_trajectory_under_feedback_controls() {
    let (h, c, a) = (0.05, 0.3, 0.7);
    let chain = DrivenChain { h, c, a, n: 30 };
    let start = ElementState::new(
        DVector::from_fn(30, |i, _| 0.1 * (i as f64).sin()),
        DVector::from_fn(30, |i, _| 0.2 * (i as f64).cos()),
    );
    let law = |k: usize, _: f64, s: &ElementState, u: &mut [f64]| {
        u[0] = a * (0.05 * k as f64).cos() - 0.5 * s.q[0];
    };
    let run = |integ: ElementIntegrator<DrivenChain>| {
        integ
            .run(start.clone())
            .steps(300)
            .feedback(law)
            .collect()
            .unwrap()
    };
    let g = gap(
        &run(ElementIntegrator::new(chain, tight())),
        &run(ElementIntegrator::minus(chain, tight())),
    );
    assert!(g <= 1e-12, "{g:e}");
}

#[test]
fn compositions_of_the_minus_side_have_orders_four_and_six() {
    let (m, d) = (1.0, 0.9);
    let toda = |h: f64| TodaN { m, d, h, n: 16 };
    let start = initial(&toda(0.1), 0.6, 1.2, 0.1);
    let last = |method: CompositionMethod, steps: usize, minus: bool| {
        let sys = toda(8.0 / steps as f64);
        let integ = if minus {
            ElementIntegrator::minus(sys, tight())
        } else {
            ElementIntegrator::new(sys, tight())
        };
        let traj = Composition::new(integ, method)
            .run(start.clone())
            .steps(steps)
            .collect()
            .unwrap();
        traj.last().q.clone()
    };
    for (method, order) in [
        (CompositionMethod::TRIPLE_JUMP, 4.0),
        (CompositionMethod::KAHAN_LI_6, 6.0),
    ] {
        let same = (last(method, 20, true) - last(method, 20, false)).amax();
        assert!(same <= 1e-11, "(−) against (+): {same:e}");
        let reference = last(method, 640, true);
        let e: Vec<f64> = [20, 40, 80]
            .iter()
            .map(|&n| (last(method, n, true) - &reference).amax())
            .collect();
        let observed = (e[1] / e[2]).log2();
        assert!(
            (observed - order).abs() < 0.5,
            "order {observed} from {e:?}"
        );
    }
}

/// The step map `(q, p, u) ↦ (q', p')` of `integ`, flattened, for central differences.
fn step_map<L: ElementLagrangian>(
    integ: &ElementIntegrator<L>,
    q: &DVector<f64>,
    p: &DVector<f64>,
    u: &[f64],
) -> DVector<f64> {
    let state = ElementState::new(q.clone(), p.clone());
    let (next, _) = integ
        .step_with(
            &mut integ.workspace(),
            StepAt::new(0, integ.time_step()).with_controls(u),
            &state,
        )
        .unwrap();
    let n = q.len();
    DVector::from_fn(2 * n, |i, _| if i < n { next.q[i] } else { next.p[i - n] })
}

/// The largest entry of `a − b` relative to the largest of `b`.
fn relative(a: &DMatrix<f64>, b: &DMatrix<f64>) -> f64 {
    (a - b).amax() / b.amax().max(1e-300)
}

#[test]
fn sensitivities_match_central_differences_with_forces_and_controls() {
    let (h, c, a) = (0.05, 0.3, 0.7);
    let n = 9;
    let chain = DrivenChain { h, c, a, n };
    let integ = ElementIntegrator::new(chain, tight());
    let q = DVector::from_fn(n, |i, _| 0.1 * (i as f64).sin());
    let p = DVector::from_fn(n, |i, _| 0.2 * (i as f64).cos());
    let u = [0.4];
    let (next, _, mut sens) = integ
        .step_sensitivity(0, &ElementState::new(q.clone(), p.clone()), &u)
        .unwrap();
    assert_eq!((sens.dim(), sens.control_dim()), (n, 1));
    let dense = sens.to_dense();
    // Central differences in every state component and in the control.
    let eps = 1e-6;
    let mut fd_state = DMatrix::zeros(2 * n, 2 * n);
    for j in 0..2 * n {
        let (mut qp, mut pp, mut qm, mut pm) = (q.clone(), p.clone(), q.clone(), p.clone());
        if j < n {
            qp[j] += eps;
            qm[j] -= eps;
        } else {
            pp[j - n] += eps;
            pm[j - n] -= eps;
        }
        let d = (step_map(&integ, &qp, &pp, &u) - step_map(&integ, &qm, &pm, &u)) / (2.0 * eps);
        fd_state.set_column(j, &d);
    }
    let fd_control = (step_map(&integ, &q, &p, &[u[0] + eps])
        - step_map(&integ, &q, &p, &[u[0] - eps]))
        / (2.0 * eps);
    let e_state = relative(&dense.state, &fd_state);
    let e_control = relative(
        &dense.control,
        &DMatrix::from_column_slice(2 * n, 1, fd_control.as_slice()),
    );
    assert!(e_state <= 1e-8, "state: {e_state:e}");
    assert!(e_control <= 1e-8, "control: {e_control:e}");
    // The drive acts: the control column is not zero.
    assert!(dense.control.amax() > 1e-3);
    // The step the sensitivity was taken at is the run's first step.
    let traj = integ
        .run(ElementState::new(q, p))
        .steps(1)
        .controls(ControlSequence::rows(&[u]))
        .collect()
        .unwrap();
    assert_eq!(traj.last(), &next);
}

#[test]
fn sensitivities_equal_the_unrolled_systems_and_are_symplectic_without_forces() {
    use element_systems::DrivenChain5;
    let (h, c, a) = (0.05, 0.3, 0.7);
    let q = DVector::from_fn(5, |i, _| 0.1 * (i as f64).sin());
    let p = DVector::from_fn(5, |i, _| 0.2 * (i as f64).cos());
    let u = [0.4];
    let integ = ElementIntegrator::new(DrivenChain { h, c, a, n: 5 }, tight());
    let (next, _, mut sens) = integ
        .step_sensitivity(3, &ElementState::new(q.clone(), p.clone()), &u)
        .unwrap();
    let dense = sens.to_dense();
    let fixed = UnreducedIntegrator::new(DrivenChain5 { h, c, a }, tight());
    let s5 = |v: &DVector<f64>| SVector::<f64, 5>::from_column_slice(v.as_slice());
    let reference = fixed
        .sensitivity(
            3,
            &UnreducedState::new(s5(&q), s5(&p)),
            &UnreducedState::new(s5(&next.q), s5(&next.p)),
            &u,
        )
        .unwrap();
    let e =
        relative(&dense.state, &reference.state).max(relative(&dense.control, &reference.control));
    assert!(e <= 1e-12, "{e:e}");
    // A conservative lattice: the step is symplectic, and its momentum map is conserved to
    // first order too (Σ dp' = Σ dp for every perturbation that keeps the translation).
    let toda = TodaN {
        m: 1.3,
        d: 0.9,
        h: 0.05,
        n: 16,
    };
    let start = initial(&toda, 0.3, 0.5, 0.1);
    let integ = ElementIntegrator::minus(toda, tight());
    let (_, _, mut sens) = integ.step_sensitivity(0, &start, &[]).unwrap();
    let dense = sens.to_dense();
    assert_eq!(dense.control.ncols(), 0);
    let defect = dense.symplecticity_defect();
    assert!(defect <= 1e-12, "symplecticity defect {defect:e}");
    let dmu = DMatrix::from_fn(1, 32, |_, j| {
        (16..32).map(|i| dense.state[(i, j)]).sum::<f64>()
    });
    for j in 0..16 {
        assert!(dmu[(0, j)].abs() <= 1e-11, "∂μ'/∂q_{j} = {:e}", dmu[(0, j)]);
        assert!((dmu[(0, 16 + j)] - 1.0).abs() <= 1e-11, "∂μ'/∂p_{j}");
    }
}

#[test]
fn the_adjoint_is_the_transpose_of_the_forward_derivative_on_a_large_lattice() {
    let n = 2000;
    let damped = DampedTodaN {
        m: 1.0,
        d: 0.9,
        c: 0.1,
        h: 0.05,
        n,
    };
    let toda = TodaN {
        m: 1.0,
        d: 0.9,
        h: 0.05,
        n,
    };
    let start = initial(&toda, 0.3, 0.5, 0.1);
    let integ = ElementIntegrator::new(damped, NewtonOptions::default());
    let (_, _, mut sens) = integ.step_sensitivity(0, &start, &[]).unwrap();
    let v = |s: f64| DVector::from_fn(n, |i, _| (s * i as f64 + 0.3).sin());
    let (dq, dp, lq, lp) = (v(0.1), v(0.37), v(0.73), v(1.1));
    let (dq1, dp1) = sens.apply(&dq, &dp, &[]).unwrap();
    let (aq, ap, au) = sens.apply_transpose(&lq, &lp).unwrap();
    assert_eq!(au.len(), 0);
    let lhs = lq.dot(&dq1) + lp.dot(&dp1);
    let rhs = aq.dot(&dq) + ap.dot(&dp);
    assert!(
        (lhs - rhs).abs() <= 1e-10 * lhs.abs().max(1.0),
        "{lhs} vs {rhs}"
    );
    // Vectors of the wrong length are typed errors.
    let err = sens
        .apply(&v(0.1).rows(0, 10).into_owned(), &dp, &[])
        .unwrap_err();
    assert!(matches!(err, StepError::InvalidSize { .. }), "{err}");
    let err = sens.apply(&dq, &dp, &[1.0]).unwrap_err();
    assert!(matches!(err, StepError::InvalidSize { .. }), "{err}");
    // A direction that is not finite is a typed error, not a NaN derivative.
    let mut bad = dq.clone();
    bad[7] = f64::NAN;
    let err = sens.apply(&bad, &dp, &[]).unwrap_err();
    assert!(matches!(err, StepError::NonFinite { step: 0, .. }), "{err}");
    assert_eq!(sens.step(), 0);
    // The sparse blocks have the stencils' pattern: three entries per column for the chain.
    assert_eq!(sens.jacobian().values.len(), 3 * n);
}

#[path = "../examples/common/cluster.rs"]
mod cluster;

/// The step Jacobian's solve is chosen by the pattern's structure, and the choice does not change
/// the trajectory beyond round-off.
#[test]
fn the_solve_is_chosen_by_structure_and_the_banded_lu_gives_the_sparse_lus_trajectory() {
    // A periodic lattice: a ring, a narrow band once reordered.
    let toda = TodaN {
        m: 1.0,
        d: 0.9,
        h: 0.05,
        n: 500,
    };
    let auto = ElementIntegrator::new(toda, tight());
    assert_eq!(auto.workspace().linear_solver(), "banded LU");
    let direct = ElementIntegrator::new(toda, tight()).with_solver(StepSolver::Direct);
    assert_eq!(direct.workspace().linear_solver(), "sparse LU");
    let start = initial(&toda, 0.3, 0.5, 0.1);
    let a = auto.run(start.clone()).steps(300).collect().unwrap();
    let b = direct.run(start).steps(300).collect().unwrap();
    let g = gap(&a, &b);
    assert!(g <= 1e-11, "{g:e}");
    // Pairs: every particle coupled to every other, no narrow band; the sparse LU.
    let c = cluster::Cluster {
        m: 1.0,
        eps: 1.0,
        sigma: 1.0,
        h: 0.002,
        n: 27,
    };
    let pairs = ElementIntegrator::new(c, NewtonOptions::default());
    assert_eq!(pairs.workspace().linear_solver(), "sparse LU");
    // Forced, the banded LU takes the pairs' band however wide.
    let forced =
        ElementIntegrator::new(c, NewtonOptions::default()).with_solver(StepSolver::Banded);
    assert_eq!(forced.workspace().linear_solver(), "banded LU");
    let s = cluster::initial(&c, 1.15, 0.2);
    let x = pairs.run(s.clone()).steps(20).collect().unwrap();
    let y = forced.run(s).steps(20).collect().unwrap();
    let g = gap(&x, &y);
    assert!(g <= 1e-10, "{g:e}");
}
