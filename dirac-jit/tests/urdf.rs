//! Articulated rigid bodies from URDF, stepped through their system text
//! (`dirac_multibody::Model::system_text`, compiled by this crate): the double pendulum and the
//! planar 3-link arm against the same systems written by hand with the attribute, the
//! pendulum's order 2 against its equations of motion solved in the test, step sensitivities
//! against central differences, the 7-DoF iiwa arm, and floating bases on `SE(3)`: a free body
//! against one written by hand, a free-floating arm keeping its total momentum.
//!
//! Run with `cargo test --release --manifest-path dirac-io/Cargo.toml --target-dir target -p
//! dirac-jit --test urdf -- --nocapture` to see the figures.

// The hand-written formulas index links and joints as the equations do.
#![allow(clippy::needless_range_loop)]

use std::sync::Arc;
use std::time::Instant;

use dirac::nalgebra::{DMatrix, DVector, Matrix3, SVector, Vector3};
use dirac::prelude::*;
use dirac_jit::{Code, Compiled, Dense, JitLie, LieCode, Reduced};
use dirac_multibody::{
    Inertial, JointPosition, JointSpec, Model, Pose, SystemText, TextKind, TextOptions,
};

fn data(name: &str) -> Model {
    let path = format!("{}/../examples/data/{name}", env!("CARGO_MANIFEST_DIR"));
    Model::from_urdf_file(path).expect("the example URDF reads")
}

fn flat(text: &SystemText) -> Arc<Code> {
    assert_eq!(text.kind, TextKind::FixedBase);
    match dirac_jit::compile_any(&text.text).unwrap_or_else(|e| panic!("{e}\n{}", text.text)) {
        Compiled::Flat(code) => code,
        _ => panic!("not a system on vector spaces"),
    }
}

fn lie(text: &SystemText) -> Arc<LieCode> {
    assert_eq!(text.kind, TextKind::FloatingBase);
    match dirac_jit::compile_any(&text.text).unwrap_or_else(|e| panic!("{e}\n{}", text.text)) {
        Compiled::Lie(code) => code,
        _ => panic!("not a system on rotation groups"),
    }
}

/// The system from the model and the one written by hand, 1000 steps each from `start` at the
/// default Newton options: their trajectories.
macro_rules! both_runs {
    ($given:expr, $by_hand:expr, $start:expr) => {{
        let opts = NewtonOptions::default();
        (
            UnreducedIntegrator::new($given, opts)
                .run($start)
                .steps(1000)
                .collect()
                .unwrap(),
            UnreducedIntegrator::new($by_hand, opts)
                .run($start)
                .steps(1000)
                .collect()
                .unwrap(),
        )
    }};
}

/// The largest entry-wise gap between two unreduced trajectories, positions and momenta,
/// relative to the size of each state (at least 1).
fn gap<const N: usize>(a: &[UnreducedState<N>], b: &[UnreducedState<N>]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(a, b)| {
            let size = a.q.amax().max(a.p.amax()).max(1.0);
            (a.q - b.q).amax().max((a.p - b.p).amax()) / size
        })
        .fold(0.0, f64::max)
}

const G: f64 = 9.81;

/// The energy and the Legendre map of a system from a URDF and of one written by hand agree
/// at sample states (`|q| ≤ scale`, `|v| ≤ scale`): the two texts are the same `L`.
fn same_lagrangian<A, B, const N: usize>(
    given: &dirac_jit::JitSystem<N, 0, N, A>,
    by_hand: &B,
    scale: f64,
) where
    A: dirac_jit::Variant<N>,
    B: ContinuousLagrangian<N>,
{
    for k in 0..10 {
        let q: SVector<f64, N> = SVector::from_fn(|i, _| scale * wave(N * k + i));
        let v: SVector<f64, N> = SVector::from_fn(|i, _| scale * wave(50 + N * k + i));
        let (e, e_hand) = (given.energy(&q, &v).unwrap(), by_hand.energy(&q, &v));
        assert!(
            (e - e_hand).abs() < 1e-13 * e_hand.abs().max(1.0),
            "{e} {e_hand}"
        );
        let (p, p_hand) = (given.legendre(&q, &v).unwrap(), by_hand.legendre(&q, &v));
        assert!(
            (p - p_hand).amax() < 1e-13 * p_hand.amax().max(1.0),
            "{p} {p_hand}"
        );
    }
}

/// The double pendulum of `examples/data/double_pendulum.urdf`: rods of mass `m_i`, centre of
/// mass `a_i` below the hinge, inertia `j_i` about it, the second hinge `l1` below the first;
/// angles about `y`, so a point `a` below a hinge turned by `θ` sits at `(−a sin θ, −a cos θ)`
/// in the `x-z` plane. `T = ½ (m1 a1² + j1) θ̇1² + ½ m2 |v_c2|² + ½ j2 (θ̇1 + θ̇2)²`.
#[reduced_lagrangian(shape(shoulder, elbow), group(), rule = midpoint)]
pub fn pendulum(q: Config, v: Velocity) -> f64 {
    let (m1, a1, j1, l1, m2, a2, j2) = (1.3, 0.45, 0.11, 1.0, 0.7, 0.6, 0.08);
    let g = 9.81;
    let phi2 = q.shoulder + q.elbow;
    let w2 = v.shoulder + v.elbow;
    // The second rod's centre of mass: −l1 (sin θ1, cos θ1) − a2 (sin φ2, cos φ2).
    let vx = -l1 * q.shoulder.cos() * v.shoulder - a2 * phi2.cos() * w2;
    let vz = l1 * q.shoulder.sin() * v.shoulder + a2 * phi2.sin() * w2;
    let kinetic = 0.5 * (m1 * a1 * a1 + j1) * v.shoulder * v.shoulder
        + 0.5 * m2 * (vx * vx + vz * vz)
        + 0.5 * j2 * w2 * w2;
    let potential =
        -m1 * g * a1 * q.shoulder.cos() - m2 * g * (l1 * q.shoulder.cos() + a2 * phi2.cos());
    kinetic - potential
}

/// The planar arm of `examples/data/three_link_arm.urdf`: links along `+x` at zero angles,
/// hinges about `y`, so link `i` at the absolute angle `φ_i = θ1 + … + θi` points along
/// `(cos φ_i, −sin φ_i)` in the `x-z` plane; lengths `l`, centres of mass `a` along the
/// links, masses `m`, inertias `j` about `y` through the centres of mass; gravity `−g e_z`.
#[reduced_lagrangian(shape(joint1, joint2, joint3), group(), rule = midpoint)]
fn arm(q: Config, v: Velocity) -> f64 {
    let (l1, l2) = (0.8, 0.6);
    let (a1, a2, a3) = (0.35, 0.3, 0.15);
    let (m1, m2, m3) = (2.0, 1.5, 0.5);
    let (j1, j2, j3) = (0.12, 0.05, 0.01);
    let g = 9.81;
    let p1 = q.joint1;
    let p2 = p1 + q.joint2;
    let p3 = p2 + q.joint3;
    let w1 = v.joint1;
    let w2 = w1 + v.joint2;
    let w3 = w2 + v.joint3;
    // d/dt (cos φ, −sin φ) = −φ̇ (sin φ, cos φ).
    let (s1, c1, s2, c2, s3, c3) = (p1.sin(), p1.cos(), p2.sin(), p2.cos(), p3.sin(), p3.cos());
    let (x1, z1) = (-a1 * s1 * w1, -a1 * c1 * w1);
    let (x2, z2) = (-l1 * s1 * w1 - a2 * s2 * w2, -l1 * c1 * w1 - a2 * c2 * w2);
    let (x3, z3) = (
        -l1 * s1 * w1 - l2 * s2 * w2 - a3 * s3 * w3,
        -l1 * c1 * w1 - l2 * c2 * w2 - a3 * c3 * w3,
    );
    let kinetic = 0.5
        * (m1 * (x1 * x1 + z1 * z1) + m2 * (x2 * x2 + z2 * z2) + m3 * (x3 * x3 + z3 * z3))
        + 0.5 * (j1 * w1 * w1 + j2 * w2 * w2 + j3 * w3 * w3);
    // Heights: −a1 sin φ1, −l1 sin φ1 − a2 sin φ2, −l1 sin φ1 − l2 sin φ2 − a3 sin φ3.
    let potential =
        g * (m1 * (-a1 * s1) + m2 * (-l1 * s1 - a2 * s2) + m3 * (-l1 * s1 - l2 * s2 - a3 * s3));
    kinetic - potential
}

