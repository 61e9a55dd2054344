//! Articulated rigid bodies from Python: `dirac.from_urdf` reads a URDF file, `dirac.Model`
//! builds the same description link by link and joint by joint; both compile the model's
//! Lagrangian (written as text by `dirac-multibody`) into a `System` (a fixed base) or a
//! `LieSystem` (a floating base, spherical joints).

use dirac_multibody::nalgebra::{Matrix3, Vector3};
use dirac_multibody::{Inertial, JointKind, JointSpec, ModelBuilder, ModelError, Pose};
use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;

use crate::{compile_error, system_object};

/// `[x, y, z]` as a vector; a `ValueError` naming `what` for any other length.
fn vector(what: &str, v: &[f64]) -> PyResult<Vector3<f64>> {
    match v {
        [x, y, z] => Ok(Vector3::new(*x, *y, *z)),
        _ => Err(PyValueError::new_err(format!(
            "{what} has {} numbers; give three, [x, y, z]",
            v.len()
        ))),
    }
}

/// Compiles `model` with `options` (gravity replaced by `gravity` when given) into the Python
/// class of its system: the one path of `from_urdf` and `Model.compile`.
fn compile_model(
    py: Python<'_>,
    mut model: dirac_multibody::Model,
    torques: bool,
    gravity: Option<Vec<f64>>,
    name: &str,
) -> PyResult<PyObject> {
    if let Some(g) = gravity {
        model = model
            .with_gravity(vector("gravity", &g)?)
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
    }
    let options = dirac_multibody::TextOptions {
        name: name.to_owned(),
        torques,
    };
    let code = py.allow_threads(|| dirac_jit::compile_model(&model, &options));
    let code = code.map_err(|e| match e {
        dirac_jit::Error::Model(e) => PyValueError::new_err(e.to_string()),
        other => compile_error(py, other),
    })?;
    system_object(py, code.compiled)
}

/// Compiles the articulated rigid bodies of a URDF file (links, joints, inertias, gravity) into
/// a system: on vector spaces (a `System`, one coordinate per joint, the midpoint rule) for a
/// fixed base, on rotation groups (a `LieSystem`, the base's pose on SE(3) beside the joints,
/// the trapezoid rule) for a floating one. With `torques`, each joint `j` gets a control
/// `tau_j` (a torque about a revolute joint's axis, a force along a prismatic one's).
/// `gravity` (three numbers) replaces the standard gravity along `−z`; `[0, 0, 0]` puts a
/// floating base in space, where its system declares the rigid motions of the whole as its
/// symmetry (`symmetry` reads `("rigid motions", [base])`) and `method="reduced"` carries the
/// total momentum as the run's parameter. Raises `OSError` when the file cannot be read and
/// `ValueError` naming the element for a model the reader or the system text refuses (a missing
/// inertia, a negative mass, a cycle, an unknown joint type, ...) or for a gravity that is not
/// three finite numbers.
#[pyfunction]
#[pyo3(signature = (path, *, torques = false, gravity = None, name = "multibody"))]
pub(crate) fn from_urdf(
    py: Python<'_>,
    path: &str,
    torques: bool,
    gravity: Option<Vec<f64>>,
    name: &str,
) -> PyResult<PyObject> {
    let model = dirac_multibody::Model::from_urdf_file(path).map_err(|e| match e {
        ModelError::Io { .. } => PyOSError::new_err(e.to_string()),
        other => PyValueError::new_err(other.to_string()),
    })?;
    compile_model(py, model, torques, gravity, name)
}

/// A tree of rigid bodies built link by link, as a URDF file describes one: `Model(root)`
/// names the root link (fixed in the world), `body(..)` adds a link with its mass properties,
/// `frame(..)` a massless link, `joint(..)` a joint between two links, and `compile(..)` builds
/// and compiles it as `from_urdf` does. The description is checked when it is compiled, by the
/// URDF reader's rules: a `ValueError` names the link or joint (a negative mass, an inertia that
/// is not a body's, a cycle, a link without a parent, an unknown joint kind).
///
/// ```python
/// arm = dirac.Model("world")
/// arm.body("rod1", mass=1.3, com=[0, 0, -0.45], inertia=[[0.11, 0, 0], [0, 0.11, 0], [0, 0, 0.002]])
/// arm.joint("shoulder", "continuous", parent="world", child="rod1", axis=[0, 1, 0])
/// pendulum = arm.compile()
/// ```
#[pyclass(module = "dirac")]
pub(crate) struct Model {
    builder: ModelBuilder,
}

