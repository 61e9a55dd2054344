//! The double pendulum and the planar 3-link arm of `examples/data/`, read from URDF, against
//! their energies, mass matrices and end positions written by hand.

// The hand-written formulas index links and joints as the equations do.
#![allow(clippy::needless_range_loop)]

use dirac_multibody::Model;
use proptest::prelude::*;

fn data(name: &str) -> Model {
    let path = format!("{}/../examples/data/{name}", env!("CARGO_MANIFEST_DIR"));
    Model::from_urdf_file(path).expect("the example URDF reads")
}

const G: f64 = 9.81;

/// The double pendulum's constants, as its URDF file gives them.
const M1: f64 = 1.3;
const A1: f64 = 0.45;
const J1: f64 = 0.11;
const L1: f64 = 1.0;
const M2: f64 = 0.7;
const A2: f64 = 0.6;
const J2: f64 = 0.08;
const TIP: f64 = 1.2;

/// Hand-written double pendulum: hinges about y, so a point at depth `a` below a hinge turned
/// by `θ` sits at `(−a sin θ, 0, −a cos θ)` from it.
fn pendulum_energies(t1: f64, t2: f64, w1: f64, w2: f64) -> (f64, f64) {
    let c2 = t2.cos();
    let w12 = w1 + w2;
    let kinetic = 0.5 * (M1 * A1 * A1 + J1) * w1 * w1
        + 0.5 * M2 * (L1 * L1 * w1 * w1 + A2 * A2 * w12 * w12 + 2.0 * L1 * A2 * w1 * w12 * c2)
        + 0.5 * J2 * w12 * w12;
    let potential = -M1 * G * A1 * t1.cos() - M2 * G * (L1 * t1.cos() + A2 * (t1 + t2).cos());
    (kinetic, potential)
}

fn pendulum_mass_matrix(t2: f64) -> [[f64; 2]; 2] {
    let c2 = t2.cos();
    let m11 = M1 * A1 * A1 + J1 + M2 * (L1 * L1 + A2 * A2 + 2.0 * L1 * A2 * c2) + J2;
    let m12 = M2 * (A2 * A2 + L1 * A2 * c2) + J2;
    let m22 = M2 * A2 * A2 + J2;
    [[m11, m12], [m12, m22]]
}

/// The arm's constants, as its URDF file gives them.
const L: [f64; 3] = [0.8, 0.6, 0.4];
const A: [f64; 3] = [0.35, 0.3, 0.15];
const M: [f64; 3] = [2.0, 1.5, 0.5];
const J: [f64; 3] = [0.12, 0.05, 0.01];

/// Hand-written planar arm along +x, hinges about y: a point at `x = a` of a link at absolute
/// angle `φ` sits at `(a cos φ, 0, −a sin φ)` from its hinge. Returns each centre of mass's
/// `(x, z)` and its Jacobian rows `∂x/∂θ_k`, `∂z/∂θ_k`, and the absolute angles.
#[allow(clippy::type_complexity)]
fn arm_kinematics(q: [f64; 3]) -> ([(f64, f64); 3], [[[f64; 3]; 2]; 3], [f64; 3]) {
    let phi = [q[0], q[0] + q[1], q[0] + q[1] + q[2]];
    let mut coms = [(0.0, 0.0); 3];
    let mut jac = [[[0.0; 3]; 2]; 3];
    for i in 0..3 {
        let (mut x, mut z) = (0.0, 0.0);
        for j in 0..i {
            x += L[j] * phi[j].cos();
            z -= L[j] * phi[j].sin();
        }
        x += A[i] * phi[i].cos();
        z -= A[i] * phi[i].sin();
        coms[i] = (x, z);
        // ∂/∂θ_k moves every φ_j with j ≥ k.
        for k in 0..=i {
            let (mut dx, mut dz) = (0.0, 0.0);
            for j in k..i {
                dx -= L[j] * phi[j].sin();
                dz -= L[j] * phi[j].cos();
            }
            dx -= A[i] * phi[i].sin();
            dz -= A[i] * phi[i].cos();
            jac[i][0][k] = dx;
            jac[i][1][k] = dz;
        }
    }
    (coms, jac, phi)
}

fn arm_mass_matrix(q: [f64; 3]) -> [[f64; 3]; 3] {
    let (_, jac, _) = arm_kinematics(q);
    let mut m = [[0.0; 3]; 3];
    for i in 0..3 {
        for r in 0..3 {
            for c in 0..3 {
                m[r][c] += M[i] * (jac[i][0][r] * jac[i][0][c] + jac[i][1][r] * jac[i][1][c]);
                // Link i turns at φ̇_i = θ̇_1 + … + θ̇_i.
                if r <= i && c <= i {
                    m[r][c] += J[i];
                }
            }
        }
    }
    m
}

fn arm_energies(q: [f64; 3], w: [f64; 3]) -> (f64, f64) {
    let (coms, jac, _) = arm_kinematics(q);
    let mut kinetic = 0.0;
    let mut potential = 0.0;
    for i in 0..3 {
        let vx: f64 = (0..3).map(|k| jac[i][0][k] * w[k]).sum();
        let vz: f64 = (0..3).map(|k| jac[i][1][k] * w[k]).sum();
        let spin: f64 = w[..=i].iter().sum();
        kinetic += 0.5 * M[i] * (vx * vx + vz * vz) + 0.5 * J[i] * spin * spin;
        potential += M[i] * G * coms[i].1;
    }
    (kinetic, potential)
}

