//! `pose(X)` coordinates from `#[reduced_lagrangian]`: a rigid body in space as one pose
//! `(R, x) ∈ SE(3)`, held to the same discrete Lagrangian written with `rotation(R)` and
//! `shape(x, y, z)`. The pose's chart `(ξ, v) ↦ (R cay(ξ), x + v)` is the product of the
//! rotation's chart and the scalars' translations, and its momentum `(Π, p)` the rotation's body
//! momentum and the scalars' momenta, so the two discrete maps on `SO(3) × ℝ³` are the same
//! equations: the trajectories agree to the Newton tolerance, not just to the order of the
//! method.

use dirac::lie::{cayley, orthogonality_defect};
use dirac::prelude::*;

/// A free rigid body in space: `L_d = tr((I − F) J_d)/h + m |x1 − x0|²/(2h)`, `F = R0ᵀ R1`.
#[reduced_lagrangian(pose(body))]
fn free_pose(q0: Config, q1: Config, h: f64, m: f64, j1: f64, j2: f64, j3: f64) -> f64 {
    let jd = Matrix3::from_diagonal(&Vector3::new(j2 + j3 - j1, j1 + j3 - j2, j1 + j2 - j3)) * 0.5;
    let f = q0.body.rotation.transpose() * q1.body.rotation;
    let dx = q1.body.translation - q0.body.translation;
    ((Matrix3::identity() - f) * jd).trace() / h + 0.5 * m * dx.norm_squared() / h
}

/// [`free_pose`] with its rotation and position as separate coordinates.
#[reduced_lagrangian(rotation(r), shape(x, y, z))]
fn free_split(q0: Config, q1: Config, h: f64, m: f64, j1: f64, j2: f64, j3: f64) -> f64 {
    let jd = Matrix3::from_diagonal(&Vector3::new(j2 + j3 - j1, j1 + j3 - j2, j1 + j2 - j3)) * 0.5;
    let f = q0.r.transpose() * q1.r;
    let (dx, dy, dz) = (q1.x - q0.x, q1.y - q0.y, q1.z - q0.z);
    ((Matrix3::identity() - f) * jd).trace() / h + 0.5 * m * (dx * dx + dy * dy + dz * dz) / h
}

/// A body in a uniform field `−g e3` with a thrust `u` along its third axis, as a continuous
/// Lagrangian `L = ½ Ω·JΩ + ½ m |ẋ|² − m g x₃` by the trapezoid rule; the thrust's virtual work
/// `u (R e3)·δx` reads the pose's spatial displacement.
#[reduced_lagrangian(pose(body), rule = trapezoid, step = h, controls(u),
    force = |dq| u * (q.body.rotation * Vector3::z()).dot(&dq.body.linear))]
fn thrust_pose(q: Config, v: Velocity, m: f64, g: f64, j1: f64, j2: f64, j3: f64, u: f64) -> f64 {
    let w = v.body.angular;
    let j = Matrix3::from_diagonal(&Vector3::new(j1, j2, j3));
    0.5 * w.dot(&(j * w)) + 0.5 * m * v.body.linear.norm_squared() - m * g * q.body.translation.z
}

/// [`thrust_pose`] with its rotation and position as separate coordinates.
#[reduced_lagrangian(rotation(r), shape(x, y, z), rule = trapezoid, step = h, controls(u),
    force = |dq| u * (q.r * Vector3::z()).dot(&Vector3::new(dq.x, dq.y, dq.z)))]
fn thrust_split(q: Config, v: Velocity, m: f64, g: f64, j1: f64, j2: f64, j3: f64, u: f64) -> f64 {
    let w = v.r;
    let j = Matrix3::from_diagonal(&Vector3::new(j1, j2, j3));
    0.5 * w.dot(&(j * w)) + 0.5 * m * (v.x * v.x + v.y * v.y + v.z * v.z) - m * g * q.z
}

fn tight() -> NewtonOptions {
    NewtonOptions {
        abs_tol: 1e-14,
        rel_tol: 1e-14,
        ..NewtonOptions::default()
    }
}

const STEPS: usize = 300;