#[pymethods]
impl Model {
    #[new]
    fn new(root: &str) -> Self {
        Self {
            builder: ModelBuilder::default().frame(root),
        }
    }

    /// Adds the link `name` with its `mass` (kg), its centre of mass `com` in the link's frame
    /// (m) and its rotational inertia about the centre of mass in the link frame's axes
    /// (`inertia`, a 3 × 3 matrix, kg m²).
    #[pyo3(signature = (name, *, mass, com = vec![0.0, 0.0, 0.0], inertia))]
    fn body(
        &mut self,
        name: &str,
        mass: f64,
        com: Vec<f64>,
        inertia: Vec<Vec<f64>>,
    ) -> PyResult<()> {
        let com = vector("com", &com)?;
        let rows: Vec<Vector3<f64>> = inertia
            .iter()
            .map(|row| vector("a row of the inertia", row))
            .collect::<PyResult<_>>()?;
        let [a, b, c] = rows[..] else {
            return Err(PyValueError::new_err(format!(
                "the inertia has {} rows; give three",
                rows.len()
            )));
        };
        let inertia = Matrix3::from_rows(&[a.transpose(), b.transpose(), c.transpose()]);
        self.builder =
            std::mem::take(&mut self.builder).body(name, Inertial::new(mass, com, inertia));
        Ok(())
    }

    /// Adds the massless link `name` (a frame: a sensor's, a tool's).
    fn frame(&mut self, name: &str) {
        self.builder = std::mem::take(&mut self.builder).frame(name);
    }

    /// Adds the joint `name` of `kind` ("revolute", "continuous", "prismatic", "spherical",
    /// "fixed" or "free") moving the link `child` relative to `parent`: its frame at `xyz`,
    /// turned by the roll, pitch and yaw `rpy`, in the parent's frame (a URDF joint's
    /// `<origin>`), about or along the unit `axis` in the joint frame (revolute, continuous,
    /// prismatic).
    #[pyo3(signature = (name, kind, *, parent, child, axis = vec![0.0, 0.0, 1.0], xyz = vec![0.0, 0.0, 0.0], rpy = vec![0.0, 0.0, 0.0]))]
    #[allow(clippy::too_many_arguments)]
    fn joint(
        &mut self,
        name: &str,
        kind: &str,
        parent: &str,
        child: &str,
        axis: Vec<f64>,
        xyz: Vec<f64>,
        rpy: Vec<f64>,
    ) -> PyResult<()> {
        let axis = vector("axis", &axis)?;
        let kind = match kind {
            "revolute" => JointKind::Revolute { axis },
            "continuous" => JointKind::Continuous { axis },
            "prismatic" => JointKind::Prismatic { axis },
            "spherical" => JointKind::Spherical,
            "fixed" => JointKind::Fixed,
            "free" => JointKind::Free,
            other => {
                return Err(PyValueError::new_err(format!(
                    "joint `{name}`: unknown kind {other:?}; give \"revolute\", \"continuous\", \
                     \"prismatic\", \"spherical\", \"fixed\" or \"free\""
                )))
            }
        };
        let (xyz, rpy) = (vector("xyz", &xyz)?, vector("rpy", &rpy)?);
        let at = Pose::from_xyz_rpy(xyz.into(), rpy.into());
        let spec = JointSpec::new(name, parent, child, kind).at(at);
        self.builder = std::mem::take(&mut self.builder).joint(spec);
        Ok(())
    }

    /// Builds the model and compiles it into a system, as `from_urdf` does a file's (the same
    /// keywords, the same classes and errors).
    #[pyo3(signature = (*, torques = false, gravity = None, name = "multibody"))]
    fn compile(
        &self,
        py: Python<'_>,
        torques: bool,
        gravity: Option<Vec<f64>>,
        name: &str,
    ) -> PyResult<PyObject> {
        let model = self
            .builder
            .clone()
            .build()
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        compile_model(py, model, torques, gravity, name)
    }
}
