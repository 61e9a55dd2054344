//! The system text of a model (`Model::system_text`): what it declares, how it names the
//! coordinates and controls, and the models it refuses with a typed error naming the joint.
//! That the text compiles and steps as written by hand is tested where the compiler is, in
//! `dirac-jit/tests/urdf.rs`.

use dirac_multibody::nalgebra::{Matrix3, Vector3};
use dirac_multibody::{Inertial, JointSpec, Model, ModelError, TextKind, TextOptions};

fn data(name: &str) -> Model {
    let path = format!("{}/../examples/data/{name}", env!("CARGO_MANIFEST_DIR"));
    Model::from_urdf_file(path).expect("the example URDF reads")
}

fn rod() -> Inertial {
    Inertial::new(
        1.0,
        Vector3::new(0.0, 0.0, -0.5),
        Matrix3::from_diagonal(&Vector3::new(0.1, 0.1, 0.01)),
    )
}

#[test]
fn a_fixed_base_is_scalar_joints_with_the_midpoint_rule() {
    let text = data("three_link_arm.urdf").system_text().unwrap();
    assert_eq!(text.kind, TextKind::FixedBase);
    assert!(text.text.contains(
        "#[reduced_lagrangian(shape(joint1, joint2, joint3), group(), rule = midpoint)]"
    ));
    assert!(text
        .text
        .contains("fn multibody(q: Config, v: Velocity) -> f64 {"));
    let joints: Vec<&str> = text.coordinates.iter().map(|c| c.joint.as_str()).collect();
    assert_eq!(joints, ["joint1", "joint2", "joint3"]);
    assert!(text.controls.is_empty());
}

#[test]
fn torques_are_controls_entering_as_virtual_work() {
    let options = TextOptions {
        name: "double pendulum".into(),
        torques: true,
    };
    let text = data("double_pendulum.urdf")
        .system_text_with(&options)
        .unwrap();
    assert_eq!(text.name, "double_pendulum");
    assert_eq!(text.controls, ["tau_shoulder", "tau_elbow"]);
    assert!(text.text.contains("controls(tau_shoulder, tau_elbow)"));
    assert!(text
        .text
        .contains("force = |dq| tau_shoulder * dq.shoulder + tau_elbow * dq.elbow"));
    assert!(text.text.contains(
        "fn double_pendulum(q: Config, v: Velocity, tau_shoulder: f64, tau_elbow: f64) -> f64"
    ));
}

#[test]
fn a_floating_base_is_a_pose_beside_the_joints_with_the_trapezoid_rule() {
    let text = data("free_body.urdf").system_text().unwrap();
    assert_eq!(text.kind, TextKind::FloatingBase);
    assert!(text
        .text
        .contains("#[reduced_lagrangian(pose(float), shape(), rule = trapezoid)]"));
    assert!(text.text.contains("v.float.angular"));
}

/// Joint names that are not identifiers become identifiers, distinct ones, and the text keeps
/// the way back to the joint.
#[test]
fn joint_names_become_distinct_identifiers() {
    let model = Model::builder()
        .frame("world")
        .body("a", rod())
        .body("b", rod())
        .body("c", rod())
        .joint(JointSpec::revolute("hip-left", "world", "a", Vector3::y()))
        .joint(JointSpec::revolute("hip left", "a", "b", Vector3::y()))
        .joint(JointSpec::prismatic("type", "b", "c", Vector3::z()))
        .build()
        .unwrap();
    let text = model.system_text().unwrap();
    let ids: Vec<&str> = text
        .coordinates
        .iter()
        .map(|c| c.identifier.as_str())
        .collect();
    assert_eq!(ids, ["hip_left", "hip_left_2", "type_"]);
    assert_eq!(text.identifier("hip left"), Some("hip_left_2"));
    assert!(text
        .text
        .contains("shape(hip_left, hip_left_2, type_), group()"));
}

/// The text grows linearly with the bodies: a fixed number of lines per body.
#[test]
fn the_text_of_a_chain_grows_linearly() {
    let chain = |n: usize| {
        let mut b = Model::builder().frame("l0");
        for i in 1..=n {
            b = b.body(format!("l{i}"), rod()).joint(
                JointSpec::revolute(
                    format!("j{i}"),
                    format!("l{}", i - 1),
                    format!("l{i}"),
                    Vector3::y(),
                )
                .at(dirac_multibody::Pose::from_translation(Vector3::new(
                    0.0, 0.0, -1.0,
                ))),
            );
        }
        b.build()
            .unwrap()
            .system_text()
            .unwrap()
            .text
            .lines()
            .count()
    };
    let (ten, twenty, forty) = (chain(10), chain(20), chain(40));
    assert_eq!(forty - twenty, 2 * (twenty - ten));
}

#[test]
fn unsupported_models_are_refused_naming_the_joint() {
    // A spherical joint is a rotation coordinate on rotation groups.
    let spherical = Model::builder()
        .frame("world")
        .body("bob", rod())
        .joint(JointSpec::spherical("ball", "world", "bob"))
        .build()
        .unwrap();
    let text = spherical.system_text().unwrap();
    assert_eq!(text.kind, TextKind::SphericalJoints);
    assert!(
        text.text
            .contains("rotation(ball), shape(), rule = trapezoid"),
        "{}",
        text.text
    );
    // A free joint below the root.
    let deep = Model::builder()
        .frame("world")
        .body("a", rod())
        .body("b", rod())
        .joint(JointSpec::revolute("hinge", "world", "a", Vector3::y()))
        .joint(JointSpec::free("float", "a", "b"))
        .build()
        .unwrap();
    match deep.system_text() {
        Err(ModelError::Unsupported { joint, .. }) => assert_eq!(joint, "float"),
        other => panic!("{other:?}"),
    }
    // A joint from the root beside the floating base.
    let beside = Model::builder()
        .frame("world")
        .body("a", rod())
        .body("b", rod())
        .joint(JointSpec::free("float", "world", "a"))
        .joint(JointSpec::revolute("hinge", "world", "b", Vector3::y()))
        .build()
        .unwrap();
    match beside.system_text() {
        Err(ModelError::Unsupported { joint, .. }) => assert_eq!(joint, "hinge"),
        other => panic!("{other:?}"),
    }
    let still = Model::builder().frame("world").build().unwrap();
    assert_eq!(still.system_text(), Err(ModelError::NothingMoves));
}
