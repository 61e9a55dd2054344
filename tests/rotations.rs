//! Rotations and directions: Lie group variational integrators from `#[reduced_lagrangian]`
//! with `rotation(..)` and `direction(..)` coordinates, checked against a hand-written LGVI.

use dirac::lie::{cayley, hat, orthogonality_defect};
use dirac::nalgebra::{DMatrix, DVector};
use dirac::prelude::*;
use dirac::systems::rotations::{
    DspOnSpheres, DspOnSpheresConfig, DspOnSpheresMomentum, HeavyTop, HeavyTopConfig,
    HeavyTopMomentum, RigidBody, RigidBodyConfig, RigidBodyMomentum, Satellite, SatelliteConfig,
    SatelliteMomentum,
};

#[path = "../examples/common/lgvi.rs"]
mod lgvi;

fn body() -> (RigidBody, Matrix3<f64>) {
    let sys = RigidBody {
        h: 0.01,
        j1: 1.0,
        j2: 2.0,
        j3: 3.0,
    };
    (sys, lgvi::nonstandard(&Vector3::new(1.0, 2.0, 3.0)))
}

#[test]
fn the_rigid_body_matches_a_hand_written_lgvi() {
    let (sys, jd) = body();
    let integ = LieIntegrator::new(sys, NewtonOptions::default());
    let s0 = sys.state(
        &RigidBodyConfig {
            r: cayley(&Vector3::new(0.2, -0.1, 0.4)),
        },
        &RigidBodyMomentum {
            r: Vector3::new(0.3, 1.0, -0.2),
        },
    );
    let traj = integ.run(s0).steps(1000).collect().unwrap();
    let (mut r, mut pi, mut xi) = (sys.config(&s0).r, sys.momenta(&s0).r, Vector3::zeros());
    let mut worst: f64 = 0.0;
    for k in 1..=1000 {
        (r, pi, xi) = lgvi::rigid_body_step(&jd, sys.h, &r, &pi, xi, 1e-16, &mut 0);
        let s = &traj.states[k];
        worst = worst
            .max((sys.config(s).r - r).amax())
            .max((sys.momenta(s).r - pi).amax());
    }
    assert!(worst < 1e-12, "{worst:e}");
}

#[test]
fn spatial_momentum_and_orthogonality_over_long_runs() {
    let (sys, _) = body();
    let integ = LieIntegrator::new(sys, NewtonOptions::default());
    let s0 = sys.state(
        &RigidBodyConfig {
            r: Matrix3::identity(),
        },
        &RigidBodyMomentum {
            r: Vector3::new(0.3, 1.0, -0.2),
        },
    );
    let pi0 = integ.spatial_momentum(&s0);
    let (mut drift, mut orth): (f64, f64) = (0.0, 0.0);
    integ
        .run(s0)
        .steps(100_000)
        .observe(|_, _, s: &LieState<9, 3>, _| {
            drift = drift.max((integ.spatial_momentum(s) - pi0).norm());
            orth = orth.max(orthogonality_defect(&sys.config(s).r));
        })
        .stream()
        .unwrap();
    // Discrete Noether for the rotation of the body in space, and products of rotations only:
    // no projection.
    assert!(
        drift < 1e-12 * pi0.norm(),
        "spatial momentum drift {drift:e}"
    );
    assert!(orth < 1e-12, "|RᵀR − I| = {orth:e}");
}

#[path = "../examples/common/cartesian_dsp.rs"]
#[allow(dead_code)]
mod cartesian;

/// The Cartesian state `(r1, r2, p1, p2)` on `S² × S²`: `n1 = r1/l1`, `n2 = (r2 − r1)/l2`, and
/// the momenta of the directions from `δr1 = l1 δn1`, `δr2 = l1 δn1 + l2 δn2`:
/// `P_n1 = l1 (p1 + p2)`, `P_n2 = l2 p2` (their tangent parts).
fn on_spheres(sys: &DspOnSpheres, s: &UnreducedState<6>) -> LieState<18, 4> {
    let r1 = Vector3::new(s.q[0], s.q[1], s.q[2]);
    let r2 = Vector3::new(s.q[3], s.q[4], s.q[5]);
    let p1 = Vector3::new(s.p[0], s.p[1], s.p[2]);
    let p2 = Vector3::new(s.p[3], s.p[4], s.p[5]);
    sys.state(
        &DspOnSpheresConfig {
            n1: r1 / sys.l1,
            n2: (r2 - r1) / sys.l2,
        },
        &DspOnSpheresMomentum {
            n1: (p1 + p2) * sys.l1,
            n2: p2 * sys.l2,
        },
    )
}

fn tight() -> NewtonOptions {
    NewtonOptions {
        abs_tol: 1e-13,
        rel_tol: 1e-13,
        ..NewtonOptions::default()
    }
}

