//! Kinematics and mechanics of a [`Model`] at a configuration and velocity, evaluated
//! numerically: forward kinematics, body velocities, kinetic and potential energy, momentum, and
//! the joint-space mass matrix. These are the reference values every integrator of the model is
//! checked against.
//!
//! # Conventions
//!
//! A configuration gives each joint's position ([`JointPosition`]): an angle or a displacement
//! for a scalar joint, a rotation `R` for a spherical joint, a pose `(R, p)` for a free joint.
//! Body `b`'s pose `X_b = (R_b, p_b)` in the world is its parent's composed with the joint's
//! placement and motion (Featherstone, *Rigid Body Dynamics Algorithms*, 2008, ch. 4, the
//! kinematic tree: `X_b = X_λ(b) · X_J · J(q)`), with
//!
//! * revolute and continuous: `J(θ) = (exp(θ [a]×), 0)`, Rodrigues' formula;
//! * prismatic: `J(d) = (1, d a)`;
//! * spherical: `J(R) = (R, 0)`; free: `J(R, p) = (R, p)`.
//!
//! A velocity is one vector of [`Model::velocity_dimension`] entries, joint by joint at
//! [`Joint::velocity_offset`](crate::Joint::velocity_offset): `θ̇` or `ḋ` for a scalar joint;
//! the body angular velocity `Ω` (`Ṙ = R [Ω]×`, in the child's frame) for a spherical joint;
//! `Ω` then the body linear velocity `V = Rᵀ ṗ` for a free joint — the body twist
//! `X⁻¹ Ẋ` of SE(3), relative to the parent. Every quantity below is in the world frame.
//!
//! # Spatial velocities, in one frame
//!
//! Body `b`'s spatial velocity `v̂_b = (ω_b, v_O,b)` — its angular velocity and the velocity of
//! the body-fixed point at the world origin — is its parent's plus its joint's,
//! `v̂_b = v̂_λ(b) + S_b q̇_b` (Featherstone's velocity recursion, ch. 3–5, with every vector in
//! the world frame, so no coordinate transforms). The motion subspace `S_b` in world coordinates, with
//! `R_b`, `p_b` the child body's pose and `â = R_b a`:
//!
//! * revolute: `S = (â, p_b × â)`, a rotation about the line through `p_b` along `â`;
//! * prismatic: `S = (0, â)`;
//! * spherical: three columns `(R_b e_k, p_b × R_b e_k)`, `k = 1, 2, 3`;
//! * free: those three, then `(0, R_b e_k)`: `ω = R_b Ω`, `ṗ_b = R_b V`.
//!
//! The centre of mass `c_b = R_b c + p_b` moves at `v_c,b = v_O,b + ω_b × c_b`.

use nalgebra::{DMatrix, Matrix3, Matrix6, Vector3, Vector6};

use crate::error::StateError;
use crate::model::{JointKind, Model};
use crate::pose::{axis_angle, skew, Pose};

/// One joint's position.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum JointPosition {
    /// An angle (revolute, continuous; rad) or a displacement (prismatic; m).
    Scalar(f64),
    /// The child's rotation relative to the joint frame (spherical).
    Rotation(Matrix3<f64>),
    /// The child's pose relative to the joint frame (free).
    Pose(Pose),
}

impl JointPosition {
    fn kind_name(&self) -> &'static str {
        match self {
            Self::Scalar(_) => "a scalar",
            Self::Rotation(_) => "a rotation",
            Self::Pose(_) => "a pose",
        }
    }
}

/// A configuration of a [`Model`]: one [`JointPosition`] per joint, in the model's joint order.
#[derive(Clone, Debug, PartialEq)]
pub struct Configuration {
    /// The joints' positions.
    pub positions: Vec<JointPosition>,
}

/// A body's velocity in the world frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyVelocity {
    /// The angular velocity `ω`.
    pub angular: Vector3<f64>,
    /// The velocity `v_c` of the centre of mass.
    pub linear: Vector3<f64>,
}

