//! The model: a tree of rigid bodies joined by joints, its configuration layout, and the one
//! assembly that both the URDF reader and [`ModelBuilder`] go through (validation, fixed joints
//! fused, bodies in topological order).

use std::collections::{HashMap, VecDeque};

use nalgebra::Vector3;

use crate::error::ModelError;
use crate::inertia::Inertial;
use crate::pose::Pose;

/// The default gravity, `(0, 0, −9.81)` m/s²: URDF has no gravity element, and its frames take
/// `z` up.
pub const STANDARD_GRAVITY: [f64; 3] = [0.0, 0.0, -9.81];

/// How a joint lets its child move relative to its parent, in the joint frame (the child's
/// frame at zero displacement).
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum JointKind {
    /// A rotation by an angle `θ` about a unit axis, with limits (URDF `revolute`).
    Revolute {
        /// The unit axis in the joint frame.
        axis: Vector3<f64>,
    },
    /// A rotation about a unit axis without limits (URDF `continuous`).
    Continuous {
        /// The unit axis in the joint frame.
        axis: Vector3<f64>,
    },
    /// A translation by `d` along a unit axis (URDF `prismatic`).
    Prismatic {
        /// The unit axis in the joint frame.
        axis: Vector3<f64>,
    },
    /// Any rotation about the joint frame's origin, `R ∈ SO(3)` (a ball joint; URDF has none).
    Spherical,
    /// No motion: the child is welded to the parent (fused into it when the model is built).
    Fixed,
    /// Any rigid motion, `(R, p) ∈ SE(3)` (URDF `floating`; a floating base).
    Free,
}

impl JointKind {
    /// The number of velocity coordinates: 1 for revolute, continuous and prismatic joints, 3
    /// for spherical, 6 for free, 0 for fixed.
    #[must_use]
    pub fn velocity_dimension(&self) -> usize {
        match self {
            Self::Revolute { .. } | Self::Continuous { .. } | Self::Prismatic { .. } => 1,
            Self::Spherical => 3,
            Self::Free => 6,
            Self::Fixed => 0,
        }
    }

    /// The URDF name of the type (`"spherical"` for a spherical joint).
    #[must_use]
    pub fn name(&self) -> &'static str {
        match self {
            Self::Revolute { .. } => "revolute",
            Self::Continuous { .. } => "continuous",
            Self::Prismatic { .. } => "prismatic",
            Self::Spherical => "spherical",
            Self::Fixed => "fixed",
            Self::Free => "floating",
        }
    }

    /// The axis of a revolute, continuous or prismatic joint.
    #[must_use]
    pub fn axis(&self) -> Option<Vector3<f64>> {
        match self {
            Self::Revolute { axis } | Self::Continuous { axis } | Self::Prismatic { axis } => {
                Some(*axis)
            }
            _ => None,
        }
    }

    /// Whether the joint has one scalar coordinate (revolute, continuous, prismatic).
    #[must_use]
    pub fn is_scalar(&self) -> bool {
        self.velocity_dimension() == 1
    }
}

/// A joint's limits, as URDF's `<limit>` gives them (zero where it gives none). Read and kept;
/// not enforced.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Limits {
    /// The lower position limit (rad or m).
    pub lower: f64,
    /// The upper position limit.
    pub upper: f64,
    /// The largest effort (N·m or N).
    pub effort: f64,
    /// The largest speed (rad/s or m/s).
    pub velocity: f64,
}

/// A joint's damping and friction, as URDF's `<dynamics>` gives them. Read and kept; not
/// applied.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Dynamics {
    /// Viscous damping (N·m·s/rad or N·s/m).
    pub damping: f64,
    /// Static friction (N·m or N).
    pub friction: f64,
}