#[test]
fn the_double_spherical_pendulum_on_two_spheres_is_the_cartesian_run() {
    // The same discrete Lagrangian on the same manifold: the same discrete trajectory, up to the
    // Newton tolerances (the Cartesian run keeps its rods to the tolerance) and the growth of
    // small differences in this chaotic motion (about ×10 per 100 steps from the paper's state).
    let h = 0.01;
    let (csys, c0) = cartesian::cartesian_initial(h);
    let sys = DspOnSpheres {
        h,
        m1: csys.m1,
        m2: csys.m2,
        l1: csys.l1,
        l2: csys.l2,
        g: csys.g,
    };
    let cart = ConstrainedIntegrator::new(csys, tight())
        .run(c0)
        .steps(300)
        .collect()
        .unwrap();
    let integ = LieIntegrator::new(sys, tight());
    let sphere = integ
        .run(on_spheres(&sys, &c0))
        .steps(300)
        .collect()
        .unwrap();
    let (mut worst, mut unit): (f64, f64) = (0.0, 0.0);
    for (c, s) in cart.states.iter().zip(&sphere.states) {
        let q = sys.config(s);
        let r2 = q.n1 * sys.l1 + q.n2 * sys.l2;
        worst = worst.max((r2 - Vector3::new(c.q[3], c.q[4], c.q[5])).amax());
        unit = unit
            .max((q.n1.norm() - 1.0).abs())
            .max((q.n2.norm() - 1.0).abs());
    }
    assert!(
        worst < 5e-9,
        "bob 2 differs from the Cartesian run by {worst:e}"
    );
    assert!(unit < 1e-15, "| |n| - 1 | = {unit:e}");
}

/// Bob 2 at `T = 1` from the paper's state with `steps` steps.
fn bob2_at_one(steps: usize) -> Vector3<f64> {
    let h = 1.0 / steps as f64;
    let (csys, c0) = cartesian::cartesian_initial(h);
    let sys = DspOnSpheres {
        h,
        m1: csys.m1,
        m2: csys.m2,
        l1: csys.l1,
        l2: csys.l2,
        g: csys.g,
    };
    let integ = LieIntegrator::new(sys, tight());
    let last = *integ
        .run(on_spheres(&sys, &c0))
        .steps(steps)
        .collect()
        .unwrap()
        .last();
    let q = sys.config(&last);
    q.n1 * sys.l1 + q.n2 * sys.l2
}

#[test]
fn the_double_spherical_pendulum_on_two_spheres_has_order_two() {
    let reference = bob2_at_one(3200);
    let e: Vec<f64> = [20, 40, 80]
        .iter()
        .map(|&n| (bob2_at_one(n) - reference).norm())
        .collect();
    for w in e.windows(2) {
        let order = (w[0] / w[1]).log2();
        assert!(
            (order - 2.0).abs() < 0.15,
            "observed order {order} from errors {e:?}"
        );
    }
}

/// The free rigid body's exact flow from `(R, Π)` over `t`: Euler's equations `Π̇ = Π × Ω`,
/// `Ω = J⁻¹ Π`, and `Ṙ = R Ω̂`, by the classical Runge–Kutta method with 20,000 steps per unit
/// time (error far below the integrators' at the steps tested).
fn rigid_body_exact(
    j: &Vector3<f64>,
    r: &Matrix3<f64>,
    pi: &Vector3<f64>,
    t: f64,
) -> (Matrix3<f64>, Vector3<f64>) {
    let f = |r: &Matrix3<f64>, pi: &Vector3<f64>| {
        let omega = pi.component_div(j);
        (r * hat(&omega), pi.cross(&omega))
    };
    let n = (20_000.0 * t).ceil() as usize;
    let dt = t / n as f64;
    let (mut r, mut pi) = (*r, *pi);
    for _ in 0..n {
        let (a1, b1) = f(&r, &pi);
        let (a2, b2) = f(&(r + a1 * (dt / 2.0)), &(pi + b1 * (dt / 2.0)));
        let (a3, b3) = f(&(r + a2 * (dt / 2.0)), &(pi + b2 * (dt / 2.0)));
        let (a4, b4) = f(&(r + a3 * dt), &(pi + b3 * dt));
        r += (a1 + a2 * 2.0 + a3 * 2.0 + a4) * (dt / 6.0);
        pi += (b1 + b2 * 2.0 + b3 * 2.0 + b4) * (dt / 6.0);
    }
    (r, pi)
}

/// `|R_N − R(1)|` after `n` steps of size `1/n`, by the base step or its triple-jump composition.
fn rigid_body_error(n: usize, composed: bool) -> f64 {
    let sys = RigidBody {
        h: 1.0 / n as f64,
        j1: 1.0,
        j2: 2.0,
        j3: 3.0,
    };
    let (r0, pi0) = (
        cayley(&Vector3::new(0.2, -0.1, 0.4)),
        Vector3::new(0.3, 1.0, -0.2),
    );
    let s0 = sys.state(&RigidBodyConfig { r: r0 }, &RigidBodyMomentum { r: pi0 });
    let integ = LieIntegrator::new(sys, tight());
    let last = if composed {
        let c = Composition::new(integ, CompositionMethod::TRIPLE_JUMP);
        *c.run(s0).steps(n).collect().unwrap().last()
    } else {
        *integ.run(s0).steps(n).collect().unwrap().last()
    };
    let (r, _) = rigid_body_exact(&Vector3::new(1.0, 2.0, 3.0), &r0, &pi0, 1.0);
    (sys.config(&last).r - r).amax()
}

