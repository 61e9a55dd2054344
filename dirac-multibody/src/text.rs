//! A model as a system given as text: the continuous Lagrangian of the tree, written in the
//! language of `#[reduced_lagrangian]`, for the run-time front end (`dirac_jit::compile_any`)
//! to differentiate, discretize and compile. Every integrator, sensitivity, step schedule and
//! output of a system given as text then serves the model, and the tree needs no integrator of
//! its own.
//!
//! # The Lagrangian
//!
//! For bodies `b` of mass `m_b`, centre of mass `c_b` in the body frame and rotational inertia
//! `I_b` about it in the body frame's axes (the model's [`Inertial`](crate::Inertial)s), in
//! gravity `g`,
//!
//! ```text
//! L(q, q̇) = Σ_b ½ m_b |v_c,b|² + ½ Ω_bᵀ I_b Ω_b + Σ_b m_b g · c_b^w,     Ω_b = R_bᵀ ω_b,
//! ```
//!
//! König's theorem for each body (the kinetic energy of its centre of mass plus that of its
//! rotation about it; Featherstone, *Rigid Body Dynamics Algorithms*, 2008, ch. 2) and the
//! potential `V = −Σ m_b g·c_b^w` of [`Model::potential_energy`]: `L = T − V` of the model's
//! [`kinetic_energy`](Model::kinetic_energy) and `potential_energy`, term by term.
//!
//! # The recursion, as let-bindings
//!
//! The text follows Featherstone's recursion in body coordinates (ch. 3–4, the kinematic
//! tree; the body-coordinate velocity recursion of ch. 5): each body's motion is written from
//! its parent's `λ(b)` as 3-vectors in the body's own frame — its angular velocity
//! `Ω_b = R_bᵀ ω_b`, the velocity `V_b = R_bᵀ ȯ_b` of its frame's origin, gravity
//! `γ_b = R_bᵀ g` — and the scalar `η_b = g·o_b`, so no 3 × 3 product of rotations appears and
//! every step is a rotation of three vectors. With the joint placement `(P_R, P_t)` in the
//! parent's frame, the joint frame has
//!
//! ```text
//! Ω_J = P_Rᵀ Ω_λ,   V_J = P_Rᵀ (V_λ + Ω_λ × P_t),   γ_J = P_Rᵀ γ_λ,   η_J = η_λ + γ_λ·P_t,
//! ```
//!
//! and the joint moves the child, with `a` its unit axis in the joint frame:
//!
//! * revolute, continuous: `R_b = R_J E(θ)` with Rodrigues' formula
//!   `E(θ) = a aᵀ + cos θ (1 − a aᵀ) + sin θ [a]×`; as `E a = a`,
//!   `Ω_b = Eᵀ Ω_J + a θ̇`, `V_b = Eᵀ V_J`, `γ_b = Eᵀ γ_J`, `η_b = η_J`;
//! * prismatic: `o_b = o_J + R_J a d`, so `Ω_b = Ω_J`, `V_b = V_J + Ω_J × a d + a ḋ`,
//!   `γ_b = γ_J`, `η_b = η_J + γ_J·a d`;
//! * spherical: `R_b = R_J R` for the child's rotation `R` in the joint frame with body
//!   angular velocity `Ω`, so `Ω_b = Rᵀ Ω_J + Ω`, `V_b = Rᵀ V_J`, `γ_b = Rᵀ γ_J`, `η_b = η_J`
//!   (the revolute joint's with `E` the free rotation `R`);
//! * free (a floating base, the child of the resting root): `R_b = R_J R`, `o_b = o_J + R_J x`
//!   for the pose `(R, x)` with body angular velocity `Ω` and velocity `ẋ`, so `Ω_b = Ω`,
//!   `V_b = Rᵀ ẋ`, `γ_b = Rᵀ γ_J`, `η_b = η_J + γ_J·x`.
//!
//! The root rests: `Ω_0 = V_0 = 0`, `γ_0 = g`, `η_0 = 0`. A body's centre of mass moves at
//! `R_bᵀ v_c,b = V_b + Ω_b × c_b` and lies at the height term `g·c_b^w = η_b + γ_b·c_b`, so
//!
//! ```text
//! L = Σ_b ½ m_b |V_b + Ω_b × c_b|² + ½ Ω_bᵀ I_b Ω_b + m_b (η_b + γ_b·c_b).
//! ```
//!
//! Each body adds a fixed number of let-bindings, so the text grows linearly with the number
//! of bodies. Constant placements, axes, inertias and the root's rest are folded into the
//! numbers written (an axis along `x`, `y` or `z` leaves four entries of `Eᵀ` that move), and
//! the compiler folds every product by a zero or a one that remains.
//!
//! # The rules
//!
//! * **A fixed base** (every joint revolute, continuous or prismatic) has one flat coordinate
//!   per joint, `shape(..)` with `group()`, and `rule = midpoint`:
//!   `L_d(q_0, q_1) = h L((q_0 + q_1)/2, (q_1 − q_0)/h)`. The rule is symmetric
//!   (`L_d(q_0, q_1; −h) = −L_d(q_1, q_0; h)`), so the variational step is of order 2 and its
//!   compositions of order 4 and 6; it evaluates `L` once per step (the trapezoid rule twice),
//!   which halves the straight-line code of every derivative; and it is the rule the
//!   attribute's own vector-space systems are written with, so the model steps as a system
//!   written by hand with the same rule does. On a vector of angles the mean of two
//!   configurations is a configuration.
//! * **A floating base** (a free joint from the root, scalar joints below it) puts the base on
//!   `SE(3)` as `pose(..)` beside the scalar joints as `shape(..)`, with `rule = trapezoid`:
//!   `L_d = (h/2)(L(q_0, v) + L(q_1, v))` with the base's body angular velocity
//!   `Ω = cay⁻¹(R_0ᵀ R_1)/h`, its velocity `(x_1 − x_0)/h` and the joints' chords. The midpoint
//!   rule is refused there (the mean of two rotations is not a rotation); the trapezoid rule is
//!   symmetric too, so the step is of order 2. A rigid motion of the whole tree,
//!   `(A, a)·(R, x) = (A R, A x + a)`, moves every body with the base and leaves `Ω`, the
//!   joints and every `|v_c,b|` and `Ω_b` unchanged: without gravity `L_d` is invariant under
//!   all of them — the text then declares `symmetry(<base>)`, checked by the compiler on
//!   sample configurations — and the step keeps the total linear and angular momentum (the
//!   discrete Noether theorem) to round-off, while the reduced integrator
//!   (`ReducedLieIntegrator`) carries them as the run's parameters, exactly; under gravity,
//!   the horizontal translations and the rotations about the vertical (not declared).
//! * **Spherical joints** (built in Rust: URDF has no spherical joint) are `rotation(..)`
//!   coordinates on `SO(3)` — the child's rotation in the joint frame, its momentum the body
//!   angular momentum — beside the scalar joints, on rotation groups with `rule = trapezoid`
//!   (with or without a floating base; [`TextKind::SphericalJoints`] for a fixed base).
//!
//! # Names
//!
//! A coordinate is named after its joint, made an identifier ([`TextCoordinate`]): characters
//! other than ASCII letters, digits and `_` become `_`, a leading digit gets a `j_` in front, a
//! Rust keyword a `_` behind, and a name taken twice a `_2`, `_3`, ... behind. With
//! [`TextOptions::torques`] each scalar joint `x` has a control `tau_x`, the torque (or force)
//! applied at the joint, entering as the virtual work `Σ τ_x δx` (`force = |dq| ..`).
//!
//! # What is not written
//!
//! Free joints below the root, and a free joint with other free joints, are refused
//! ([`ModelError::Unsupported`]); a model without a moving joint has nothing to step
//! ([`ModelError::NothingMoves`]). Limits and `<dynamics>` damping are not written.

