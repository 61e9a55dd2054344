//! Systems on rotation groups given as text against the same systems compiled in: the facade's
//! rigid body, heavy top, satellite with a reaction wheel and double spherical pendulum on two
//! spheres, and systems written here once for both (a continuous Lagrangian, six bodies on the
//! sparse backend, adaptive steps, a rigid body in space as one pose, discrete and continuous). Every integrator — the Lie group variational step on both
//! sides, the reduced steps of both kinds of symmetry, compositions, controls, sensitivities
//! and adaptive steps — takes the same steps bit for bit.

use std::sync::Arc;

use dirac::prelude::*;
use dirac::runtime::lie::{cayley, LiePartials};
use dirac::systems::rotations::{DspOnSpheres, HeavyTop, RigidBody, Satellite, SatelliteConfig};
use dirac_jit::{compile_lie, JitLie, LieCode};

use super::{function, same};

const ROTATIONS: &str = include_str!("../../../src/systems/rotations.rs");

fn lie_code(source: &str, name: &str) -> Arc<LieCode> {
    compile_lie(&function(source, name)).unwrap_or_else(|e| panic!("{name}:\n{e}"))
}

/// The (+) and (−) runs, and a triple-jump composition, of both systems from `start`.
fn same_lie_runs<L, J, const P: usize, const N: usize>(
    compiled: L,
    jit: J,
    start: LieState<P, N>,
    steps: usize,
) where
    L: LieLagrangian<P, N>,
    J: LieLagrangian<P, N>,
{
    let opts = NewtonOptions::default();
    let a = LieIntegrator::new(compiled.clone(), opts)
        .run(start)
        .steps(steps)
        .collect()
        .unwrap();
    let b = LieIntegrator::new(jit.clone(), opts)
        .run(start)
        .steps(steps)
        .collect()
        .unwrap();
    same(&a.states, &b.states, "(+)");
    same(&a.stats, &b.stats, "(+) Newton statistics");
    let a = LieIntegrator::minus(compiled.clone(), opts)
        .run(start)
        .steps(steps)
        .collect()
        .unwrap();
    let b = LieIntegrator::minus(jit.clone(), opts)
        .run(start)
        .steps(steps)
        .collect()
        .unwrap();
    same(&a.states, &b.states, "(−)");
    let a = Composition::new(
        LieIntegrator::new(compiled, opts),
        CompositionMethod::TRIPLE_JUMP,
    )
    .run(start)
    .steps(steps / 10)
    .collect()
    .unwrap();
    let b = Composition::new(
        LieIntegrator::new(jit, opts),
        CompositionMethod::TRIPLE_JUMP,
    )
    .run(start)
    .steps(steps / 10)
    .collect()
    .unwrap();
    same(&a.states, &b.states, "triple jump");
}

/// The reduced runs of both systems from `start`.
fn same_reduced_runs<L, J, const P: usize, const N: usize>(
    compiled: L,
    jit: J,
    start: LieState<P, N>,
    steps: usize,
) where
    L: LieSymmetric<P, N>,
    J: LieSymmetric<P, N>,
{
    let opts = NewtonOptions::default();
    let a = ReducedLieIntegrator::new(compiled, opts);
    let b = ReducedLieIntegrator::new(jit, opts);
    assert_eq!(a.system().symmetry(), b.system().symmetry(), "the symmetry");
    let (sa, sb) = (a.reduce(&start), b.reduce(&start));
    assert_eq!(sa, sb, "the momentum map");
    let ta = a.run(sa).steps(steps).collect().unwrap();
    let tb = b.run(sb).steps(steps).collect().unwrap();
    same(&ta.states, &tb.states, "reduced");
}

