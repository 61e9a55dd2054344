//! The URDF reader: `<robot>`'s `<link>` and `<joint>` elements into a [`Model`].
//!
//! What is read: each link's `<inertial>` (`<origin xyz rpy>`, `<mass value>`, `<inertia ixx
//! ixy ixz iyy iyz izz>`, the inertia about the centre of mass in the `<origin>` frame); each
//! joint's `type`, `<parent link>`, `<child link>`, `<origin xyz rpy>`, `<axis xyz>` (default
//! `1 0 0`), `<limit lower upper effort velocity>` and `<dynamics damping friction>` (kept,
//! neither enforced nor applied). Joint types: `revolute`, `continuous`, `prismatic`, `fixed`,
//! `floating`; `planar` and `<mimic>` are refused as [`ModelError::Unsupported`] rather than
//! read wrongly, and any other type is [`ModelError::UnknownJointType`]. Everything else —
//! `<visual>`, `<collision>`, `<material>`, `<transmission>`, `<gazebo>`, vendor extensions —
//! is geometry or tooling and is ignored.
//!
//! A link without `<inertial>` is a massless frame, accepted where it means one: the root link
//! (the world, fixed in space) and a link welded to its parent by a fixed joint (an end
//! effector's frame, a sensor mount). A link that moves must have one
//! ([`ModelError::MissingInertia`]); an `<inertial>` is never filled in with zeros.

use std::path::Path;

use nalgebra::{Matrix3, Vector3};
use roxmltree::{Document, Node};

use crate::error::ModelError;
use crate::inertia::Inertial;
use crate::model::{assemble, Dynamics, JointKind, JointSpec, Limits, Model, STANDARD_GRAVITY};
use crate::pose::Pose;

impl Model {
    /// Reads a model from URDF text, with gravity [`STANDARD_GRAVITY`] (change it with
    /// [`Model::with_gravity`]). See the [`urdf`](crate::urdf) module for what is read.
    ///
    /// ```
    /// # fn main() -> Result<(), dirac_multibody::ModelError> {
    /// let model = dirac_multibody::Model::from_urdf_str(r#"
    ///   <robot name="pendulum">
    ///     <link name="world"/>
    ///     <link name="bob">
    ///       <inertial>
    ///         <origin xyz="0 0 -1"/>
    ///         <mass value="1"/>
    ///         <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/>
    ///       </inertial>
    ///     </link>
    ///     <joint name="hinge" type="continuous">
    ///       <parent link="world"/> <child link="bob"/> <axis xyz="0 1 0"/>
    ///     </joint>
    ///   </robot>"#)?;
    /// assert_eq!(model.joints()[0].name, "hinge");
    /// let q = model.configuration_from_scalars(&[0.0]).unwrap();
    /// assert!((model.potential_energy(&q).unwrap() + 9.81).abs() < 1e-12); // V = −m g·c
    /// # Ok(())
    /// # }
    /// ```
    ///
    /// # Errors
    /// A [`ModelError`] naming the element at fault; malformed XML as [`ModelError::Xml`] with
    /// the parser's message (line and column).
    pub fn from_urdf_str(text: &str) -> Result<Model, ModelError> {
        let doc = Document::parse(text).map_err(|e| ModelError::Xml {
            message: e.to_string(),
        })?;
        let robot = doc.root_element();
        if robot.tag_name().name() != "robot" {
            return Err(ModelError::NotUrdf {
                found: robot.tag_name().name().to_owned(),
            });
        }
        let mut links = Vec::new();
        let mut joints = Vec::new();
        for node in robot.children().filter(Node::is_element) {
            match node.tag_name().name() {
                "link" => links.push(read_link(node)?),
                "joint" => joints.push(read_joint(node)?),
                _ => {}
            }
        }
        assemble(links, joints, Vector3::from(STANDARD_GRAVITY))
    }

    /// Reads a model from a URDF file ([`Model::from_urdf_str`]).
    ///
    /// # Errors
    /// [`ModelError::Io`] if the file cannot be read, else as [`Model::from_urdf_str`].
    pub fn from_urdf_file(path: impl AsRef<Path>) -> Result<Model, ModelError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|e| ModelError::Io {
            path: path.display().to_string(),
            message: e.to_string(),
        })?;
        Self::from_urdf_str(&text)
    }
}

fn child<'a, 'input>(node: Node<'a, 'input>, tag: &str) -> Option<Node<'a, 'input>> {
    node.children()
        .find(|n| n.is_element() && n.tag_name().name() == tag)
}

fn required<'a>(
    node: Node<'a, '_>,
    attribute: &'static str,
    element: &str,
) -> Result<&'a str, ModelError> {
    node.attribute(attribute)
        .ok_or_else(|| ModelError::MissingAttribute {
            element: element.to_owned(),
            attribute,
        })
}

fn number(text: &str, attribute: &'static str, element: &str) -> Result<f64, ModelError> {
    match text.trim().parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ => Err(ModelError::InvalidNumber {
            element: element.to_owned(),
            attribute,
            value: text.to_owned(),
            expected: "a finite number",
        }),
    }
}

fn triple(text: &str, attribute: &'static str, element: &str) -> Result<[f64; 3], ModelError> {
    let invalid = || ModelError::InvalidNumber {
        element: element.to_owned(),
        attribute,
        value: text.to_owned(),
        expected: "3 finite numbers",
    };
    let mut out = [0.0_f64; 3];
    let mut parts = text.split_whitespace();
    for x in &mut out {
        *x = parts
            .next()
            .ok_or_else(invalid)?
            .parse()
            .map_err(|_| invalid())?;
        if !x.is_finite() {
            return Err(invalid());
        }
    }
    if parts.next().is_some() {
        return Err(invalid());
    }
    Ok(out)
}