/// The total momentum of a model, in the world frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Momentum {
    /// The linear momentum `Σ m v_c`.
    pub linear: Vector3<f64>,
    /// The angular momentum about the world origin, `Σ (c × m v_c + R I Rᵀ ω)`.
    pub angular: Vector3<f64>,
}

fn expected_kind(kind: &JointKind) -> &'static str {
    match kind {
        JointKind::Spherical => "a rotation",
        JointKind::Free => "a pose",
        _ => "a scalar",
    }
}

impl Model {
    /// The configuration with every angle and displacement zero and every rotation the
    /// identity: the description's pose of the tree.
    #[must_use]
    pub fn neutral_configuration(&self) -> Configuration {
        let positions = self
            .joints
            .iter()
            .map(|j| match j.kind {
                JointKind::Spherical => JointPosition::Rotation(Matrix3::identity()),
                JointKind::Free => JointPosition::Pose(Pose::identity()),
                _ => JointPosition::Scalar(0.0),
            })
            .collect();
        Configuration { positions }
    }

    /// The configuration of a tree whose joints are all scalar, from one value per joint.
    ///
    /// # Errors
    /// [`StateError::NotScalarJointed`] for a model with spherical or free joints,
    /// [`StateError::JointCount`] for a wrong length, [`StateError::NonFinite`].
    pub fn configuration_from_scalars(&self, q: &[f64]) -> Result<Configuration, StateError> {
        if let Some(j) = self.joints.iter().find(|j| !j.kind.is_scalar()) {
            return Err(StateError::NotScalarJointed {
                joint: j.name.clone(),
            });
        }
        let config = Configuration {
            positions: q.iter().map(|&x| JointPosition::Scalar(x)).collect(),
        };
        self.check_configuration(&config)?;
        Ok(config)
    }

    /// Checks that a configuration fits this model: one position per joint, of the joint's
    /// kind, finite, rotations orthonormal with determinant 1 to `1e-9`.
    ///
    /// # Errors
    /// The [`StateError`] found first.
    pub fn check_configuration(&self, config: &Configuration) -> Result<(), StateError> {
        if config.positions.len() != self.joints.len() {
            return Err(StateError::JointCount {
                expected: self.joints.len(),
                found: config.positions.len(),
            });
        }
        for (joint, position) in self.joints.iter().zip(&config.positions) {
            let wrong = || StateError::WrongKind {
                joint: joint.name.clone(),
                expected: expected_kind(&joint.kind),
                found: position.kind_name(),
            };
            let rotation = match (&joint.kind, position) {
                (JointKind::Spherical, JointPosition::Rotation(r)) => Some(r),
                (JointKind::Free, JointPosition::Pose(x)) => {
                    if !x.translation.iter().all(|v| v.is_finite()) {
                        return Err(StateError::NonFinite {
                            joint: joint.name.clone(),
                        });
                    }
                    Some(&x.rotation)
                }
                (JointKind::Spherical | JointKind::Free, _) => return Err(wrong()),
                (_, JointPosition::Scalar(x)) => {
                    if !x.is_finite() {
                        return Err(StateError::NonFinite {
                            joint: joint.name.clone(),
                        });
                    }
                    None
                }
                _ => return Err(wrong()),
            };
            if let Some(r) = rotation {
                if !r.iter().all(|v| v.is_finite()) {
                    return Err(StateError::NonFinite {
                        joint: joint.name.clone(),
                    });
                }
                let deviation = Pose::rotation_defect(r);
                if deviation > 1e-9 {
                    return Err(StateError::NotARotation {
                        joint: joint.name.clone(),
                        deviation,
                    });
                }
            }
        }
        Ok(())
    }

    fn check_velocity(&self, v: &[f64]) -> Result<(), StateError> {
        if v.len() != self.velocity_dimension {
            return Err(StateError::VelocityLength {
                expected: self.velocity_dimension,
                found: v.len(),
            });
        }
        match v.iter().position(|x| !x.is_finite()) {
            Some(index) => Err(StateError::NonFiniteVelocity { index }),
            None => Ok(()),
        }
    }