/// The names, kinds and parameters the integrators and output read.
fn same_description<L, J, const P: usize, const N: usize>(compiled: &L, jit: &J)
where
    L: LieLagrangian<P, N>,
    J: LieLagrangian<P, N>,
{
    let all = |s: &dyn Fn(usize) -> Option<(String, CoordinateKind)>| {
        (0..).map_while(s).collect::<Vec<_>>()
    };
    assert_eq!(
        all(&|i| compiled.coordinate(i).map(|(n, k)| (n.to_owned(), k))),
        all(&|i| jit.coordinate(i).map(|(n, k)| (n.to_owned(), k)))
    );
    assert_eq!(compiled.parameter_names(), jit.parameter_names());
    assert_eq!(compiled.parameter_values(), jit.parameter_values());
    assert_eq!(compiled.control_count(), jit.control_count());
    assert_eq!(compiled.control_names(), jit.control_names());
    assert_eq!(compiled.coordinate_names(), jit.coordinate_names());
    assert_eq!(compiled.time_index(), jit.time_index());
}

/// `L_d` at two nearby points, to round-off: the text's `R0ᵀ R1` is formed entry by entry where
/// the compiled-in function multiplies nalgebra matrices.
fn same_lagrangian<L, J, const P: usize, const N: usize>(compiled: &L, jit: &J, q: &LieState<P, N>)
where
    L: LieLagrangian<P, N>,
    J: LieLagrangian<P, N>,
{
    let z = SVector::<f64, N>::from_fn(|i, _| 0.01 * (i as f64 + 1.0));
    let q1 = compiled.retract(&q.q, &z);
    assert_eq!(q1, jit.retract(&q.q, &z), "the retraction");
    let (a, b) = (compiled.lagrangian(&q.q, &q1), jit.lagrangian(&q.q, &q1));
    assert!((a - b).abs() <= 1e-14 * a.abs().max(1.0), "L_d: {a} vs {b}");
}

#[test]
fn the_rigid_body_steps_bit_for_bit_reduced_or_not() {
    let code = lie_code(ROTATIONS, "rigid_body");
    assert_eq!(code.system().name, "RigidBody");
    let compiled = RigidBody {
        h: 0.01,
        j1: 1.0,
        j2: 2.0,
        j3: 3.0,
    };
    let jit: JitLie<9, 3> = code.instantiate(&compiled.parameter_values()).unwrap();
    let r = cayley(&Vector3::new(0.1, 0.2, -0.3));
    let start = jit
        .state(&[r.transpose().as_slice()], &[&[0.3, 1.0, 0.2]])
        .unwrap();
    assert_eq!(
        start,
        compiled.state(
            &dirac::systems::rotations::RigidBodyConfig { r },
            &dirac::systems::rotations::RigidBodyMomentum {
                r: Vector3::new(0.3, 1.0, 0.2)
            }
        )
    );
    same_description(&compiled, &jit);
    same_lagrangian(&compiled, &jit, &start);
    same_lie_runs(compiled, jit, start, 500);
    let reduced = code
        .instantiate_reduced::<9, 3>(&compiled.parameter_values())
        .unwrap();
    same_reduced_runs(compiled, reduced, start, 500);
}

#[test]
fn the_heavy_top_steps_bit_for_bit_reduced_about_its_axis() {
    let code = lie_code(ROTATIONS, "heavy_top");
    let compiled = HeavyTop {
        h: 0.01,
        j1: 1.0,
        j2: 1.0,
        j3: 0.5,
        mgl: 2.0,
    };
    let jit: JitLie<9, 3> = code.instantiate(&compiled.parameter_values()).unwrap();
    let r = cayley(&Vector3::new(0.4, -0.1, 0.2));
    let start = jit
        .state(&[r.transpose().as_slice()], &[&[0.2, -0.1, 3.0]])
        .unwrap();
    same_description(&compiled, &jit);
    same_lagrangian(&compiled, &jit, &start);
    same_lie_runs(compiled, jit, start, 500);
    let reduced = code
        .instantiate_reduced::<9, 3>(&compiled.parameter_values())
        .unwrap();
    same_reduced_runs(compiled, reduced, start, 500);
}

