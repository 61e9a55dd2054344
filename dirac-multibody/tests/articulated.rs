//! The recursive step of a fixed-base tree against the model's own mechanics (its energies and
//! mass matrix, evaluated by other code), a tight solve of the joint-space equations of motion,
//! and its own guarantees: the typed errors, order 2 and the iteration count.

use dirac_multibody::nalgebra::{DMatrix, DVector, Matrix3, Vector3};
use dirac_multibody::{ArticulatedIntegrator, Inertial, JointSpec, Model, ModelError, Pose};
use dirac_runtime::prelude::*;

/// A chain of `n` rods hinged alternately about `y` and `x` (so that it swings in 3-D), with
/// a slider about `z` as the third joint when `slide` (a prismatic joint in the tree).
fn chain(n: usize, slide: bool) -> Model {
    let rod = Inertial::new(
        1.0,
        Vector3::new(0.01, 0.0, -0.25),
        Matrix3::new(0.02, 0.001, 0.0, 0.001, 0.021, 0.0, 0.0, 0.0, 0.004),
    );
    let mut b = Model::builder().frame("l0");
    for i in 1..=n {
        let axis = if i % 2 == 1 {
            Vector3::y()
        } else {
            Vector3::x()
        };
        let at = Pose::from_translation(Vector3::new(0.0, 0.0, if i == 1 { 0.0 } else { -0.5 }));
        let (parent, child) = (format!("l{}", i - 1), format!("l{i}"));
        let joint = if slide && i == 3 {
            JointSpec::prismatic(format!("j{i}"), parent, child, Vector3::z())
        } else {
            JointSpec::revolute(format!("j{i}"), parent, child, axis)
        };
        b = b.body(format!("l{i}"), rod).joint(joint.at(at));
    }
    b.build().expect("a chain is a tree")
}

/// A tree: a trunk with two branches of two links each.
fn tree() -> Model {
    let rod = Inertial::new(
        0.7,
        Vector3::new(0.0, 0.02, -0.2),
        Matrix3::from_diagonal(&Vector3::new(0.015, 0.012, 0.003)),
    );
    let down = Pose::from_translation(Vector3::new(0.0, 0.0, -0.4));
    let spec = |name: &str, parent: &str, axis: Vector3<f64>, at: Pose| {
        JointSpec::revolute(name, parent, name.replace('j', "b"), axis).at(at)
    };
    Model::builder()
        .frame("b0")
        .body("b1", rod)
        .body("b2", rod)
        .body("b3", rod)
        .body("b4", rod)
        .body("b5", rod)
        .joint(spec("j1", "b0", Vector3::y(), Pose::identity()))
        .joint(spec("j2", "b1", Vector3::x(), down))
        .joint(spec("j3", "b2", Vector3::y(), down))
        .joint(spec(
            "j4",
            "b1",
            Vector3::new(0.0, 0.6, 0.8),
            Pose::from_translation(Vector3::new(0.1, 0.0, -0.4)),
        ))
        .joint(spec("j5", "b4", Vector3::z(), down))
        .build()
        .expect("a tree")
}

/// `L(q, v) = T − V` by the model's own functions.
fn lagrangian(model: &Model, q: &[f64], v: &[f64]) -> f64 {
    let c = model.configuration_from_scalars(q).unwrap();
    model.kinetic_energy(&c, v).unwrap() - model.potential_energy(&c).unwrap()
}

fn mass(model: &Model, q: &[f64]) -> DMatrix<f64> {
    model
        .mass_matrix(&model.configuration_from_scalars(q).unwrap())
        .unwrap()
}

/// `∂L/∂q` by central differences of the model's `T − V`.
fn lagrangian_q(model: &Model, q: &[f64], v: &[f64]) -> DVector<f64> {
    let eps = 1e-6;
    DVector::from_fn(q.len(), |j, _| {
        let (mut a, mut b) = (q.to_vec(), q.to_vec());
        a[j] += eps;
        b[j] -= eps;
        (lagrangian(model, &a, v) - lagrangian(model, &b, v)) / (2.0 * eps)
    })
}