/// A joint as described, before the model is assembled: its parent and child links by name,
/// the placement of the joint frame in the parent link's frame, its kind.
#[derive(Clone, Debug, PartialEq)]
pub struct JointSpec {
    /// The joint's name.
    pub name: String,
    /// The parent link's name.
    pub parent: String,
    /// The child link's name.
    pub child: String,
    /// The joint frame in the parent link's frame (URDF `<origin>`); the child link's frame is
    /// the joint frame moved by the joint.
    pub placement: Pose,
    /// The kind, with the axis where it has one (normalized when the model is built).
    pub kind: JointKind,
    /// Limits, if given.
    pub limits: Option<Limits>,
    /// Damping and friction, if given.
    pub dynamics: Option<Dynamics>,
}

impl JointSpec {
    /// A joint of any kind at the identity placement.
    #[must_use]
    pub fn new(
        name: impl Into<String>,
        parent: impl Into<String>,
        child: impl Into<String>,
        kind: JointKind,
    ) -> Self {
        Self {
            name: name.into(),
            parent: parent.into(),
            child: child.into(),
            placement: Pose::identity(),
            kind,
            limits: None,
            dynamics: None,
        }
    }

    /// A revolute joint about `axis` (in the joint frame).
    #[must_use]
    pub fn revolute(
        name: impl Into<String>,
        parent: impl Into<String>,
        child: impl Into<String>,
        axis: Vector3<f64>,
    ) -> Self {
        Self::new(name, parent, child, JointKind::Revolute { axis })
    }

    /// A prismatic joint along `axis` (in the joint frame).
    #[must_use]
    pub fn prismatic(
        name: impl Into<String>,
        parent: impl Into<String>,
        child: impl Into<String>,
        axis: Vector3<f64>,
    ) -> Self {
        Self::new(name, parent, child, JointKind::Prismatic { axis })
    }

    /// A spherical (ball) joint.
    #[must_use]
    pub fn spherical(
        name: impl Into<String>,
        parent: impl Into<String>,
        child: impl Into<String>,
    ) -> Self {
        Self::new(name, parent, child, JointKind::Spherical)
    }

    /// A fixed joint.
    #[must_use]
    pub fn fixed(
        name: impl Into<String>,
        parent: impl Into<String>,
        child: impl Into<String>,
    ) -> Self {
        Self::new(name, parent, child, JointKind::Fixed)
    }

    /// A free (floating) joint.
    #[must_use]
    pub fn free(
        name: impl Into<String>,
        parent: impl Into<String>,
        child: impl Into<String>,
    ) -> Self {
        Self::new(name, parent, child, JointKind::Free)
    }

    /// The joint frame's placement in the parent link's frame.
    #[must_use]
    pub fn at(mut self, placement: Pose) -> Self {
        self.placement = placement;
        self
    }

    /// Limits (kept, not enforced).
    #[must_use]
    pub fn with_limits(mut self, limits: Limits) -> Self {
        self.limits = Some(limits);
        self
    }
}

/// A rigid body of the assembled model: one moving link together with every link a fixed joint
/// welds to it. Its frame is that first link's frame.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct Body {
    /// The name of the body's first link.
    pub name: String,
    /// The mass, the centre of mass in the body frame and the rotational inertia about it in the
    /// body frame's axes, the fused links' merged in.
    pub inertial: Inertial,
    /// The parent body (`None` for the root, which is fixed in the world).
    pub parent: Option<usize>,
    /// The index of the joint that moves this body (`None` for the root).
    pub joint: Option<usize>,
}

/// A moving joint of the assembled model, between two bodies.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct Joint {
    /// The joint's name.
    pub name: String,
    /// The kind (never [`JointKind::Fixed`] here: fixed joints are fused), axes normalized.
    pub kind: JointKind,
    /// The parent body.
    pub parent: usize,
    /// The child body (`joints[i].child == i + 1`: the root has no joint).
    pub child: usize,
    /// The joint frame in the parent body's frame (fused placements composed in).
    pub placement: Pose,
    /// Limits, if given.
    pub limits: Option<Limits>,
    /// Damping and friction, if given.
    pub dynamics: Option<Dynamics>,
    /// The index of the joint's first velocity coordinate.
    pub velocity_offset: usize,
}