/// The double pendulum from its URDF takes the steps of the one written by hand, to 1e-12
/// over 1000 steps; the text names its coordinates after the URDF's joints.
#[test]
fn double_pendulum_from_urdf_steps_as_written_by_hand() {
    let h = 0.01;
    let text = data("double_pendulum.urdf").system_text().unwrap();
    let code = flat(&text);
    assert_eq!(code.system().shape, ["shoulder", "elbow"]);
    let given = code.instantiate::<2, 0, 2>(&[h]).unwrap();
    let by_hand = Pendulum { h };
    same_lagrangian(&given, &by_hand, 0.5);
    let start = UnreducedState::new([0.6, -0.3], [0.2, 0.3]);
    let (a, b) = both_runs!(given, by_hand, start);
    let worst = gap(&a.states, &b.states);
    println!(
        "double pendulum: URDF against by hand, largest relative gap {worst:.1e} over 1000 steps"
    );
    assert!(worst < 1e-12, "{worst:e}");
    // The motion is not trivial: the elbow swings through a wide range.
    let range = a
        .states
        .iter()
        .map(|s| s.q[1])
        .fold(f64::NEG_INFINITY, f64::max)
        - a.states
            .iter()
            .map(|s| s.q[1])
            .fold(f64::INFINITY, f64::min);
    assert!(range > 0.5, "{range}");
}

/// The planar 3-link arm from its URDF takes the steps of the one written by hand, to 1e-12
/// over 1000 steps.
#[test]
fn three_link_arm_from_urdf_steps_as_written_by_hand() {
    let h = 0.01;
    let text = data("three_link_arm.urdf").system_text().unwrap();
    let code = flat(&text);
    let given = code.instantiate::<3, 0, 3>(&[h]).unwrap();
    let by_hand = Arm { h };
    same_lagrangian(&given, &by_hand, 2.0);
    // Swinging about the hanging arm (φ = π/2), where the motion is regular: a chaotic one
    // would amplify the round-off that separates two ways of writing one L.
    let start = UnreducedState::new([1.2, 0.3, -0.2], [0.1, -0.05, 0.02]);
    let (a, b) = both_runs!(given, by_hand, start);
    let worst = gap(&a.states, &b.states);
    println!("3-link arm: URDF against by hand, largest relative gap {worst:.1e} over 1000 steps");
    assert!(worst < 1e-12, "{worst:e}");
}

/// A cart on a slope and a pole hinged on it, written by hand: the cart slides a distance `s`
/// along the unit axis `a = (2, 0, 1)/√5`, the pole turns by `θ` about `y` at `0.1` above the
/// cart, its centre of mass `0.5` along it (up at `θ = 0`): at
/// `(s a_x + 0.5 sin θ, 0.1 + s a_z + 0.5 cos θ)` in the `x-z` plane.
#[reduced_lagrangian(shape(s, theta), group(), rule = midpoint)]
fn cart_pole(q: Config, v: Velocity) -> f64 {
    let (big, m, j, g) = (1.0, 0.3, 0.02, 9.81);
    let (ax, az) = (2.0 / 5.0_f64.sqrt(), 1.0 / 5.0_f64.sqrt());
    let vx = v.s * ax + 0.5 * q.theta.cos() * v.theta;
    let vz = v.s * az - 0.5 * q.theta.sin() * v.theta;
    let kinetic =
        0.5 * big * v.s * v.s + 0.5 * m * (vx * vx + vz * vz) + 0.5 * j * v.theta * v.theta;
    let potential = big * g * q.s * az + m * g * (0.1 + q.s * az + 0.5 * q.theta.cos());
    kinetic - potential
}

/// The cart and pole as a model built in Rust, its joints named `h` and `q` (the text's own
/// names for the time step and the configuration: the coordinates are fields, `q.h` and
/// `q.q`, so they may be).
fn cart_pole_model() -> Model {
    let cart = Inertial::new(
        1.0,
        Vector3::zeros(),
        Matrix3::from_diagonal(&Vector3::new(0.01, 0.01, 0.01)),
    );
    let pole = Inertial::new(
        0.3,
        Vector3::new(0.0, 0.0, 0.5),
        Matrix3::from_diagonal(&Vector3::new(0.02, 0.02, 0.001)),
    );
    Model::builder()
        .frame("world")
        .body("cart", cart)
        .body("pole", pole)
        .joint(JointSpec::prismatic(
            "h",
            "world",
            "cart",
            Vector3::new(2.0, 0.0, 1.0),
        ))
        .joint(
            JointSpec::revolute("q", "cart", "pole", Vector3::y())
                .at(Pose::from_translation(Vector3::new(0.0, 0.0, 0.1))),
        )
        .build()
        .unwrap()
}

/// A prismatic joint: the cart and pole built in Rust and compiled by `compile_model` take
/// the steps of the one written by hand, to 1e-12 over 1000 steps.
#[test]
fn cart_pole_from_a_model_steps_as_written_by_hand() {
    let h = 0.01;
    let code = dirac_jit::compile_model(&cart_pole_model(), &TextOptions::default()).unwrap();
    assert_eq!(code.text.identifier("h"), Some("h"));
    let Compiled::Flat(flat) = &code.compiled else {
        panic!("a fixed base")
    };
    let given = flat.instantiate::<2, 0, 2>(&[h]).unwrap();
    let by_hand = CartPole { h };
    same_lagrangian(&given, &by_hand, 1.0);
    let start = UnreducedState::new([0.2, 0.1], [0.3, -0.05]);
    let (a, b) = both_runs!(given, by_hand, start);
    let worst = gap(&a.states, &b.states);
    println!(
        "cart and pole: model against by hand, largest relative gap {worst:.1e} over 1000 steps"
    );
    assert!(worst < 1e-12, "{worst:e}");
    // A model the text does not support is the model's typed error, naming the joint: a
    // free joint below the root.
    let rod = Inertial::new(
        1.0,
        Vector3::new(0.0, 0.0, -1.0),
        Matrix3::identity() * 0.01,
    );
    let deep = Model::builder()
        .frame("world")
        .body("a", rod)
        .body("b", rod)
        .joint(JointSpec::revolute("hinge", "world", "a", Vector3::y()))
        .joint(JointSpec::free("float", "a", "b"))
        .build()
        .unwrap();
    match dirac_jit::compile_model(&deep, &TextOptions::default()) {
        Err(dirac_jit::Error::Model(dirac_multibody::ModelError::Unsupported {
            joint, ..
        })) => {
            assert_eq!(joint, "float")
        }
        other => panic!("{other:?}"),
    }
}

/// The double pendulum's equations of motion in the absolute angles `φ1 = θ1`,
/// `φ2 = θ1 + θ2`: with `I1 = m1 a1² + j1 + m2 l1²`, `I2 = m2 a2² + j2`, `k = m2 l1 a2`,
/// `Δ = φ2 − φ1`, Lagrange's equations of `T = ½ I1 φ̇1² + ½ I2 φ̇2² + k φ̇1 φ̇2 cos Δ`,
/// `V = −(m1 a1 + m2 l1) g cos φ1 − m2 a2 g cos φ2` are
///
/// ```text
/// I1 φ̈1 + k cos Δ φ̈2 =  k sin Δ φ̇2² − (m1 a1 + m2 l1) g sin φ1
/// k cos Δ φ̈1 + I2 φ̈2 = −k sin Δ φ̇1² − m2 a2 g sin φ2
/// ```
fn pendulum_rate(y: &[f64; 4]) -> [f64; 4] {
    let (m1, a1, j1, l1, m2, a2, j2) = (1.3, 0.45, 0.11, 1.0, 0.7, 0.6, 0.08);
    let (i1, i2, k) = (
        m1 * a1 * a1 + j1 + m2 * l1 * l1,
        m2 * a2 * a2 + j2,
        m2 * l1 * a2,
    );
    let [p1, p2, w1, w2] = *y;
    let d = p2 - p1;
    let (b1, b2) = (
        k * d.sin() * w2 * w2 - (m1 * a1 + m2 * l1) * G * p1.sin(),
        -k * d.sin() * w1 * w1 - m2 * a2 * G * p2.sin(),
    );
    let (m11, m12, m22) = (i1, k * d.cos(), i2);
    let det = m11 * m22 - m12 * m12;
    [
        w1,
        w2,
        (m22 * b1 - m12 * b2) / det,
        (m11 * b2 - m12 * b1) / det,
    ]
}

/// The classical Runge–Kutta method with `n` steps to time `t`.
fn rk4(mut y: [f64; 4], t: f64, n: usize) -> [f64; 4] {
    let h = t / n as f64;
    let add = |y: &[f64; 4], k: &[f64; 4], c: f64| std::array::from_fn(|i| y[i] + c * k[i]);
    for _ in 0..n {
        let k1 = pendulum_rate(&y);
        let k2 = pendulum_rate(&add(&y, &k1, h / 2.0));
        let k3 = pendulum_rate(&add(&y, &k2, h / 2.0));
        let k4 = pendulum_rate(&add(&y, &k3, h));
        y = std::array::from_fn(|i| y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]));
    }
    y
}