use std::collections::HashSet;
use std::fmt::Write as _;

use nalgebra::{Matrix3, Vector3};

use crate::error::ModelError;
use crate::model::{JointKind, Model};
use crate::pose::skew;

/// How [`Model::system_text_with`] writes the text.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TextOptions {
    /// The function's name (made an identifier as the coordinates are); the compiled system's
    /// name.
    pub name: String,
    /// Whether each scalar joint `x` gets a control `tau_x`: a torque about a revolute joint's
    /// axis, a force along a prismatic joint's, as the virtual work `τ_x δx`.
    pub torques: bool,
}

impl Default for TextOptions {
    fn default() -> Self {
        Self {
            name: "multibody".to_owned(),
            torques: false,
        }
    }
}

/// Which front end a [`SystemText`] is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum TextKind {
    /// A fixed base: scalar joint coordinates on a vector space, `rule = midpoint`.
    FixedBase,
    /// A floating base: the base's `pose(..)` on `SE(3)` beside the joints (spherical joints
    /// as `rotation(..)`), `rule = trapezoid`.
    FloatingBase,
    /// A fixed base with spherical joints: their `rotation(..)` coordinates on `SO(3)` beside
    /// the scalar joints, `rule = trapezoid`.
    SphericalJoints,
}

/// One coordinate of a [`SystemText`]: the identifier the text names it by and the joint it
/// belongs to.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TextCoordinate {
    /// The identifier (`q.<identifier>` in the text, the compiled system's coordinate name).
    pub identifier: String,
    /// The joint's name in the model (the URDF's), which the identifier may differ from.
    pub joint: String,
}