#[test]
fn the_rigid_body_has_order_two_and_the_triple_jump_order_four() {
    for (composed, order, steps) in [(false, 2.0, [20, 40, 80]), (true, 4.0, [10, 20, 40])] {
        let e: Vec<f64> = steps
            .iter()
            .map(|&n| rigid_body_error(n, composed))
            .collect();
        for w in e.windows(2) {
            let observed = (w[0] / w[1]).log2();
            assert!(
                (observed - order).abs() < 0.2,
                "order {observed} (expected {order}) from errors {e:?}"
            );
        }
    }
}

#[test]
fn the_heavy_top_keeps_its_two_momenta_and_a_bounded_energy() {
    let sys = HeavyTop {
        h: 0.01,
        j1: 1.0,
        j2: 1.0,
        j3: 0.4,
        mgl: 2.0,
    };
    let integ = LieIntegrator::new(sys, NewtonOptions::default());
    let s0 = sys.state(
        &HeavyTopConfig {
            r: cayley(&Vector3::new(0.6, 0.0, 0.0)),
        },
        &HeavyTopMomentum {
            r: Vector3::new(0.1, 0.3, 4.0),
        },
    );
    let energy = |s: &LieState<9, 3>| sys.energy(s);
    let (vertical0, axial0, e0) = (integ.spatial_momentum(&s0).z, s0.p[2], energy(&s0));
    let (mut vertical, mut axial, mut spread): (f64, f64, f64) = (0.0, 0.0, 0.0);
    let (mut half, mut second_half): (f64, f64) = (0.0, 0.0);
    let steps = 100_000;
    integ
        .run(s0)
        .steps(steps)
        .observe(|k, _, s: &LieState<9, 3>, _| {
            vertical = vertical.max((integ.spatial_momentum(s).z - vertical0).abs());
            axial = axial.max((s.p[2] - axial0).abs());
            let de = (energy(s) - e0).abs();
            spread = spread.max(de);
            if k < steps / 2 {
                half = half.max(de);
            } else {
                second_half = second_half.max(de);
            }
        })
        .stream()
        .unwrap();
    println!("heavy top: vertical {vertical:e} axial {axial:e} energy {spread:e} ({half:e}, {second_half:e})");
    assert!(
        vertical < 1e-11 * vertical0.abs().max(1.0),
        "vertical momentum drift {vertical:e}"
    );
    assert!(
        axial < 1e-11 * axial0.abs(),
        "axial momentum drift {axial:e}"
    );
    // The energy oscillates at O(h²) and does not drift: the second half of the run reaches no
    // further than the first did (to within a third).
    assert!(spread < 1e-2 * e0.abs(), "energy spread {spread:e}");
    assert!(
        second_half < 1.35 * half,
        "energy error {half:e} then {second_half:e}"
    );
}

#[test]
fn the_heavy_top_matches_a_hand_written_lgvi() {
    // An asymmetric body: the 3-D pendulum.
    let sys = HeavyTop {
        h: 0.01,
        j1: 1.0,
        j2: 1.5,
        j3: 0.4,
        mgl: 2.0,
    };
    let jd = lgvi::nonstandard(&Vector3::new(1.0, 1.5, 0.4));
    let integ = LieIntegrator::new(sys, NewtonOptions::default());
    let s0 = sys.state(
        &HeavyTopConfig {
            r: cayley(&Vector3::new(0.6, -0.3, 0.2)),
        },
        &HeavyTopMomentum {
            r: Vector3::new(0.5, -0.3, 2.0),
        },
    );
    let traj = integ.run(s0).steps(1000).collect().unwrap();
    let (mut r, mut pi, mut xi) = (sys.config(&s0).r, sys.momenta(&s0).r, Vector3::zeros());
    let mut worst: f64 = 0.0;
    for s in &traj.states[1..] {
        (r, pi, xi) = lgvi::heavy_top_step(&jd, sys.h, sys.mgl, &r, &pi, xi, 1e-16, &mut 0);
        worst = worst
            .max((sys.config(s).r - r).amax())
            .max((sys.momenta(s).r - pi).amax());
    }
    assert!(worst < 1e-12, "{worst:e}");
}