/// A named frame: a link of the description, possibly fused into a body.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct Frame {
    /// The link's name.
    pub name: String,
    /// The body it belongs to.
    pub body: usize,
    /// Its placement in that body's frame (the identity for a body's first link).
    pub placement: Pose,
}

/// What a configuration coordinate holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CoordinateKind {
    /// An angle (revolute, continuous) or a displacement (prismatic).
    Scalar,
    /// A rotation matrix in SO(3) (spherical joints, a free joint's attitude).
    Rotation,
    /// A position in R³ (a free joint's translation).
    Position,
}

/// One coordinate of the configuration layout, named after its joint: `<joint>` for a scalar,
/// `<joint>.rotation` for a spherical joint, `<joint>.rotation` and `<joint>.position` for a
/// free joint.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Coordinate {
    /// The name.
    pub name: String,
    /// The joint it belongs to.
    pub joint: usize,
    /// What it holds.
    pub kind: CoordinateKind,
}

/// A tree of rigid bodies joined by joints, with gravity.
///
/// Body 0 is the root: the description's root link with every link fixed to it, fixed in the
/// world (its pose is the identity). Every other body `i` is moved by joint `i − 1` relative to
/// its parent body, and parents come before children. Fixed joints do not appear: their child
/// links are fused into the parent's body (masses merged by the parallel-axis theorem), and
/// their names stay as [`Frame`]s. A floating base is the child of a [`JointKind::Free`] joint
/// from a massless root (the world).
///
/// ```
/// use dirac_multibody::nalgebra::{Matrix3, Vector3};
/// use dirac_multibody::{Inertial, JointSpec, Model};
///
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// // A rod hanging from a hinge about y: centre of mass 0.5 below it.
/// let inertia = Matrix3::from_diagonal(&Vector3::new(0.1, 0.1, 0.01));
/// let rod = Inertial::new(1.0, Vector3::new(0.0, 0.0, -0.5), inertia);
/// let model = Model::builder()
///     .frame("world")
///     .body("arm", rod)
///     .joint(JointSpec::revolute("shoulder", "world", "arm", Vector3::y()))
///     .build()?;
/// assert_eq!(model.bodies().len(), 2);
/// let q = model.configuration_from_scalars(&[std::f64::consts::FRAC_PI_2])?;
/// assert!(model.potential_energy(&q)?.abs() < 1e-15); // swung up to the hinge's height
/// assert_eq!(model.coordinates()[0].name, "shoulder");
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Model {
    pub(crate) bodies: Vec<Body>,
    pub(crate) joints: Vec<Joint>,
    pub(crate) frames: Vec<Frame>,
    pub(crate) coordinates: Vec<Coordinate>,
    pub(crate) gravity: Vector3<f64>,
    pub(crate) velocity_dimension: usize,
}

impl Model {
    /// A builder for a model written in Rust; it validates as the URDF reader does.
    #[must_use]
    pub fn builder() -> ModelBuilder {
        ModelBuilder::default()
    }

    /// The bodies, root first, parents before children.
    #[must_use]
    pub fn bodies(&self) -> &[Body] {
        &self.bodies
    }

    /// The moving joints; joint `i` moves body `i + 1`.
    #[must_use]
    pub fn joints(&self) -> &[Joint] {
        &self.joints
    }

    /// Every link of the description as a frame on its body.
    #[must_use]
    pub fn frames(&self) -> &[Frame] {
        &self.frames
    }

    /// The configuration layout, joint by joint.
    #[must_use]
    pub fn coordinates(&self) -> &[Coordinate] {
        &self.coordinates
    }

    /// The gravity vector in the world frame.
    #[must_use]
    pub fn gravity(&self) -> Vector3<f64> {
        self.gravity
    }

    /// The same model under another gravity vector (an error if it is not finite).
    pub fn with_gravity(mut self, gravity: Vector3<f64>) -> Result<Self, ModelError> {
        check_gravity(&gravity)?;
        self.gravity = gravity;
        Ok(self)
    }

