//! Every malformed description as its typed error, naming the element at fault; configurations
//! and velocities that do not fit a model as theirs. Never a panic.

use dirac_multibody::nalgebra::{Matrix3, Vector3};
use dirac_multibody::{
    Configuration, InertiaDefect, Inertial, JointPosition, JointSpec, Model, ModelError, Pose,
    StateError,
};

const INERTIAL: &str = r#"<inertial><origin xyz="0 0 -0.5"/><mass value="1"/>
  <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.01"/></inertial>"#;

/// A robot from links (name, inertial XML) and joint XML.
fn robot(links: &[(&str, &str)], joints: &str) -> String {
    let mut text = String::from("<robot name=\"r\">\n");
    for (name, inertial) in links {
        text += &format!("<link name=\"{name}\">{inertial}</link>\n");
    }
    text + joints + "</robot>"
}

fn joint(name: &str, kind: &str, parent: &str, child: &str) -> String {
    format!(
        r#"<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>
           <axis xyz="0 1 0"/></joint>"#
    )
}

fn read(text: &str) -> ModelError {
    Model::from_urdf_str(text).expect_err("a malformed model")
}

fn inertial(mass: &str, [ixx, ixy, ixz, iyy, iyz, izz]: [&str; 6]) -> String {
    format!(
        r#"<inertial><mass value="{mass}"/><inertia ixx="{ixx}" ixy="{ixy}" ixz="{ixz}"
           iyy="{iyy}" iyz="{iyz}" izz="{izz}"/></inertial>"#
    )
}

#[test]
fn the_well_formed_reference_reads() {
    let text = robot(
        &[("world", ""), ("arm", INERTIAL)],
        &joint("j", "revolute", "world", "arm"),
    );
    let model = Model::from_urdf_str(&text).unwrap();
    assert_eq!(model.bodies().len(), 2);
}

#[test]
fn missing_inertia_of_a_moving_link() {
    let text = robot(
        &[("world", ""), ("arm", "")],
        &joint("hinge", "revolute", "world", "arm"),
    );
    assert_eq!(
        read(&text),
        ModelError::MissingInertia {
            link: "arm".into(),
            joint: "hinge".into()
        }
    );
    // Massless frames are accepted where they mean one: the root, and fused by a fixed joint.
    let text = robot(
        &[("world", ""), ("arm", INERTIAL), ("sensor", "")],
        &(joint("hinge", "revolute", "world", "arm") + &joint("mount", "fixed", "arm", "sensor")),
    );
    assert!(Model::from_urdf_str(&text).is_ok());
}

#[test]
fn negative_mass() {
    let bad = inertial("-2", ["0.1", "0", "0", "0.1", "0", "0.1"]);
    let text = robot(
        &[("world", ""), ("arm", &bad)],
        &joint("j", "revolute", "world", "arm"),
    );
    assert_eq!(
        read(&text),
        ModelError::NegativeMass {
            link: "arm".into(),
            mass: -2.0
        }
    );
    // Refused on a fused link too.
    let text = robot(
        &[("world", ""), ("arm", INERTIAL), ("tool", &bad)],
        &(joint("j", "revolute", "world", "arm") + &joint("f", "fixed", "arm", "tool")),
    );
    assert_eq!(
        read(&text),
        ModelError::NegativeMass {
            link: "tool".into(),
            mass: -2.0
        }
    );
}

#[test]
fn zero_mass_of_a_moving_body() {
    let zero = inertial("0", ["0", "0", "0", "0", "0", "0"]);
    let text = robot(
        &[("world", ""), ("arm", &zero)],
        &joint("j", "revolute", "world", "arm"),
    );
    assert_eq!(
        read(&text),
        ModelError::ZeroMass {
            body: "arm".into(),
            joint: "j".into()
        }
    );
    // A massless link that moves is fine when a fixed joint welds mass to it.
    let text = robot(
        &[("world", ""), ("arm", &zero), ("weight", INERTIAL)],
        &(joint("j", "revolute", "world", "arm") + &joint("f", "fixed", "arm", "weight")),
    );
    assert!(Model::from_urdf_str(&text).is_ok());
}