#[test]
fn a_satellite_with_a_reaction_wheel_keeps_both_momenta() {
    // A rotation and an ordinary coordinate in one system.
    let sys = Satellite {
        h: 0.01,
        j1: 2.0,
        j2: 3.0,
        j3: 4.0,
        jw: 0.5,
        u: 0.0,
    };
    let integ = LieIntegrator::new(sys, NewtonOptions::default());
    let s0 = sys.state(
        &SatelliteConfig {
            r: cayley(&Vector3::new(0.1, 0.2, -0.3)),
            phi: 0.0,
        },
        &SatelliteMomentum {
            r: Vector3::new(0.4, -0.2, 1.0),
            phi: 0.7,
        },
    );
    let pi0 = integ.spatial_momentum(&s0);
    let (mut wheel, mut spatial): (f64, f64) = (0.0, 0.0);
    integ
        .run(s0)
        .steps(20_000)
        .observe(|_, _, s: &LieState<10, 4>, _| {
            wheel = wheel.max((sys.momenta(s).phi - 0.7).abs());
            spatial = spatial.max((integ.spatial_momentum(s) - pi0).norm());
        })
        .stream()
        .unwrap();
    assert!(wheel < 1e-13, "wheel momentum drift {wheel:e}");
    assert!(
        spatial < 1e-12 * pi0.norm(),
        "spatial momentum drift {spatial:e}"
    );
}

#[test]
fn states_off_the_group_are_rejected_before_the_first_step() {
    let (sys, _) = body();
    let integ = LieIntegrator::new(sys, NewtonOptions::default());
    let mut s0 = sys.state(
        &RigidBodyConfig {
            r: Matrix3::identity(),
        },
        &RigidBodyMomentum {
            r: Vector3::new(0.3, 1.0, -0.2),
        },
    );
    s0.q[1] = 1e-6;
    let err = integ.run(s0).steps(10).collect().unwrap_err();
    assert!(matches!(err.source, StepError::OffManifold { .. }), "{err}");
    assert_eq!(err.trajectory.states.len(), 1);
    let _ = hat(&Vector3::x());
}

/// Six free rigid bodies in one system (`N = 18`, above the dense backend's size: the sparse
/// backend), each with the moments of [`RigidBody`] scaled by its index.
#[reduced_lagrangian(rotation(r1, r2, r3, r4, r5, r6))]
fn six_bodies(q0: Config, q1: Config, h: f64) -> f64 {
    let jd = Matrix3::from_diagonal(&Vector3::new(2.0, 1.0, 0.0));
    let one = Matrix3::identity();
    let (f1, f2, f3) = (
        q0.r1.transpose() * q1.r1,
        q0.r2.transpose() * q1.r2,
        q0.r3.transpose() * q1.r3,
    );
    let (f4, f5, f6) = (
        q0.r4.transpose() * q1.r4,
        q0.r5.transpose() * q1.r5,
        q0.r6.transpose() * q1.r6,
    );
    (((one - f1) * jd).trace()
        + ((one - f2) * jd).trace() * 2.0
        + ((one - f3) * jd).trace() * 3.0
        + ((one - f4) * jd).trace() * 4.0
        + ((one - f5) * jd).trace() * 5.0
        + ((one - f6) * jd).trace() * 6.0)
        / h
}

#[test]
fn a_large_system_on_the_sparse_backend_matches_its_parts() {
    let sys = SixBodies { h: 0.01 };
    let rotations: Vec<Matrix3<f64>> = (1..=6)
        .map(|i| cayley(&Vector3::new(0.1 * i as f64, -0.2, 0.3)))
        .collect();
    let momenta: Vec<Vector3<f64>> = (1..=6)
        .map(|i| Vector3::new(0.3, 1.0, -0.2 * i as f64))
        .collect();
    let s0 = sys.state(
        &SixBodiesConfig {
            r1: rotations[0],
            r2: rotations[1],
            r3: rotations[2],
            r4: rotations[3],
            r5: rotations[4],
            r6: rotations[5],
        },
        &SixBodiesMomentum {
            r1: momenta[0],
            r2: momenta[1],
            r3: momenta[2],
            r4: momenta[3],
            r5: momenta[4],
            r6: momenta[5],
        },
    );
    let backend = std::any::type_name::<<SixBodies as LieLagrangian<54, 18>>::Linear>();
    assert!(backend.contains("SparseLu"), "{backend}");
    let all = LieIntegrator::new(sys, tight())
        .run(s0)
        .steps(500)
        .collect()
        .unwrap();
    let last = sys.config(all.last());
    let ends = [last.r1, last.r2, last.r3, last.r4, last.r5, last.r6];
    for i in 0..6 {
        // Body i alone: J_d scaled by i + 1 is J = diag(1, 2, 3) scaled.
        let s = (i + 1) as f64;
        let one = RigidBody {
            h: 0.01,
            j1: s,
            j2: 2.0 * s,
            j3: 3.0 * s,
        };
        let start = one.state(
            &RigidBodyConfig { r: rotations[i] },
            &RigidBodyMomentum { r: momenta[i] },
        );
        let alone = LieIntegrator::new(one, tight())
            .run(start)
            .steps(500)
            .collect()
            .unwrap();
        let d = (one.config(alone.last()).r - ends[i]).amax();
        assert!(d < 1e-12, "body {i}: {d:e}");
    }
}

