//! The free body of `examples/data/free_body.urdf` against `m v` and `I ω` in closed form; fixed
//! joints fused by the parallel-axis theorem; a free tree with a spherical joint built in Rust,
//! whose energy and momenta transform as they must under a rotation of the whole tree.

use dirac_multibody::nalgebra::{Matrix3, Vector3};
use dirac_multibody::{Configuration, Inertial, JointPosition, JointSpec, Model, ModelError, Pose};
use proptest::prelude::*;

fn data(name: &str) -> Model {
    let path = format!("{}/../examples/data/{name}", env!("CARGO_MANIFEST_DIR"));
    Model::from_urdf_file(path).expect("the example URDF reads")
}

fn rot_x(a: f64) -> Matrix3<f64> {
    let (s, c) = a.sin_cos();
    Matrix3::new(1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c)
}
fn rot_y(a: f64) -> Matrix3<f64> {
    let (s, c) = a.sin_cos();
    Matrix3::new(c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c)
}
fn rot_z(a: f64) -> Matrix3<f64> {
    let (s, c) = a.sin_cos();
    Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
}

/// A rotation from three angles (any parametrization will do for random rotations).
fn rotation(a: [f64; 3]) -> Matrix3<f64> {
    rot_z(a[0]) * rot_y(a[1]) * rot_x(a[2])
}

fn cross_matrix(c: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -c.z, c.y, c.z, 0.0, -c.x, -c.y, c.x, 0.0)
}

fn assert_vec_close(found: &Vector3<f64>, expected: &Vector3<f64>, tol: f64, what: &str) {
    let scale = expected.norm().max(1.0);
    assert!(
        (found - expected).norm() <= tol * scale,
        "{what}: {found:?} vs {expected:?}"
    );
}

/// The free body's file: mass 2.5, centre of mass (0.1, −0.05, 0.2), the inertia given in a
/// frame rotated by rpy (0.5, −0.2, 0.3).
fn free_body_constants() -> (f64, Vector3<f64>, Matrix3<f64>) {
    let urdf_inertia = Matrix3::new(0.3, 0.01, -0.02, 0.01, 0.4, 0.03, -0.02, 0.03, 0.5);
    let r = rot_z(0.3) * rot_y(-0.2) * rot_x(0.5);
    (
        2.5,
        Vector3::new(0.1, -0.05, 0.2),
        r * urdf_inertia * r.transpose(),
    )
}

#[test]
fn free_body_layout() {
    let model = data("free_body.urdf");
    let names: Vec<&str> = model
        .coordinates()
        .iter()
        .map(|c| c.name.as_str())
        .collect();
    assert_eq!(names, ["float.rotation", "float.position"]);
    assert_eq!(model.velocity_dimension(), 6);
    let (mass, com, inertia) = free_body_constants();
    let body = &model.bodies()[1].inertial;
    assert_eq!(body.mass, mass);
    assert_vec_close(&body.com, &com, 1e-15, "centre of mass");
    assert!(
        (body.inertia - inertia).amax() < 1e-15,
        "{} vs {inertia}",
        body.inertia
    );
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// `p = m v_c`, `L = c × m v_c + R I Ω`, `T = ½ m |v_c|² + ½ Ωᵀ I Ω`, `V = −m g·c`, and the
    /// mass matrix `[[I + m [c]×ᵀ[c]×, m [c]×], [m [c]×ᵀ, m 1]]` in the body twist (Ω, V),
    /// with `v_c = R (V + Ω × c)`.
    #[test]
    fn free_body_against_closed_forms(
        angles in proptest::array::uniform3(-3.2..3.2f64),
        p in proptest::array::uniform3(-2.0..2.0f64),
        twist in proptest::array::uniform6(-3.0..3.0f64),
    ) {
        let model = data("free_body.urdf");
        let (mass, com, inertia) = free_body_constants();
        let r = rotation(angles);
        let p = Vector3::from(p);
        let q = Configuration { positions: vec![JointPosition::Pose(Pose::new(r, p))] };
        let omega = Vector3::new(twist[0], twist[1], twist[2]);
        let v_body = Vector3::new(twist[3], twist[4], twist[5]);

        let c_world = r * com + p;
        let v_c = r * (v_body + omega.cross(&com));
        let linear = v_c * mass;
        let angular = c_world.cross(&linear) + r * inertia * omega;
        let kinetic = 0.5 * mass * v_c.norm_squared() + 0.5 * omega.dot(&(inertia * omega));
        let potential = -mass * model.gravity().dot(&c_world);

        let h = model.momentum(&q, &twist).unwrap();
        assert_vec_close(&h.linear, &linear, 1e-13, "linear momentum");
        assert_vec_close(&h.angular, &angular, 1e-13, "angular momentum");
        let t = model.kinetic_energy(&q, &twist).unwrap();
        prop_assert!((t - kinetic).abs() <= 1e-13 * kinetic.max(1.0), "T {} vs {}", t, kinetic);
        let v = model.potential_energy(&q).unwrap();
        prop_assert!((v - potential).abs() <= 1e-13 * potential.abs().max(1.0));

        let vel = model.body_velocities(&q, &twist).unwrap();
        assert_vec_close(&vel[1].angular, &(r * omega), 1e-14, "ω");
        assert_vec_close(&vel[1].linear, &v_c, 1e-13, "v_c");

        let m = model.mass_matrix(&q).unwrap();
        let cx = cross_matrix(&com);
        let top_left = inertia + cx.transpose() * cx * mass;
        for i in 0..3 {
            for j in 0..3 {
                prop_assert!((m[(i, j)] - top_left[(i, j)]).abs() < 1e-13);
                prop_assert!((m[(i, j + 3)] - mass * cx[(i, j)]).abs() < 1e-13);
                prop_assert!((m[(i + 3, j)] - mass * cx[(j, i)]).abs() < 1e-13);
                let diag = if i == j { mass } else { 0.0 };
                prop_assert!((m[(i + 3, j + 3)] - diag).abs() < 1e-13);
            }
        }
    }
}