fn inf(v: &DVector<f64>) -> f64 {
    v.amax()
}

/// One step's momenta are the discrete Legendre transforms of the midpoint rule, evaluated by
/// other code: `(p_k + p_{k+1})/2 = L_v = M(q̄) v` and `(p_{k+1} − p_k)/h = L_q + τ` at
/// `q̄ = (q_k + q_{k+1})/2`, `v = (q_{k+1} − q_k)/h`.
#[test]
fn a_step_is_the_midpoint_rule_of_the_models_lagrangian() {
    for (model, name) in [(chain(6, true), "chain"), (tree(), "tree")] {
        let n = model.joints().len();
        let h = 0.01;
        let integ = ArticulatedIntegrator::new(&model, h, NewtonOptions::default()).unwrap();
        let q: Vec<f64> = (0..n).map(|j| 0.3 * (j as f64 + 1.0).sin()).collect();
        let v: Vec<f64> = (0..n).map(|j| 0.8 * (2.0 * j as f64 + 0.5).cos()).collect();
        let start = integ.state(&q, &v).unwrap();
        // The continuous Legendre transform: p = M(q) v.
        let mv = mass(&model, &q) * DVector::from_column_slice(&v);
        assert!(inf(&(&start.p - &mv)) < 1e-12, "{name}: p = M v");
        let tau: Vec<f64> = (0..n).map(|j| 0.5 - 0.2 * j as f64).collect();
        let traj = integ
            .run(start.clone())
            .steps(1)
            .controls(ControlSequence::flat(&tau, n))
            .collect()
            .unwrap();
        let next = traj.last();
        let qbar: Vec<f64> = (0..n).map(|j| 0.5 * (q[j] + next.q[j])).collect();
        let rate: Vec<f64> = (0..n).map(|j| (next.q[j] - q[j]) / h).collect();
        let lv = mass(&model, &qbar) * DVector::from_column_slice(&rate);
        let mean = (&start.p + &next.p) / 2.0;
        assert!(inf(&(&mean - &lv)) < 1e-11, "{name}: (p0 + p1)/2 = M(q̄) v");
        let lq = lagrangian_q(&model, &qbar, &rate) + DVector::from_column_slice(&tau);
        let change = (&next.p - &start.p) / h;
        let gap = inf(&(&change - &lq));
        assert!(
            gap < 1e-6 * inf(&lq).max(1.0),
            "{name}: (p1 − p0)/h = L_q + τ, gap {gap:e}"
        );
    }
}

/// The velocity and the energy of a state: `v = M⁻¹ p`, `E = T + V` by the model.
#[test]
fn velocity_and_energy_are_the_models() {
    let model = tree();
    let integ = ArticulatedIntegrator::new(&model, 0.01, NewtonOptions::default()).unwrap();
    let q = [0.2, -0.4, 0.9, 0.1, -1.3];
    let p = DVector::from_column_slice(&[0.3, -0.1, 0.05, 0.2, -0.02]);
    let state = ElementState::new(DVector::from_column_slice(&q), p.clone());
    let v = integ.velocity(&state).unwrap();
    let m = mass(&model, &q);
    let expected = m.clone().lu().solve(&p).unwrap();
    assert!(inf(&(&v - &expected)) < 1e-12);
    let c = model.configuration_from_scalars(&q).unwrap();
    let e = model.kinetic_energy(&c, v.as_slice()).unwrap() + model.potential_energy(&c).unwrap();
    assert!((integ.energy(&state).unwrap() - e).abs() < 1e-12);
}