/// The free rigid body as a continuous Lagrangian `L(R, Ω) = ½ Ωᵀ J Ω`, trapezoid rule.
#[reduced_lagrangian(rotation(r), rule = trapezoid)]
fn spinning(q: Config, v: Velocity, j1: f64, j2: f64, j3: f64) -> f64 {
    let _ = q.r;
    0.5 * (j1 * v.r.x * v.r.x + j2 * v.r.y * v.r.y + j3 * v.r.z * v.r.z)
}

/// `|R_N − R(1)|` of the continuous-Lagrangian rigid body after `n` steps of size `1/n`.
fn spinning_error(n: usize, composed: bool) -> f64 {
    let sys = Spinning {
        h: 1.0 / n as f64,
        j1: 1.0,
        j2: 2.0,
        j3: 3.0,
    };
    let (r0, pi0) = (
        cayley(&Vector3::new(0.2, -0.1, 0.4)),
        Vector3::new(0.3, 1.0, -0.2),
    );
    let s0 = sys.state(&SpinningConfig { r: r0 }, &SpinningMomentum { r: pi0 });
    let integ = LieIntegrator::new(sys, tight());
    let last = if composed {
        *Composition::new(integ, CompositionMethod::TRIPLE_JUMP)
            .run(s0)
            .steps(n)
            .collect()
            .unwrap()
            .last()
    } else {
        *integ.run(s0).steps(n).collect().unwrap().last()
    };
    let (r, _) = rigid_body_exact(&Vector3::new(1.0, 2.0, 3.0), &r0, &pi0, 1.0);
    (sys.config(&last).r - r).amax()
}

#[test]
fn a_continuous_lagrangian_in_the_body_angular_velocity_has_order_two_and_four() {
    for (composed, order, steps) in [(false, 2.0, [20, 40, 80]), (true, 4.0, [10, 20, 40])] {
        let e: Vec<f64> = steps.iter().map(|&n| spinning_error(n, composed)).collect();
        for w in e.windows(2) {
            let observed = (w[0] / w[1]).log2();
            assert!(
                (observed - order).abs() < 0.2,
                "order {observed} (expected {order}) from {e:?}"
            );
        }
    }
    // The velocity it reads is the body angular velocity: the emitted type carries it.
    let v = SpinningVelocity {
        r: Vector3::new(1.0, 0.0, 0.0),
    };
    let l = spinning(
        SpinningConfig {
            r: Matrix3::identity(),
        },
        v,
        2.0,
        3.0,
        4.0,
    );
    assert_eq!(l, 1.0);
}

#[test]
fn a_wheel_torque_control_moves_the_wheel_momentum_by_h_u_and_keeps_the_spatial_momentum() {
    let sys = Satellite {
        h: 0.01,
        j1: 2.0,
        j2: 3.0,
        j3: 4.0,
        jw: 0.5,
        u: 0.0,
    };
    let integ = LieIntegrator::new(sys, NewtonOptions::default());
    let s0 = sys.state(
        &SatelliteConfig {
            r: cayley(&Vector3::new(0.1, 0.2, -0.3)),
            phi: 0.0,
        },
        &SatelliteMomentum {
            r: Vector3::new(0.4, -0.2, 1.0),
            phi: 0.7,
        },
    );
    let pi0 = integ.spatial_momentum(&s0);
    // A feedback law: the motor torque from the time and the state.
    let law = |_k: usize, t: f64, s: &LieState<10, 4>, u: &mut [f64]| {
        u[0] = (2.0 * t).sin() - 0.1 * s.p[3]
    };
    let traj = integ.run(s0).steps(2000).feedback(law).collect().unwrap();
    let mut worst_pi: f64 = 0.0;
    let mut worst_wheel: f64 = 0.0;
    for k in 0..2000 {
        let (a, b) = (&traj.states[k], &traj.states[k + 1]);
        let mut u = [0.0];
        law(k, traj.times[k], a, &mut u);
        // p_φ changes by f_d^− + f_d^+ = h u exactly (the Lagrangian does not read φ).
        worst_wheel = worst_wheel.max((b.p[3] - a.p[3] - sys.h * u[0]).abs());
        worst_pi = worst_pi.max((integ.spatial_momentum(b) - pi0).norm());
    }
    assert!(worst_wheel < 1e-14, "wheel balance {worst_wheel:e}");
    assert!(
        worst_pi < 1e-12 * pi0.norm(),
        "spatial momentum drift {worst_pi:e}"
    );
    // The wrong number of controls is a typed error of the step.
    let rows = [[1.0, 2.0]; 3];
    let err = integ
        .run(s0)
        .steps(3)
        .controls(ControlSequence::rows(&rows))
        .collect();
    assert!(matches!(
        err.unwrap_err().source,
        StepError::InvalidControls {
            expected: 1,
            found: 2,
            ..
        }
    ));
}

/// A rigid body driven by a constant torque `τ` fixed in the body: continuous form.
#[reduced_lagrangian(rotation(r), rule = trapezoid,
    force = |dq| t1 * dq.r.x + t2 * dq.r.y + t3 * dq.r.z)]