/// An arm link with a tool welded to it by a fixed joint at a rotated, offset origin, the tool's
/// inertial frame rotated too: the arm body's merged mass properties against the parallel-axis
/// theorem computed here.
#[test]
fn fixed_joint_fuses_by_the_parallel_axis_theorem() {
    let model = Model::from_urdf_str(
        r#"<robot name="fused">
          <link name="world"/>
          <link name="arm">
            <inertial>
              <origin xyz="0.2 0 0.05" rpy="0 0 0"/>
              <mass value="3"/>
              <inertia ixx="0.02" ixy="0" ixz="0" iyy="0.05" iyz="0" izz="0.05"/>
            </inertial>
          </link>
          <link name="tool">
            <inertial>
              <origin xyz="0.01 0.02 0.03" rpy="0.3 0 0"/>
              <mass value="0.5"/>
              <inertia ixx="0.004" ixy="0" ixz="0" iyy="0.003" iyz="0" izz="0.002"/>
            </inertial>
          </link>
          <link name="tool_tip"/>
          <joint name="shoulder" type="revolute">
            <parent link="world"/> <child link="arm"/> <axis xyz="0 0 1"/>
          </joint>
          <joint name="mount" type="fixed">
            <parent link="arm"/> <child link="tool"/>
            <origin xyz="0.5 0 0" rpy="0 0 1.5707963267948966"/>
          </joint>
          <joint name="tip" type="fixed">
            <parent link="tool"/> <child link="tool_tip"/> <origin xyz="0 0.1 0"/>
          </joint>
        </robot>"#,
    )
    .unwrap();
    assert_eq!(model.bodies().len(), 2, "world and arm, the tool fused");
    assert_eq!(model.joints().len(), 1);

    // The tool's mass properties in the arm's frame.
    let mount = rot_z(std::f64::consts::FRAC_PI_2);
    let tool_frame = rot_x(0.3);
    let tool_mass = 0.5;
    let tool_com = mount * Vector3::new(0.01, 0.02, 0.03) + Vector3::new(0.5, 0.0, 0.0);
    let tool_inertia = mount
        * tool_frame
        * Matrix3::from_diagonal(&Vector3::new(0.004, 0.003, 0.002))
        * tool_frame.transpose()
        * mount.transpose();
    let arm_mass = 3.0;
    let arm_com = Vector3::new(0.2, 0.0, 0.05);
    let arm_inertia = Matrix3::from_diagonal(&Vector3::new(0.02, 0.05, 0.05));

    let mass = arm_mass + tool_mass;
    let com = (arm_com * arm_mass + tool_com * tool_mass) / mass;
    let steiner =
        |m: f64, d: Vector3<f64>| (Matrix3::identity() * d.dot(&d) - d * d.transpose()) * m;
    let inertia = arm_inertia
        + steiner(arm_mass, arm_com - com)
        + tool_inertia
        + steiner(tool_mass, tool_com - com);

    let arm = &model.bodies()[1].inertial;
    assert!((arm.mass - mass).abs() < 1e-15);
    assert_vec_close(&arm.com, &com, 1e-15, "merged centre of mass");
    assert!(
        (arm.inertia - inertia).amax() < 1e-15,
        "{} vs {inertia}",
        arm.inertia
    );

    // The fused links stay as frames: the tip at (0.5, 0, 0) + R_z(π/2) (0, 0.1, 0).
    let frame = model.frame("tool_tip").unwrap();
    assert_eq!(frame.body, 1);
    assert_vec_close(
        &frame.placement.translation,
        &Vector3::new(0.4, 0.0, 0.0),
        1e-15,
        "tip",
    );
    let q = model.configuration_from_scalars(&[0.7]).unwrap();
    let poses = model.forward_kinematics(&q).unwrap();
    let tip = model.frame_pose(&poses, "tool_tip").unwrap().translation;
    assert_vec_close(
        &tip,
        &(rot_z(0.7) * Vector3::new(0.4, 0.0, 0.0)),
        1e-15,
        "tip pose",
    );
}