/// A model's Lagrangian as text for the run-time front end, with the names it uses.
#[derive(Clone, Debug, PartialEq)]
pub struct SystemText {
    /// The text: one function with its `#[reduced_lagrangian(..)]` attribute.
    pub text: String,
    /// The function's name.
    pub name: String,
    /// Which front end it is for.
    pub kind: TextKind,
    /// The coordinates in the text's order, which is the model's joint order: for a floating
    /// base the pose first, then the scalar joints.
    pub coordinates: Vec<TextCoordinate>,
    /// The controls' names (`tau_<identifier>`, one per scalar joint) when asked for, in the
    /// coordinates' order; they are the parameters before `h`.
    pub controls: Vec<String>,
}

impl SystemText {
    /// The identifier of the coordinate of joint `joint` (by the model's name).
    #[must_use]
    pub fn identifier(&self, joint: &str) -> Option<&str> {
        self.coordinates
            .iter()
            .find(|c| c.joint == joint)
            .map(|c| c.identifier.as_str())
    }
}

impl std::fmt::Display for SystemText {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.text)
    }
}

/// Rust's keywords, strict and reserved: not identifiers.
const KEYWORDS: &[&str] = &[
    "as", "async", "await", "break", "const", "continue", "crate", "dyn", "else", "enum", "extern",
    "false", "fn", "for", "if", "impl", "in", "let", "loop", "match", "mod", "move", "mut", "pub",
    "ref", "return", "self", "Self", "static", "struct", "super", "trait", "true", "type",
    "unsafe", "use", "where", "while", "abstract", "become", "box", "do", "final", "gen", "macro",
    "override", "priv", "try", "typeof", "unsized", "virtual", "yield", "union",
];

/// `name` made an identifier (see the module's [names](self#names)), not one of `taken`.
fn identifier(name: &str, taken: &HashSet<String>) -> String {
    let mut id: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if id.is_empty() || id == "_" || id.starts_with(|c: char| c.is_ascii_digit()) {
        id.insert_str(0, "j_");
    }
    if KEYWORDS.contains(&id.as_str()) {
        id.push('_');
    }
    if !taken.contains(&id) {
        return id;
    }
    (2..)
        .map(|k| format!("{id}_{k}"))
        .find(|candidate| !taken.contains(candidate))
        .expect("a free suffix exists")
}

/// A literal that Rust and the text front end read back as the same `f64` (the shortest
/// representation that round-trips), negative ones in parentheses.
fn num(x: f64) -> String {
    let text = format!("{x:?}");
    if x.is_sign_negative() && x != 0.0 {
        format!("({text})")
    } else if x == 0.0 {
        "0.0".to_owned()
    } else {
        text
    }
}

fn vec3(v: &Vector3<f64>) -> String {
    if *v == Vector3::zeros() {
        "Vector3::zeros()".to_owned()
    } else {
        format!("Vector3::new({}, {}, {})", num(v.x), num(v.y), num(v.z))
    }
}

fn mat3(m: &Matrix3<f64>) -> String {
    if *m == Matrix3::identity() {
        return "Matrix3::identity()".to_owned();
    }
    let entries: Vec<String> = (0..3)
        .flat_map(|i| (0..3).map(move |j| (i, j)))
        .map(|(i, j)| num(m[(i, j)]))
        .collect();
    format!("Matrix3::new({})", entries.join(", "))
}