/// The start: a generic attitude, a position off the origin, momenta in every direction.
fn start() -> (Matrix3<f64>, Vector3<f64>, Vector3<f64>, Vector3<f64>) {
    (
        cayley(&Vector3::new(0.2, -0.1, 0.4)),
        Vector3::new(1.0, -2.0, 0.5),
        Vector3::new(0.3, 1.0, -0.2),
        Vector3::new(0.4, -0.1, 0.2),
    )
}

#[test]
fn a_free_pose_steps_as_a_rotation_and_three_scalars() {
    let (r, x, pi, p) = start();
    let pose = FreePose {
        h: 0.05,
        m: 2.0,
        j1: 1.0,
        j2: 2.0,
        j3: 3.0,
    };
    let split = FreeSplit {
        h: 0.05,
        m: 2.0,
        j1: 1.0,
        j2: 2.0,
        j3: 3.0,
    };
    assert_eq!((FreePose::POINT_DIM, FreePose::CONFIG_DIM), (12, 6));
    let s0 = pose.state(
        &FreePoseConfig {
            body: FreePosePose {
                rotation: r,
                translation: x,
            },
        },
        &FreePoseMomentum {
            body: FreePosePoseMomentum {
                angular: pi,
                linear: p,
            },
        },
    );
    let t0 = split.state(
        &FreeSplitConfig {
            r,
            x: x.x,
            y: x.y,
            z: x.z,
        },
        &FreeSplitMomentum {
            r: pi,
            x: p.x,
            y: p.y,
            z: p.z,
        },
    );
    let a = LieIntegrator::new(pose, tight())
        .run(s0)
        .steps(STEPS)
        .collect()
        .unwrap();
    let b = LieIntegrator::new(split, tight())
        .run(t0)
        .steps(STEPS)
        .collect()
        .unwrap();
    let mut worst: f64 = 0.0;
    for (s, t) in a.states.iter().zip(&b.states) {
        let (c, d) = (pose.config(s).body, split.config(t));
        let (m, n) = (pose.momenta(s).body, split.momenta(t));
        worst = worst
            .max((c.rotation - d.r).amax())
            .max((c.translation - Vector3::new(d.x, d.y, d.z)).amax())
            .max((m.angular - n.r).amax())
            .max((m.linear - Vector3::new(n.x, n.y, n.z)).amax());
    }
    assert_eq!(a.states.len(), STEPS + 1);
    // The same equations solved to 1e-14: only round-off in the order of the operations.
    assert!(worst < 1e-13, "pose and split runs differ by {worst:e}");
}

#[test]
fn a_free_pose_keeps_its_linear_and_angular_momentum_in_space() {
    let (r, x, pi, p) = start();
    let pose = FreePose {
        h: 0.05,
        m: 2.0,
        j1: 1.0,
        j2: 2.0,
        j3: 3.0,
    };
    let s0 = pose.state(
        &FreePoseConfig {
            body: FreePosePose {
                rotation: r,
                translation: x,
            },
        },
        &FreePoseMomentum {
            body: FreePosePoseMomentum {
                angular: pi,
                linear: p,
            },
        },
    );
    // The momentum map of rigid motions (A, a)·(R, x) = (AR, Ax + a): ℓ = p, π = RΠ + x × p.
    let spatial = |s: &LieState<12, 6>| {
        let (c, m) = (pose.config(s).body, pose.momenta(s).body);
        (
            m.linear,
            c.rotation * m.angular + c.translation.cross(&m.linear),
        )
    };
    let (l0, pi0) = spatial(&s0);
    let (mut drift, mut orth): (f64, f64) = (0.0, 0.0);
    LieIntegrator::new(pose, NewtonOptions::default())
        .run(s0)
        .steps(2000)
        .observe(|_, _, s: &LieState<12, 6>, _| {
            let (l, pi) = spatial(s);
            drift = drift.max((l - l0).norm()).max((pi - pi0).norm());
            orth = orth.max(orthogonality_defect(&pose.config(s).body.rotation));
        })
        .stream()
        .unwrap();
    // Discrete Noether for the rigid motions of the body in space (L_d reads R0ᵀR1 and
    // x1 − x0 only), and products of rotations only: no projection.
    assert!(drift < 1e-12 * pi0.norm(), "momentum drift {drift:e}");
    assert!(orth < 1e-12, "|RᵀR − I| = {orth:e}");
}

