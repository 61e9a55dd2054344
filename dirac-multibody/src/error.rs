//! The errors of building or reading a model ([`ModelError`]) and of evaluating it at a
//! configuration and velocity ([`StateError`]). Each names the element at fault: the link, the
//! joint, the XML element and attribute.

use thiserror::Error;

/// What is wrong with a link's inertia (see [`ModelError::InvalidInertia`]).
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum InertiaDefect {
    /// A mass, centre of mass or inertia entry is NaN or infinite.
    NonFinite,
    /// The rotational inertia matrix is not symmetric (largest `|I − Iᵀ|` entry).
    NotSymmetric {
        /// The largest entry of `|I − Iᵀ|`.
        asymmetry: f64,
    },
    /// The rotational inertia of a link with positive mass has an eigenvalue that is not
    /// positive (or, for a massless link, one that is negative).
    NotPositiveDefinite {
        /// The principal moments (eigenvalues), ascending.
        moments: [f64; 3],
    },
    /// The principal moments violate the triangle inequality `J₁ + J₂ ≥ J₃`, which every
    /// physical mass distribution satisfies.
    TriangleInequality {
        /// The principal moments (eigenvalues), ascending.
        moments: [f64; 3],
    },
}

impl std::fmt::Display for InertiaDefect {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::NonFinite => write!(f, "a mass, centre of mass or inertia entry is not finite"),
            Self::NotSymmetric { asymmetry } => {
                write!(
                    f,
                    "the inertia matrix is not symmetric (|I - I^T| up to {asymmetry:e})"
                )
            }
            Self::NotPositiveDefinite { moments } => write!(
                f,
                "the inertia matrix is not positive definite (principal moments {moments:?})"
            ),
            Self::TriangleInequality { moments } => write!(
                f,
                "the principal moments {moments:?} violate the triangle inequality \
                 J1 + J2 >= J3 (no mass distribution has them)"
            ),
        }
    }
}

/// A model that cannot be built: a malformed URDF document, or a description (from URDF or
/// from [`ModelBuilder`](crate::ModelBuilder)) that is not a tree of bodies with physical
/// inertias. Every variant names the element at fault.
#[derive(Clone, Debug, Error, PartialEq)]
#[non_exhaustive]
pub enum ModelError {
    /// The text is not well-formed XML; `message` is the parser's, with line and column.
    #[error("malformed XML: {message}")]
    Xml {
        /// The XML parser's message.
        message: String,
    },
    /// The file could not be read.
    #[error("cannot read {path}: {message}")]
    Io {
        /// The path given.
        path: String,
        /// The operating system's message.
        message: String,
    },
    /// The document's root element is not `<robot>`.
    #[error("the root element is <{found}>, not <robot>: not a URDF document")]
    NotUrdf {
        /// The root element's name.
        found: String,
    },
    /// A required child element is missing (`<mass>` in an `<inertial>`, `<parent>` in a joint).
    #[error("{element}: missing <{child}>")]
    MissingElement {
        /// The element that lacks it, e.g. `joint "elbow"`.
        element: String,
        /// The missing child's tag.
        child: &'static str,
    },
    /// A required attribute is missing.
    #[error("{element}: missing attribute `{attribute}`")]
    MissingAttribute {
        /// The element that lacks it, e.g. `<inertia> of link "upper_arm"`.
        element: String,
        /// The attribute's name.
        attribute: &'static str,
    },
    /// An attribute that must hold finite numbers does not.
    #[error("{element}: attribute `{attribute}` = {value:?} is not {expected}")]
    InvalidNumber {
        /// The element, e.g. `<origin> of joint "elbow"`.
        element: String,
        /// The attribute's name.
        attribute: &'static str,
        /// The attribute's text.
        value: String,
        /// What it must be: "a finite number" or "3 finite numbers".
        expected: &'static str,
    },
    /// Two links, or two joints, share a name.
    #[error("two {kind}s are named {name:?}")]
    DuplicateName {
        /// "link" or "joint".
        kind: &'static str,
        /// The name given twice.
        name: String,
    },
    /// A link that moves has no `<inertial>`. A link without one is accepted only as the root
    /// (the world) or when a fixed joint fuses it into its parent (a massless frame).
    #[error(
        "link {link:?} has no <inertial> but moves (joint {joint:?}): only the root link and \
         links fused by a fixed joint may be massless frames"
    )]
    MissingInertia {
        /// The link's name.
        link: String,
        /// The moving joint whose child it is.
        joint: String,
    },
    /// A link's mass is negative.
    #[error("link {link:?} has a negative mass {mass}")]
    NegativeMass {
        /// The link's name.
        link: String,
        /// Its mass.
        mass: f64,
    },
    /// A body that moves (a link with the links fused into it by fixed joints) has no mass.
    #[error("body {body:?} moves (joint {joint:?}) but its mass is zero")]
    ZeroMass {
        /// The body's name (its first link's).
        body: String,
        /// The moving joint whose child it is.
        joint: String,
    },
    /// A link's inertia is not that of a mass distribution.
    #[error("link {link:?}: {defect}")]
    InvalidInertia {
        /// The link's name.
        link: String,
        /// What is wrong.
        defect: InertiaDefect,
    },
    /// A joint names a link that does not exist.
    #[error("joint {joint:?} names an unknown {role} link {link:?}")]
    UnknownLink {
        /// The joint's name.
        joint: String,
        /// "parent" or "child".
        role: &'static str,
        /// The name it gives.
        link: String,
    },
    /// A link is the child of two joints.
    #[error("link {link:?} has two parents: it is the child of joints {first:?} and {second:?}")]
    TwoParents {
        /// The link's name.
        link: String,
        /// The first joint naming it as child.
        first: String,
        /// The second.
        second: String,
    },
    /// The joints close a loop: the link's chain of parents comes back to it.
    #[error("the joints form a cycle through link {link:?}")]
    Cycle {
        /// A link on the cycle.
        link: String,
    },
    /// More than one link has no parent.
    #[error("more than one root link (links without a parent): {roots:?}")]
    MultipleRoots {
        /// The links without a parent.
        roots: Vec<String>,
    },
    /// The model has no links.
    #[error("the model has no links")]
    Empty,
    /// A joint type this library does not know.
    #[error(
        "joint {joint:?} has unknown type {kind:?} (known: revolute, continuous, prismatic, \
         fixed, floating)"
    )]
    UnknownJointType {
        /// The joint's name.
        joint: String,
        /// The type it gives.
        kind: String,
    },
    /// A URDF joint type or element this library reads but does not support yet (`planar`
    /// joints, `<mimic>`), or a joint that a system text does not support yet (spherical
    /// joints, a free joint below the root: [`Model::system_text`](crate::Model::system_text)).
    #[error("joint {joint:?}: {feature} is not supported")]
    Unsupported {
        /// The joint's name.
        joint: String,
        /// What is not supported, e.g. `type "planar"`.
        feature: String,
    },
    /// A revolute, continuous or prismatic joint's axis is zero (or not finite).
    #[error("joint {joint:?} has a zero axis")]
    ZeroAxis {
        /// The joint's name.
        joint: String,
    },
    /// A placement's rotation is not a rotation matrix (builder input).
    #[error("joint {joint:?}: its placement's rotation is not orthonormal with determinant 1")]
    InvalidPlacement {
        /// The joint's name.
        joint: String,
    },
    /// The model has no moving joint: its system text would have no coordinate
    /// ([`Model::system_text`](crate::Model::system_text)).
    #[error("the model has no moving joint: nothing to step")]
    NothingMoves,
    /// The gravity vector is not finite.
    #[error("gravity {gravity:?} is not finite")]
    InvalidGravity {
        /// The vector given.
        gravity: [f64; 3],
    },
}