/// A vector known to be zero, known as numbers, or named by a let-binding.
#[derive(Clone, Debug)]
enum Vec3 {
    Zero,
    Const(Vector3<f64>),
    Named(String),
}

impl Vec3 {
    fn text(&self) -> String {
        match self {
            Vec3::Zero => "Vector3::zeros()".to_owned(),
            Vec3::Const(v) => vec3(v),
            Vec3::Named(n) => n.clone(),
        }
    }

    /// The vector's text as a term of a sum, empty for zero.
    fn term(&self) -> String {
        match self {
            Vec3::Zero => String::new(),
            v => v.text(),
        }
    }
}

/// A scalar known as a number or named by a let-binding.
#[derive(Clone, Debug)]
enum Scalar {
    Const(f64),
    Named(String),
}

impl Scalar {
    /// The scalar's text as a term of a sum, empty for zero.
    fn term(&self) -> String {
        match self {
            Scalar::Const(c) if *c == 0.0 => String::new(),
            Scalar::Const(c) => num(*c),
            Scalar::Named(n) => n.clone(),
        }
    }
}

/// `a + b + ...` of the terms that are not empty, or `None` when all are.
fn sum(terms: &[String]) -> Option<String> {
    let terms: Vec<&str> = terms
        .iter()
        .filter(|t| !t.is_empty())
        .map(String::as_str)
        .collect();
    if terms.is_empty() {
        None
    } else {
        Some(terms.join(" + "))
    }
}

/// A body's motion in its own frame, as the text knows it: the angular velocity `Ω_b`, the
/// velocity `V_b` of the frame's origin, gravity `γ_b = R_bᵀ g`, and the height term
/// `η_b = g·o_b` of the origin (module docs, [the recursion](self#the-recursion-as-let-bindings)).
#[derive(Clone, Debug)]
struct Motion {
    w: Vec3,
    d: Vec3,
    g: Vec3,
    y: Scalar,
}

/// The lines of the function's body.
struct Writer {
    out: String,
}

impl Writer {
    fn line(&mut self, s: &str) {
        self.out.push_str("    ");
        self.out.push_str(s);
        self.out.push('\n');
    }

    /// `expression` bound to `name`, or `Zero` when there is none.
    fn bind(&mut self, name: &str, expression: Option<String>) -> Vec3 {
        match expression {
            None => Vec3::Zero,
            Some(e) => {
                self.line(&format!("let {name} = {e};"));
                Vec3::Named(name.to_owned())
            }
        }
    }

    /// `m v` for a constant rotation `m`: folded when `v` is zero or a number or `m` the
    /// identity, else bound to `name`.
    fn rotate(&mut self, m: &Matrix3<f64>, v: &Vec3, name: &str) -> Vec3 {
        match v {
            Vec3::Zero => Vec3::Zero,
            Vec3::Const(x) => Vec3::Const(m * x),
            named if *m == Matrix3::identity() => named.clone(),
            Vec3::Named(x) => self.bind(name, Some(format!("{} * {x}", mat3(m)))),
        }
    }
}

/// The entries of `Eᵀ` for Rodrigues' `E(θ) = a aᵀ + cos θ (1 − a aᵀ) + sin θ [a]×`, with
/// `sin θ` and `cos θ` named `s` and `k`: `(Eᵀ)_ij = a_i a_j + (δ_ij − a_i a_j) k − [a]×_ij s`
/// (`[a]×` is skew), zero terms left out, so an axis along `x`, `y` or `z` gives the plane
/// rotation's four entries and a one.
fn rodrigues_transposed(axis: &Vector3<f64>, s: &str, k: &str) -> String {
    let cross = skew(axis);
    let mut entries = Vec::with_capacity(9);
    for i in 0..3 {
        for j in 0..3 {
            let outer = axis[i] * axis[j];
            let delta = if i == j { 1.0 } else { 0.0 };
            let mut terms = Vec::new();
            if outer != 0.0 {
                terms.push(num(outer));
            }
            for (coefficient, name) in [(delta - outer, k), (-cross[(i, j)], s)] {
                if coefficient == 1.0 {
                    terms.push(name.to_owned());
                } else if coefficient == -1.0 {
                    terms.push(format!("-{name}"));
                } else if coefficient != 0.0 {
                    terms.push(format!("{} * {name}", num(coefficient)));
                }
            }
            entries.push(sum(&terms).unwrap_or_else(|| "0.0".to_owned()));
        }
    }
    format!("Matrix3::new({})", entries.join(", "))
}

