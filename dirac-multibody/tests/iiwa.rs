//! The KUKA iiwa 14 of `examples/data/iiwa14.urdf`: its layout, its mass against the file's,
//! its height when stretched upright, and its mass matrix against its kinetic energy.

use dirac_multibody::nalgebra::{DVector, Vector3};
use dirac_multibody::Model;

fn iiwa() -> (Model, String) {
    let path = format!(
        "{}/../examples/data/iiwa14.urdf",
        env!("CARGO_MANIFEST_DIR")
    );
    let text = std::fs::read_to_string(&path).unwrap();
    (
        Model::from_urdf_file(&path).expect("the iiwa URDF reads"),
        text,
    )
}

/// Every `<mass value="…"/>` of the file, read by plain text search.
fn masses_in(text: &str) -> Vec<f64> {
    text.split("<mass value=\"")
        .skip(1)
        .map(|rest| rest[..rest.find('"').unwrap()].parse().unwrap())
        .collect()
}

#[test]
fn iiwa_layout_and_mass() {
    let (model, text) = iiwa();
    assert_eq!(model.joints().len(), 7);
    assert_eq!(
        model.bodies().len(),
        8,
        "link_0 fused into the massless base, 7 moving links"
    );
    assert_eq!(model.velocity_dimension(), 7);
    let names: Vec<&str> = model
        .coordinates()
        .iter()
        .map(|c| c.name.as_str())
        .collect();
    assert_eq!(
        names,
        (1..=7)
            .map(|i| format!("iiwa_joint_{i}"))
            .collect::<Vec<_>>()
    );
    assert_eq!(model.bodies()[0].name, "base");
    assert_eq!(model.bodies()[7].name, "iiwa_link_7");
    for (i, body) in model.bodies().iter().enumerate() {
        let parent = body.parent;
        assert_eq!(parent, i.checked_sub(1), "a chain, parents first");
    }

    let masses = masses_in(&text);
    assert_eq!(masses.len(), 8);
    let in_file: f64 = masses.iter().sum();
    assert!(
        (model.total_mass() - in_file).abs() < 1e-12,
        "{} vs {in_file}",
        model.total_mass()
    );
    assert!((in_file - 30.61).abs() < 1e-12);
    assert_eq!(
        model.bodies()[0].inertial.mass,
        5.0,
        "link_0's 5 kg in the root body"
    );

    for frame in ["base", "iiwa_link_0", "iiwa_link_ee", "iiwa_link_ee_kuka"] {
        let body = model.frame(frame).unwrap().body;
        assert_eq!(
            body,
            if frame.starts_with("iiwa_link_ee") {
                7
            } else {
                0
            },
            "{frame}"
        );
    }
    let limits = model.joints()[6].limits.unwrap();
    assert_eq!(
        (limits.lower, limits.upper),
        (-3.05432619099, 3.05432619099)
    );
    assert_eq!(model.joints()[0].dynamics.unwrap().damping, 0.5);
}

/// Stretched upright (every angle zero) the flange is 0.36 + 0.42 + 0.4 + 0.126 = 1.306 m above
/// the base, on its axis: the placements' rotations undo each other along the chain.
#[test]
fn iiwa_upright_height() {
    let (model, _) = iiwa();
    let poses = model
        .forward_kinematics(&model.neutral_configuration())
        .unwrap();
    let ee = model
        .frame_pose(&poses, "iiwa_link_ee")
        .unwrap()
        .translation;
    assert!(
        (ee - Vector3::new(0.0, 0.0, 1.306)).norm() < 1e-12,
        "{ee:?}"
    );
    // Joint 1 turns the whole arm about the vertical: the flange stays put.
    let turned = model
        .configuration_from_scalars(&[1.1, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0])
        .unwrap();
    let poses = model.forward_kinematics(&turned).unwrap();
    let ee_turned = model
        .frame_pose(&poses, "iiwa_link_ee")
        .unwrap()
        .translation;
    assert!((ee_turned - ee).norm() < 1e-12);
    // Joint 2 tilts the arm above the shoulder (0.36 m up) by 1 rad: its 0.946 m reach tilts
    // with it.
    let bent = model
        .configuration_from_scalars(&[0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0])
        .unwrap();
    let poses = model.forward_kinematics(&bent).unwrap();
    let ee_bent = model
        .frame_pose(&poses, "iiwa_link_ee")
        .unwrap()
        .translation;
    let reach = 0.946_f64;
    assert!(
        (ee_bent.z - (0.36 + reach * 1.0_f64.cos())).abs() < 1e-12,
        "{ee_bent:?}"
    );
    assert!(((ee_bent.x.powi(2) + ee_bent.y.powi(2)).sqrt() - reach * 1.0_f64.sin()).abs() < 1e-12);
}

/// `T = ½ vᵀ M v` at states spread over the joint ranges: the mass matrix (composite-rigid-body
/// algorithm) and the body velocities agree on a 7-joint chain with rotated placements.
#[test]
fn mass_matrix_is_the_kinetic_energy_on_the_iiwa() {
    let (model, _) = iiwa();
    let mut seed = 0x2545_f491_4f6c_dd1d_u64;
    let mut uniform = move || {
        // xorshift64*: a fixed sequence, enough for states spread over the joint ranges.
        seed ^= seed >> 12;
        seed ^= seed << 25;
        seed ^= seed >> 27;
        (seed.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    for _ in 0..32 {
        let q: Vec<f64> = (0..7).map(|_| 3.0 * uniform()).collect();
        let v: Vec<f64> = (0..7).map(|_| 2.0 * uniform()).collect();
        let config = model.configuration_from_scalars(&q).unwrap();
        let m = model.mass_matrix(&config).unwrap();
        assert!(m.clone().cholesky().is_some());
        assert!((&m - m.transpose()).amax() == 0.0);
        let vv = DVector::from_column_slice(&v);
        let t = model.kinetic_energy(&config, &v).unwrap();
        let quadratic = 0.5 * vv.dot(&(&m * &vv));
        assert!(
            (t - quadratic).abs() <= 1e-13 * t.max(1.0),
            "T {t} vs ½vᵀMv {quadratic}"
        );
    }
}
