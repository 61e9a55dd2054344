//! # dirac-multibody
//!
//! Articulated rigid bodies as data: a tree of bodies joined by revolute, continuous,
//! prismatic, spherical, fixed and free joints, read from URDF or built in Rust, with the
//! kinematics and mechanics of the tree evaluated numerically — forward kinematics, body
//! velocities, kinetic and potential energy, linear and angular momentum, and the joint-space
//! mass matrix. Used through `dirac::multibody`.
//!
//! ```
//! use dirac_multibody::Model;
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let model = Model::from_urdf_str(r#"
//!   <robot name="double_pendulum">
//!     <link name="world"/>
//!     <link name="upper">
//!       <inertial><origin xyz="0 0 -1"/><mass value="1"/>
//!         <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
//!     </link>
//!     <link name="lower">
//!       <inertial><origin xyz="0 0 -1"/><mass value="1"/>
//!         <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
//!     </link>
//!     <joint name="shoulder" type="continuous">
//!       <parent link="world"/><child link="upper"/><axis xyz="0 1 0"/>
//!     </joint>
//!     <joint name="elbow" type="continuous">
//!       <parent link="upper"/><child link="lower"/><origin xyz="0 0 -1"/><axis xyz="0 1 0"/>
//!     </joint>
//!   </robot>"#)?;
//! let q = model.configuration_from_scalars(&[0.3, -0.2])?;
//! let v = [1.0, 0.5];
//! let m = model.mass_matrix(&q)?;
//! let t = model.kinetic_energy(&q, &v)?;
//! // T = ½ q̇ᵀ M(q) q̇
//! let quadratic = 0.5 * (m[(0, 0)] * v[0] * v[0] + 2.0 * m[(0, 1)] * v[0] * v[1] + m[(1, 1)] * v[1] * v[1]);
//! assert!((t - quadratic).abs() < 1e-12);
//! # Ok(())
//! # }
//! ```
//!
//! ## The model
//!
//! A [`Model`] is a tree of [`Body`]s in topological order (parents first). Body 0 is the root,
//! fixed in the world: the description's root link. Every other body is moved relative to its
//! parent by one [`Joint`]. Fixed joints are fused when the model is built: the child link's
//! mass properties are merged into the parent's body by the parallel-axis theorem
//! ([`Inertial::merged`]), and the link stays as a named [`Frame`]. A floating base is the
//! child of a free joint from a massless root. Each body carries its mass, its centre of mass in
//! its frame, and its rotational inertia about the centre of mass in its frame's axes, checked
//! to be that of a mass distribution: symmetric, positive definite, principal moments
//! satisfying the triangle inequality ([`InertiaDefect`]).
//!
//! The configuration layout ([`Model::coordinates`]) names each coordinate after its joint:
//! `<joint>` for an angle or displacement, `<joint>.rotation` (SO(3)) for a spherical joint,
//! `<joint>.rotation` and `<joint>.position` (SE(3)) for a free joint.
//!
//! ## Reading URDF
//!
//! [`Model::from_urdf_str`] and [`Model::from_urdf_file`] read `<link>` and `<joint>` elements
//! (the [`urdf`] module says which parts); [`Model::builder`] builds the same description in
//! Rust and validates it by the same code. Bad input is a typed [`ModelError`] naming the link,
//! joint, element or attribute, never a panic.
//!
//! ## Kinematics and mechanics
//!
//! The [`kinematics`] module derives what [`Model`] evaluates at a [`Configuration`] and a
//! velocity: [`Model::forward_kinematics`], [`Model::body_velocities`],
//! [`Model::kinetic_energy`], [`Model::potential_energy`], [`Model::momentum`] and
//! [`Model::mass_matrix`] (the composite-rigid-body algorithm), after Featherstone, *Rigid Body
//! Dynamics Algorithms* (Springer, 2008), chapters 2–6.
//!
//! ## Stepping a model
//!
//! [`Model::system_text`] writes the model's Lagrangian as a system given as text (the
//! [`text`] module derives it): scalar joints with the midpoint rule for a fixed base, the base
//! on `SE(3)` beside them with the trapezoid rule for a floating one. The run-time front end
//! (`dirac_jit::compile_any`, or `dirac_jit::compile_model`) compiles it to machine code, and
//! every integrator of the run API steps it.

#![warn(missing_docs)]

pub mod articulated;
mod error;
mod inertia;
pub mod kinematics;
mod model;
mod pose;
pub mod text;
pub mod urdf;

pub use articulated::{
    ArticulatedIntegrator, ArticulatedSolver, ArticulatedWorkspace, MassOperator,
};
pub use error::{InertiaDefect, ModelError, StateError};
pub use inertia::{parallel_axis, principal_moments, Inertial};
pub use kinematics::{BodyVelocity, Configuration, JointPosition, Momentum};
pub use model::{
    Body, Coordinate, CoordinateKind, Dynamics, Frame, Joint, JointKind, JointSpec, Limits, Model,
    ModelBuilder, STANDARD_GRAVITY,
};
pub use pose::{axis_angle, skew, Pose};
pub use text::{SystemText, TextCoordinate, TextKind, TextOptions};

/// The linear algebra the model's vectors and matrices are written in.
pub use nalgebra;