impl Model {
    /// The model's Lagrangian as a system given as text, with the default
    /// [`TextOptions`]: see [`Model::system_text_with`].
    ///
    /// # Errors
    /// As [`Model::system_text_with`].
    pub fn system_text(&self) -> Result<SystemText, ModelError> {
        self.system_text_with(&TextOptions::default())
    }

    /// The model's continuous Lagrangian `L = T − V` as the text of one function carrying
    /// `#[reduced_lagrangian(..)]`, for the run-time front end (`dirac_jit::compile_any`):
    /// scalar joints on a vector space with the midpoint rule for a fixed base, the base on
    /// `SE(3)` with the trapezoid rule for a floating one. The [module docs](crate::text)
    /// derive the text and say why these rules.
    ///
    /// ```
    /// # fn main() -> Result<(), Box<dyn std::error::Error>> {
    /// let model = dirac_multibody::Model::from_urdf_str(r#"
    ///   <robot name="pendulum">
    ///     <link name="world"/>
    ///     <link name="bob">
    ///       <inertial><origin xyz="0 0 -1"/><mass value="1"/>
    ///         <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
    ///     </link>
    ///     <joint name="hinge-1" type="continuous">
    ///       <parent link="world"/><child link="bob"/><axis xyz="0 1 0"/>
    ///     </joint>
    ///   </robot>"#)?;
    /// let text = model.system_text()?;
    /// assert!(text.text.contains("#[reduced_lagrangian(shape(hinge_1), group(), rule = midpoint)]"));
    /// assert_eq!(text.identifier("hinge-1"), Some("hinge_1"));
    /// # Ok(())
    /// # }
    /// ```
    ///
    /// # Errors
    /// [`ModelError::NothingMoves`] for a model without moving joints;
    /// [`ModelError::Unsupported`] naming a free joint that is not the
    /// root's only moving child.
    pub fn system_text_with(&self, options: &TextOptions) -> Result<SystemText, ModelError> {
        if self.joints.is_empty() {
            return Err(ModelError::NothingMoves);
        }
        let mut floating = None;
        for (j, joint) in self.joints.iter().enumerate() {
            match joint.kind {
                JointKind::Free if joint.parent != 0 || floating.is_some() => {
                    return Err(ModelError::Unsupported {
                        joint: joint.name.clone(),
                        feature: "a free joint that is not the root's only moving child, \
                                  in a system text"
                            .to_owned(),
                    })
                }
                JointKind::Free => floating = Some(j),
                _ => {}
            }
        }
        if let Some(f) = floating {
            // The base must carry the whole tree: no other joint hangs from the root.
            if let Some(other) = self
                .joints
                .iter()
                .find(|j| j.parent == 0 && j.child != f + 1)
            {
                return Err(ModelError::Unsupported {
                    joint: other.name.clone(),
                    feature: "a joint from the root beside a floating base, in a system text"
                        .to_owned(),
                });
            }
        }
        let mut taken = HashSet::new();
        let name = identifier(&options.name, &taken);
        taken.insert(name.clone());
        let mut coordinates = Vec::with_capacity(self.joints.len());
        for joint in &self.joints {
            let id = identifier(&joint.name, &taken);
            taken.insert(id.clone());
            coordinates.push(TextCoordinate {
                identifier: id,
                joint: joint.name.clone(),
            });
        }
        let scalars: Vec<&str> = self
            .joints
            .iter()
            .zip(&coordinates)
            .filter(|(j, _)| j.kind.is_scalar())
            .map(|(_, c)| c.identifier.as_str())
            .collect();
        let controls: Vec<String> = if options.torques {
            scalars.iter().map(|s| format!("tau_{s}")).collect()
        } else {
            Vec::new()
        };
        let spherical: Vec<&str> = self
            .joints
            .iter()
            .zip(&coordinates)
            .filter(|(j, _)| j.kind == JointKind::Spherical)
            .map(|(_, c)| c.identifier.as_str())
            .collect();
        let body = self.lagrangian_body(&coordinates);
        let mut attribute = if floating.is_none() && spherical.is_empty() {
            format!("shape({}), group(), rule = midpoint", scalars.join(", "))
        } else {
            let mut keys = Vec::new();
            if let Some(f) = floating {
                keys.push(format!("pose({})", coordinates[f].identifier));
            }
            if !spherical.is_empty() {
                keys.push(format!("rotation({})", spherical.join(", ")));
            }
            keys.push(format!("shape({})", scalars.join(", ")));
            keys.push("rule = trapezoid".to_owned());
            // Out of gravity a floating tree is invariant under every rigid motion of the
            // whole: declared, so that the reduced integrator can carry its momentum.
            if let Some(f) = floating.filter(|_| self.gravity == Vector3::zeros()) {
                keys.push(format!("symmetry({})", coordinates[f].identifier));
            }
            keys.join(", ")
        };
        if !controls.is_empty() {
            let work: Vec<String> = scalars
                .iter()
                .zip(&controls)
                .map(|(s, tau)| format!("{tau} * dq.{s}"))
                .collect();
            write!(
                attribute,
                ",\n    controls({}),\n    force = |dq| {}",
                controls.join(", "),
                work.join(" + ")
            )
            .expect("writing to a String");
        }
        let parameters: String = controls.iter().map(|c| format!(", {c}: f64")).collect();
        let kind = match (floating, spherical.is_empty()) {
            (Some(_), _) => TextKind::FloatingBase,
            (None, false) => TextKind::SphericalJoints,
            (None, true) => TextKind::FixedBase,
        };
        let text =
            format!(
            "// The Lagrangian L = T - V of a tree of {} moving {}, written by dirac-multibody.\n\
             #[reduced_lagrangian({attribute})]\n\
             fn {name}(q: Config, v: Velocity{parameters}) -> f64 {{\n{body}}}\n",
            self.joints.len(),
            if self.joints.len() == 1 { "body" } else { "bodies" }
        );
        Ok(SystemText {
            text,
            name,
            kind,
            coordinates,
            controls,
        })
    }