#[test]
fn the_double_spherical_pendulum_on_two_spheres_steps_bit_for_bit() {
    let code = lie_code(ROTATIONS, "dsp_on_spheres");
    let compiled = DspOnSpheres::paper(0.01);
    let jit: JitLie<18, 4> = code.instantiate(&compiled.parameter_values()).unwrap();
    let start = compiled.paper_initial_state();
    // The same state from the unit vectors and the momenta in space.
    let m = jit.momenta(&start);
    let q = jit.configuration(&start.q);
    let again = jit.state(&[&q[0], &q[1]], &[&m[0], &m[1]]).unwrap();
    assert_eq!(again.q, start.q);
    assert!((again.p - start.p).norm() < 1e-15 * start.p.norm());
    same_description(&compiled, &jit);
    same_lagrangian(&compiled, &jit, &start);
    same_lie_runs(compiled, jit, start, 500);
    let reduced = code
        .instantiate_reduced::<18, 4>(&compiled.parameter_values())
        .unwrap();
    same_reduced_runs(compiled, reduced, start, 500);
}

#[test]
fn the_satellite_steps_bit_for_bit_under_control_with_the_same_sensitivities() {
    let code = lie_code(ROTATIONS, "satellite");
    let compiled = Satellite {
        h: 0.01,
        j1: 2.0,
        j2: 3.0,
        j3: 4.0,
        jw: 0.5,
        u: 0.0,
    };
    let jit: JitLie<10, 4> = code.instantiate(&compiled.parameter_values()).unwrap();
    let start = compiled.state(
        &SatelliteConfig {
            r: cayley(&Vector3::new(0.1, 0.2, -0.3)),
            phi: 0.0,
        },
        &dirac::systems::rotations::SatelliteMomentum {
            r: Vector3::new(0.4, -0.2, 1.0),
            phi: 0.7,
        },
    );
    same_description(&compiled, &jit);
    same_lie_runs(compiled, jit.clone(), start, 300);
    let law = |_: usize, t: f64, s: &LieState<10, 4>, u: &mut [f64]| {
        u[0] = 0.3 * (2.0 * t).sin() - 0.1 * s.p[3];
    };
    let opts = NewtonOptions::default();
    let a = LieIntegrator::new(compiled, opts)
        .run(start)
        .steps(300)
        .feedback(law)
        .collect()
        .unwrap();
    let b = LieIntegrator::new(jit.clone(), opts)
        .run(start)
        .steps(300)
        .feedback(law)
        .collect()
        .unwrap();
    same(&a.states, &b.states, "under feedback");
    let z = SVector::<f64, 4>::new(0.01, -0.02, 0.005, 0.03);
    let pa: LiePartials = compiled.step_partials(&start.q, &start.p, &z).unwrap();
    let pb = jit.step_partials(&start.q, &start.p, &z).unwrap();
    assert_eq!(pa, pb, "the step's partial derivatives");
    let a = LieIntegrator::new(compiled, opts)
        .step_sensitivity(0, &start, &[0.3])
        .unwrap();
    let b = LieIntegrator::new(jit, opts)
        .step_sensitivity(0, &start, &[0.3])
        .unwrap();
    assert_eq!(a, b, "the step's sensitivity");
    let reduced = code
        .instantiate_reduced::<10, 4>(&compiled.parameter_values())
        .unwrap();
    same_reduced_runs(compiled, reduced, start, 300);
}

compiled_and_text!(SPINNING:
    /// A free body as a continuous Lagrangian in its body angular velocity, discretized by the
    /// trapezoid rule.
    #[reduced_lagrangian(rotation(r), rule = trapezoid, symmetry(r))]
    fn spinning(_q: Config, v: Velocity, j1: f64, j2: f64, j3: f64) -> f64 {
        0.5 * (j1 * v.r.x * v.r.x + j2 * v.r.y * v.r.y + j3 * v.r.z * v.r.z)
    }
);