    /// Every body's pose in the world, `X_b = X_λ(b) · X_J · J(q)` (see the module
    /// [conventions](crate::kinematics#conventions)); the root's is the identity.
    ///
    /// # Errors
    /// A configuration that does not fit the model ([`Model::check_configuration`]).
    pub fn forward_kinematics(&self, config: &Configuration) -> Result<Vec<Pose>, StateError> {
        self.check_configuration(config)?;
        let mut poses = Vec::with_capacity(self.bodies.len());
        poses.push(Pose::identity());
        for (joint, position) in self.joints.iter().zip(&config.positions) {
            let motion = match (joint.kind, position) {
                (
                    JointKind::Revolute { axis } | JointKind::Continuous { axis },
                    JointPosition::Scalar(t),
                ) => Pose::from_rotation(axis_angle(&axis, *t)),
                (JointKind::Prismatic { axis }, JointPosition::Scalar(d)) => {
                    Pose::from_translation(axis * *d)
                }
                (_, JointPosition::Rotation(r)) => Pose::from_rotation(*r),
                (_, JointPosition::Pose(x)) => *x,
                _ => unreachable!("checked by check_configuration"),
            };
            let pose = poses[joint.parent]
                .compose(&joint.placement)
                .compose(&motion);
            poses.push(pose);
        }
        Ok(poses)
    }

    /// A named frame's pose in the world, from the bodies' poses (`poses` as
    /// [`forward_kinematics`](Model::forward_kinematics) returns them); `None` for an unknown
    /// name or a slice of another model.
    #[must_use]
    pub fn frame_pose(&self, poses: &[Pose], name: &str) -> Option<Pose> {
        let frame = self.frame(name)?;
        Some(poses.get(frame.body)?.compose(&frame.placement))
    }

    /// The centre of mass of the whole model in the world, `Σ m c / Σ m` (the root's mass
    /// included; the origin for a massless model).
    ///
    /// # Errors
    /// A configuration that does not fit the model.
    pub fn centre_of_mass(&self, config: &Configuration) -> Result<Vector3<f64>, StateError> {
        let poses = self.forward_kinematics(config)?;
        let total = self.total_mass();
        if total == 0.0 {
            return Ok(Vector3::zeros());
        }
        let moment: Vector3<f64> = self
            .bodies
            .iter()
            .zip(&poses)
            .map(|(b, x)| x.transform_point(&b.inertial.com) * b.inertial.mass)
            .sum();
        Ok(moment / total)
    }

    /// Joint `j`'s motion subspace in world coordinates (module docs), one column per
    /// velocity coordinate, each `(angular; linear at the origin)`.
    fn motion_subspace(&self, poses: &[Pose], j: usize) -> Vec<Vector6<f64>> {
        let joint = &self.joints[j];
        let x = &poses[joint.child];
        let rotation_about = |a: Vector3<f64>| {
            let lin = x.translation.cross(&a);
            Vector6::new(a.x, a.y, a.z, lin.x, lin.y, lin.z)
        };
        let translation_along = |a: Vector3<f64>| Vector6::new(0.0, 0.0, 0.0, a.x, a.y, a.z);
        let frame_axes = || (0..3).map(|k| x.rotation.column(k).into_owned());
        match joint.kind {
            JointKind::Revolute { axis } | JointKind::Continuous { axis } => {
                vec![rotation_about(x.rotation * axis)]
            }
            JointKind::Prismatic { axis } => vec![translation_along(x.rotation * axis)],
            JointKind::Spherical => frame_axes().map(rotation_about).collect(),
            JointKind::Free => frame_axes()
                .map(rotation_about)
                .chain(frame_axes().map(translation_along))
                .collect(),
            JointKind::Fixed => Vec::new(),
        }
    }