#[test]
fn a_continuous_pose_with_a_force_and_a_control_steps_as_its_split_form() {
    let (r, x, _, _) = start();
    let pose = ThrustPose {
        h: 0.02,
        m: 1.5,
        g: 9.81,
        j1: 1.0,
        j2: 1.5,
        j3: 2.5,
        u: 20.0,
    };
    let split = ThrustSplit {
        h: 0.02,
        m: 1.5,
        g: 9.81,
        j1: 1.0,
        j2: 1.5,
        j3: 2.5,
        u: 20.0,
    };
    // From the same velocity: the body angular velocity Ω and the spatial velocity ẋ, the
    // pose's chart velocity (Ω, ẋ) and the split form's (Ω, ẋ₁, ẋ₂, ẋ₃) alike.
    let velocity = SVector::<f64, 6>::from([0.5, -1.0, 2.0, 0.1, 0.2, 3.0]);
    let q0 = ThrustPoseConfig {
        body: ThrustPosePose {
            rotation: r,
            translation: x,
        },
    };
    let s0 = pose
        .discrete_legendre_state(&q0.to_point(), &velocity)
        .unwrap();
    let q0 = ThrustSplitConfig {
        r,
        x: x.x,
        y: x.y,
        z: x.z,
    };
    let t0 = split
        .discrete_legendre_state(&q0.to_point(), &velocity)
        .unwrap();
    let a = LieIntegrator::new(pose, tight())
        .run(s0)
        .steps(STEPS)
        .collect()
        .unwrap();
    let b = LieIntegrator::new(split, tight())
        .run(t0)
        .steps(STEPS)
        .collect()
        .unwrap();
    let mut worst: f64 = 0.0;
    for (s, t) in a.states.iter().zip(&b.states) {
        let (c, d) = (pose.config(s).body, split.config(t));
        worst = worst
            .max((c.rotation - d.r).amax())
            .max((c.translation - Vector3::new(d.x, d.y, d.z)).amax() / 100.0);
    }
    // The thrust lifts the body: it moved, and moved the same way.
    let top = pose.config(&a.states[STEPS]).body.translation;
    assert!((top - x).norm() > 1.0, "the body barely moved: {top}");
    assert!(worst < 1e-12, "pose and split runs differ by {worst:e}");
}

/// A body on a Kepler orbit in space, its steps following `|x|^{3/2}` (adaptive steps: the
/// physical time `t` a group coordinate, the step monitor a function of the pose's position).
#[reduced_lagrangian(pose(body), group(t), rule = trapezoid,
    time(t), adapt = |q| q.body.translation.norm().powf(1.5))]
fn orbiting_pose(q: Config, v: Velocity, k: f64, j1: f64, j2: f64, j3: f64) -> f64 {
    let w = v.body.angular;
    0.5 * v.body.linear.norm_squared()
        + k / q.body.translation.norm()
        + 0.5 * (j1 * w.x * w.x + j2 * w.y * w.y + j3 * w.z * w.z)
}

/// [`orbiting_pose`] with its rotation and position as separate coordinates (the same point
/// layout: `R` row by row, then `x, y, z`, then `t`).
#[reduced_lagrangian(rotation(r), shape(x, y, z), group(t), rule = trapezoid,
    time(t), adapt = |q| (q.x * q.x + q.y * q.y + q.z * q.z).sqrt().powf(1.5))]
fn orbiting_split(q: Config, v: Velocity, k: f64, j1: f64, j2: f64, j3: f64) -> f64 {
    let w = v.r;
    0.5 * (v.x * v.x + v.y * v.y + v.z * v.z)
        + k / (q.x * q.x + q.y * q.y + q.z * q.z).sqrt()
        + 0.5 * (j1 * w.x * w.x + j2 * w.y * w.y + j3 * w.z * w.z)
}