#[test]
fn a_continuous_lagrangian_steps_bit_for_bit() {
    let code = compile_lie(SPINNING).unwrap();
    assert!(code.system().continuous);
    let compiled = Spinning {
        j1: 1.0,
        j2: 2.0,
        j3: 3.0,
        h: 0.02,
    };
    let jit: JitLie<9, 3> = code.instantiate(&compiled.parameter_values()).unwrap();
    let start = jit
        .state(
            &[cayley(&Vector3::new(0.3, 0.0, 0.1)).transpose().as_slice()],
            &[&[1.0, 0.5, -0.3]],
        )
        .unwrap();
    same_description(&compiled, &jit);
    same_lagrangian(&compiled, &jit, &start);
    same_lie_runs(compiled, jit, start, 300);
}

compiled_and_text!(SIX_BODIES:
    /// Six free bodies in one system: 18 chart coordinates, the sparse backend.
    #[reduced_lagrangian(rotation(r1, r2, r3, r4, r5, r6))]
    fn six_bodies(q0: Config, q1: Config, h: f64) -> f64 {
        let jd = Matrix3::from_diagonal(&Vector3::new(2.0, 1.0, 0.0));
        let one = Matrix3::identity();
        let f = [
            q0.r1.transpose() * q1.r1,
            q0.r2.transpose() * q1.r2,
            q0.r3.transpose() * q1.r3,
        ];
        let g = [
            q0.r4.transpose() * q1.r4,
            q0.r5.transpose() * q1.r5,
            q0.r6.transpose() * q1.r6,
        ];
        (((one - f[0]) * jd).trace()
            + ((one - f[1]) * jd).trace() * 2.0
            + ((one - f[2]) * jd).trace() * 3.0
            + ((one - g[0]) * jd).trace() * 4.0
            + ((one - g[1]) * jd).trace() * 5.0
            + ((one - g[2]) * jd).trace() * 6.0)
            / h
    }
);

#[test]
fn six_bodies_step_bit_for_bit_on_the_sparse_backend() {
    let code = compile_lie(SIX_BODIES).unwrap();
    let compiled = SixBodies { h: 0.01 };
    assert!(code.instantiate::<54, 18>(&[0.01]).is_err(), "dense at 18");
    let jit = code.instantiate_sparse::<54, 18>(&[0.01]).unwrap();
    let rotations: Vec<Vec<f64>> = (1..=6)
        .map(|i| {
            cayley(&Vector3::new(0.1 * f64::from(i), -0.2, 0.3))
                .transpose()
                .as_slice()
                .to_vec()
        })
        .collect();
    let momenta: Vec<[f64; 3]> = (1..=6).map(|i| [0.3, 1.0, -0.2 * f64::from(i)]).collect();
    let q: Vec<&[f64]> = rotations.iter().map(Vec::as_slice).collect();
    let p: Vec<&[f64]> = momenta.iter().map(|m| &m[..]).collect();
    let start = jit.state(&q, &p).unwrap();
    same_lie_runs(compiled, jit, start, 200);
}

compiled_and_text!(SWINGING:
    /// The spherical pendulum with adaptive steps, shorter near the bottom.
    #[reduced_lagrangian(direction(n), group(t), rule = trapezoid, symmetry(n, axis = z),
        time(t), adapt = |q| 1.5 + q.n.z)]
    fn swinging(q: Config, v: Velocity, g: f64) -> f64 {
        0.5 * v.n.dot(&v.n) - g * q.n.z
    }
);