fn optional_triple(
    node: Node<'_, '_>,
    attribute: &'static str,
    element: &str,
    default: [f64; 3],
) -> Result<[f64; 3], ModelError> {
    node.attribute(attribute)
        .map_or(Ok(default), |t| triple(t, attribute, element))
}

/// An `<origin xyz rpy>` child (the identity if absent).
fn origin(parent: Node<'_, '_>, owner: &str) -> Result<Pose, ModelError> {
    let Some(node) = child(parent, "origin") else {
        return Ok(Pose::identity());
    };
    let element = format!("<origin> of {owner}");
    let xyz = optional_triple(node, "xyz", &element, [0.0; 3])?;
    let rpy = optional_triple(node, "rpy", &element, [0.0; 3])?;
    Ok(Pose::from_xyz_rpy(xyz, rpy))
}

fn read_link(node: Node<'_, '_>) -> Result<(String, Option<Inertial>), ModelError> {
    let name = required(node, "name", "<link>")?.to_owned();
    let owner = format!("link {name:?}");
    let Some(inertial) = child(node, "inertial") else {
        return Ok((name, None));
    };
    let element = format!("<inertial> of {owner}");
    let frame = origin(inertial, &element)?;
    let mass_node = child(inertial, "mass").ok_or_else(|| ModelError::MissingElement {
        element: element.clone(),
        child: "mass",
    })?;
    let mass_element = format!("<mass> of {owner}");
    let mass = number(
        required(mass_node, "value", &mass_element)?,
        "value",
        &mass_element,
    )?;
    let inertia_node = child(inertial, "inertia").ok_or(ModelError::MissingElement {
        element,
        child: "inertia",
    })?;
    let inertia_element = format!("<inertia> of {owner}");
    let entry = |attribute: &'static str| {
        number(
            required(inertia_node, attribute, &inertia_element)?,
            attribute,
            &inertia_element,
        )
    };
    let (ixx, ixy, ixz) = (entry("ixx")?, entry("ixy")?, entry("ixz")?);
    let (iyy, iyz, izz) = (entry("iyy")?, entry("iyz")?, entry("izz")?);
    let inertia = Matrix3::new(ixx, ixy, ixz, ixy, iyy, iyz, ixz, iyz, izz);
    // The inertia is given about the centre of mass in the <origin> frame: rotate it into the
    // link frame, I_link = R I Rᵀ, with the centre of mass at the origin's translation.
    let local = Inertial::new(mass, Vector3::zeros(), inertia).transformed(&frame);
    Ok((name, Some(local)))
}

fn read_joint(node: Node<'_, '_>) -> Result<JointSpec, ModelError> {
    let name = required(node, "name", "<joint>")?.to_owned();
    let owner = format!("joint {name:?}");
    let kind_text = required(node, "type", &owner)?;
    if child(node, "mimic").is_some() {
        return Err(ModelError::Unsupported {
            joint: name,
            feature: "<mimic>".to_owned(),
        });
    }
    let link_of = |tag: &'static str| -> Result<String, ModelError> {
        let element = child(node, tag).ok_or_else(|| ModelError::MissingElement {
            element: owner.clone(),
            child: tag,
        })?;
        Ok(required(element, "link", &format!("<{tag}> of {owner}"))?.to_owned())
    };
    let parent = link_of("parent")?;
    let child_link = link_of("child")?;
    let placement = origin(node, &owner)?;
    let axis = match child(node, "axis") {
        Some(axis) => Vector3::from(optional_triple(
            axis,
            "xyz",
            &format!("<axis> of {owner}"),
            [1.0, 0.0, 0.0],
        )?),
        None => Vector3::x(),
    };
    let kind = match kind_text {
        "revolute" => JointKind::Revolute { axis },
        "continuous" => JointKind::Continuous { axis },
        "prismatic" => JointKind::Prismatic { axis },
        "fixed" => JointKind::Fixed,
        "floating" => JointKind::Free,
        "planar" => {
            return Err(ModelError::Unsupported {
                joint: name,
                feature: "type \"planar\"".to_owned(),
            })
        }
        other => {
            return Err(ModelError::UnknownJointType {
                joint: name,
                kind: other.to_owned(),
            })
        }
    };
    let limits = match child(node, "limit") {
        Some(limit) => {
            let element = format!("<limit> of {owner}");
            let value = |attribute: &'static str| {
                limit
                    .attribute(attribute)
                    .map_or(Ok(0.0), |t| number(t, attribute, &element))
            };
            Some(Limits {
                lower: value("lower")?,
                upper: value("upper")?,
                effort: value("effort")?,
                velocity: value("velocity")?,
            })
        }
        None => None,
    };
    let dynamics = match child(node, "dynamics") {
        Some(dynamics) => {
            let element = format!("<dynamics> of {owner}");
            let value = |attribute: &'static str| {
                dynamics
                    .attribute(attribute)
                    .map_or(Ok(0.0), |t| number(t, attribute, &element))
            };
            Some(Dynamics {
                damping: value("damping")?,
                friction: value("friction")?,
            })
        }
        None => None,
    };
    Ok(JointSpec {
        name,
        parent,
        child: child_link,
        placement,
        kind,
        limits,
        dynamics,
    })
}