#[test]
fn an_adaptive_pose_steps_as_its_split_form() {
    let (r, _, _, _) = start();
    let (e, eps): (f64, f64) = (0.6, 0.02);
    let (r0, speed) = (1.0 - e, ((1.0 + e) / (1.0 - e)).sqrt());
    let omega = Vector3::new(0.3, 0.5, -0.07);
    let pose = OrbitingPose {
        h: eps,
        k: 1.0,
        j1: 1.0,
        j2: 2.0,
        j3: 3.0,
    };
    let split = OrbitingSplit {
        h: eps,
        k: 1.0,
        j1: 1.0,
        j2: 2.0,
        j3: 3.0,
    };
    let s0 = pose
        .unreduced_state(
            &OrbitingPoseConfig {
                body: OrbitingPosePose {
                    rotation: r,
                    translation: Vector3::new(r0, 0.0, 0.0),
                },
                t: 0.0,
            },
            &OrbitingPoseVelocity {
                body: OrbitingPosePoseVelocity {
                    angular: omega,
                    linear: Vector3::new(0.0, speed, 0.1),
                },
                t: 1.0,
            },
        )
        .unwrap();
    let t0 = split
        .unreduced_state(
            &OrbitingSplitConfig {
                r,
                x: r0,
                y: 0.0,
                z: 0.0,
                t: 0.0,
            },
            &OrbitingSplitVelocity {
                r: omega,
                x: 0.0,
                y: speed,
                z: 0.1,
                t: 1.0,
            },
        )
        .unwrap();
    // The same state on the energy level (the same layout), to round-off in `p_t = −E`.
    assert_eq!(s0.q, t0.q);
    assert!((s0.p - t0.p).amax() < 1e-14, "{} vs {}", s0.p, t0.p);
    let a = LieIntegrator::new(pose, tight())
        .run(s0)
        .steps(STEPS)
        .collect()
        .unwrap();
    let b = LieIntegrator::new(split, tight())
        .run(t0)
        .steps(STEPS)
        .collect()
        .unwrap();
    let mut worst: f64 = 0.0;
    for (s, t) in a.states.iter().zip(&b.states) {
        worst = worst.max((s.q - t.q).amax()).max((s.p - t.p).amax());
    }
    // The steps follow the orbit: the last covered more physical time than `STEPS · ε` at
    // periapsis would.
    let time = a.states[STEPS].q[12];
    assert!(time > 2.0 * STEPS as f64 * eps * r0.powf(1.5), "t = {time}");
    assert!(worst < 1e-12, "pose and split runs differ by {worst:e}");
}

/// The step's sensitivities (the partial derivatives the compiler emits for dense systems) in
/// the pose's chart `(ξ, v)` are the split form's in its charts `(ξ, x, y, z)`: the same
/// coordinates in the same order, so the same matrices.
#[test]
fn a_pose_step_has_the_sensitivities_of_its_split_form() {
    let (r, x, _, _) = start();
    let pose = ThrustPose {
        h: 0.02,
        m: 1.5,
        g: 9.81,
        j1: 1.0,
        j2: 1.5,
        j3: 2.5,
        u: 20.0,
    };
    let split = ThrustSplit {
        h: 0.02,
        m: 1.5,
        g: 9.81,
        j1: 1.0,
        j2: 1.5,
        j3: 2.5,
        u: 20.0,
    };
    let velocity = SVector::<f64, 6>::from([0.5, -1.0, 2.0, 0.1, 0.2, 3.0]);
    let q0 = ThrustPoseConfig {
        body: ThrustPosePose {
            rotation: r,
            translation: x,
        },
    };
    let s0 = pose
        .discrete_legendre_state(&q0.to_point(), &velocity)
        .unwrap();
    let q0 = ThrustSplitConfig {
        r,
        x: x.x,
        y: x.y,
        z: x.z,
    };
    let t0 = split
        .discrete_legendre_state(&q0.to_point(), &velocity)
        .unwrap();
    let (_, _, a) = LieIntegrator::new(pose, tight())
        .step_sensitivity(0, &s0, &[20.0])
        .unwrap();
    let (_, _, b) = LieIntegrator::new(split, tight())
        .step_sensitivity(0, &t0, &[20.0])
        .unwrap();
    assert_eq!(a.state.shape(), (12, 12));
    assert_eq!(a.control.shape(), (12, 1));
    let scale = a.state.amax().max(1.0);
    assert!(
        (&a.state - &b.state).amax() < 1e-12 * scale,
        "{}",
        (&a.state - &b.state).amax()
    );
    assert!((&a.control - &b.control).amax() < 1e-12 * a.control.amax().max(1.0));
    // The thrust moves the position: its control column is not zero there.
    assert!(a.control.rows(3, 3).amax() > 1e-6, "{}", a.control);
}