    /// The function's body: the recursion of the module docs as let-bindings, then `T − V`.
    fn lagrangian_body(&self, coordinates: &[TextCoordinate]) -> String {
        let mut out = Writer { out: String::new() };
        let g = self.gravity;
        let mut known: Vec<Motion> = Vec::with_capacity(self.bodies.len());
        known.push(Motion {
            w: Vec3::Zero,
            d: Vec3::Zero,
            g: if g == Vector3::zeros() {
                Vec3::Zero
            } else {
                Vec3::Const(g)
            },
            y: Scalar::Const(0.0),
        });
        // The constant part of L (the root's potential, fixed heights), then the other terms.
        let root = &self.bodies[0].inertial;
        let mut constant = root.mass * g.dot(&root.com);
        let mut terms = Vec::new();
        for (j, joint) in self.joints.iter().enumerate() {
            let b = joint.child;
            let x = &coordinates[j].identifier;
            let body = &self.bodies[b];
            let parent = known[joint.parent].clone();
            out.line(&format!(
                "// body {b}, {:?}: joint {:?} ({}) from {:?}",
                body.name,
                joint.name,
                joint.kind.name(),
                self.bodies[joint.parent].name
            ));
            let motion = self.joint_motion(&mut out, b, x, &joint.kind, &joint.placement, &parent);
            // T_b = ½ m |V_b + Ω_b × c|² + ½ Ω_bᵀ I Ω_b, and m g·c^w = m (η_b + γ_b·c).
            let inertial = &body.inertial;
            let (m, c) = (inertial.mass, inertial.com);
            let across = match (&motion.w, c == Vector3::zeros()) {
                (Vec3::Zero, _) | (_, true) => String::new(),
                (w, false) => format!("{}.cross(&{})", w.text(), vec3(&c)),
            };
            let mut energy = Vec::new();
            if let Vec3::Named(vc) = out.bind(&format!("vc_{b}"), sum(&[motion.d.term(), across])) {
                energy.push(format!("{} * {vc}.norm_squared()", num(0.5 * m)));
            }
            if let Vec3::Named(w) = &motion.w {
                // The symmetric part: a transformed inertia may be asymmetric by round-off.
                let inertia = (inertial.inertia + inertial.inertia.transpose()) * 0.5;
                energy.push(format!("0.5 * {w}.dot(&({} * {w}))", mat3(&inertia)));
            }
            match &motion.y {
                Scalar::Const(y) => constant += m * y,
                Scalar::Named(y) => energy.push(format!("{} * {y}", num(m))),
            }
            match &motion.g {
                Vec3::Zero => {}
                Vec3::Const(gb) => constant += m * gb.dot(&c),
                Vec3::Named(gb) if c != Vector3::zeros() => {
                    energy.push(format!("{gb}.dot(&{})", vec3(&(c * m))));
                }
                Vec3::Named(_) => {}
            }
            if !energy.is_empty() {
                out.line(&format!("let l_{b} = {};", energy.join(" + ")));
                terms.push(format!("l_{b}"));
            }
            known.push(motion);
        }
        if constant != 0.0 {
            terms.push(num(constant));
        }
        out.line(&sum(&terms).unwrap_or_else(|| "0.0".to_owned()));
        out.out
    }