/// The double pendulum from its URDF converges at order 2 to the solution of its equations
/// of motion (Runge–Kutta at 2·10⁵ steps in the test): the error at `t = 2` falls by 4 each
/// time `h` halves. The start is a position and a velocity, through the text's Legendre map.
#[test]
fn double_pendulum_from_urdf_is_of_order_two() {
    let text = data("double_pendulum.urdf").system_text().unwrap();
    let code = flat(&text);
    let (t1, t2, w1, w2) = (1.0, -0.5, 0.3, 1.1);
    let exact = rk4([t1, t1 + t2, w1, w1 + w2], 2.0, 200_000);
    let errors: Vec<f64> = [0.04, 0.02, 0.01, 0.005]
        .iter()
        .map(|&h| {
            let sys = code.instantiate::<2, 0, 2>(&[h]).unwrap();
            let start = sys.unreduced_state::<2, 0>([t1, t2], [w1, w2]).unwrap();
            let steps = (2.0 / h).round() as usize;
            let traj = UnreducedIntegrator::new(sys, NewtonOptions::default())
                .run(start)
                .steps(steps)
                .collect()
                .unwrap();
            let q = traj.last().q;
            (q[0] - exact[0]).abs().max((q[0] + q[1] - exact[1]).abs())
        })
        .collect();
    let orders: Vec<f64> = errors.windows(2).map(|e| (e[0] / e[1]).log2()).collect();
    println!("double pendulum: errors at t = 2 {errors:?}, observed orders {orders:.3?}");
    for order in orders {
        assert!((order - 2.0).abs() < 0.1, "{order}");
    }
}

/// The step sensitivities of the 3-link arm with joint torques as controls against central
/// differences of its steps, in the state and in the torques; and, without torques, the
/// step-map Jacobian from the Hessian of `L_d` against the sensitivities.
#[test]
fn arm_step_sensitivities_match_central_differences() {
    let h = 0.01;
    let model = data("three_link_arm.urdf");
    let options = TextOptions {
        name: "arm".into(),
        torques: true,
    };
    let text = model.system_text_with(&options).unwrap();
    assert_eq!(text.controls, ["tau_joint1", "tau_joint2", "tau_joint3"]);
    let code = flat(&text);
    assert_eq!(
        code.system().parameters,
        ["tau_joint1", "tau_joint2", "tau_joint3", "h"]
    );
    let sys = code.instantiate::<3, 0, 3>(&[0.0, 0.0, 0.0, h]).unwrap();
    let integ = UnreducedIntegrator::new(sys, NewtonOptions::default());
    let start = UnreducedState::new([0.3, -0.5, 0.8], [0.2, -0.1, 0.05]);
    let u = [1.5, -0.7, 0.2];
    let (_, _, lin) = integ.step_sensitivity(0, &start, &u).unwrap();
    let next = |s: &UnreducedState<3>, u: &[f64]| {
        let (n, _, _) = integ.step_sensitivity(0, s, u).unwrap();
        let mut out = [0.0; 6];
        out[..3].copy_from_slice(n.q.as_slice());
        out[3..].copy_from_slice(n.p.as_slice());
        out
    };
    let eps = 1e-6;
    let mut worst: f64 = 0.0;
    for c in 0..9 {
        let shifted = |sign: f64| {
            let (mut s, mut v) = (start, u);
            match c {
                0..=2 => s.q[c] += sign * eps,
                3..=5 => s.p[c - 3] += sign * eps,
                _ => v[c - 6] += sign * eps,
            }
            next(&s, &v)
        };
        let (plus, minus) = (shifted(1.0), shifted(-1.0));
        for r in 0..6 {
            let fd = (plus[r] - minus[r]) / (2.0 * eps);
            let exact = if c < 6 {
                lin.state[(r, c)]
            } else {
                lin.control[(r, c - 6)]
            };
            worst = worst.max((fd - exact).abs());
        }
    }
    println!("3-link arm: sensitivities against central differences, largest gap {worst:.1e}");
    assert!(worst < 1e-7, "{worst:e}");
    // The torques act: each moves the next momenta by about h (the midpoint rule's discrete
    // force is (h/2) τ at each end).
    for c in 0..3 {
        assert!(
            (lin.control[(3 + c, c)] - h).abs() < 0.1 * h,
            "{}",
            lin.control
        );
    }

    // Without controls: the step-map Jacobian of the conservative text is the same matrix.
    let free = flat(&model.system_text().unwrap())
        .instantiate::<3, 0, 3>(&[h])
        .unwrap();
    let free = UnreducedIntegrator::new(free, NewtonOptions::default());
    let (to, _) = free.step_from(0, &start, &start.q).unwrap();
    let jac = free.step_jacobian(0, &start, &to).unwrap();
    let (_, _, at_rest) = integ.step_sensitivity(0, &start, &[0.0; 3]).unwrap();
    let diff = (&jac.state - &at_rest.state).amax();
    assert!(diff < 1e-10, "{diff:e}");
}

/// A random-looking but fixed sequence in `[-1, 1]`.
fn wave(k: usize) -> f64 {
    ((k as f64 + 1.0) * 12.9898).sin()
}

/// The 7-DoF iiwa arm: its text compiles, its energy and Legendre map are those of the model
/// (`T + V` and `M(q) q̇` of `dirac-multibody`, at sample states), and 1000 steps of `h = 1 ms`
/// keep the energy to an error small against the kinetic energy the arm reaches, which falls by
/// 4 when `h` halves (the bounded error of the modified energy, of order 2). Prints the text's
/// length, the compile time and the step time.
#[test]
fn iiwa_compiles_and_steps_with_bounded_energy_error() {
    let model = data("iiwa14.urdf");
    let text = model.system_text().unwrap();
    let started = Instant::now();
    let code = flat(&text);
    let compile = started.elapsed();
    let h = 1e-3;
    let sys = code.instantiate::<7, 0, 7>(&[h]).unwrap();
    for k in 0..5 {
        let q: SVector<f64, 7> = SVector::from_fn(|i, _| 1.5 * wave(7 * k + i));
        let v: SVector<f64, 7> = SVector::from_fn(|i, _| 2.0 * wave(100 + 7 * k + i));
        let config = model.configuration_from_scalars(q.as_slice()).unwrap();
        let energy = model.kinetic_energy(&config, v.as_slice()).unwrap()
            + model.potential_energy(&config).unwrap();
        let e = sys.energy(&q, &v).unwrap();
        assert!(
            (e - energy).abs() < 1e-12 * energy.abs().max(1.0),
            "{e} {energy}"
        );
        let m = model.mass_matrix(&config).unwrap();
        let p = m * DVector::from_column_slice(v.as_slice());
        let legendre = sys.legendre(&q, &v).unwrap();
        let worst = (0..7)
            .map(|i| (legendre[i] - p[i]).abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-12 * p.amax().max(1.0), "{worst:e}");
    }
    let q0 = [0.3, 0.5, -0.2, -1.2, 0.4, 0.7, -0.1];
    let v0 = [0.5, -0.4, 0.8, 0.6, -1.0, 0.9, 1.5];
    // The largest energy error over 1 s at h and h/2: bounded, and of order 2 (the error of a
    // variational integrator's modified energy, not a drift).
    let run = |h: f64| {
        let sys = code.instantiate::<7, 0, 7>(&[h]).unwrap();
        let start = sys.unreduced_state::<7, 0>(q0, v0).unwrap();
        let integ = UnreducedIntegrator::new(sys, NewtonOptions::default());
        let steps = (1.0 / h).round() as usize;
        let started = Instant::now();
        let traj = integ.run(start).steps(steps).collect().unwrap();
        let per_step = started.elapsed().as_secs_f64() / steps as f64;
        let energies = integ.energies(&traj).unwrap().nodes;
        let e0 = energies[0];
        let error = energies.iter().map(|e| (e - e0).abs()).fold(0.0, f64::max);
        // The energy's scale: the largest kinetic energy of the model along the run (at the
        // steps' midpoints, with their chord velocities), as the arm falls and swings.
        let kinetic = traj
            .states
            .windows(2)
            .map(|w| {
                let q = (w[0].q + w[1].q) / 2.0;
                let v = (w[1].q - w[0].q) / h;
                let config = model.configuration_from_scalars(q.as_slice()).unwrap();
                model.kinetic_energy(&config, v.as_slice()).unwrap()
            })
            .fold(0.0, f64::max);
        (error, kinetic, per_step, (traj.last().q - start.q).amax())
    };
    let (error, kinetic, per_step, moved) = run(1e-3);
    let (finer, _, _, _) = run(5e-4);
    println!(
        "iiwa14: text {} bytes, {} lines; compiled in {:.0} ms; {:.1} us per step; \
         energy error {error:.2e} J over 1000 steps of 1 ms ({finer:.2e} J at 0.5 ms; \
         kinetic energy up to {kinetic:.2} J)",
        text.text.len(),
        text.text.lines().count(),
        compile.as_secs_f64() * 1e3,
        per_step * 1e6
    );
    assert!(error < 1e-3 * kinetic, "{error:e} against {kinetic}");
    let order = (error / finer).log2();
    assert!((order - 2.0).abs() < 0.3, "energy error of order {order}");
    assert!(moved > 0.1, "{moved}");
}