/// A configuration or velocity that does not fit the model it is evaluated with.
#[derive(Clone, Debug, Error, PartialEq)]
#[non_exhaustive]
pub enum StateError {
    /// The configuration has a different number of joints than the model.
    #[error("the configuration has {found} joint positions, the model {expected} joints")]
    JointCount {
        /// The model's moving joints.
        expected: usize,
        /// The configuration's entries.
        found: usize,
    },
    /// A joint's position is of the wrong kind (an angle for a spherical joint, …).
    #[error("joint {joint:?} takes {expected}, the configuration gives {found}")]
    WrongKind {
        /// The joint's name.
        joint: String,
        /// What it takes: "a scalar", "a rotation", "a pose".
        expected: &'static str,
        /// What was given.
        found: &'static str,
    },
    /// A joint's position holds NaN or infinity.
    #[error("joint {joint:?}: the position is not finite")]
    NonFinite {
        /// The joint's name.
        joint: String,
    },
    /// A rotation is not orthonormal with determinant 1 (to 1e-9).
    #[error("joint {joint:?}: the rotation is not orthonormal (|RᵀR − I| = {deviation:e})")]
    NotARotation {
        /// The joint's name.
        joint: String,
        /// The largest entry of `|RᵀR − I|` (or `|det R − 1|`).
        deviation: f64,
    },
    /// The velocity vector's length differs from the model's velocity dimension.
    #[error("the velocity has {found} entries, the model {expected}")]
    VelocityLength {
        /// [`Model::velocity_dimension`](crate::Model::velocity_dimension).
        expected: usize,
        /// The length given.
        found: usize,
    },
    /// The velocity holds NaN or infinity.
    #[error("velocity entry {index} is not finite")]
    NonFiniteVelocity {
        /// The first entry at fault.
        index: usize,
    },
    /// A scalar vector given for a model that has spherical or free joints.
    #[error("joint {joint:?} is not a scalar joint: build the configuration joint by joint")]
    NotScalarJointed {
        /// The first joint that is not revolute, continuous or prismatic.
        joint: String,
    },
}
