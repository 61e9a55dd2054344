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
    println!("worst {worst:e}");
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
    println!("drift {:e} orth {orth:e}", drift / pi0.norm());
    let _ = hat(&pi0);
}