    /// Body `b`'s motion from its parent's through its joint (coordinate `x`), written as
    /// let-bindings where it is not a number ([the recursion](self#the-recursion-as-let-bindings)).
    fn joint_motion(
        &self,
        out: &mut Writer,
        b: usize,
        x: &str,
        kind: &JointKind,
        placement: &crate::pose::Pose,
        parent: &Motion,
    ) -> Motion {
        let (pt, prt) = (placement.translation, placement.rotation.transpose());
        // The joint frame: Ω_J = P_Rᵀ Ω_λ, V_J = P_Rᵀ (V_λ + Ω_λ × P_t), γ_J = P_Rᵀ γ_λ,
        // η_J = η_λ + γ_λ·P_t.
        let w_j = out.rotate(&prt, &parent.w, &format!("wj_{b}"));
        let carried = match (&parent.w, pt == Vector3::zeros()) {
            (Vec3::Zero, _) | (_, true) => String::new(),
            (w, false) => format!("{}.cross(&{})", w.text(), vec3(&pt)),
        };
        let v_sum = if carried.is_empty() {
            parent.d.clone()
        } else {
            out.bind(&format!("vs_{b}"), sum(&[parent.d.term(), carried]))
        };
        let d_j = out.rotate(&prt, &v_sum, &format!("dj_{b}"));
        let g_j = out.rotate(&prt, &parent.g, &format!("gj_{b}"));
        let y_j = match (&parent.y, &parent.g) {
            (y, _) if pt == Vector3::zeros() => y.clone(),
            (y, Vec3::Zero) => y.clone(),
            (Scalar::Const(y), Vec3::Const(g)) => Scalar::Const(y + g.dot(&pt)),
            (y, g) => {
                let rise = format!("{}.dot(&{})", g.text(), vec3(&pt));
                let value = sum(&[y.term(), rise]).expect("a rise");
                out.line(&format!("let yj_{b} = {value};"));
                Scalar::Named(format!("yj_{b}"))
            }
        };
        match *kind {
            JointKind::Revolute { axis } | JointKind::Continuous { axis } => {
                // Ω_b = Eᵀ Ω_J + a θ̇, V_b = Eᵀ V_J, γ_b = Eᵀ γ_J, η_b = η_J.
                out.line(&format!("let s_{b} = q.{x}.sin();"));
                out.line(&format!("let k_{b} = q.{x}.cos();"));
                let e = rodrigues_transposed(&axis, &format!("s_{b}"), &format!("k_{b}"));
                out.line(&format!("let e_{b} = {e};"));
                let turned = |v: &Vec3| match v {
                    Vec3::Zero => String::new(),
                    v => format!("e_{b} * {}", v.text()),
                };
                let w = out.bind(
                    &format!("w_{b}"),
                    sum(&[turned(&w_j), format!("{} * v.{x}", vec3(&axis))]),
                );
                let d = out.bind(&format!("d_{b}"), sum(&[turned(&d_j)]));
                let g = out.bind(&format!("g_{b}"), sum(&[turned(&g_j)]));
                Motion { w, d, g, y: y_j }
            }
            JointKind::Prismatic { axis } => {
                // Ω_b = Ω_J, V_b = V_J + Ω_J × a d + a ḋ, γ_b = γ_J, η_b = η_J + γ_J·a d.
                let across = match &w_j {
                    Vec3::Zero => String::new(),
                    w => format!("{}.cross(&({} * q.{x}))", w.text(), vec3(&axis)),
                };
                let d = out.bind(
                    &format!("d_{b}"),
                    sum(&[d_j.term(), across, format!("{} * v.{x}", vec3(&axis))]),
                );
                let rise = match &g_j {
                    Vec3::Zero => None,
                    Vec3::Const(g) if g.dot(&axis) == 0.0 => None,
                    Vec3::Const(g) => Some(format!("{} * q.{x}", num(g.dot(&axis)))),
                    Vec3::Named(g) => Some(format!("{g}.dot(&{}) * q.{x}", vec3(&axis))),
                };
                let y = match rise {
                    None => y_j,
                    Some(rise) => {
                        let base = y_j.term();
                        out.line(&format!(
                            "let y_{b} = {};",
                            sum(&[base, rise]).expect("a rise")
                        ));
                        Scalar::Named(format!("y_{b}"))
                    }
                };
                Motion {
                    w: w_j,
                    d,
                    g: g_j,
                    y,
                }
            }
            JointKind::Free => {
                // A child of the root (checked): Ω_b = Ω, V_b = Rᵀ ẋ, γ_b = Rᵀ γ_J,
                // η_b = η_J + γ_J·x.
                let w = out.bind(&format!("w_{b}"), Some(format!("v.{x}.angular")));
                out.line(&format!("let rt_{b} = q.{x}.rotation.transpose();"));
                let d = out.bind(&format!("d_{b}"), Some(format!("rt_{b} * v.{x}.linear")));
                let g = match &g_j {
                    Vec3::Zero => Vec3::Zero,
                    g => out.bind(&format!("g_{b}"), Some(format!("rt_{b} * {}", g.text()))),
                };
                let y = match &g_j {
                    Vec3::Zero => y_j,
                    g => {
                        let base = y_j.term();
                        let rise = format!("{}.dot(&q.{x}.translation)", g.text());
                        out.line(&format!(
                            "let y_{b} = {};",
                            sum(&[base, rise]).expect("a rise")
                        ));
                        Scalar::Named(format!("y_{b}"))
                    }
                };
                Motion { w, d, g, y }
            }
            JointKind::Spherical => {
                // The child's rotation `R` in the joint frame and its body angular velocity
                // `Ω`: Ω_b = Rᵀ Ω_J + Ω, V_b = Rᵀ V_J, γ_b = Rᵀ γ_J, η_b = η_J.
                out.line(&format!("let rt_{b} = q.{x}.transpose();"));
                let turned = |v: &Vec3| match v {
                    Vec3::Zero => String::new(),
                    v => format!("rt_{b} * {}", v.text()),
                };
                let w = out.bind(&format!("w_{b}"), sum(&[turned(&w_j), format!("v.{x}")]));
                let d = out.bind(&format!("d_{b}"), sum(&[turned(&d_j)]));
                let g = out.bind(&format!("g_{b}"), sum(&[turned(&g_j)]));
                Motion { w, d, g, y: y_j }
            }
            JointKind::Fixed => unreachable!("fused before the body is written"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identifiers_are_rust_identifiers_and_distinct() {
        let mut taken = HashSet::new();
        let mut next = |name: &str| {
            let id = identifier(name, &taken);
            taken.insert(id.clone());
            id
        };
        assert_eq!(next("iiwa_joint_1"), "iiwa_joint_1");
        assert_eq!(next("elbow-left"), "elbow_left");
        assert_eq!(next("elbow left"), "elbow_left_2");
        assert_eq!(next("2nd"), "j_2nd");
        assert_eq!(next("type"), "type_");
        assert_eq!(next(""), "j_");
        assert_eq!(next("ünï"), "_n_");
    }

    #[test]
    fn literals_read_back_as_the_same_numbers() {
        for x in [
            0.0,
            -0.0,
            1.0,
            -1.0,
            0.1,
            -2.5e-7,
            1e20,
            123.456,
            f64::MIN_POSITIVE,
        ] {
            let text = num(x);
            let bare = text.trim_start_matches('(').trim_end_matches(')');
            assert_eq!(
                bare.parse::<f64>().unwrap(),
                if x == 0.0 { 0.0 } else { x },
                "{text}"
            );
        }
        assert_eq!(num(-0.5), "(-0.5)");
    }
}