#[test]
fn inertia_not_positive_definite() {
    let bad = inertial("1", ["0.1", "0", "0", "0.1", "0", "-0.01"]);
    let text = robot(
        &[("world", ""), ("arm", &bad)],
        &joint("j", "revolute", "world", "arm"),
    );
    match read(&text) {
        ModelError::InvalidInertia {
            link,
            defect: InertiaDefect::NotPositiveDefinite { moments },
        } => {
            assert_eq!(link, "arm");
            assert!((moments[0] + 0.01).abs() < 1e-15, "{moments:?}");
        }
        other => panic!("{other:?}"),
    }
    // A point mass (zero inertia) is not positive definite either.
    let point = inertial("1", ["0", "0", "0", "0", "0", "0"]);
    let text = robot(
        &[("world", ""), ("bob", &point)],
        &joint("j", "revolute", "world", "bob"),
    );
    assert!(matches!(
        read(&text),
        ModelError::InvalidInertia {
            defect: InertiaDefect::NotPositiveDefinite { .. },
            ..
        }
    ));
}

#[test]
fn inertia_violating_the_triangle_inequality() {
    let bad = inertial("1", ["0.1", "0", "0", "0.1", "0", "0.3"]);
    let text = robot(
        &[("world", ""), ("arm", &bad)],
        &joint("j", "revolute", "world", "arm"),
    );
    assert_eq!(
        read(&text),
        ModelError::InvalidInertia {
            link: "arm".into(),
            defect: InertiaDefect::TriangleInequality {
                moments: [0.1, 0.1, 0.3]
            },
        }
    );
    // A flat plate (J1 + J2 = J3) is a mass distribution.
    let plate = inertial("1", ["0.1", "0", "0", "0.2", "0", "0.3"]);
    let text = robot(
        &[("world", ""), ("arm", &plate)],
        &joint("j", "revolute", "world", "arm"),
    );
    assert!(Model::from_urdf_str(&text).is_ok());
}

#[test]
fn asymmetric_inertia_from_the_builder() {
    let mut inertia = Matrix3::from_diagonal(&Vector3::new(0.1, 0.1, 0.1));
    inertia[(0, 1)] = 0.01;
    let err = Model::builder()
        .frame("world")
        .body("arm", Inertial::new(1.0, Vector3::zeros(), inertia))
        .joint(JointSpec::revolute("j", "world", "arm", Vector3::z()))
        .build()
        .unwrap_err();
    assert_eq!(
        err,
        ModelError::InvalidInertia {
            link: "arm".into(),
            defect: InertiaDefect::NotSymmetric { asymmetry: 0.01 },
        }
    );
}

#[test]
fn non_finite_mass_properties_from_the_builder() {
    let err = Model::builder()
        .frame("world")
        .body(
            "arm",
            Inertial::new(f64::NAN, Vector3::zeros(), Matrix3::identity()),
        )
        .joint(JointSpec::revolute("j", "world", "arm", Vector3::z()))
        .build()
        .unwrap_err();
    assert_eq!(
        err,
        ModelError::InvalidInertia {
            link: "arm".into(),
            defect: InertiaDefect::NonFinite
        }
    );
}

#[test]
fn cycle() {
    let text = robot(
        &[("world", ""), ("a", INERTIAL), ("b", INERTIAL)],
        &(joint("j0", "revolute", "world", "a")
            + &joint("j1", "revolute", "a", "b")
            + &joint("j2", "revolute", "b", "a")),
    );
    // `a` is the child of j0 and j2: two parents, found first.
    assert_eq!(
        read(&text),
        ModelError::TwoParents {
            link: "a".into(),
            first: "j0".into(),
            second: "j2".into()
        }
    );
    // A loop that leaves one root: the root reaches neither link of the loop.
    let text = robot(
        &[
            ("world", ""),
            ("a", INERTIAL),
            ("b", INERTIAL),
            ("c", INERTIAL),
        ],
        &(joint("j0", "revolute", "world", "c")
            + &joint("j1", "revolute", "a", "b")
            + &joint("j2", "revolute", "b", "a")),
    );
    match read(&text) {
        ModelError::Cycle { link } => assert!(link == "a" || link == "b", "{link}"),
        other => panic!("{other:?}"),
    }
    // Every link on a loop: no root at all.
    let text = robot(
        &[("a", INERTIAL), ("b", INERTIAL)],
        &(joint("j1", "revolute", "a", "b") + &joint("j2", "revolute", "b", "a")),
    );
    assert!(matches!(read(&text), ModelError::Cycle { .. }));
    // A joint from a link to itself.
    let text = robot(
        &[("world", ""), ("a", INERTIAL)],
        &joint("j", "revolute", "a", "a"),
    );
    assert_eq!(read(&text), ModelError::Cycle { link: "a".into() });
}