/// A floating base with an arm: base (free) → upper (spherical) → lower (prismatic), built in
/// Rust, no gravity.
fn free_tree() -> Result<Model, ModelError> {
    let box_inertia = |a: f64, b: f64, c: f64| Matrix3::from_diagonal(&Vector3::new(a, b, c));
    Model::builder()
        .frame("world")
        .body(
            "base",
            Inertial::new(
                10.0,
                Vector3::new(0.0, 0.1, 0.0),
                box_inertia(1.0, 1.2, 1.5),
            ),
        )
        .body(
            "upper",
            Inertial::new(
                2.0,
                Vector3::new(0.0, 0.0, 0.3),
                box_inertia(0.1, 0.1, 0.02),
            ),
        )
        .body(
            "lower",
            Inertial::new(
                1.0,
                Vector3::new(0.1, 0.0, 0.2),
                box_inertia(0.05, 0.04, 0.03),
            ),
        )
        .joint(JointSpec::free("float", "world", "base"))
        .joint(
            JointSpec::spherical("shoulder", "base", "upper")
                .at(Pose::new(rot_x(0.4), Vector3::new(0.3, 0.0, 0.5))),
        )
        .joint(
            JointSpec::prismatic("slide", "upper", "lower", Vector3::new(0.0, 1.0, 1.0))
                .at(Pose::from_translation(Vector3::new(0.0, 0.0, 0.6))),
        )
        .gravity(Vector3::zeros())
        .build()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Rotating and translating the whole tree (the base's pose `X ↦ (Q, b) X`, joint
    /// positions and every body twist unchanged) leaves the kinetic energy and the mass matrix
    /// unchanged, rotates the linear momentum by `Q` and turns the angular momentum about the
    /// origin into `Q L + b × Q p`; and `T = ½ vᵀ M v` throughout.
    #[test]
    fn free_tree_under_a_rigid_motion_of_the_whole(
        base in proptest::array::uniform3(-3.2..3.2f64),
        shoulder in proptest::array::uniform3(-3.2..3.2f64),
        q_rot in proptest::array::uniform3(-3.2..3.2f64),
        b in proptest::array::uniform3(-2.0..2.0f64),
        slide in -0.5..0.5f64,
        v in proptest::collection::vec(-2.0..2.0f64, 10),
    ) {
        let model = free_tree().unwrap();
        prop_assert_eq!(model.velocity_dimension(), 10);
        let names: Vec<&str> = model.coordinates().iter().map(|c| c.name.as_str()).collect();
        prop_assert_eq!(names, ["float.rotation", "float.position", "shoulder.rotation", "slide"]);

        let base_pose = Pose::new(rotation(base), Vector3::new(0.2, -0.1, 0.3));
        let config = |x: Pose| Configuration {
            positions: vec![
                JointPosition::Pose(x),
                JointPosition::Rotation(rotation(shoulder)),
                JointPosition::Scalar(slide),
            ],
        };
        let q = config(base_pose);
        let motion = Pose::new(rotation(q_rot), Vector3::from(b));
        let moved = config(motion.compose(&base_pose));

        let t = model.kinetic_energy(&q, &v).unwrap();
        let t_moved = model.kinetic_energy(&moved, &v).unwrap();
        prop_assert!((t - t_moved).abs() <= 1e-13 * t.max(1.0), "T {} vs {}", t, t_moved);

        let m = model.mass_matrix(&q).unwrap();
        let m_moved = model.mass_matrix(&moved).unwrap();
        prop_assert!((&m - &m_moved).amax() <= 1e-12 * m.amax());
        prop_assert!(m.clone().cholesky().is_some(), "M is positive definite");
        let vv = dirac_multibody::nalgebra::DVector::from_column_slice(&v);
        let quadratic = 0.5 * vv.dot(&(&m * &vv));
        prop_assert!((t - quadratic).abs() <= 1e-13 * t.max(1.0), "T {} vs ½vᵀMv {}", t, quadratic);

        let h = model.momentum(&q, &v).unwrap();
        let h_moved = model.momentum(&moved, &v).unwrap();
        let qm = motion.rotation;
        assert_vec_close(&h_moved.linear, &(qm * h.linear), 1e-13, "linear momentum");
        let angular = qm * h.angular + motion.translation.cross(&(qm * h.linear));
        assert_vec_close(&h_moved.angular, &angular, 1e-13, "angular momentum");
    }
}

/// `exp(t [Ω]×)` by Rodrigues' formula.
fn exp_so3(omega: &Vector3<f64>, t: f64) -> Matrix3<f64> {
    let angle = omega.norm() * t;
    if omega.norm() == 0.0 {
        return Matrix3::identity();
    }
    dirac_multibody::axis_angle(&(omega / omega.norm()), angle)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(32))]

    /// The velocity convention against forward kinematics alone: moving the free tree's joints
    /// along the curve `R(t) = R exp(t [Ω]×)`, `p(t) = p + t R V`, `d(t) = d + t ḋ`, the central
    /// differences of every centre of mass and attitude are the body velocities' `v_c` and `ω`.
    #[test]
    fn body_velocities_are_the_derivatives_of_forward_kinematics(
        base in proptest::array::uniform3(-3.2..3.2f64),
        shoulder in proptest::array::uniform3(-3.2..3.2f64),
        slide in -0.5..0.5f64,
        v in proptest::collection::vec(-2.0..2.0f64, 10),
    ) {
        let model = free_tree().unwrap();
        let (r0, p0, s0) = (rotation(base), Vector3::new(0.2, -0.1, 0.3), rotation(shoulder));
        let omega_base = Vector3::new(v[0], v[1], v[2]);
        let v_base = Vector3::new(v[3], v[4], v[5]);
        let omega_shoulder = Vector3::new(v[6], v[7], v[8]);
        let at = |t: f64| Configuration {
            positions: vec![
                JointPosition::Pose(Pose::new(r0 * exp_so3(&omega_base, t), p0 + r0 * v_base * t)),
                JointPosition::Rotation(s0 * exp_so3(&omega_shoulder, t)),
                JointPosition::Scalar(slide + v[9] * t),
            ],
        };
        let h = 1e-5;
        let (before, now, after) = (
            model.forward_kinematics(&at(-h)).unwrap(),
            model.forward_kinematics(&at(0.0)).unwrap(),
            model.forward_kinematics(&at(h)).unwrap(),
        );
        let velocities = model.body_velocities(&at(0.0), &v).unwrap();
        for (b, body) in model.bodies().iter().enumerate().skip(1) {
            let com = |x: &Pose| x.transform_point(&body.inertial.com);
            let v_c = (com(&after[b]) - com(&before[b])) / (2.0 * h);
            assert_vec_close(&velocities[b].linear, &v_c, 1e-8, "v_c");
            let w = (after[b].rotation - before[b].rotation) / (2.0 * h) * now[b].rotation.transpose();
            let omega = Vector3::new(w[(2, 1)], w[(0, 2)], w[(1, 0)]);
            assert_vec_close(&velocities[b].angular, &omega, 1e-8, "ω");
        }
    }
}