    /// The number of velocity coordinates (the sum of the joints' [`JointKind::velocity_dimension`]).
    #[must_use]
    pub fn velocity_dimension(&self) -> usize {
        self.velocity_dimension
    }

    /// The body of this name (a body is named after its first link).
    #[must_use]
    pub fn body_index(&self, name: &str) -> Option<usize> {
        self.bodies.iter().position(|b| b.name == name)
    }

    /// The joint of this name.
    #[must_use]
    pub fn joint_index(&self, name: &str) -> Option<usize> {
        self.joints.iter().position(|j| j.name == name)
    }

    /// The frame of the link of this name.
    #[must_use]
    pub fn frame(&self, name: &str) -> Option<&Frame> {
        self.frames.iter().find(|f| f.name == name)
    }

    /// The total mass, the root's included.
    #[must_use]
    pub fn total_mass(&self) -> f64 {
        self.bodies.iter().map(|b| b.inertial.mass).sum()
    }

    /// Whether every joint is revolute, continuous or prismatic.
    #[must_use]
    pub fn is_scalar_jointed(&self) -> bool {
        self.joints.iter().all(|j| j.kind.is_scalar())
    }
}

/// Builds a [`Model`] in Rust: links (massive bodies or massless frames), joints, gravity.
/// [`build`](ModelBuilder::build) validates as the URDF reader does and fuses fixed joints.
#[derive(Clone, Debug, Default)]
pub struct ModelBuilder {
    links: Vec<(String, Option<Inertial>)>,
    joints: Vec<JointSpec>,
    gravity: Option<Vector3<f64>>,
}

impl ModelBuilder {
    /// A link with mass properties in its own frame.
    #[must_use]
    pub fn body(mut self, name: impl Into<String>, inertial: Inertial) -> Self {
        self.links.push((name.into(), Some(inertial)));
        self
    }

    /// A link without mass properties: the root (the world), or a frame fused by a fixed joint.
    #[must_use]
    pub fn frame(mut self, name: impl Into<String>) -> Self {
        self.links.push((name.into(), None));
        self
    }

    /// A joint between two links named before or after it.
    #[must_use]
    pub fn joint(mut self, joint: JointSpec) -> Self {
        self.joints.push(joint);
        self
    }

    /// The gravity vector (default [`STANDARD_GRAVITY`]).
    #[must_use]
    pub fn gravity(mut self, gravity: Vector3<f64>) -> Self {
        self.gravity = Some(gravity);
        self
    }

    /// Validates the description and assembles the model.
    ///
    /// # Errors
    /// A [`ModelError`] naming the element at fault: duplicate names, unknown links, a link with
    /// two parents, a cycle, several roots, a zero axis, a link that moves without mass
    /// properties, a negative mass, a moving body of zero mass, an inertia that is not that of
    /// a mass distribution.
    pub fn build(self) -> Result<Model, ModelError> {
        assemble(
            self.links,
            self.joints,
            self.gravity.unwrap_or(Vector3::from(STANDARD_GRAVITY)),
        )
    }
}

fn check_gravity(gravity: &Vector3<f64>) -> Result<(), ModelError> {
    if gravity.iter().all(|g| g.is_finite()) {
        Ok(())
    } else {
        Err(ModelError::InvalidGravity {
            gravity: (*gravity).into(),
        })
    }
}

/// Normalizes a joint's axis; a zero or non-finite one is an error.
fn normalized_kind(joint: &JointSpec) -> Result<JointKind, ModelError> {
    let unit = |axis: Vector3<f64>| {
        let norm = axis.norm();
        if norm.is_finite() && norm > 0.0 {
            Ok(axis / norm)
        } else {
            Err(ModelError::ZeroAxis {
                joint: joint.name.clone(),
            })
        }
    };
    Ok(match joint.kind {
        JointKind::Revolute { axis } => JointKind::Revolute { axis: unit(axis)? },
        JointKind::Continuous { axis } => JointKind::Continuous { axis: unit(axis)? },
        JointKind::Prismatic { axis } => JointKind::Prismatic { axis: unit(axis)? },
        other => other,
    })
}