#[allow(clippy::too_many_arguments)]
fn torqued(q: Config, v: Velocity, j1: f64, j2: f64, j3: f64, t1: f64, t2: f64, t3: f64) -> f64 {
    let _ = q.r;
    0.5 * (j1 * v.r.x * v.r.x + j2 * v.r.y * v.r.y + j3 * v.r.z * v.r.z)
}

#[test]
fn a_body_torque_obeys_the_forced_noether_balance_step_by_step() {
    let sys = Torqued {
        h: 0.01,
        j1: 1.0,
        j2: 2.0,
        j3: 3.0,
        t1: 0.3,
        t2: -0.2,
        t3: 0.5,
    };
    let integ = LieIntegrator::new(sys, NewtonOptions::default());
    let s0 = sys.state(
        &TorquedConfig {
            r: cayley(&Vector3::new(0.2, -0.1, 0.4)),
        },
        &TorquedMomentum {
            r: Vector3::new(0.3, 1.0, -0.2),
        },
    );
    let traj = integ.run(s0).steps(1000).collect().unwrap();
    let tau = Vector3::new(sys.t1, sys.t2, sys.t3);
    let mut worst: f64 = 0.0;
    for w in traj.states.windows(2) {
        // π_{k+1} − π_k = R_k f_d^− + R_{k+1} f_d^+ with f_d^± = (h/2) τ (the trapezoid rule).
        let (ra, rb) = (sys.config(&w[0]).r, sys.config(&w[1]).r);
        let impulse = (ra + rb) * tau * (0.5 * sys.h);
        let balance = integ.spatial_momentum(&w[1]) - integ.spatial_momentum(&w[0]) - impulse;
        worst = worst.max(balance.amax());
    }
    assert!(worst < 1e-14, "forced Noether balance off by {worst:e}");
}

/// The columns of a step's sensitivity by central differences on the group: the state is
/// perturbed in the chart at `s0` (`φ_{q0}(±ε e_j)`, or `p0 ± ε e_j`), the controls by `±ε`, and
/// each perturbed result is read in the chart at the nominal next point (`w`, and the momenta
/// in the frame of `φ_{q1}(w)`).
fn central_differences<L, const P: usize, const N: usize>(
    integ: &LieIntegrator<L, P, N>,
    s0: &LieState<P, N>,
    u: &[f64],
    eps: f64,
    momentum_at: impl Fn(&LieState<P, N>, &SVector<f64, P>) -> SVector<f64, N>,
) -> (DMatrix<f64>, DMatrix<f64>)
where
    L: LieLagrangian<P, N>,
{
    let (next, _) = integ
        .step_with(
            &mut integ.workspace(),
            StepAt::new(0, integ.time_step()).with_controls(u),
            s0,
        )
        .unwrap();
    let read = |s: &LieState<P, N>| {
        let w = integ.chart_coordinates(&next.q, &s.q);
        let at = integ.system().retract(&next.q, &w);
        let p = momentum_at(s, &at);
        let mut v = DVector::zeros(2 * N);
        v.rows_mut(0, N).copy_from(&w);
        v.rows_mut(N, N).copy_from(&p);
        v
    };
    let step = |s: &LieState<P, N>, u: &[f64]| {
        integ
            .step_with(
                &mut integ.workspace(),
                StepAt::new(0, integ.time_step()).with_controls(u),
                s,
            )
            .unwrap()
            .0
    };
    let mut state = DMatrix::zeros(2 * N, 2 * N);
    for j in 0..2 * N {
        let shifted = |sign: f64| {
            let mut s = *s0;
            if j < N {
                let mut d = SVector::<f64, N>::zeros();
                d[j] = sign * eps;
                s.q = integ.system().retract(&s0.q, &d);
            } else {
                s.p[j - N] += sign * eps;
            }
            read(&step(&s, u))
        };
        state.set_column(j, &((shifted(1.0) - shifted(-1.0)) / (2.0 * eps)));
    }
    let mut control = DMatrix::zeros(2 * N, u.len());
    for j in 0..u.len() {
        let shifted = |sign: f64| {
            let mut v = u.to_vec();
            v[j] += sign * eps;
            read(&step(s0, &v))
        };
        control.set_column(j, &((shifted(1.0) - shifted(-1.0)) / (2.0 * eps)));
    }
    (state, control)
}