#[test]
fn adaptive_steps_on_a_sphere_are_bit_for_bit() {
    let code = compile_lie(SWINGING).unwrap();
    let compiled = Swinging { g: 1.0, h: 0.05 };
    let jit: JitLie<10, 3> = code.instantiate(&compiled.parameter_values()).unwrap();
    let n = Vector3::new(0.6, 0.0, -0.8);
    let start = compiled
        .unreduced_state(
            &SwingingConfig { n, t: 0.0 },
            &SwingingVelocity {
                n: Vector3::new(0.0, 0.7, 0.0),
                t: 1.0,
            },
        )
        .unwrap();
    let q = jit.configuration(&start.q);
    let point = jit.state(&[&q[0], &q[1]], &[&[0.0; 3], &[0.0]]).unwrap().q;
    assert_eq!(
        jit.unreduced_state(&point, &[0.0, 0.7, 0.0, 1.0]).unwrap(),
        start
    );
    assert!(jit.unreduced_state(&point, &[0.0, 0.7]).is_err());
    same_description(&compiled, &jit);
    same_lie_runs(compiled, jit, start, 400);
    let reduced = code
        .instantiate_reduced::<10, 3>(&compiled.parameter_values())
        .unwrap();
    same_reduced_runs(compiled, reduced, start, 400);
}

#[test]
fn the_wrong_dimensions_or_kind_are_errors() {
    let code = lie_code(ROTATIONS, "rigid_body");
    let e = code
        .instantiate::<9, 4>(&[0.01, 1.0, 2.0, 3.0])
        .unwrap_err();
    assert!(e.to_string().contains("P = 9, N = 4"), "{e}");
    let e = code
        .instantiate_sparse::<9, 3>(&[0.01, 1.0, 2.0, 3.0])
        .unwrap_err();
    assert!(e.to_string().contains("instantiate"), "{e}");
    let body = code.instantiate::<9, 3>(&[0.01, 1.0, 2.0, 3.0]).unwrap();
    let e = body.state(&[&[1.0; 9]], &[&[0.0; 3]]).unwrap_err();
    assert!(e.to_string().contains("is not a rotation"), "{e}");
    let e = compile_lie(SIX_BODIES)
        .unwrap()
        .instantiate_reduced_sparse::<54, 18>(&[0.01])
        .unwrap_err();
    assert!(e.to_string().contains("declares no symmetry"), "{e}");
    // The other kind of text, each way.
    let e = dirac_jit::compile(&function(ROTATIONS, "rigid_body")).unwrap_err();
    assert!(e.to_string().contains("compile_lie"), "{e}");
    let flat = "#[reduced_lagrangian(shape(x), group())]\n\
                fn f(q0: Config, q1: Config, h: f64) -> f64 { (q1.x - q0.x) * (q1.x - q0.x) / h }";
    let e = compile_lie(flat).unwrap_err();
    assert!(e.to_string().contains("compiles with `compile`"), "{e}");
    assert!(matches!(
        dirac_jit::compile_any(&function(ROTATIONS, "rigid_body")),
        Ok(dirac_jit::Compiled::Lie(_))
    ));
    assert!(matches!(
        dirac_jit::compile_any(flat),
        Ok(dirac_jit::Compiled::Flat(_))
    ));
}

compiled_and_text!(BODY_IN_SPACE:
    /// A rigid body in space as one pose (`J = diag(1, 2, 3)`, so `J_d = diag(2, 1, 0)`): the
    /// Lie group variational integrator's kinetic term, gravity by the trapezoid rule, and a
    /// thrust along the body's third axis as the trapezoid rule's discrete forces.
    #[reduced_lagrangian(pose(b),
        force = |dq0, dq1| 0.5 * h * thrust
            * ((q0.b.rotation * Vector3::z()).dot(&dq0.b.linear)
                + (q1.b.rotation * Vector3::z()).dot(&dq1.b.linear)))]
    fn body_in_space(q0: Config, q1: Config, h: f64, m: f64, g: f64, thrust: f64) -> f64 {
        let jd = Matrix3::from_diagonal(&Vector3::new(2.0, 1.0, 0.0));
        let f = q0.b.rotation.transpose() * q1.b.rotation;
        let dx = q1.b.translation - q0.b.translation;
        ((Matrix3::identity() - f) * jd).trace() / h + 0.5 * m * dx.norm_squared() / h
            - 0.5 * h * m * g * (q0.b.translation.z + q1.b.translation.z)
    }
);