/// A branching tree with every kind of scalar joint: a prismatic joint below two revolute
/// ones (so the slide is carried by a turning body), two branches from one body, placements
/// turned by `rpy`, centres of mass off the frames, inertias with products, gravity askew.
fn mixed_tree() -> Model {
    let body = |m: f64, c: [f64; 3], d: [f64; 3], p: f64| {
        let i = Matrix3::new(d[0], p, -p, p, d[1], 0.5 * p, -p, 0.5 * p, d[2]);
        Inertial::new(m, Vector3::from(c), i)
    };
    let at = |xyz: [f64; 3], rpy: [f64; 3]| Pose::from_xyz_rpy(xyz, rpy);
    Model::builder()
        .frame("world")
        .body("a", body(2.0, [0.1, 0.0, -0.3], [0.2, 0.25, 0.1], 0.01))
        .body("b", body(1.5, [0.0, 0.2, -0.1], [0.1, 0.12, 0.08], -0.005))
        .body(
            "c",
            body(0.8, [0.05, -0.02, 0.1], [0.03, 0.04, 0.05], 0.002),
        )
        .body("d", body(1.1, [-0.1, 0.1, 0.0], [0.06, 0.05, 0.07], 0.003))
        .body("e", body(0.5, [0.0, 0.0, 0.2], [0.02, 0.02, 0.01], 0.0))
        .joint(
            JointSpec::revolute("r1", "world", "a", Vector3::new(0.0, 0.3, 1.0))
                .at(at([0.0, 0.0, 0.5], [0.1, 0.0, 0.0])),
        )
        .joint(
            JointSpec::revolute("r2", "a", "b", Vector3::x())
                .at(at([0.3, 0.1, -0.6], [0.0, 0.4, -0.2])),
        )
        .joint(
            JointSpec::prismatic("slide", "b", "c", Vector3::new(1.0, -1.0, 0.5))
                .at(at([0.0, 0.2, -0.4], [0.3, 0.0, 0.7])),
        )
        .joint(
            JointSpec::revolute("branch", "a", "d", Vector3::y())
                .at(at([-0.2, 0.0, -0.6], [0.0, 0.0, 0.5])),
        )
        .joint(JointSpec::new(
            "wrist",
            "c",
            "e",
            dirac_multibody::JointKind::Continuous {
                axis: Vector3::new(1.0, 1.0, 1.0),
            },
        ))
        .gravity(Vector3::new(1.0, -2.0, -9.0))
        .build()
        .unwrap()
}

/// The text of a branching tree with a carried prismatic joint has the model's energy and
/// Legendre map: `T + V` and `M(q) q̇` of `dirac-multibody` (the composite-rigid-body
/// algorithm in the world frame, written independently), at sample states.
#[test]
fn a_mixed_tree_has_the_model_energy_and_mass_matrix() {
    let model = mixed_tree();
    let code = flat(&model.system_text().unwrap());
    let sys = code.instantiate::<5, 0, 5>(&[0.01]).unwrap();
    for k in 0..20 {
        let q: SVector<f64, 5> = SVector::from_fn(|i, _| 2.0 * wave(5 * k + i));
        let v: SVector<f64, 5> = SVector::from_fn(|i, _| 3.0 * wave(200 + 5 * k + i));
        let config = model.configuration_from_scalars(q.as_slice()).unwrap();
        let energy = model.kinetic_energy(&config, v.as_slice()).unwrap()
            + model.potential_energy(&config).unwrap();
        let e = sys.energy(&q, &v).unwrap();
        assert!(
            (e - energy).abs() < 1e-12 * energy.abs().max(1.0),
            "{e} {energy}"
        );
        let p = model.mass_matrix(&config).unwrap() * DVector::from_column_slice(v.as_slice());
        let legendre = sys.legendre(&q, &v).unwrap();
        let worst = (0..5)
            .map(|i| (legendre[i] - p[i]).abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-12 * p.amax().max(1.0), "{worst:e}");
    }
}

// ---------------------------------------------------------------------------------------------
// Floating bases.

/// The free body of `examples/data/free_body.urdf` written by hand: its pose `(R, x)` is the
/// body frame's, the centre of mass at `c` in it, the inertia `I` about the centre of mass in
/// the body frame's axes (the URDF's, turned by its `rpy`): `L = ½ m |ẋ + R (Ω × c)|² + ½ Ωᵀ I Ω
/// + m g·(x + R c)`.
#[reduced_lagrangian(pose(float), rule = trapezoid)]
fn free_body(
    q: Config,
    v: Velocity,
    m: f64,
    c1: f64,
    c2: f64,
    c3: f64,
    i11: f64,
    i12: f64,
    i13: f64,
    i22: f64,
    i23: f64,
    i33: f64,
) -> f64 {
    let c = Vector3::new(c1, c2, c3);
    let inertia = Matrix3::new(i11, i12, i13, i12, i22, i23, i13, i23, i33);
    let r = q.float.rotation;
    let omega = v.float.angular;
    let vc = v.float.linear + r * omega.cross(&c);
    let height = q.float.translation.z + (r * c).z;
    0.5 * m * vc.norm_squared() + 0.5 * omega.dot(&(inertia * omega)) - m * 9.81 * height
}

/// The rotation `cay(ξ)`.
fn cayley(xi: &Vector3<f64>) -> Matrix3<f64> {
    dirac::lie::cayley(xi)
}

/// A pose's 12 numbers as a state takes them: the rotation row by row, then the position.
fn pose_numbers(r: &Matrix3<f64>, x: &Vector3<f64>) -> Vec<f64> {
    let mut out: Vec<f64> = r.transpose().as_slice().to_vec();
    out.extend_from_slice(x.as_slice());
    out
}

/// The free body from its URDF (one floating joint) takes the steps of the rigid body on
/// `SE(3)` written by hand, to 1e-12 over 1000 steps, falling and tumbling.
#[test]
fn free_body_from_urdf_steps_as_written_by_hand() {
    let h = 0.01;
    let model = data("free_body.urdf");
    let text = model.system_text().unwrap();
    let code = lie(&text);
    let given: JitLie<12, 6> = code.instantiate(&[h]).unwrap();
    let body = &model.bodies()[1].inertial;
    let i = body.inertia;
    let by_hand = FreeBody {
        h,
        m: body.mass,
        c1: body.com.x,
        c2: body.com.y,
        c3: body.com.z,
        i11: i[(0, 0)],
        i12: i[(0, 1)],
        i13: i[(0, 2)],
        i22: i[(1, 1)],
        i23: i[(1, 2)],
        i33: i[(2, 2)],
    };
    let r0 = cayley(&Vector3::new(0.3, -0.2, 0.4));
    let x0 = Vector3::new(1.0, -2.0, 0.5);
    let (pi0, p0) = (Vector3::new(0.4, 1.0, -0.3), Vector3::new(0.9, -0.3, 0.6));
    let s_given = given
        .state(
            &[&pose_numbers(&r0, &x0)],
            &[&[pi0.x, pi0.y, pi0.z, p0.x, p0.y, p0.z]],
        )
        .unwrap();
    let s_hand = by_hand.state(
        &FreeBodyConfig {
            float: FreeBodyPose {
                rotation: r0,
                translation: x0,
            },
        },
        &FreeBodyMomentum {
            float: FreeBodyPoseMomentum {
                angular: pi0,
                linear: p0,
            },
        },
    );
    assert_eq!(s_given.q, s_hand.q);
    assert_eq!(s_given.p, s_hand.p);
    let opts = NewtonOptions::default();
    let a = LieIntegrator::new(given, opts)
        .run(s_given)
        .steps(1000)
        .collect()
        .unwrap();
    let b = LieIntegrator::new(by_hand, opts)
        .run(s_hand)
        .steps(1000)
        .collect()
        .unwrap();
    let worst = a
        .states
        .iter()
        .zip(&b.states)
        .map(|(a, b)| (a.q - b.q).amax().max((a.p - b.p).amax()))
        .fold(0.0, f64::max);
    let worst = worst / a.last().q.amax().max(1.0);
    println!("free body: URDF against by hand, largest relative gap {worst:.1e} over 1000 steps");
    assert!(worst < 1e-12, "{worst:e}");
}

