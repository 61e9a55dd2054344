//! Rotations and directions: Lie group variational integrators from `#[reduced_lagrangian]`
//! with `rotation(..)` and `direction(..)` coordinates, checked against a hand-written LGVI.

use dirac::lie::{cayley, hat, orthogonality_defect, vee};
use dirac::prelude::*;

/// The free rigid body's discrete Lagrangian of Lee, Leok & McClamroch:
/// `L_d = tr((I − F) J_d)/h`, `F = R0ᵀ R1`, `J_d = ½ tr(J) I − J`.
#[reduced_lagrangian(rotation(r))]
fn rigid_body(q0: Config, q1: Config, h: f64, j1: f64, j2: f64, j3: f64) -> f64 {
    let jd = Matrix3::from_diagonal(&Vector3::new(j2 + j3 - j1, j1 + j3 - j2, j1 + j2 - j3)) * 0.5;
    let f = q0.r.transpose() * q1.r;
    ((Matrix3::identity() - f) * jd).trace() / h
}

/// A hand-written LGVI step for the same `L_d`: Newton on `h Π_k = vee(F J_d − J_d Fᵀ)` with
/// `F = cay(ξ)` and a central-difference Jacobian, then `R_{k+1} = R_k F`, `Π_{k+1} = Fᵀ Π_k`.
fn lgvi_step(
    jd: &Matrix3<f64>,
    h: f64,
    r: &Matrix3<f64>,
    pi: &Vector3<f64>,
) -> (Matrix3<f64>, Vector3<f64>) {
    let res = |xi: &Vector3<f64>| {
        let f = cayley(xi);
        vee(&(f * jd - jd * f.transpose())) - h * pi
    };
    let mut xi = Vector3::zeros();
    for _ in 0..50 {
        let r0 = res(&xi);
        if r0.amax() < 1e-15 {
            break;
        }
        let mut jac = Matrix3::zeros();
        for c in 0..3 {
            let mut d = Vector3::zeros();
            d[c] = 1e-7;
            jac.set_column(c, &((res(&(xi + d)) - res(&(xi - d))) / 2e-7));
        }
        xi -= jac.lu().solve(&r0).unwrap();
    }
    let f = cayley(&xi);
    (r * f, f.transpose() * pi)
}

fn body() -> (RigidBody, Matrix3<f64>) {
    let sys = RigidBody {
        h: 0.01,
        j1: 1.0,
        j2: 2.0,
        j3: 3.0,
    };
    let jd = Matrix3::from_diagonal(&Vector3::new(2.0, 1.0, 0.0));
    (sys, jd)
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
    let (mut r, mut pi) = (sys.config(&s0).r, sys.momenta(&s0).r);
    let mut worst: f64 = 0.0;
    for k in 1..=1000 {
        (r, pi) = lgvi_step(&jd, sys.h, &r, &pi);
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

/// The paper's double spherical pendulum on `S² × S²`: the two link directions, the same
/// discrete Lagrangian as the Cartesian run with rod constraints (midpoint rule: chord
/// velocities, the potential averaged), so the two give the same discrete trajectory.
#[reduced_lagrangian(direction(n1, n2))]
#[allow(clippy::too_many_arguments)]
fn dsp_sphere(q0: Config, q1: Config, h: f64, m1: f64, m2: f64, l1: f64, l2: f64, g: f64) -> f64 {
    let d1 = (q1.n1 - q0.n1) * l1;
    let d2 = d1 + (q1.n2 - q0.n2) * l2;
    let z1 = 0.5 * l1 * (q0.n1.z + q1.n1.z);
    let z2 = z1 + 0.5 * l2 * (q0.n2.z + q1.n2.z);
    (0.5 * m1 * d1.norm_squared() + 0.5 * m2 * d2.norm_squared()) / h - h * g * (m1 * z1 + m2 * z2)
}

#[path = "../examples/common/cartesian_dsp.rs"]
mod cartesian;

/// The Cartesian state `(r1, r2, p1, p2)` on `S² × S²`: `n1 = r1/l1`, `n2 = (r2 − r1)/l2`, and
/// the momenta of the directions from `δr1 = l1 δn1`, `δr2 = l1 δn1 + l2 δn2`:
/// `P_n1 = l1 (p1 + p2)`, `P_n2 = l2 p2` (their tangent parts).
fn on_spheres(sys: &DspSphere, s: &UnreducedState<6>) -> LieState<18, 4> {
    let r1 = Vector3::new(s.q[0], s.q[1], s.q[2]);
    let r2 = Vector3::new(s.q[3], s.q[4], s.q[5]);
    let p1 = Vector3::new(s.p[0], s.p[1], s.p[2]);
    let p2 = Vector3::new(s.p[3], s.p[4], s.p[5]);
    sys.state(
        &DspSphereConfig {
            n1: r1 / sys.l1,
            n2: (r2 - r1) / sys.l2,
        },
        &DspSphereMomentum {
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
    let sys = DspSphere {
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
    let sys = DspSphere {
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

/// The heavy (Lagrange) top: a symmetric body (`J = diag(j1, j1, j3)`) on a fixed point with its
/// centre of mass on its axis, at distance `l` (`mgl = m g l`), the trapezoid rule on the
/// potential `m g l (R e3)·e3`.
#[reduced_lagrangian(rotation(r))]
fn heavy_top(q0: Config, q1: Config, h: f64, j1: f64, j3: f64, mgl: f64) -> f64 {
    let jd = Matrix3::from_diagonal(&Vector3::new(0.5 * j3, 0.5 * j3, j1 - 0.5 * j3));
    let f = q0.r.transpose() * q1.r;
    ((Matrix3::identity() - f) * jd).trace() / h - 0.5 * h * mgl * (q0.r[(2, 2)] + q1.r[(2, 2)])
}

#[test]
fn the_heavy_top_keeps_its_two_momenta_and_a_bounded_energy() {
    let sys = HeavyTop {
        h: 0.01,
        j1: 1.0,
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
    let energy = |s: &LieState<9, 3>| {
        let (q, p) = (sys.config(s), sys.momenta(s));
        let omega = p.r.component_div(&Vector3::new(1.0, 1.0, 0.4));
        0.5 * p.r.dot(&omega) + sys.mgl * q.r[(2, 2)]
    };
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