#[test]
fn link_with_two_parents() {
    let text = robot(
        &[("world", ""), ("a", INERTIAL), ("b", INERTIAL)],
        &(joint("j1", "revolute", "world", "a")
            + &joint("j2", "revolute", "world", "b")
            + &joint("j3", "revolute", "a", "b")),
    );
    assert_eq!(
        read(&text),
        ModelError::TwoParents {
            link: "b".into(),
            first: "j2".into(),
            second: "j3".into()
        }
    );
}

#[test]
fn joint_naming_an_unknown_link() {
    let text = robot(
        &[("world", ""), ("arm", INERTIAL)],
        &joint("j", "revolute", "world", "hand"),
    );
    assert_eq!(
        read(&text),
        ModelError::UnknownLink {
            joint: "j".into(),
            role: "child",
            link: "hand".into()
        }
    );
    let text = robot(
        &[("world", ""), ("arm", INERTIAL)],
        &joint("j", "revolute", "ground", "arm"),
    );
    assert_eq!(
        read(&text),
        ModelError::UnknownLink {
            joint: "j".into(),
            role: "parent",
            link: "ground".into()
        }
    );
}

#[test]
fn unknown_joint_type() {
    let text = robot(
        &[("world", ""), ("arm", INERTIAL)],
        &joint("j", "hinge", "world", "arm"),
    );
    assert_eq!(
        read(&text),
        ModelError::UnknownJointType {
            joint: "j".into(),
            kind: "hinge".into()
        }
    );
    // URDF has no ball joint: "spherical" is not a URDF type.
    let text = robot(
        &[("world", ""), ("arm", INERTIAL)],
        &joint("j", "spherical", "world", "arm"),
    );
    assert!(matches!(read(&text), ModelError::UnknownJointType { .. }));
}

#[test]
fn planar_joints_and_mimic_are_unsupported() {
    let text = robot(
        &[("world", ""), ("arm", INERTIAL)],
        &joint("j", "planar", "world", "arm"),
    );
    assert_eq!(
        read(&text),
        ModelError::Unsupported {
            joint: "j".into(),
            feature: "type \"planar\"".into()
        }
    );
    let mimic = r#"<joint name="m" type="revolute"><parent link="world"/><child link="arm"/>
        <mimic joint="other" multiplier="2"/></joint>"#;
    let text = robot(&[("world", ""), ("arm", INERTIAL)], mimic);
    assert_eq!(
        read(&text),
        ModelError::Unsupported {
            joint: "m".into(),
            feature: "<mimic>".into()
        }
    );
}

#[test]
fn zero_axis() {
    let zero = r#"<joint name="j" type="prismatic"><parent link="world"/><child link="arm"/>
        <axis xyz="0 0 0"/></joint>"#;
    let text = robot(&[("world", ""), ("arm", INERTIAL)], zero);
    assert_eq!(read(&text), ModelError::ZeroAxis { joint: "j".into() });
    let err = Model::builder()
        .frame("world")
        .body(
            "arm",
            Inertial::new(1.0, Vector3::zeros(), Matrix3::identity()),
        )
        .joint(JointSpec::revolute("k", "world", "arm", Vector3::zeros()))
        .build()
        .unwrap_err();
    assert_eq!(err, ModelError::ZeroAxis { joint: "k".into() });
}