/// The free body's exact motion to time `t` from the body frame's pose `(r0, x0)`, its body
/// angular velocity `omega0` and the velocity `xdot0` of its origin: the centre of mass
/// `C = x + R c` falls on its parabola, and the attitude turns by Euler's equations
/// `I Ω̇ = (I Ω) × Ω`, `Ṙ = R Ω̂` (gravity acts at the centre of mass), solved by Runge–Kutta at
/// `n` steps. Returns the frame's pose `(R, C − R c)`.
fn free_body_exact(
    body: &Inertial,
    (r0, x0): (Matrix3<f64>, Vector3<f64>),
    (omega0, xdot0): (Vector3<f64>, Vector3<f64>),
    t: f64,
    n: usize,
) -> (Matrix3<f64>, Vector3<f64>) {
    let (i, c) = (body.inertia, body.com);
    let i_inv = i.try_inverse().expect("a positive definite inertia");
    let rate =
        |r: &Matrix3<f64>, w: &Vector3<f64>| (r * w.cross_matrix(), i_inv * (i * w).cross(w));
    let (mut r, mut w) = (r0, omega0);
    let h = t / n as f64;
    for _ in 0..n {
        let (k1r, k1w) = rate(&r, &w);
        let (k2r, k2w) = rate(&(r + k1r * (h / 2.0)), &(w + k1w * (h / 2.0)));
        let (k3r, k3w) = rate(&(r + k2r * (h / 2.0)), &(w + k2w * (h / 2.0)));
        let (k4r, k4w) = rate(&(r + k3r * h), &(w + k3w * h));
        r += (k1r + k2r * 2.0 + k3r * 2.0 + k4r) * (h / 6.0);
        w += (k1w + k2w * 2.0 + k3w * 2.0 + k4w) * (h / 6.0);
    }
    let c0 = x0 + r0 * c;
    let cdot0 = xdot0 + r0 * omega0.cross(&c);
    let centre = c0 + cdot0 * t + Vector3::new(0.0, 0.0, -G) * (0.5 * t * t);
    (r, centre - r * c)
}

/// The free body from its URDF converges at order 2 to its exact motion (the centre of mass on
/// its parabola, the attitude by Euler's equations), started from a pose and a velocity through
/// the model's mass matrix: the error at `t = 1` falls by 4 each time `h` halves.
#[test]
fn free_body_from_urdf_is_of_order_two() {
    let model = data("free_body.urdf");
    let code = lie(&model.system_text().unwrap());
    let body = model.bodies()[1].inertial;
    let r0 = cayley(&Vector3::new(0.3, -0.2, 0.4));
    let x0 = Vector3::new(1.0, -2.0, 0.5);
    let (omega0, xdot0) = (Vector3::new(1.5, -0.8, 2.0), Vector3::new(0.9, -0.3, 3.0));
    // The momenta of the pose and velocity: M(q) (Ω, Rᵀ ẋ), the linear part back in space.
    let mut config = model.neutral_configuration();
    config.positions[0] = JointPosition::Pose(Pose::new(r0, x0));
    let v = r0.transpose() * xdot0;
    let velocity = DVector::from_vec(vec![omega0.x, omega0.y, omega0.z, v.x, v.y, v.z]);
    let p = model.mass_matrix(&config).unwrap() * velocity;
    let linear = r0 * Vector3::new(p[3], p[4], p[5]);
    let (r_exact, x_exact) = free_body_exact(&body, (r0, x0), (omega0, xdot0), 1.0, 100_000);
    let errors: Vec<f64> = [0.02, 0.01, 0.005]
        .iter()
        .map(|&h| {
            let sys: JitLie<12, 6> = code.instantiate(&[h]).unwrap();
            let start = sys
                .state(
                    &[&pose_numbers(&r0, &x0)],
                    &[&[p[0], p[1], p[2], linear.x, linear.y, linear.z]],
                )
                .unwrap();
            let steps = (1.0 / h).round() as usize;
            let traj = LieIntegrator::new(sys, NewtonOptions::default())
                .run(start)
                .steps(steps)
                .collect()
                .unwrap();
            let q = traj.last().q;
            let r = Matrix3::from_fn(|i, j| q[3 * i + j]);
            let x = Vector3::new(q[9], q[10], q[11]);
            (r - r_exact).amax().max((x - x_exact).amax())
        })
        .collect();
    let orders: Vec<f64> = errors.windows(2).map(|e| (e[0] / e[1]).log2()).collect();
    println!("free body: errors at t = 1 {errors:?}, observed orders {orders:.3?}");
    for order in orders {
        assert!((order - 2.0).abs() < 0.15, "{order}");
    }
}

/// A satellite base (a free joint) carrying a 2-joint arm, out of gravity: a box-like base, a
/// revolute shoulder about the base's `z`, a revolute elbow about the upper arm's `y`.
fn floating_arm() -> Model {
    let base = Inertial::new(
        50.0,
        Vector3::new(0.02, -0.01, 0.0),
        Matrix3::from_diagonal(&Vector3::new(4.0, 5.0, 6.0)),
    );
    let upper = Inertial::new(
        3.0,
        Vector3::new(0.0, 0.0, 0.4),
        Matrix3::from_diagonal(&Vector3::new(0.17, 0.17, 0.01)),
    );
    let fore = Inertial::new(
        2.0,
        Vector3::new(0.3, 0.0, 0.0),
        Matrix3::from_diagonal(&Vector3::new(0.005, 0.07, 0.07)),
    );
    Model::builder()
        .frame("world")
        .body("base", base)
        .body("upper", upper)
        .body("fore", fore)
        .joint(JointSpec::free("float", "world", "base"))
        .joint(
            JointSpec::revolute("shoulder", "base", "upper", Vector3::z())
                .at(Pose::from_xyz_rpy([0.5, 0.2, 0.6], [0.1, 0.0, 0.0])),
        )
        .joint(
            JointSpec::revolute("elbow", "upper", "fore", Vector3::y())
                .at(Pose::from_translation(Vector3::new(0.0, 0.0, 0.8))),
        )
        .gravity(Vector3::zeros())
        .build()
        .unwrap()
}

/// The model's configuration and velocity at a state of the floating arm's text, the
/// velocity solving `M(q) v = p` for the state's momenta in the model's coordinates (`Π`, the
/// base's body linear momentum `Rᵀ p`, the joints'): the inverse Legendre map at the node.
fn model_state(model: &Model, s: &LieState<14, 8>) -> (dirac_multibody::Configuration, Vec<f64>) {
    let q = &s.q;
    let r = Matrix3::from_fn(|i, j| q[3 * i + j]);
    let x = Vector3::new(q[9], q[10], q[11]);
    let mut config = model.neutral_configuration();
    config.positions[0] = JointPosition::Pose(Pose::new(r, x));
    config.positions[1] = JointPosition::Scalar(q[12]);
    config.positions[2] = JointPosition::Scalar(q[13]);
    let linear = r.transpose() * Vector3::new(s.p[3], s.p[4], s.p[5]);
    let p = DVector::from_vec(vec![
        s.p[0], s.p[1], s.p[2], linear.x, linear.y, linear.z, s.p[6], s.p[7],
    ]);
    let m: DMatrix<f64> = model.mass_matrix(&config).unwrap();
    let v = m.lu().solve(&p).expect("a regular mass matrix");
    (config, v.as_slice().to_vec())
}