fn assert_close(found: f64, expected: f64, tol: f64, what: &str) {
    let scale = expected.abs().max(1.0);
    assert!(
        (found - expected).abs() <= tol * scale,
        "{what}: {found} vs {expected} (difference {:e})",
        found - expected
    );
}

#[test]
fn double_pendulum_layout() {
    let model = data("double_pendulum.urdf");
    assert_eq!(model.bodies().len(), 3, "world, rod1, rod2 (tip fused)");
    let names: Vec<&str> = model
        .coordinates()
        .iter()
        .map(|c| c.name.as_str())
        .collect();
    assert_eq!(names, ["shoulder", "elbow"]);
    assert_eq!(model.velocity_dimension(), 2);
    assert_close(model.total_mass(), M1 + M2, 1e-15, "total mass");
    assert!(model.is_scalar_jointed());
}

#[test]
fn three_link_arm_layout() {
    let model = data("three_link_arm.urdf");
    assert_eq!(model.bodies().len(), 4);
    let names: Vec<&str> = model
        .coordinates()
        .iter()
        .map(|c| c.name.as_str())
        .collect();
    assert_eq!(names, ["joint1", "joint2", "joint3"]);
    let limits = model.joints()[1].limits.expect("joint2 has limits");
    assert_eq!(
        (limits.lower, limits.upper, limits.effort),
        (-2.5, 2.5, 30.0)
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn double_pendulum_against_hand_written(
        t1 in -3.2..3.2f64, t2 in -3.2..3.2f64, w1 in -5.0..5.0f64, w2 in -5.0..5.0f64,
    ) {
        let model = data("double_pendulum.urdf");
        let q = model.configuration_from_scalars(&[t1, t2]).unwrap();
        let (kinetic, potential) = pendulum_energies(t1, t2, w1, w2);
        assert_close(model.kinetic_energy(&q, &[w1, w2]).unwrap(), kinetic, 1e-13, "T");
        assert_close(model.potential_energy(&q).unwrap(), potential, 1e-13, "V");

        let m = model.mass_matrix(&q).unwrap();
        let expected = pendulum_mass_matrix(t2);
        for r in 0..2 {
            for c in 0..2 {
                assert_close(m[(r, c)], expected[r][c], 1e-13, "M");
                prop_assert_eq!(m[(r, c)], m[(c, r)]);
            }
        }
        prop_assert!(m.clone().cholesky().is_some(), "M is positive definite");

        // The tip: 1.0 m down rod 1, then 1.2 m down rod 2.
        let poses = model.forward_kinematics(&q).unwrap();
        let tip = model.frame_pose(&poses, "tip").unwrap().translation;
        let expected_tip = [
            -L1 * t1.sin() - TIP * (t1 + t2).sin(),
            0.0,
            -L1 * t1.cos() - TIP * (t1 + t2).cos(),
        ];
        for k in 0..3 {
            assert_close(tip[k], expected_tip[k], 1e-14, "tip");
        }
    }

    #[test]
    fn three_link_arm_against_hand_written(
        q in proptest::array::uniform3(-3.2..3.2f64),
        w in proptest::array::uniform3(-4.0..4.0f64),
    ) {
        let model = data("three_link_arm.urdf");
        let config = model.configuration_from_scalars(&q).unwrap();
        let (kinetic, potential) = arm_energies(q, w);
        assert_close(model.kinetic_energy(&config, &w).unwrap(), kinetic, 1e-13, "T");
        assert_close(model.potential_energy(&config).unwrap(), potential, 1e-13, "V");

        let m = model.mass_matrix(&config).unwrap();
        let expected = arm_mass_matrix(q);
        for r in 0..3 {
            for c in 0..3 {
                assert_close(m[(r, c)], expected[r][c], 1e-13, "M");
                prop_assert_eq!(m[(r, c)], m[(c, r)]);
            }
        }
        prop_assert!(m.clone().cholesky().is_some(), "M is positive definite");

        let (coms, _, phi) = arm_kinematics(q);
        let poses = model.forward_kinematics(&config).unwrap();
        for (i, body) in ["link1", "link2", "link3"].iter().enumerate() {
            let b = model.body_index(body).unwrap();
            let c = poses[b].transform_point(&model.bodies()[b].inertial.com);
            assert_close(c.x, coms[i].0, 1e-14, "centre of mass x");
            assert_close(c.z, coms[i].1, 1e-14, "centre of mass z");
        }
        let hand = model.frame_pose(&poses, "hand").unwrap().translation;
        let hand_x: f64 = (0..3).map(|i| L[i] * phi[i].cos()).sum();
        let hand_z: f64 = (0..3).map(|i| -L[i] * phi[i].sin()).sum();
        assert_close(hand.x, hand_x, 1e-14, "hand x");
        assert_close(hand.y, 0.0, 1e-14, "hand y");
        assert_close(hand.z, hand_z, 1e-14, "hand z");
    }
}