#[test]
fn malformed_xml_carries_the_parsers_message() {
    let text = "<robot name=\"r\">\n  <link name=\"a\">\n</robot>";
    match read(text) {
        ModelError::Xml { message } => {
            assert!(message.contains("3:"), "the position, line 3: {message}");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn not_a_urdf_document() {
    assert_eq!(
        read("<sdf version=\"1.9\"/>"),
        ModelError::NotUrdf {
            found: "sdf".into()
        }
    );
}

#[test]
fn more_than_one_root() {
    let text = robot(
        &[("world", ""), ("arm", INERTIAL), ("stray", INERTIAL)],
        &joint("j", "revolute", "world", "arm"),
    );
    assert_eq!(
        read(&text),
        ModelError::MultipleRoots {
            roots: vec!["world".into(), "stray".into()]
        }
    );
}

#[test]
fn missing_elements_and_attributes() {
    let no_mass =
        r#"<inertial><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>"#;
    let text = robot(
        &[("world", ""), ("arm", no_mass)],
        &joint("j", "revolute", "world", "arm"),
    );
    assert_eq!(
        read(&text),
        ModelError::MissingElement {
            element: "<inertial> of link \"arm\"".into(),
            child: "mass"
        }
    );
    let no_izz = r#"<inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0"/></inertial>"#;
    let text = robot(
        &[("world", ""), ("arm", no_izz)],
        &joint("j", "revolute", "world", "arm"),
    );
    assert_eq!(
        read(&text),
        ModelError::MissingAttribute {
            element: "<inertia> of link \"arm\"".into(),
            attribute: "izz"
        }
    );
    let no_child = r#"<joint name="j" type="revolute"><parent link="world"/></joint>"#;
    let text = robot(&[("world", ""), ("arm", INERTIAL)], no_child);
    assert_eq!(
        read(&text),
        ModelError::MissingElement {
            element: "joint \"j\"".into(),
            child: "child"
        }
    );
    let no_type = r#"<joint name="j"><parent link="world"/><child link="arm"/></joint>"#;
    let text = robot(&[("world", ""), ("arm", INERTIAL)], no_type);
    assert_eq!(
        read(&text),
        ModelError::MissingAttribute {
            element: "joint \"j\"".into(),
            attribute: "type"
        }
    );
    let text = "<robot name=\"r\"><link/></robot>";
    assert_eq!(
        read(text),
        ModelError::MissingAttribute {
            element: "<link>".into(),
            attribute: "name"
        }
    );
}

#[test]
fn invalid_numbers() {
    let bad_origin = r#"<joint name="j" type="revolute"><parent link="world"/><child link="arm"/>
        <origin xyz="0 0"/></joint>"#;
    let text = robot(&[("world", ""), ("arm", INERTIAL)], bad_origin);
    assert_eq!(
        read(&text),
        ModelError::InvalidNumber {
            element: "<origin> of joint \"j\"".into(),
            attribute: "xyz",
            value: "0 0".into(),
            expected: "3 finite numbers",
        }
    );
    let nan_mass = inertial("NaN", ["1", "0", "0", "1", "0", "1"]);
    let text = robot(
        &[("world", ""), ("arm", &nan_mass)],
        &joint("j", "revolute", "world", "arm"),
    );
    assert!(matches!(
        read(&text),
        ModelError::InvalidNumber {
            attribute: "value",
            ..
        }
    ));
    let word = inertial("1", ["heavy", "0", "0", "1", "0", "1"]);
    let text = robot(
        &[("world", ""), ("arm", &word)],
        &joint("j", "revolute", "world", "arm"),
    );
    assert!(matches!(
        read(&text),
        ModelError::InvalidNumber {
            attribute: "ixx",
            ..
        }
    ));
}

#[test]
fn duplicate_names_and_an_empty_robot() {
    let text = robot(&[("world", ""), ("world", INERTIAL)], "");
    assert_eq!(
        read(&text),
        ModelError::DuplicateName {
            kind: "link",
            name: "world".into()
        }
    );
    let text = robot(
        &[("world", ""), ("a", INERTIAL), ("b", INERTIAL)],
        &(joint("j", "revolute", "world", "a") + &joint("j", "revolute", "a", "b")),
    );
    assert_eq!(
        read(&text),
        ModelError::DuplicateName {
            kind: "joint",
            name: "j".into()
        }
    );
    assert_eq!(read("<robot name=\"r\"/>"), ModelError::Empty);
}

#[test]
fn unreadable_file() {
    let err = Model::from_urdf_file("/nonexistent/robot.urdf").unwrap_err();
    assert!(matches!(err, ModelError::Io { ref path, .. } if path == "/nonexistent/robot.urdf"));
}

#[test]
fn invalid_placement_and_gravity_from_the_builder() {
    let build = |placement: Pose, gravity: Vector3<f64>| {
        Model::builder()
            .frame("world")
            .body(
                "arm",
                Inertial::new(1.0, Vector3::zeros(), Matrix3::identity()),
            )
            .joint(JointSpec::revolute("j", "world", "arm", Vector3::z()).at(placement))
            .gravity(gravity)
            .build()
    };
    let sheared = Pose::from_rotation(Matrix3::new(1.0, 0.1, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0));
    assert_eq!(
        build(sheared, Vector3::zeros()).unwrap_err(),
        ModelError::InvalidPlacement { joint: "j".into() }
    );
    assert_eq!(
        build(Pose::identity(), Vector3::new(0.0, f64::INFINITY, 0.0)).unwrap_err(),
        ModelError::InvalidGravity {
            gravity: [0.0, f64::INFINITY, 0.0]
        }
    );
}

#[test]
fn configurations_and_velocities_that_do_not_fit() {
    let model = Model::builder()
        .frame("world")
        .body(
            "a",
            Inertial::new(1.0, Vector3::zeros(), Matrix3::identity()),
        )
        .body(
            "b",
            Inertial::new(1.0, Vector3::zeros(), Matrix3::identity()),
        )
        .joint(JointSpec::spherical("ball", "world", "a"))
        .joint(JointSpec::revolute("hinge", "a", "b", Vector3::x()))
        .build()
        .unwrap();
    assert_eq!(
        model.configuration_from_scalars(&[0.0, 0.0]).unwrap_err(),
        StateError::NotScalarJointed {
            joint: "ball".into()
        }
    );
    let q = |ball: JointPosition, hinge: JointPosition| Configuration {
        positions: vec![ball, hinge],
    };
    let good = q(
        JointPosition::Rotation(Matrix3::identity()),
        JointPosition::Scalar(0.1),
    );
    assert!(model.kinetic_energy(&good, &[0.0; 4]).is_ok());

    let short = Configuration {
        positions: vec![JointPosition::Scalar(0.0)],
    };
    assert_eq!(
        model.forward_kinematics(&short).unwrap_err(),
        StateError::JointCount {
            expected: 2,
            found: 1
        }
    );
    let swapped = q(
        JointPosition::Scalar(0.1),
        JointPosition::Rotation(Matrix3::identity()),
    );
    assert_eq!(
        model.mass_matrix(&swapped).unwrap_err(),
        StateError::WrongKind {
            joint: "ball".into(),
            expected: "a rotation",
            found: "a scalar"
        }
    );
    let scaled = q(
        JointPosition::Rotation(Matrix3::identity() * 1.1),
        JointPosition::Scalar(0.0),
    );
    assert!(matches!(
        model.potential_energy(&scaled).unwrap_err(),
        StateError::NotARotation { ref joint, .. } if joint == "ball"
    ));
    let reflected = q(
        JointPosition::Rotation(Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, -1.0))),
        JointPosition::Scalar(0.0),
    );
    assert!(matches!(
        model.potential_energy(&reflected).unwrap_err(),
        StateError::NotARotation { .. }
    ));
    let nan = q(
        JointPosition::Rotation(Matrix3::identity()),
        JointPosition::Scalar(f64::NAN),
    );
    assert_eq!(
        model.momentum(&nan, &[0.0; 4]).unwrap_err(),
        StateError::NonFinite {
            joint: "hinge".into()
        }
    );
    assert_eq!(
        model.kinetic_energy(&good, &[0.0; 3]).unwrap_err(),
        StateError::VelocityLength {
            expected: 4,
            found: 3
        }
    );
    assert_eq!(
        model
            .body_velocities(&good, &[0.0, f64::INFINITY, 0.0, 0.0])
            .unwrap_err(),
        StateError::NonFiniteVelocity { index: 1 }
    );
}