/// A free-floating base with a 2-joint arm, out of gravity, over 10⁴ steps: the total
/// linear and angular momentum of the model (`dirac-multibody`'s `momentum` at each node's
/// configuration and velocity) stays constant to ~1e-13 relative, as the discrete Noether
/// theorem says for a Lagrangian invariant under the rigid motions of the whole tree; and it
/// is the momentum map the integrator reports.
#[test]
fn floating_arm_keeps_its_total_momentum() {
    let h = 0.01;
    let model = floating_arm();
    let text = model.system_text().unwrap();
    let code = lie(&text);
    let sys: JitLie<14, 8> = code.instantiate(&[h]).unwrap();
    // Start from a velocity: the momenta M(q) v, in the text's coordinates.
    let r0 = cayley(&Vector3::new(0.2, 0.1, -0.3));
    let x0 = Vector3::new(0.5, -0.2, 1.0);
    let mut config = model.neutral_configuration();
    config.positions[0] = JointPosition::Pose(Pose::new(r0, x0));
    config.positions[1] = JointPosition::Scalar(0.4);
    config.positions[2] = JointPosition::Scalar(-0.9);
    let v0 = DVector::from_vec(vec![0.05, -0.02, 0.1, 0.2, 0.1, -0.05, 1.5, -2.0]);
    let p0 = model.mass_matrix(&config).unwrap() * &v0;
    let linear = r0 * Vector3::new(p0[3], p0[4], p0[5]);
    let start = sys
        .state(
            &[&pose_numbers(&r0, &x0), &[0.4], &[-0.9]],
            &[
                &[p0[0], p0[1], p0[2], linear.x, linear.y, linear.z],
                &[p0[6]],
                &[p0[7]],
            ],
        )
        .unwrap();
    let integ = LieIntegrator::new(sys, NewtonOptions::default());
    let traj = integ.run(start).steps(10_000).collect().unwrap();
    let first = model.momentum(&config, v0.as_slice()).unwrap();
    let scale = first.linear.norm() + first.angular.norm();
    let (l0, a0) = (
        integ.linear_momentum(&start),
        integ.spatial_momentum(&start),
    );
    let (mut worst, mut reported, mut kept): (f64, f64, f64) = (0.0, 0.0, 0.0);
    for s in &traj.states {
        let (c, v) = model_state(&model, s);
        let m = model.momentum(&c, &v).unwrap();
        worst = worst.max((m.linear - first.linear).norm() + (m.angular - first.angular).norm());
        let (l, a) = (integ.linear_momentum(s), integ.spatial_momentum(s));
        reported = reported.max((l - m.linear).norm() + (a - m.angular).norm());
        kept = kept.max((l - l0).norm() + (a - a0).norm());
    }
    let joints = traj
        .states
        .iter()
        .map(|s| s.q[13])
        .fold(f64::INFINITY, f64::min);
    println!(
        "floating arm over 10^4 steps, relative to |momentum| = {scale:.2}: the integrator's \
         momentum map drifts {:.1e}, the model's momentum {:.1e}, the two differ by {:.1e}; \
         elbow down to {joints:.2}",
        kept / scale,
        worst / scale,
        reported / scale
    );
    assert!(kept < 1e-13 * scale, "{:e}", kept / scale);
    // The model's momentum adds the round-off of its own evaluation at each node (the mass
    // matrix, its factorization, the bodies' velocities) to the integrator's.
    assert!(worst < 1e-12 * scale, "{:e}", worst / scale);
    assert!(reported < 1e-12 * scale, "{:e}", reported / scale);
    // The arm moves: the base turns as the joints swing.
    let base_turn = (Matrix3::from_fn(|i, j| traj.last().q[3 * i + j]) - r0).amax();
    assert!(base_turn > 0.1, "{base_turn}");
}

/// Out of gravity the floating arm's text declares the rigid motions of the whole tree as its
/// symmetry (`symmetry(<base>)`), and the reduced integrator carries the total momentum as the
/// run's parameters: the linear momentum copied bit for bit, the angular momentum about the
/// origin `R Π + x × p` equal to it at every step to the round-off of one evaluation (the
/// unreduced run's gathers a little each step), the joints and base following the unreduced
/// run's to round-off.
#[test]
fn floating_arm_reduced_by_rigid_motions_carries_its_momentum() {
    let h = 0.01;
    let model = floating_arm();
    let text = model.system_text().unwrap();
    assert!(text.text.contains("symmetry(float)"), "{}", text.text);
    let code = lie(&text);
    let sys: JitLie<14, 8> = code.instantiate(&[h]).unwrap();
    let r0 = cayley(&Vector3::new(0.2, 0.1, -0.3));
    // Far from the origin and drifting: `x × p` is large against the momentum about the base.
    let x0 = Vector3::new(40.0, -25.0, 10.0);
    let linear = Vector3::new(3.0, 1.0, -2.0);
    let start = sys
        .state(
            &[&pose_numbers(&r0, &x0), &[0.4], &[-0.9]],
            &[
                &[0.05, -0.02, 0.1, linear.x, linear.y, linear.z],
                &[0.3],
                &[-0.2],
            ],
        )
        .unwrap();
    let reduced_sys: JitLie<14, 8, Dense, Reduced> = code.instantiate_reduced(&[h]).unwrap();
    let reduced = ReducedLieIntegrator::new(reduced_sys, NewtonOptions::default());
    let unreduced = LieIntegrator::new(sys, NewtonOptions::default());
    let a = reduced
        .run(reduced.reduce(&start))
        .steps(5000)
        .collect()
        .unwrap();
    let b = unreduced.run(start).steps(5000).collect().unwrap();
    let pi = a.states[0].mu;
    let (mut held, mut gathered): (f64, f64) = (0.0, 0.0);
    for (x, y) in a.states.iter().zip(&b.states) {
        assert_eq!(&x.p.as_slice()[3..6], linear.as_slice());
        assert_eq!(x.mu, pi);
        held = held.max((reduced.momentum_map(&x.unreduced()).unwrap() - pi).norm());
        gathered = gathered.max((unreduced.spatial_momentum(y) - pi).norm());
    }
    let apart = (0..14)
        .map(|i| (a.states[200].q[i] - b.states[200].q[i]).abs())
        .fold(0.0, f64::max);
    println!(
        "floating arm reduced by rigid motions, |π| = {:.3}: reduced {:.1e}, unreduced {:.1e}; \
         200 steps apart by {apart:.1e}",
        pi.norm(),
        held / pi.norm(),
        gathered / pi.norm()
    );
    let one = 4.0 * f64::EPSILON * x0.norm() * linear.norm();
    assert!(held < one, "{held:e} against {one:e}");
    assert!(apart < 1e-11 * x0.norm(), "{apart:e}");
}

/// The satellite with its arm driven by joint torques under a feedback law (a PD law moving the
/// joints to new angles): the torques are internal, so the total linear and angular momentum
/// of the whole system stays put to round-off over 5000 steps while the joints swing over and
/// the base turns to compensate; the forced Noether balance of the base's pose has no force in
/// it.
#[test]
fn floating_arm_under_joint_torques_keeps_its_total_momentum() {
    let h = 0.01;
    let model = floating_arm();
    let options = TextOptions {
        name: "space_arm".into(),
        torques: true,
    };
    let text = model.system_text_with(&options).unwrap();
    assert_eq!(text.controls, ["tau_shoulder", "tau_elbow"]);
    let code = lie(&text);
    let sys: JitLie<14, 8> = code.instantiate(&[0.0, 0.0, h]).unwrap();
    let r0 = cayley(&Vector3::new(0.2, 0.1, -0.3));
    let x0 = Vector3::new(0.5, -0.2, 1.0);
    let start = sys
        .state(
            &[&pose_numbers(&r0, &x0), &[0.4], &[-0.9]],
            &[&[0.3, -0.1, 0.2, 1.0, 0.5, -0.2], &[0.0], &[0.0]],
        )
        .unwrap();
    let integ = LieIntegrator::new(sys, NewtonOptions::default());
    let target = [1.5, 0.6];
    let traj = integ
        .run(start)
        .steps(5000)
        .feedback(move |_k, _t, s: &LieState<14, 8>, u: &mut [f64]| {
            u[0] = -20.0 * (s.q[12] - target[0]) - 8.0 * s.p[6];
            u[1] = -20.0 * (s.q[13] - target[1]) - 8.0 * s.p[7];
        })
        .collect()
        .unwrap();
    let (l0, a0) = (
        integ.linear_momentum(&start),
        integ.spatial_momentum(&start),
    );
    let scale = l0.norm() + a0.norm();
    let drift = traj
        .states
        .iter()
        .map(|s| (integ.linear_momentum(s) - l0).norm() + (integ.spatial_momentum(s) - a0).norm())
        .fold(0.0, f64::max);
    let last = traj.last();
    let reached = (last.q[12] - target[0])
        .abs()
        .max((last.q[13] - target[1]).abs());
    let base_turn = (Matrix3::from_fn(|i, j| last.q[3 * i + j]) - r0).amax();
    println!(
        "space arm under torques: momentum drift {:.1e} relative over 5000 steps; joints within \
         {reached:.1e} of their targets; the base turned by {base_turn:.2} (largest entry of R - R0)",
        drift / scale
    );
    assert!(drift < 1e-13 * scale, "{:e}", drift / scale);
    // Near the targets, off by what the tumbling base's motion asks of the PD law.
    assert!(reached < 5e-2, "{reached}");
    assert!(base_turn > 0.05, "{base_turn}");
}

/// A small deterministic generator (an LCG) for the random trees below.
struct Lcg(u64);