/// The joint-space equations of motion `M(q) q̈ = L_q − (∂(M v)/∂q) v + τ`, each term from the
/// model (its mass matrix and, by central differences, its Lagrangian), solved by RK4 at a step
/// small enough that its error is below the differences' round-off.
fn rate(model: &Model, y: &[f64]) -> Vec<f64> {
    let n = y.len() / 2;
    let (q, v) = (&y[..n], &y[n..]);
    let eps = 1e-6;
    let vv = DVector::from_column_slice(v);
    let (mut a, mut b) = (q.to_vec(), q.to_vec());
    for j in 0..n {
        a[j] += eps * v[j];
        b[j] -= eps * v[j];
    }
    let mdot_v = (mass(model, &a) - mass(model, &b)) * &vv / (2.0 * eps);
    let rhs = lagrangian_q(model, q, v) - mdot_v;
    let acc = mass(model, q).lu().solve(&rhs).unwrap();
    v.iter().copied().chain(acc.iter().copied()).collect()
}

fn rk4(model: &Model, mut y: Vec<f64>, t: f64, steps: usize) -> Vec<f64> {
    let h = t / steps as f64;
    let add = |y: &[f64], k: &[f64], c: f64| -> Vec<f64> {
        y.iter().zip(k).map(|(a, b)| a + c * b).collect()
    };
    for _ in 0..steps {
        let k1 = rate(model, &y);
        let k2 = rate(model, &add(&y, &k1, h / 2.0));
        let k3 = rate(model, &add(&y, &k2, h / 2.0));
        let k4 = rate(model, &add(&y, &k3, h));
        for i in 0..y.len() {
            y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
    }
    y
}

/// The chain's joint angles converge at order 2 to the solution of its equations of motion.
#[test]
fn the_chain_is_of_order_two_against_its_equations_of_motion() {
    let model = chain(3, false);
    let (q0, v0) = ([0.6, -0.3, 0.4], [0.0, 0.5, -0.2]);
    let t = 0.4;
    let y0: Vec<f64> = q0.iter().chain(&v0).copied().collect();
    let reference = rk4(&model, y0, t, 400);
    let errors: Vec<f64> = [20, 40, 80]
        .iter()
        .map(|&steps| {
            let h = t / steps as f64;
            let integ = ArticulatedIntegrator::new(&model, h, NewtonOptions::default()).unwrap();
            let traj = integ
                .run(integ.state(&q0, &v0).unwrap())
                .steps(steps)
                .collect()
                .unwrap();
            let q = &traj.last().q;
            (0..3)
                .map(|j| (q[j] - reference[j]).abs())
                .fold(0.0, f64::max)
        })
        .collect();
    for pair in errors.windows(2) {
        let order = (pair[0] / pair[1]).log2();
        assert!((order - 2.0).abs() < 0.1, "order {order} from {errors:?}");
    }
}

/// Without torques and forces the energy error stays bounded over a long run, and a long chain
/// needs few corrections a step.
#[test]
fn a_long_chain_keeps_its_energy_with_few_corrections() {
    let model = chain(60, false);
    let integ = ArticulatedIntegrator::new(&model, 1e-3, NewtonOptions::default()).unwrap();
    let q: Vec<f64> = (0..60).map(|j| if j == 0 { 0.8 } else { 0.02 }).collect();
    let start = integ.state(&q, &vec![0.0; 60]).unwrap();
    let e0 = integ.energy(&start).unwrap();
    let traj = integ.run(start).steps(400).collect().unwrap();
    let worst = traj
        .states
        .iter()
        .step_by(20)
        .map(|s| (integ.energy(s).unwrap() - e0).abs())
        .fold(0.0, f64::max);
    // The chain's energy scale is its weight times its length, about 60 · 9.81 · 15 J.
    assert!(worst < 1e-4 * 9000.0, "energy error {worst:e}");
    let mean = traj.stats.mean_iterations();
    assert!(mean <= 3.0, "mean corrections {mean}");
}

/// Compositions raise the order: the triple jump of the same step is of order 4.
#[test]
fn the_triple_jump_of_the_recursive_step_is_of_order_four() {
    let model = chain(3, true);
    let (q0, v0) = ([0.6, -0.3, 0.1], [0.0, 0.5, -0.2]);
    let t = 0.4;
    let fine = {
        let integ =
            ArticulatedIntegrator::new(&model, t / 640.0, NewtonOptions::default()).unwrap();
        let c = Composition::new(integ, CompositionMethod::TRIPLE_JUMP);
        let start = c.base().state(&q0, &v0).unwrap();
        c.run(start).steps(640).collect().unwrap().last().q.clone()
    };
    let errors: Vec<f64> = [10, 20, 40]
        .iter()
        .map(|&steps| {
            let integ =
                ArticulatedIntegrator::new(&model, t / steps as f64, NewtonOptions::default())
                    .unwrap();
            let c = Composition::new(integ, CompositionMethod::TRIPLE_JUMP);
            let start = c.base().state(&q0, &v0).unwrap();
            let q = c
                .run(start)
                .steps(steps)
                .collect()
                .unwrap()
                .last()
                .q
                .clone();
            inf(&(q - &fine))
        })
        .collect();
    for pair in errors.windows(2) {
        let order = (pair[0] / pair[1]).log2();
        assert!((order - 4.0).abs() < 0.2, "order {order} from {errors:?}");
    }
}

#[test]
fn bad_input_is_a_typed_error() {
    // A spherical joint is refused, naming the joint.
    let ball = Model::builder()
        .frame("world")
        .body(
            "bob",
            Inertial::new(
                1.0,
                Vector3::new(0.0, 0.0, -1.0),
                Matrix3::identity() * 0.01,
            ),
        )
        .joint(JointSpec::spherical("ball", "world", "bob"))
        .build()
        .unwrap();
    match ArticulatedIntegrator::new(&ball, 0.01, NewtonOptions::default()) {
        Err(ModelError::Unsupported { joint, .. }) => assert_eq!(joint, "ball"),
        other => panic!("{other:?}"),
    }
    let model = chain(4, false);
    let integ = ArticulatedIntegrator::new(&model, 0.01, NewtonOptions::default()).unwrap();
    assert!(integ.state(&[0.0; 3], &[0.0; 4]).is_err());
    assert!(integ.state(&[0.0, f64::NAN, 0.0, 0.0], &[0.0; 4]).is_err());
    // Controls of the wrong number, a state of the wrong size, a non-finite start.
    let start = integ.state(&[0.1; 4], &[0.0; 4]).unwrap();
    let err = integ
        .run(start.clone())
        .steps(3)
        .controls(ControlSequence::flat(&[0.0; 9], 3))
        .collect()
        .unwrap_err();
    assert!(matches!(
        err.source,
        StepError::InvalidControls {
            expected: 4,
            found: 3,
            ..
        }
    ));
    let small = ElementState::new(DVector::zeros(3), DVector::zeros(3));
    assert!(matches!(
        integ.run(small).steps(1).collect().unwrap_err().source,
        StepError::InvalidSize { .. }
    ));
    let mut bad = start.clone();
    bad.p[2] = f64::INFINITY;
    assert!(matches!(
        integ.run(bad).steps(1).collect().unwrap_err().source,
        StepError::NonFinite { step: 0, .. }
    ));
    // A step that cannot converge keeps the states before it.
    let options = NewtonOptions {
        max_iterations: 1,
        ..NewtonOptions::default()
    };
    let tight = ArticulatedIntegrator::new(&model, 0.05, options).unwrap();
    let fast = tight.state(&[0.1; 4], &[30.0, -30.0, 30.0, -30.0]).unwrap();
    let err = tight.run(fast).steps(50).collect().unwrap_err();
    assert!(
        matches!(err.source, StepError::NotConverged { .. }),
        "{:?}",
        err.source
    );
    assert_eq!(err.trajectory.states.len(), err.trajectory.stats.len() + 1);
}