compiled_and_text!(FLYING_BODY:
    /// The same body as a continuous Lagrangian in its body angular velocity and its velocity
    /// in space, the thrust a force, both by the trapezoid rule.
    #[reduced_lagrangian(pose(b), rule = trapezoid,
        force = |dq| thrust * (q.b.rotation * Vector3::z()).dot(&dq.b.linear))]
    fn flying_body(q: Config, v: Velocity, m: f64, g: f64, thrust: f64) -> f64 {
        let (omega, xdot) = (v.b.angular, v.b.linear);
        0.5 * (omega.x * omega.x + 2.0 * omega.y * omega.y + 3.0 * omega.z * omega.z)
            + 0.5 * m * xdot.norm_squared()
            - m * g * q.b.translation.z
    }
);

/// A tumbling, drifting pose as the text's systems take it (`R` row by row, then `x`) and its
/// momentum `(Π, p)`.
fn pose_value() -> (Vec<f64>, [f64; 6]) {
    let r = cayley(&Vector3::new(0.3, -0.2, 0.4));
    let mut value = dirac::lie::rows(&r).to_vec();
    value.extend([1.0, -2.0, 0.5]);
    (value, [0.4, 1.0, -0.3, 0.9, -0.3, 0.6])
}

#[test]
fn a_body_in_space_steps_bit_for_bit() {
    let code = compile_lie(BODY_IN_SPACE).unwrap();
    let compiled = BodyInSpace {
        h: 0.01,
        m: 3.0,
        g: 9.81,
        thrust: 40.0,
    };
    let jit: JitLie<12, 6> = code.instantiate(&compiled.parameter_values()).unwrap();
    let (value, momentum) = pose_value();
    let start = jit.state(&[&value], &[&momentum]).unwrap();
    let emitted = compiled.state(
        &BodyInSpaceConfig {
            b: BodyInSpacePose {
                rotation: cayley(&Vector3::new(0.3, -0.2, 0.4)),
                translation: Vector3::new(1.0, -2.0, 0.5),
            },
        },
        &BodyInSpaceMomentum {
            b: BodyInSpacePoseMomentum {
                angular: Vector3::new(0.4, 1.0, -0.3),
                linear: Vector3::new(0.9, -0.3, 0.6),
            },
        },
    );
    assert_eq!(start, emitted);
    assert_eq!(jit.configuration(&start.q), vec![value]);
    assert_eq!(jit.momenta(&start), vec![momentum.to_vec()]);
    same_description(&compiled, &jit);
    same_lagrangian(&compiled, &jit, &start);
    // The momentum map of the rigid motions, read through either system.
    let (a, b) = (
        LieIntegrator::new(compiled, NewtonOptions::default()),
        LieIntegrator::new(jit.clone(), NewtonOptions::default()),
    );
    assert_eq!(a.rigid_momentum(&start), b.rigid_momentum(&start));
    same_lie_runs(compiled, jit, start, 300);
}

#[test]
fn a_continuous_body_in_space_steps_bit_for_bit() {
    let code = compile_lie(FLYING_BODY).unwrap();
    assert!(code.system().continuous);
    let compiled = FlyingBody {
        h: 0.01,
        m: 3.0,
        g: 9.81,
        thrust: 40.0,
    };
    let jit: JitLie<12, 6> = code.instantiate(&compiled.parameter_values()).unwrap();
    let (value, momentum) = pose_value();
    let start = jit.state(&[&value], &[&momentum]).unwrap();
    same_description(&compiled, &jit);
    same_lagrangian(&compiled, &jit, &start);
    same_lie_runs(compiled, jit, start, 300);
}