impl Lcg {
    /// A number in `[-1, 1)`.
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }

    fn vector(&mut self, scale: f64) -> Vector3<f64> {
        Vector3::new(self.next(), self.next(), self.next()) * scale
    }

    fn below(&mut self, n: usize) -> usize {
        (((self.next() + 1.0) / 2.0) * n as f64) as usize % n
    }
}

/// A random tree of four moving joints (revolute, continuous or prismatic, about random axes,
/// each from a random earlier link) and two fixed joints fusing massive links into their
/// parents, with random placements, centres of mass, inertias and gravity.
fn random_tree(seed: u64) -> Model {
    let mut rng = Lcg(seed);
    let inertial = |rng: &mut Lcg| {
        // Principal moments that satisfy the triangle inequality.
        let d = Vector3::new(0.06, 0.07, 0.08) + rng.vector(0.005);
        let turn = cayley(&rng.vector(1.0));
        Inertial::new(
            1.0 + rng.next().abs(),
            rng.vector(0.3),
            turn * Matrix3::from_diagonal(&d) * turn.transpose(),
        )
    };
    let mut builder = Model::builder().frame("l0");
    for i in 1..=6 {
        let parent = format!("l{}", rng.below(i));
        let placement = Pose::new(cayley(&rng.vector(1.0)), rng.vector(0.5));
        let axis = rng.vector(1.0) + Vector3::new(0.0, 0.0, 0.1);
        let (name, child) = (format!("j{i}"), format!("l{i}"));
        let spec = match i {
            // Two fixed joints, the rest moving.
            2 | 5 => JointSpec::fixed(name, parent, child.clone()),
            3 => JointSpec::prismatic(name, parent, child.clone(), axis),
            4 => JointSpec::new(
                name,
                parent,
                child.clone(),
                dirac_multibody::JointKind::Continuous { axis },
            ),
            _ => JointSpec::revolute(name, parent, child.clone(), axis),
        };
        builder = builder
            .body(child, inertial(&mut rng))
            .joint(spec.at(placement));
    }
    builder
        .gravity(rng.vector(10.0))
        .build()
        .expect("a random tree")
}

/// Random trees (random joint kinds, axes, placements, branching, fused links, inertias and
/// gravity): the text's energy and Legendre map are the model's `T + V` and `M(q) q̇`.
#[test]
fn random_trees_have_the_model_energy_and_mass_matrix() {
    for seed in 1..=8 {
        let model = random_tree(seed);
        assert_eq!(model.joints().len(), 4, "seed {seed}");
        let code = flat(&model.system_text().unwrap());
        let sys = code.instantiate::<4, 0, 4>(&[0.01]).unwrap();
        let mut rng = Lcg(1000 + seed);
        for _ in 0..10 {
            let q: SVector<f64, 4> = SVector::from_fn(|_, _| 2.0 * rng.next());
            let v: SVector<f64, 4> = SVector::from_fn(|_, _| 3.0 * rng.next());
            let config = model.configuration_from_scalars(q.as_slice()).unwrap();
            let energy = model.kinetic_energy(&config, v.as_slice()).unwrap()
                + model.potential_energy(&config).unwrap();
            let e = sys.energy(&q, &v).unwrap();
            assert!(
                (e - energy).abs() < 1e-12 * energy.abs().max(1.0),
                "seed {seed}: {e} {energy}"
            );
            let p = model.mass_matrix(&config).unwrap() * DVector::from_column_slice(v.as_slice());
            let legendre = sys.legendre(&q, &v).unwrap();
            let worst = (0..4)
                .map(|i| (legendre[i] - p[i]).abs())
                .fold(0.0, f64::max);
            assert!(worst < 1e-12 * p.amax().max(1.0), "seed {seed}: {worst:e}");
        }
    }
}

/// The satellite with its arm falling under gravity: the Lagrangian keeps the horizontal
/// translations and the rotations about the vertical, so the horizontal linear momentum and
/// the vertical angular momentum stay put to round-off over 1000 steps (10 s of fall), while
/// the vertical linear momentum falls by the total weight's impulse, `M g t`. (Over 5000 steps
/// the kept components drift to 2e-11 relative: Newton's residual tolerance is relative to the
/// momenta's scale, which the fall's growing vertical momentum sets.)
#[test]
fn floating_arm_in_gravity_keeps_the_momenta_gravity_allows() {
    let h = 0.01;
    let g = 9.81;
    let model = floating_arm()
        .with_gravity(Vector3::new(0.0, 0.0, -g))
        .unwrap();
    let code = lie(&model.system_text().unwrap());
    let sys: JitLie<14, 8> = code.instantiate(&[h]).unwrap();
    let r0 = cayley(&Vector3::new(0.2, 0.1, -0.3));
    let x0 = Vector3::new(0.5, -0.2, 1.0);
    let start = sys
        .state(
            &[&pose_numbers(&r0, &x0), &[0.4], &[-0.9]],
            &[&[0.3, -0.1, 0.2, 1.0, 0.5, 2.0], &[0.1], &[-0.2]],
        )
        .unwrap();
    let integ = LieIntegrator::new(sys, NewtonOptions::default());
    let traj = integ.run(start).steps(1000).collect().unwrap();
    let (l0, a0) = (
        integ.linear_momentum(&start),
        integ.spatial_momentum(&start),
    );
    let weight = model.total_mass() * g;
    let (mut kept, mut fall): (f64, f64) = (0.0, 0.0);
    for (k, s) in traj.states.iter().enumerate() {
        let (l, a) = (integ.linear_momentum(s), integ.spatial_momentum(s));
        kept = kept.max(
            (l.x - l0.x)
                .abs()
                .max((l.y - l0.y).abs())
                .max((a.z - a0.z).abs()),
        );
        fall = fall.max((l.z - (l0.z - weight * h * k as f64)).abs());
    }
    let scale = l0.norm() + a0.norm();
    println!(
        "floating arm in gravity: horizontal and vertical-axis momenta kept to {:.1e} relative \
         over 1000 steps; the vertical momentum off M g t by {fall:.1e} (M g t = {:.0})",
        kept / scale,
        weight * h * 1000.0
    );
    assert!(kept < 1e-12 * scale, "{:e}", kept / scale);
    assert!(fall < 1e-9 * weight * h * 1000.0, "{fall:e}");
}

/// The recursive step of a fixed-base tree (`ArticulatedIntegrator`: two passes over the tree,
/// GMRES corrections preconditioned by the articulated-body solve) and the compiled system text
/// of the same model (the compiler's derivatives, a dense LU) step the same discrete
/// Lagrangian: the same trajectory over 1000 steps, up to the Newton tolerance, for the 3-link
/// arm and the 7-DoF iiwa, with joint torques on the iiwa.
#[test]
fn the_recursive_step_follows_the_compiled_text() {
    use dirac_multibody::ArticulatedIntegrator;
    fn compare<const N: usize>(model: &Model, h: f64, q0: [f64; N], v0: [f64; N], torques: bool) {
        let options = TextOptions {
            torques,
            ..TextOptions::default()
        };
        let code = flat(&model.system_text_with(&options).unwrap());
        let tau: Vec<f64> = (0..N)
            .map(|j| if torques { 2.0 * wave(50 + j) } else { 0.0 })
            .collect();
        // The controls come first among the parameters, the time step last.
        let mut parameters = if torques { tau.clone() } else { Vec::new() };
        parameters.push(h);
        let sys = code.instantiate::<N, 0, N>(&parameters).unwrap();
        let compiled = UnreducedIntegrator::new(sys.clone(), NewtonOptions::default());
        let p0 = sys
            .legendre(&SVector::from(q0), &SVector::from(v0))
            .unwrap();
        let a = compiled
            .run(UnreducedState::new(q0, p0))
            .steps(1000)
            .collect()
            .unwrap();
        let recursive = ArticulatedIntegrator::new(model, h, NewtonOptions::default()).unwrap();
        let start = recursive.state(&q0, &v0).unwrap();
        assert!((0..N).all(|j| (start.p[j] - p0[j]).abs() < 1e-12 * p0.amax().max(1.0)));
        let b = recursive
            .run(start)
            .steps(1000)
            .feedback(|_, _, _: &ElementState, out: &mut [f64]| out.copy_from_slice(&tau))
            .collect()
            .unwrap();
        // Step by step: the compiled step from each state of the recursive run lands on the
        // next one, to the Newton tolerance (no accumulation).
        let mut step_gap: f64 = 0.0;
        for k in 0..1000 {
            let (x, y) = (&b.states[k], &b.states[k + 1]);
            let from = UnreducedState::new(
                SVector::<f64, N>::from_column_slice(x.q.as_slice()),
                SVector::<f64, N>::from_column_slice(x.p.as_slice()),
            );
            let (z, _) = compiled.step(k, &from).unwrap();
            let scale = y.p.amax().max(1.0);
            for j in 0..N {
                step_gap = step_gap
                    .max((z.q[j] - y.q[j]).abs())
                    .max((z.p[j] - y.p[j]).abs() / scale);
            }
        }
        // Over the run: the two trajectories part only as the motion amplifies those gaps.
        let mut run_gap: f64 = 0.0;
        for (x, y) in a.states.iter().zip(&b.states).take(101) {
            let scale = x.p.amax().max(1.0);
            for j in 0..N {
                run_gap = run_gap
                    .max((x.q[j] - y.q[j]).abs())
                    .max((x.p[j] - y.p[j]).abs() / scale);
            }
        }
        println!(
            "recursive against compiled, {N} joints: largest one-step gap {step_gap:.1e}, \
             over 100 steps {run_gap:.1e}, mean corrections {}",
            b.stats.mean_iterations()
        );
        assert!(step_gap < 1e-11, "{step_gap:e}");
        assert!(run_gap < 1e-10, "{run_gap:e}");
    }
    compare(
        &data("three_link_arm.urdf"),
        0.01,
        [1.2, 0.3, -0.2],
        [0.1, -0.05, 0.02],
        false,
    );
    compare(
        &data("iiwa14.urdf"),
        1e-3,
        [0.3, 0.5, -0.2, -1.2, 0.4, 0.7, -0.1],
        [0.5, -0.4, 0.8, 0.6, -1.0, 0.9, 1.5],
        true,
    );
}