#[test]
fn step_sensitivities_match_central_differences_on_the_group() {
    // A rotation with a control (the satellite's wheel motor).
    let sat = Satellite {
        h: 0.05,
        j1: 2.0,
        j2: 3.0,
        j3: 4.0,
        jw: 0.5,
        u: 0.0,
    };
    let integ = LieIntegrator::new(sat, tight());
    let s0 = sat.state(
        &SatelliteConfig {
            r: cayley(&Vector3::new(0.1, 0.2, -0.3)),
            phi: 0.4,
        },
        &SatelliteMomentum {
            r: Vector3::new(0.4, -0.2, 1.0),
            phi: 0.7,
        },
    );
    let (_, _, sens) = integ.step_sensitivity(0, &s0, &[0.3]).unwrap();
    let (state, control) = central_differences(&integ, &s0, &[0.3], 1e-6, |s, _| s.p);
    let d = (&sens.state - &state)
        .amax()
        .max((&sens.control - &control).amax());
    assert!(
        d < 1e-7 * state.amax(),
        "satellite: {d:e}\n{}\n{}",
        sens.state,
        state
    );
    // Two directions: momenta compared in the frame of the point they are read at.
    let dsp = DspOnSpheres::paper(0.05);
    let integ = LieIntegrator::new(dsp, tight());
    let s0 = dsp.paper_initial_state();
    let (_, _, sens) = integ.step_sensitivity(0, &s0, &[]).unwrap();
    // Its momenta are ~10⁴ times the positions' scale: a larger step keeps the differences
    // above the Newton tolerance's noise.
    let (state, _) =
        central_differences(&integ, &s0, &[], 1e-4, |s, at| dsp.momenta(s).to_chart(at));
    let d = (&sens.state - &state).amax();
    assert!(
        d < 1e-7 * state.amax(),
        "double spherical pendulum: {d:e}\n{:.4}\n{:.4}",
        sens.state,
        state
    );
    // A conservative system: the rigid body, whose step map is a symplectomorphism in canonical
    // coordinates; here only its chart derivatives are compared.
    let (body, _) = body();
    let integ = LieIntegrator::new(body, tight());
    let s0 = body.state(
        &RigidBodyConfig {
            r: cayley(&Vector3::new(0.2, -0.1, 0.4)),
        },
        &RigidBodyMomentum {
            r: Vector3::new(0.3, 1.0, -0.2),
        },
    );
    let (_, _, sens) = integ.step_sensitivity(0, &s0, &[]).unwrap();
    let (state, _) = central_differences(&integ, &s0, &[], 1e-6, |s, _| s.p);
    let d = (&sens.state - &state).amax();
    assert!(d < 1e-7 * state.amax(), "rigid body: {d:e}");
}

/// A spacecraft: a rigid body in space, its position `(x, y, z)` declared as translations, a
/// thruster along its third axis with thrust `u` (a control), trapezoid rule on its work.
#[reduced_lagrangian(rotation(r), group(x, y, z), controls(u),
    force = |dq0, dq1| 0.5 * h * u * ((q0.r * Vector3::z()).dot(&Vector3::new(dq0.x, dq0.y, dq0.z))
        + (q1.r * Vector3::z()).dot(&Vector3::new(dq1.x, dq1.y, dq1.z))))]
#[allow(clippy::too_many_arguments)]
fn spacecraft(q0: Config, q1: Config, h: f64, m: f64, j1: f64, j2: f64, j3: f64, u: f64) -> f64 {
    let jd = Matrix3::from_diagonal(&Vector3::new(j2 + j3 - j1, j1 + j3 - j2, j1 + j2 - j3)) * 0.5;
    let f = q0.r.transpose() * q1.r;
    let dx = Vector3::new(q1.x - q0.x, q1.y - q0.y, q1.z - q0.z);
    ((Matrix3::identity() - f) * jd).trace() / h + 0.5 * m * dx.norm_squared() / h
}

#[test]
fn declared_translations_keep_their_momenta_bit_for_bit_and_balance_a_thrust() {
    let sys = Spacecraft {
        h: 0.01,
        m: 3.0,
        j1: 1.0,
        j2: 2.0,
        j3: 3.0,
        u: 0.0,
    };
    let integ = LieIntegrator::new(sys, NewtonOptions::default());
    let s0 = sys.state(
        &SpacecraftConfig {
            r: cayley(&Vector3::new(0.3, -0.2, 0.1)),
            x: 1.0,
            y: -2.0,
            z: 0.5,
        },
        &SpacecraftMomentum {
            r: Vector3::new(0.4, 1.0, -0.3),
            x: 0.3,
            y: -0.1,
            z: 0.2,
        },
    );
    // Coasting: the linear momentum is copied, bit for bit.
    let coast = integ.run(s0).steps(1000).collect().unwrap();
    for s in &coast.states {
        assert_eq!(&s.p.as_slice()[3..], &s0.p.as_slice()[3..]);
    }
    // Thrusting: μ_{k+1} − μ_k = f_d^− + f_d^+ = (h/2) u (R_k e3 + R_{k+1} e3).
    let thrust = [[0.8]; 500];
    let traj = integ
        .run(s0)
        .steps(500)
        .controls(ControlSequence::rows(&thrust))
        .collect()
        .unwrap();
    let mut worst: f64 = 0.0;
    for w in traj.states.windows(2) {
        let (ra, rb) = (sys.config(&w[0]).r, sys.config(&w[1]).r);
        let impulse = (ra + rb) * Vector3::z() * (0.5 * sys.h * 0.8);
        let change = Vector3::new(
            w[1].p[3] - w[0].p[3],
            w[1].p[4] - w[0].p[4],
            w[1].p[5] - w[0].p[5],
        );
        worst = worst.max((change - impulse).amax());
    }
    assert!(worst < 1e-15, "the thrust's impulse is off by {worst:e}");
    // (The thrust does move the momentum.)
    assert!(traj.states[1..].iter().all(|s| s.p[3] != s0.p[3]));
}

