//! Articulated rigid bodies read from URDF (`dirac-multibody`), compiled through their system
//! text: [`compile_model`].

use dirac_multibody::{Model, SystemText, TextOptions};

use crate::{compile_any, Compiled, Error};

/// A model's system text and its machine code.
#[derive(Clone, Debug)]
pub struct ModelCode {
    /// The text, with the coordinates' identifiers and the joints they belong to (the URDF's
    /// names, which the identifiers may differ from) and the controls' names.
    pub text: SystemText,
    /// The compiled system: on vector spaces ([`Compiled::Flat`]) for a fixed base, on
    /// rotation groups ([`Compiled::Lie`]) for a floating one.
    pub compiled: Compiled,
}

/// Compiles a model of articulated rigid bodies: its Lagrangian written as text by
/// [`Model::system_text_with`] (scalar joints with the midpoint rule for a fixed base, the
/// base's pose on `SE(3)` with the trapezoid rule for a floating one), then [`compile_any`].
/// Every integrator, sensitivity and output of a system given as text then runs the model.
///
/// ```
/// use dirac_jit::{compile_model, Compiled};
/// use dirac_multibody::{Model, TextOptions};
/// use dirac_runtime::prelude::*;
///
/// let model = Model::from_urdf_str(r#"
///   <robot name="pendulum">
///     <link name="world"/>
///     <link name="bob">
///       <inertial><origin xyz="0 0 -1"/><mass value="1"/>
///         <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial>
///     </link>
///     <joint name="hinge" type="continuous">
///       <parent link="world"/><child link="bob"/><axis xyz="0 1 0"/>
///     </joint>
///   </robot>"#)?;
/// let code = compile_model(&model, &TextOptions::default())?;
/// let Compiled::Flat(flat) = &code.compiled else { unreachable!("a fixed base") };
/// assert_eq!(flat.system().shape, ["hinge"]);
/// let pendulum = flat.instantiate::<1, 0, 1>(&[0.01])?; // h, the only parameter
/// let start = pendulum.unreduced_state::<1, 0>([0.5], [0.0])?;
/// let traj = UnreducedIntegrator::new(pendulum, NewtonOptions::default())
///     .run(start)
///     .steps(100)
///     .collect()?;
/// assert!(traj.last().q[0] < 0.5); // swinging back
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Errors
/// [`Error::Model`] for a model the text does not support (a spherical joint, a free joint
/// below the root, nothing that moves); the text front end's errors otherwise.
pub fn compile_model(model: &Model, options: &TextOptions) -> Result<ModelCode, Error> {
    let text = model.system_text_with(options)?;
    let compiled = compile_any(&text.text)?;
    Ok(ModelCode { text, compiled })
}