// ---------------------------------------------------------------------------------------------
// Spherical joints.

/// A rigid pendulum on a ball joint written by hand: the bob's rotation `R` about the pivot
/// (its frame at the pivot), its centre of mass at `c` in that frame, its inertia `I` about the
/// centre of mass: `L = ½ m |Ω × c|² + ½ Ωᵀ I Ω + m (Rᵀ g)·c`.
#[reduced_lagrangian(rotation(ball), rule = trapezoid)]
fn ball_pendulum(q: Config, v: Velocity) -> f64 {
    let c = Vector3::new(0.05, -0.02, -0.5);
    let inertia = Matrix3::new(0.03, 0.002, 0.0, 0.002, 0.025, 0.001, 0.0, 0.001, 0.01);
    let g = Vector3::new(0.0, 0.0, -9.81);
    let w = v.ball;
    0.5 * 1.3 * w.cross(&c).norm_squared()
        + 0.5 * w.dot(&(inertia * w))
        + 1.3 * (q.ball.transpose() * g).dot(&c)
}

fn ball_pendulum_model() -> Model {
    let inertia = Matrix3::new(0.03, 0.002, 0.0, 0.002, 0.025, 0.001, 0.0, 0.001, 0.01);
    Model::builder()
        .frame("world")
        .body(
            "bob",
            Inertial::new(1.3, Vector3::new(0.05, -0.02, -0.5), inertia),
        )
        .joint(JointSpec::spherical("ball", "world", "bob"))
        .gravity(Vector3::new(0.0, 0.0, -9.81))
        .build()
        .unwrap()
}

/// A spherical joint is a rotation coordinate: the pendulum on a ball joint built in Rust
/// steps as the one written by hand, to 1e-12 over 1000 steps.
#[test]
fn a_ball_joint_pendulum_steps_as_written_by_hand() {
    let h = 0.01;
    let text = ball_pendulum_model().system_text().unwrap();
    assert_eq!(text.kind, TextKind::SphericalJoints);
    let Compiled::Lie(code) = dirac_jit::compile_any(&text.text).unwrap() else {
        panic!("a spherical joint is on rotation groups")
    };
    let given: JitLie<9, 3> = code.instantiate(&[h]).unwrap();
    let by_hand = BallPendulum { h };
    let r0 = cayley(&Vector3::new(0.4, -0.3, 0.2));
    let q: [f64; 9] = std::array::from_fn(|k| r0[(k / 3, k % 3)]);
    let start = LieState::from_row_major(q, [0.2, -0.4, 0.3]);
    let a = LieIntegrator::new(given, NewtonOptions::default())
        .run(start)
        .steps(1000)
        .collect()
        .unwrap();
    let b = LieIntegrator::new(by_hand, NewtonOptions::default())
        .run(start)
        .steps(1000)
        .collect()
        .unwrap();
    let worst = a
        .states
        .iter()
        .zip(&b.states)
        .map(|(x, y)| (x.q - y.q).amax().max((x.p - y.p).amax()))
        .fold(0.0, f64::max);
    println!("ball pendulum: model against by hand, largest gap {worst:.1e} over 1000 steps");
    assert!(worst < 1e-12, "{worst:e}");
}

/// `cay⁻¹(F) = 2 vee(F − Fᵀ)/(1 + tr F)`.
fn cayley_inverse(f: &Matrix3<f64>) -> Vector3<f64> {
    let s = f - f.transpose();
    Vector3::new(s[(2, 1)], s[(0, 2)], s[(1, 0)]) * (2.0 / (1.0 + f.trace()))
}

/// A chain of a ball joint, a hinge and a slider: the text's `L_d(q_0, q_1)` is the trapezoid
/// rule of the model's own `T − V` (its kinematics written independently), with the ball's body
/// angular velocity `cay⁻¹(R_0ᵀ R_1)/h` and the scalars' chords, at sample pairs.
#[test]
fn a_chain_with_a_ball_joint_has_the_models_lagrangian() {
    let body = |m: f64, c: [f64; 3]| {
        Inertial::new(
            m,
            Vector3::from(c),
            Matrix3::new(0.04, 0.003, 0.0, 0.003, 0.05, -0.002, 0.0, -0.002, 0.03),
        )
    };
    let model = Model::builder()
        .frame("world")
        .body("a", body(2.0, [0.1, 0.0, -0.3]))
        .body("b", body(1.0, [0.0, 0.1, -0.2]))
        .body("c", body(0.5, [0.05, 0.0, 0.1]))
        .joint(JointSpec::spherical("ball", "world", "a"))
        .joint(
            JointSpec::revolute("hinge", "a", "b", Vector3::new(0.0, 0.6, 0.8))
                .at(Pose::from_xyz_rpy([0.1, 0.0, -0.6], [0.2, 0.0, 0.1])),
        )
        .joint(
            JointSpec::prismatic("slide", "b", "c", Vector3::x())
                .at(Pose::from_xyz_rpy([0.0, 0.0, -0.4], [0.0, 0.3, 0.0])),
        )
        .gravity(Vector3::new(0.5, -1.0, -9.5))
        .build()
        .unwrap();
    let text = model.system_text().unwrap();
    assert!(
        text.text.contains("rotation(ball), shape(hinge, slide)"),
        "{}",
        text.text
    );
    let Compiled::Lie(code) = dirac_jit::compile_any(&text.text).unwrap() else {
        panic!("a spherical joint is on rotation groups")
    };
    let h = 0.01;
    let sys: JitLie<11, 5> = code.instantiate(&[h]).unwrap();
    let lagrangian = |r: &Matrix3<f64>, s: [f64; 2], v: &[f64]| {
        let mut config = model.neutral_configuration();
        config.positions[0] = JointPosition::Rotation(*r);
        config.positions[1] = JointPosition::Scalar(s[0]);
        config.positions[2] = JointPosition::Scalar(s[1]);
        model.kinetic_energy(&config, v).unwrap() - model.potential_energy(&config).unwrap()
    };
    for k in 0..10 {
        let r0 = cayley(&Vector3::new(wave(3 * k), wave(3 * k + 1), wave(3 * k + 2)));
        let f = cayley(&(Vector3::new(wave(40 + k), wave(50 + k), wave(60 + k)) * 0.05));
        let r1 = r0 * f;
        let (s0, s1) = (
            [wave(70 + k), 0.3 * wave(80 + k)],
            [wave(90 + k), 0.3 * wave(100 + k)],
        );
        let omega = cayley_inverse(&f) / h;
        let v = [
            omega.x,
            omega.y,
            omega.z,
            (s1[0] - s0[0]) / h,
            (s1[1] - s0[1]) / h,
        ];
        let expected = 0.5 * h * (lagrangian(&r0, s0, &v) + lagrangian(&r1, s1, &v));
        let point = |r: &Matrix3<f64>, s: [f64; 2]| {
            let mut q = SVector::<f64, 11>::zeros();
            for i in 0..9 {
                q[i] = r[(i / 3, i % 3)];
            }
            q[9] = s[0];
            q[10] = s[1];
            q
        };
        let found = sys.lagrangian(&point(&r0, s0), &point(&r1, s1));
        assert!(
            (found - expected).abs() < 1e-12 * expected.abs().max(1.0),
            "{found} {expected}"
        );
    }
}