    /// The bodies' spatial velocities `v̂_b = v̂_λ(b) + S_b q̇_b` in the world frame at the
    /// origin (module docs).
    fn spatial_velocities(&self, poses: &[Pose], v: &[f64]) -> Vec<Vector6<f64>> {
        let mut out = vec![Vector6::zeros(); self.bodies.len()];
        for (j, joint) in self.joints.iter().enumerate() {
            let mut vb = out[joint.parent];
            for (k, column) in self.motion_subspace(poses, j).iter().enumerate() {
                vb += column * v[joint.velocity_offset + k];
            }
            out[joint.child] = vb;
        }
        out
    }

    /// Every body's angular velocity `ω` and centre-of-mass velocity `v_c` in the world frame,
    /// from `v̂_b = v̂_λ(b) + S_b q̇_b` and `v_c = v_O + ω × c` (module docs).
    ///
    /// # Errors
    /// A configuration or velocity that does not fit the model.
    pub fn body_velocities(
        &self,
        config: &Configuration,
        v: &[f64],
    ) -> Result<Vec<BodyVelocity>, StateError> {
        let poses = self.forward_kinematics(config)?;
        self.check_velocity(v)?;
        Ok(self.velocities_at(&poses, v))
    }

    fn velocities_at(&self, poses: &[Pose], v: &[f64]) -> Vec<BodyVelocity> {
        self.spatial_velocities(poses, v)
            .iter()
            .zip(self.bodies.iter().zip(poses))
            .map(|(vb, (body, x))| {
                let angular = vb.fixed_rows::<3>(0).into_owned();
                let origin = vb.fixed_rows::<3>(3).into_owned();
                let c = x.transform_point(&body.inertial.com);
                BodyVelocity {
                    angular,
                    linear: origin + angular.cross(&c),
                }
            })
            .collect()
    }

    /// The kinetic energy `T = Σ_b ½ m_b |v_c,b|² + ½ ω_bᵀ R_b I_b R_bᵀ ω_b` (König's theorem:
    /// the motion of each body's centre of mass plus its rotation about it; Featherstone
    /// ch. 2, the kinetic energy `½ v̂ᵀ I v̂` of a rigid body).
    ///
    /// # Errors
    /// A configuration or velocity that does not fit the model.
    pub fn kinetic_energy(&self, config: &Configuration, v: &[f64]) -> Result<f64, StateError> {
        let poses = self.forward_kinematics(config)?;
        self.check_velocity(v)?;
        let velocities = self.velocities_at(&poses, v);
        Ok(self
            .bodies
            .iter()
            .zip(poses.iter().zip(&velocities))
            .map(|(body, (x, bv))| {
                let i = &body.inertial;
                let rotational =
                    (x.rotation * i.inertia * x.rotation.transpose() * bv.angular).dot(&bv.angular);
                0.5 * (i.mass * bv.linear.norm_squared() + rotational)
            })
            .sum())
    }

    /// The potential energy of gravity, `V = −Σ_b m_b g · c_b` (zero at the world origin; the
    /// root's constant term included).
    ///
    /// # Errors
    /// A configuration that does not fit the model.
    pub fn potential_energy(&self, config: &Configuration) -> Result<f64, StateError> {
        let poses = self.forward_kinematics(config)?;
        Ok(-self
            .bodies
            .iter()
            .zip(&poses)
            .map(|(b, x)| b.inertial.mass * self.gravity.dot(&x.transform_point(&b.inertial.com)))
            .sum::<f64>())
    }

    /// The total linear momentum `Σ m v_c` and angular momentum about the world origin
    /// `Σ (c × m v_c + R I Rᵀ ω)` (Featherstone ch. 2, spatial momentum `I v̂`, summed over the
    /// bodies).
    ///
    /// # Errors
    /// A configuration or velocity that does not fit the model.
    pub fn momentum(&self, config: &Configuration, v: &[f64]) -> Result<Momentum, StateError> {
        let poses = self.forward_kinematics(config)?;
        self.check_velocity(v)?;
        let velocities = self.velocities_at(&poses, v);
        let mut total = Momentum {
            linear: Vector3::zeros(),
            angular: Vector3::zeros(),
        };
        for (body, (x, bv)) in self.bodies.iter().zip(poses.iter().zip(&velocities)) {
            let i = &body.inertial;
            let c = x.transform_point(&i.com);
            let p = bv.linear * i.mass;
            total.linear += p;
            total.angular +=
                c.cross(&p) + x.rotation * i.inertia * x.rotation.transpose() * bv.angular;
        }
        Ok(total)
    }