/// The discrete Legendre momentum from an attitude and an angular velocity, against closed
/// forms: for the free rigid body `Π = vee(F J_d − J_d Fᵀ)/h` with `F = cay(hΩ)` (the Lie group
/// variational integrator's own equation), `JΩ − (h/2) JΩ × Ω` to `O(h²)`; the heavy top's
/// differs from the free body's by `−(h/2) M` with the gravity torque `M = m g l Rᵀe3 × e3`; and
/// the run from it takes the step `R cay(hΩ)`.
#[test]
fn the_discrete_legendre_state_from_an_angular_velocity_matches_its_closed_forms() {
    use dirac::lie::{cayley, vee};
    use dirac::systems::rotations::{HeavyTop, HeavyTopConfig, RigidBody, RigidBodyConfig};
    let (j1, j2, j3) = (1.0, 2.0, 3.0);
    let j = Vector3::new(j1, j2, j3);
    let jd = Matrix3::from_diagonal(&Vector3::new(j2 + j3 - j1, j1 + j3 - j2, j1 + j2 - j3)) * 0.5;
    let r = cayley(&Vector3::new(0.3, -0.5, 0.2));
    let omega = Vector3::new(0.7, -0.4, 1.3);
    let free_momentum = |h: f64| {
        let body = RigidBody { h, j1, j2, j3 };
        let point = RigidBodyConfig { r }.to_point();
        body.discrete_legendre_state(&point, &omega).unwrap().p
    };
    let h = 0.05;
    let f = cayley(&(h * omega));
    let closed = vee(&(f * jd - jd * f.transpose())) / h;
    let pi = free_momentum(h);
    assert!((pi - closed).amax() < 1e-13, "{pi} vs {closed}");
    // Not JΩ: the momentum at the step's start of a motion whose velocity mid-step is Ω,
    // Π = JΩ − (h/2) JΩ × Ω + O(h²) (Euler's Π̇ = Π × Ω run back half a step): the difference
    // from JΩ halves with the step, what is left of it after the half-step term falls by 4.
    let jw = j.component_mul(&omega);
    let off = |h: f64| (free_momentum(h) - jw).amax();
    let ratio = off(h) / off(h / 2.0);
    assert!(off(h) > 1e-3 && (ratio - 2.0).abs() < 0.1, "ratio {ratio}");
    let left = |h: f64| (free_momentum(h) - (jw - 0.5 * h * jw.cross(&omega))).amax();
    let ratio = left(h) / left(h / 2.0);
    assert!((ratio - 4.0).abs() < 0.1, "ratio {ratio}");
    // A potential adds (h/2) times its torque.
    let mgl = 2.0;
    let top = HeavyTop { h, j1, j2, j3, mgl };
    let state = top
        .discrete_legendre_state(&HeavyTopConfig { r }.to_point(), &omega)
        .unwrap();
    let e3 = Vector3::z();
    let torque = mgl * e3.cross(&(r.transpose() * e3));
    assert!(
        (state.p - (pi + 0.5 * h * torque)).amax() < 1e-13,
        "{}",
        state.p
    );
    // The run from it moves by R cay(hΩ) in its first step.
    let traj = LieIntegrator::new(top, NewtonOptions::default())
        .run(state)
        .steps(1)
        .collect()
        .unwrap();
    assert!((top.config(&traj.states[1]).r - r * f).amax() < 1e-12);
    // A state that is not finite is a typed error.
    assert!(matches!(
        top.discrete_legendre_state(
            &HeavyTopConfig { r }.to_point(),
            &Vector3::new(f64::NAN, 0.0, 0.0)
        ),
        Err(StepError::NonFinite { .. })
    ));
}

/// A stored point lists each rotation row by row, and the constructor says so in its name: the
/// rows of `R` give the state of `R`; nalgebra's column-major slice of `R` would give `Rᵀ`.
#[test]
fn a_state_from_a_point_reads_rotations_row_by_row() {
    use dirac::lie::{cayley, rows};
    use dirac::systems::rotations::{RigidBody, RigidBodyConfig};
    let body = RigidBody {
        h: 0.1,
        j1: 1.0,
        j2: 2.0,
        j3: 3.0,
    };
    let r = cayley(&Vector3::new(0.3, -0.5, 0.2));
    let p = Vector3::new(0.1, 0.2, 0.3);
    let state = LieState::from_row_major(rows(&r), p);
    assert_eq!(body.config(&state).r, r);
    assert_eq!(state.q, RigidBodyConfig { r }.to_point());
    let column_major: [f64; 9] = r.as_slice().try_into().unwrap();
    let transposed = LieState::from_row_major(column_major, p);
    assert_eq!(body.config(&transposed).r, r.transpose());
}