/// The one assembly of a description into a [`Model`] (see [`ModelBuilder::build`]).
pub(crate) fn assemble(
    links: Vec<(String, Option<Inertial>)>,
    specs: Vec<JointSpec>,
    gravity: Vector3<f64>,
) -> Result<Model, ModelError> {
    check_gravity(&gravity)?;
    if links.is_empty() {
        return Err(ModelError::Empty);
    }
    let mut index = HashMap::with_capacity(links.len());
    for (i, (name, _)) in links.iter().enumerate() {
        if index.insert(name.as_str(), i).is_some() {
            return Err(ModelError::DuplicateName {
                kind: "link",
                name: name.clone(),
            });
        }
    }
    let mut joint_names = HashMap::with_capacity(specs.len());
    for j in &specs {
        if joint_names.insert(j.name.as_str(), ()).is_some() {
            return Err(ModelError::DuplicateName {
                kind: "joint",
                name: j.name.clone(),
            });
        }
    }
    // Each link's mass properties, on their own.
    for (name, inertial) in &links {
        if let Some(inertial) = inertial {
            if inertial.mass < 0.0 {
                return Err(ModelError::NegativeMass {
                    link: name.clone(),
                    mass: inertial.mass,
                });
            }
            inertial
                .check()
                .map_err(|defect| ModelError::InvalidInertia {
                    link: name.clone(),
                    defect,
                })?;
        }
    }
    // The tree: one parent joint per link, no cycle, one root.
    let mut parent_joint: Vec<Option<usize>> = vec![None; links.len()];
    let mut kinds = Vec::with_capacity(specs.len());
    let mut ends = Vec::with_capacity(specs.len());
    for (j, spec) in specs.iter().enumerate() {
        kinds.push(normalized_kind(spec)?);
        let rotation_ok = Pose::rotation_defect(&spec.placement.rotation) <= 1e-9;
        let translation_ok = spec.placement.translation.iter().all(|x| x.is_finite());
        if !(rotation_ok && translation_ok) {
            return Err(ModelError::InvalidPlacement {
                joint: spec.name.clone(),
            });
        }
        let find = |role: &'static str, link: &str| {
            index
                .get(link)
                .copied()
                .ok_or_else(|| ModelError::UnknownLink {
                    joint: spec.name.clone(),
                    role,
                    link: link.to_owned(),
                })
        };
        let parent = find("parent", &spec.parent)?;
        let child = find("child", &spec.child)?;
        if parent == child {
            return Err(ModelError::Cycle {
                link: spec.child.clone(),
            });
        }
        if let Some(first) = parent_joint[child] {
            return Err(ModelError::TwoParents {
                link: spec.child.clone(),
                first: specs[first].name.clone(),
                second: spec.name.clone(),
            });
        }
        parent_joint[child] = Some(j);
        ends.push((parent, child));
    }
    let on_cycle = |start: usize| {
        // Every link has at most one parent: following parents from a link that the root
        // does not reach must come back to a link already seen, which lies on a cycle.
        let mut seen = vec![false; links.len()];
        let mut link = start;
        while !seen[link] {
            seen[link] = true;
            match parent_joint[link] {
                Some(j) => link = ends[j].0,
                None => break,
            }
        }
        ModelError::Cycle {
            link: links[link].0.clone(),
        }
    };
    let roots: Vec<usize> = (0..links.len())
        .filter(|&l| parent_joint[l].is_none())
        .collect();
    let root = match roots.as_slice() {
        [] => return Err(on_cycle(0)),
        [root] => *root,
        _ => {
            return Err(ModelError::MultipleRoots {
                roots: roots.iter().map(|&l| links[l].0.clone()).collect(),
            })
        }
    };
    let mut children: Vec<Vec<usize>> = vec![Vec::new(); links.len()];
    for (j, &(parent, _)) in ends.iter().enumerate() {
        children[parent].push(j);
    }

    // Breadth first from the root: parents before children, fixed joints fused.
    let mut bodies = vec![Body {
        name: links[root].0.clone(),
        inertial: links[root].1.unwrap_or_else(Inertial::zero),
        parent: None,
        joint: None,
    }];
    let mut joints: Vec<Joint> = Vec::new();
    let mut frames = vec![Frame {
        name: links[root].0.clone(),
        body: 0,
        placement: Pose::identity(),
    }];
    // Each link's body and its placement in that body's frame.
    let mut link_body: Vec<Option<(usize, Pose)>> = vec![None; links.len()];
    link_body[root] = Some((0, Pose::identity()));
    let mut queue = VecDeque::from([root]);
    let mut reached = 1;
    while let Some(link) = queue.pop_front() {
        let (body, in_body) = link_body[link].expect("queued links are placed");
        for &j in &children[link] {
            let spec = &specs[j];
            let child = ends[j].1;
            let placement = in_body.compose(&spec.placement);
            let (name, inertial) = &links[child];
            if let JointKind::Fixed = kinds[j] {
                if let Some(inertial) = inertial {
                    let merged = bodies[body]
                        .inertial
                        .merged(&inertial.transformed(&placement));
                    bodies[body].inertial = merged;
                }
                link_body[child] = Some((body, placement));
                frames.push(Frame {
                    name: name.clone(),
                    body,
                    placement,
                });
            } else {
                let inertial = inertial.ok_or_else(|| ModelError::MissingInertia {
                    link: name.clone(),
                    joint: spec.name.clone(),
                })?;
                let new = bodies.len();
                bodies.push(Body {
                    name: name.clone(),
                    inertial,
                    parent: Some(body),
                    joint: Some(joints.len()),
                });
                joints.push(Joint {
                    name: spec.name.clone(),
                    kind: kinds[j],
                    parent: body,
                    child: new,
                    placement,
                    limits: spec.limits,
                    dynamics: spec.dynamics,
                    velocity_offset: 0,
                });
                link_body[child] = Some((new, Pose::identity()));
                frames.push(Frame {
                    name: name.clone(),
                    body: new,
                    placement: Pose::identity(),
                });
            }
            reached += 1;
            queue.push_back(child);
        }
    }
    if reached < links.len() {
        let unreached = (0..links.len())
            .find(|&l| link_body[l].is_none())
            .expect("counted");
        return Err(on_cycle(unreached));
    }
    // Moving bodies need mass; merged inertias are checked again (they are sums of valid ones).
    for body in &bodies[1..] {
        let joint = &joints[body.joint.expect("non-root bodies have joints")];
        if body.inertial.mass <= 0.0 {
            return Err(ModelError::ZeroMass {
                body: body.name.clone(),
                joint: joint.name.clone(),
            });
        }
        body.inertial
            .check()
            .map_err(|defect| ModelError::InvalidInertia {
                link: body.name.clone(),
                defect,
            })?;
    }
    let mut coordinates = Vec::new();
    let mut offset = 0;
    for (j, joint) in joints.iter_mut().enumerate() {
        joint.velocity_offset = offset;
        offset += joint.kind.velocity_dimension();
        let named = |suffix: &str, kind| Coordinate {
            name: format!("{}{suffix}", joint.name),
            joint: j,
            kind,
        };
        match joint.kind {
            JointKind::Spherical => coordinates.push(named(".rotation", CoordinateKind::Rotation)),
            JointKind::Free => {
                coordinates.push(named(".rotation", CoordinateKind::Rotation));
                coordinates.push(named(".position", CoordinateKind::Position));
            }
            _ => coordinates.push(named("", CoordinateKind::Scalar)),
        }
    }
    Ok(Model {
        bodies,
        joints,
        frames,
        coordinates,
        gravity,
        velocity_dimension: offset,
    })
}