    /// The joint-space mass matrix `M(q)`, with `T = ½ q̇ᵀ M q̇` in the velocity coordinates of
    /// the module docs (for spherical and free joints, their body angular and linear
    /// velocities), by the composite-rigid-body algorithm (Featherstone ch. 6, §6.2) written
    /// in the world frame, where every coordinate transform is the identity:
    ///
    /// * each body's spatial inertia about the world origin, `I_b = [[Ī_c + m [c]×[c]×ᵀ,
    ///   m [c]×], [m [c]×ᵀ, m 1]]` with `Ī_c = R I Rᵀ` (Featherstone ch. 2, the spatial inertia
    ///   of a body whose centre of mass is at `c`);
    /// * the composite inertias `I^c_b = I_b + Σ_{children} I^c_child`, leaves first;
    /// * `M_ii = S_iᵀ I^c_i S_i`, and for each ancestor joint `j` of `i`,
    ///   `M_ij = M_jiᵀ = S_iᵀ I^c_i S_j`; every other block is zero.
    ///
    /// This follows from `T = Σ_b ½ v̂_bᵀ I_b v̂_b` with `v̂_b = Σ_{j ⪯ b} S_j q̇_j`: the term in
    /// `q̇_iᵀ (·) q̇_j` collects every body below both `i` and `j`, the subtree of the deeper one.
    /// The cost is `O(n d)` for `n` bodies of depth `d`.
    ///
    /// # Errors
    /// A configuration that does not fit the model.
    pub fn mass_matrix(&self, config: &Configuration) -> Result<DMatrix<f64>, StateError> {
        let poses = self.forward_kinematics(config)?;
        let mut composite: Vec<Matrix6<f64>> = self
            .bodies
            .iter()
            .zip(&poses)
            .map(|(body, x)| {
                let i = &body.inertial;
                let c = skew(&x.transform_point(&i.com));
                let rotational = x.rotation * i.inertia * x.rotation.transpose();
                let mut spatial = Matrix6::zeros();
                spatial
                    .fixed_view_mut::<3, 3>(0, 0)
                    .copy_from(&(rotational + c * c.transpose() * i.mass));
                spatial
                    .fixed_view_mut::<3, 3>(0, 3)
                    .copy_from(&(c * i.mass));
                spatial
                    .fixed_view_mut::<3, 3>(3, 0)
                    .copy_from(&(c.transpose() * i.mass));
                spatial
                    .fixed_view_mut::<3, 3>(3, 3)
                    .copy_from(&(Matrix3::identity() * i.mass));
                spatial
            })
            .collect();
        for b in (1..self.bodies.len()).rev() {
            if let Some(parent) = self.bodies[b].parent {
                let child = composite[b];
                composite[parent] += child;
            }
        }
        let n = self.velocity_dimension;
        let subspaces: Vec<Vec<Vector6<f64>>> = (0..self.joints.len())
            .map(|j| self.motion_subspace(&poses, j))
            .collect();
        let mut m = DMatrix::zeros(n, n);
        for (i, joint) in self.joints.iter().enumerate() {
            let forces: Vec<Vector6<f64>> = subspaces[i]
                .iter()
                .map(|s| composite[joint.child] * s)
                .collect();
            let mut ancestor = Some(i);
            while let Some(j) = ancestor {
                let other = &self.joints[j];
                for (a, f) in forces.iter().enumerate() {
                    for (b, s) in subspaces[j].iter().enumerate() {
                        let value = f.dot(s);
                        m[(joint.velocity_offset + a, other.velocity_offset + b)] = value;
                        m[(other.velocity_offset + b, joint.velocity_offset + a)] = value;
                    }
                }
                ancestor = self.bodies[other.parent].joint;
            }
        }
        Ok(m)
    }
}
