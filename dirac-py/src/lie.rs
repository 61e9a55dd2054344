//! Systems on rotation groups from Python (`dirac.LieSystem`): a start given coordinate by
//! coordinate (rotation matrices, unit vectors, scalars, and their momenta), runs of the Lie
//! group variational integrator (both sides, its compositions) and of the reduced integrator
//! of the declared symmetry, trajectories as NumPy arrays per coordinate, Parquet output.
//!
//! Any number of rotations, directions, poses and scalars: the integrators are generic over the
//! sizes `P` (a stored point) and `N` (the chart), fixed or chosen at run time. A small system
//! (at most two rotation or direction coordinates, at most 8 chart coordinates) runs at fixed
//! sizes, on stack vectors and the dense LU (`dirac_jit::with_lie_dimensions`, its fixed-size
//! instances); any other at the sizes its text declares (`dirac_jit::DynJitLie`, vectors a run
//! allocates once), so no size is refused. Which integrator runs is decided by `dirac_jit::run`
//! (`run_lie!`); this module reads the start and flattens the trajectories.

use std::sync::Arc;

use dirac_compiler::text::LieSymmetryKind;
use dirac_jit::run::LieStart;
use dirac_jit::{Compiled, DynJitLie, JitLie, LieCode};
use dirac_runtime::lie::{
    Group, LieIntegratorOf, LieModel, LieStateOf, LieTrajectoryOf, ReducedLieIntegratorOf,
    ReducedLieStateOf, ReducedLieTrajectoryOf, SpatialMomentum, SymmetricLieModel,
};
use dirac_runtime::nalgebra::allocator::Allocator;
use dirac_runtime::nalgebra::{DefaultAllocator, Dim, OVector};
use dirac_runtime::{Drive, StepStats};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::calls;
use crate::ensemble;
use crate::keywords::{self, Keywords};
use crate::parquet::{written, ToParquet};
use crate::runs::{collected, Collect, Ensemble, Flatten};

/// A run's trajectory flattened for NumPy: the times, per coordinate its configurations and
/// momenta (each with the shape of one row), and the spatial angular and linear momenta (and the
/// symmetry's momentum of a reduced run) per state.
pub(crate) struct Flat {
    t: Vec<f64>,
    q: Vec<Vec<f64>>,
    p: Vec<Vec<f64>>,
    spatial: Vec<f64>,
    linear: Vec<f64>,
    mu: Option<Vec<f64>>,
    iterations: Vec<usize>,
    residuals: Vec<f64>,
}

/// A system on rotation groups at any sizes, unreduced or reduced: the code it runs, which
/// shows its states coordinate by coordinate.
trait Coded {
    fn lie_code(&self) -> &Arc<LieCode>;
}

impl<const P: usize, const N: usize, B, R> Coded for JitLie<P, N, B, R> {
    fn lie_code(&self) -> &Arc<LieCode> {
        self.code()
    }
}

impl<R> Coded for DynJitLie<R> {
    fn lie_code(&self) -> &Arc<LieCode> {
        self.code()
    }
}

/// The states of a run flattened: each coordinate's configuration and momentum, the spatial
/// angular and linear momenta (`rigid`), a reduced run's `μ`.
fn flat<P: Dim, N: Dim>(
    code: &LieCode,
    rigid: impl Fn(&LieStateOf<P, N>) -> SpatialMomentum,
    states: impl Iterator<Item = (LieStateOf<P, N>, Option<[f64; 3]>)>,
    times: &[f64],
    stats: &[StepStats],
) -> Flat
where
    DefaultAllocator: Allocator<P> + Allocator<N>,
{
    let coordinates = code.system().coordinates.len();
    let mut out = Flat {
        t: times.to_vec(),
        q: vec![Vec::new(); coordinates],
        p: vec![Vec::new(); coordinates],
        spatial: Vec::with_capacity(3 * times.len()),
        linear: Vec::with_capacity(3 * times.len()),
        mu: None,
        iterations: stats.iter().map(|s| s.iterations).collect(),
        residuals: stats.iter().map(|s| s.residual).collect(),
    };
    for (state, mu) in states {
        let (q, p) = code.state_values(state.q.as_slice(), state.p.as_slice());
        for (all, one) in out.q.iter_mut().zip(q) {
            all.extend(one);
        }
        for (all, one) in out.p.iter_mut().zip(p) {
            all.extend(one);
        }
        let momentum = rigid(&state);
        out.spatial.extend(momentum.angular.iter().copied());
        out.linear.extend(momentum.linear.iter().copied());
        if let Some(mu) = mu {
            out.mu.get_or_insert_with(Vec::new).extend(mu);
        }
    }
    out
}

impl<L, P: Dim, N: Dim> Flatten for LieIntegratorOf<L, P, N>
where
    L: LieModel<P, N> + Coded,
    DefaultAllocator: Allocator<P> + Allocator<N>,
    OVector<f64, P>: Send + Sync,
    OVector<f64, N>: Send + Sync,
    Self: Drive<State = LieStateOf<P, N>, Trajectory = LieTrajectoryOf<P, N>> + Sync,
{
    type Flat = Flat;

    fn flat_states(&self, states: &[LieStateOf<P, N>], times: &[f64], stats: &[StepStats]) -> Flat {
        let states = states.iter().map(|s| (s.clone(), None));
        flat(
            self.system().lie_code(),
            |s| self.rigid_momentum(s),
            states,
            times,
            stats,
        )
    }

    fn flat(&self, t: &LieTrajectoryOf<P, N>) -> Flat {
        self.flat_states(&t.states, &t.times, &t.stats)
    }
}

impl<L, P: Dim, N: Dim> Flatten for ReducedLieIntegratorOf<L, P, N>
where
    L: SymmetricLieModel<P, N> + Coded,
    DefaultAllocator: Allocator<P> + Allocator<N>,
    OVector<f64, P>: Send + Sync,
    OVector<f64, N>: Send + Sync,
    Self: Drive<State = ReducedLieStateOf<P, N>, Trajectory = ReducedLieTrajectoryOf<P, N>> + Sync,
{
    type Flat = Flat;

    /// The reduced states as their unreduced states, with `μ`.
    fn flat_states(
        &self,
        states: &[ReducedLieStateOf<P, N>],
        times: &[f64],
        stats: &[StepStats],
    ) -> Flat {
        let states = states.iter().map(|s| (s.unreduced(), Some(s.mu.into())));
        let rigid = |s: &LieStateOf<P, N>| self.unreduced().rigid_momentum(s);
        flat(self.system().lie_code(), rigid, states, times, stats)
    }

    fn flat(&self, t: &ReducedLieTrajectoryOf<P, N>) -> Flat {
        self.flat_states(&t.states, &t.times, &t.stats)
    }
}

/// A system on rotation groups given as text, compiled to machine code.
#[pyclass(frozen, module = "dirac._dirac")]
pub(crate) struct LieSystem {
    code: Arc<LieCode>,
}

impl LieSystem {
    pub(crate) fn new(code: Arc<LieCode>) -> PyResult<LieSystem> {
        Ok(LieSystem { code })
    }

    fn dims(&self) -> (usize, usize) {
        let s = self.code.system();
        (s.point_len(), s.chart_len())
    }

    /// The system as the run request checks it.
    fn compiled(&self) -> Compiled {
        Compiled::Lie(Arc::clone(&self.code))
    }

    /// Reads the start: `q` and `p` (or `v`) mappings by coordinate name.
    fn start(
        &self,
        q: &Bound<'_, PyDict>,
        p: Option<&Bound<'_, PyDict>>,
        v: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<LieStart> {
        let coords = &self.code.system().coordinates;
        let kinds = self.code.kinds();
        let read = |d: &Bound<'_, PyDict>, what: &str, len: &dyn Fn(&dyn Group) -> usize| {
            for key in d.keys() {
                let key: String = key.extract()?;
                if !coords.iter().any(|c| c.name == key) {
                    return Err(PyValueError::new_err(format!(
                        "`{what}` names `{key}`, not a coordinate; the coordinates: {}",
                        names(coords)
                    )));
                }
            }
            coords
                .iter()
                .zip(kinds)
                .map(|(c, kind)| {
                    let value = d.get_item(&c.name)?.ok_or_else(|| {
                        PyValueError::new_err(format!("`{what}` needs `{}`", c.name))
                    })?;
                    let flat: Vec<f64> = if let Ok(x) = value.extract::<f64>() {
                        vec![x]
                    } else {
                        let np = value.py().import("numpy")?;
                        np.call_method1(
                            "ravel",
                            (np.call_method1("asarray", (value, "float64"))?,),
                        )?
                        .extract()?
                    };
                    let want = len(kind.group());
                    if flat.len() != want {
                        return Err(PyValueError::new_err(format!(
                            "`{what}[\"{}\"]` has {} values; a {} takes {want}",
                            c.name,
                            flat.len(),
                            kind.name()
                        )));
                    }
                    Ok(flat)
                })
                .collect::<PyResult<Vec<Vec<f64>>>>()
        };
        let q = read(q, "q", &|g| g.value_len())?;
        match (p, v) {
            (Some(_), Some(_)) => Err(PyValueError::new_err(
                "give the momenta `p` or the velocities `v`, not both",
            )),
            (Some(p), None) => Ok(LieStart {
                q,
                p: Some(read(p, "p", &|g| g.momentum_value_len())?),
                v: None,
            }),
            (None, Some(v)) => {
                if self.code.system().adaptive.is_none() {
                    return Err(PyValueError::new_err(
                        "velocities `v` start a system with adaptive steps; give the momenta `p`",
                    ));
                }
                // A velocity has a momentum's components.
                let v = read(v, "v", &|g| g.momentum_value_len())?;
                Ok(LieStart {
                    q,
                    p: None,
                    v: Some(v.concat()),
                })
            }
            (None, None) => Err(PyValueError::new_err(
                "the start needs the momenta `p` (or, with adaptive steps, the velocities `v`)",
            )),
        }
    }

    fn to_dict<'py>(&self, py: Python<'py>, flat: Flat) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        let rows = flat.t.len();
        d.set_item("t", PyArray1::from_vec(py, flat.t))?;
        for (key, data, momentum) in [("q", flat.q, false), ("p", flat.p, true)] {
            let by_name = PyDict::new(py);
            let coordinates = self.code.system().coordinates.iter();
            for ((c, kind), values) in coordinates.zip(self.code.kinds()).zip(data) {
                let shape = match momentum {
                    false => kind.group().value_shape(),
                    true => kind.group().momentum_shape(),
                };
                let mut full = vec![rows];
                full.extend(shape);
                let shaped = PyArray1::from_vec(py, values).reshape(full)?;
                by_name.set_item(&c.name, shaped)?;
            }
            d.set_item(key, by_name)?;
        }
        d.set_item(
            "spatial_momentum",
            PyArray1::from_vec(py, flat.spatial).reshape([rows, 3])?,
        )?;
        d.set_item(
            "linear_momentum",
            PyArray1::from_vec(py, flat.linear).reshape([rows, 3])?,
        )?;
        if let Some(mu) = flat.mu {
            d.set_item("mu", PyArray1::from_vec(py, mu).reshape([rows, 3])?)?;
        }
        d.set_item("iterations", PyArray1::from_vec(py, flat.iterations))?;
        d.set_item("residuals", PyArray1::from_vec(py, flat.residuals))?;
        Ok(d)
    }
}

// `LieSystem.run`, `write` and `ensemble`: their arguments and options.
keywords::methods!("LieSystem", ["q", "p", "v"], run = keywords::RUN);

impl LieSystem {
    /// The bytes one state of a collected run costs until its arrays are returned: the state
    /// the integrator keeps (the stored point, the chart momentum, a reduced run's `μ`), its
    /// time and statistics, and its flattened copy (each coordinate's configuration and
    /// momentum, the spatial angular and linear momenta and `μ`, the time, the iterations and
    /// residual).
    fn row_bytes(&self) -> u128 {
        let (point, chart) = self.dims();
        let kept = 8 * (point + chart + 3 + 1) + std::mem::size_of::<StepStats>();
        let coordinates: usize = self
            .code
            .kinds()
            .iter()
            .map(|k| k.group().value_len() + k.group().momentum_value_len())
            .sum();
        (kept + 8 * (coordinates + 9 + 1) + 16) as u128
    }
}

fn names(coords: &[dirac_compiler::text::LieCoordinate]) -> String {
    coords
        .iter()
        .map(|c| c.name.as_str())
        .collect::<Vec<_>>()
        .join(", ")
}

#[pymethods]
impl LieSystem {
    /// The type name the attribute would emit.
    #[getter]
    fn name(&self) -> String {
        self.code.system().name.clone()
    }

    /// The coordinates as `(name, kind)`, kind the keyword that declares it: one of "shape",
    /// "group", "rotation", "direction", "pose".
    #[getter]
    fn coordinates(&self) -> Vec<(String, &'static str)> {
        let coordinates = self.code.system().coordinates.iter();
        coordinates
            .zip(self.code.kinds())
            .map(|(c, k)| (c.name.clone(), k.name()))
            .collect()
    }

    /// The parameters, in declaration order.
    #[getter]
    fn parameters(&self) -> Vec<String> {
        self.code.system().parameters.clone()
    }

    /// The controls' names.
    #[getter]
    fn controls(&self) -> Vec<String> {
        let s = self.code.system();
        crate::inputs::control_names(&s.parameters, &s.controls)
    }

    /// The declared symmetry: `None`, `("rotations", [R])` for every rotation of `R`,
    /// `("rigid motions", [X])` for every rigid motion of the pose `X`, or `("axis x|y|z",
    /// [names])` for the rotations about a coordinate axis.
    #[getter]
    fn symmetry(&self) -> Option<(String, Vec<String>)> {
        let s = self.code.system();
        let name = |i: usize| s.coordinates[i].name.clone();
        s.symmetry.as_ref().map(|sym| match &sym.kind {
            LieSymmetryKind::Rotations { coordinate } => {
                ("rotations".to_owned(), vec![name(*coordinate)])
            }
            LieSymmetryKind::RigidMotions { coordinate } => {
                ("rigid motions".to_owned(), vec![name(*coordinate)])
            }
            LieSymmetryKind::Axis { axis, coordinates } => (
                format!("axis {}", ["x", "y", "z"][*axis]),
                coordinates.iter().map(|&i| name(i)).collect(),
            ),
        })
    }

    /// Seconds from text to machine code.
    #[getter]
    fn compile_time(&self) -> f64 {
        self.code.compile_time().as_secs_f64()
    }

    /// Integrates `steps` steps (with `end_time`, up to that time, reached exactly, and at most
    /// `steps`; with `schedule`, a list of at least `steps` sizes, step `k` of size `schedule[k]`)
    /// from the start `q` (a dict by coordinate: a rotation's 3×3
    /// matrix, a direction's unit vector, a pose's 12 numbers — its rotation row by row, then
    /// its position —, a scalar) with the momenta `p` (a rotation's body momentum, a
    /// direction's momentum as a vector in space, a pose's 6 — its body angular momentum, then
    /// its linear momentum in space —, a scalar's), or with adaptive steps the velocities `v` (a
    /// rotation's body angular velocity). `method` is "plus" (or "unreduced"), "minus" or
    /// "reduced" (by the declared symmetry); `order` 2, 4 or 6. Returns a dict of NumPy arrays: `t`, `q` and `p`
    /// (dicts by coordinate, one row per state, each row shaped as the start gives it: a pose's
    /// `(12,)`, its momentum's `(6,)`), the spatial angular momentum `spatial_momentum`
    /// (steps+1, 3) and the poses' linear momentum `linear_momentum` (steps+1, 3; zero without
    /// poses), `mu` for a reduced run, and per step
    /// `iterations` and `residuals`. Raises `StepError` with the trajectory so far,
    /// `KeyboardInterrupt` with the trajectory so far at Ctrl-C, `OutOfMemoryError` (before
    /// running) when the trajectory cannot be allocated, and `TypeError` for a keyword it does
    /// not take.
    #[pyo3(signature = (parameters, steps, q, p = None, v = None, **keywords))]
    #[allow(clippy::too_many_arguments, reason = "the Python arguments, one each")]
    fn run<'py>(
        &self,
        py: Python<'py>,
        parameters: &Bound<'py, PyAny>,
        steps: usize,
        q: &Bound<'py, PyDict>,
        p: Option<&Bound<'py, PyDict>>,
        v: Option<&Bound<'py, PyDict>>,
        keywords: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let r = Keywords::read(py, &RUN, keywords, Some(&[]))?.request(&self.compiled(), steps)?;
        let params = crate::inputs::values_of(&self.code.system().parameters, parameters)?;
        let start = self.start(q, p, v)?;
        calls::check_memory(
            || format!("a run of {steps} steps (every state kept)"),
            steps as u128 + 1,
            self.row_bytes(),
        )?;
        let code = Arc::clone(&self.code);
        let (result, interrupt) = calls::interruptible(py, |cancel| {
            let starts = std::slice::from_ref(&start);
            let job = Collect::new(cancel, false);
            collected(dirac_jit::run_lie!(&code, &params, starts, &r, job))
        })?;
        crate::results::finish_run(py, result, interrupt, |flat| self.to_dict(py, flat))
    }

    /// Integrates `steps` steps (order 2) from the start of `run` and writes every state to
    /// Apache Parquet at `path` (a directory of parts: the stored point and the chart momentum,
    /// columns named after the coordinates, the description in the metadata). Returns a dict
    /// with `steps`, `t` and `path`; a failed step raises `StepError` with `step`, `residual`
    /// and `path`, the states before it written; Ctrl-C raises `KeyboardInterrupt` with
    /// `steps`, `t` and `path`, the states so far written.
    #[pyo3(signature = (parameters, steps, path, q, p = None, v = None, **keywords))]
    #[allow(clippy::too_many_arguments, reason = "the Python arguments, one each")]
    fn write<'py>(
        &self,
        py: Python<'py>,
        parameters: &Bound<'py, PyAny>,
        steps: usize,
        path: std::path::PathBuf,
        q: &Bound<'py, PyDict>,
        p: Option<&Bound<'py, PyDict>>,
        v: Option<&Bound<'py, PyDict>>,
        keywords: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let r =
            Keywords::read(py, &WRITE, keywords, Some(&[]))?.request(&self.compiled(), steps)?;
        let params = crate::inputs::values_of(&self.code.system().parameters, parameters)?;
        let start = self.start(q, p, v)?;
        let (written, interrupt) = calls::interruptible(py, |cancel| {
            let out = ToParquet {
                path: &path,
                cancel,
            };
            written(dirac_jit::run_lie!(
                &self.code,
                &params,
                std::slice::from_ref(&start),
                &r,
                out
            ))
        })?;
        crate::parquet::written_dict(py, written, interrupt)
    }

    /// An ensemble: one run (order 2) per member, in parallel on all cores, from the starts of
    /// `run` with a leading member axis (`q={"R": array (members, 3, 3)}`, `p=..` or `v=..`
    /// likewise). Returns the dict of `run` with one more leading axis and `failed`, the list of
    /// `(member, step, message)`; the first failed member raises `StepError` (with `member` and
    /// `ensemble`) after all have run; Ctrl-C raises `KeyboardInterrupt` with `ensemble`, the
    /// states so far (NaN after each member's last).
    #[pyo3(signature = (parameters, steps, q, p = None, v = None, **keywords))]
    #[allow(clippy::too_many_arguments, reason = "the Python arguments, one each")]
    fn ensemble<'py>(
        &self,
        py: Python<'py>,
        parameters: &Bound<'py, PyAny>,
        steps: usize,
        q: &Bound<'py, PyDict>,
        p: Option<&Bound<'py, PyDict>>,
        v: Option<&Bound<'py, PyDict>>,
        keywords: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let kw = Keywords::read(py, &ENSEMBLE, keywords, Some(&[]))?;
        let r = kw.ensemble_request(&self.compiled(), steps)?;
        let params = crate::inputs::values_of(&self.code.system().parameters, parameters)?;
        let given = PyDict::new(py);
        given.set_item("q", q)?;
        if let Some(p) = p {
            given.set_item("p", p)?;
        }
        if let Some(v) = v {
            given.set_item("v", v)?;
        }
        let starts = ensemble::member_starts(py, &given)?
            .iter()
            .enumerate()
            .map(|(i, start)| {
                let part = |key: &str| -> PyResult<Option<Bound<'py, PyDict>>> {
                    Ok(match start.get_item(key)? {
                        Some(d) => Some(d.downcast_into::<PyDict>()?),
                        None => None,
                    })
                };
                let q = part("q")?.expect("q is given");
                self.start(&q, part("p")?.as_ref(), part("v")?.as_ref())
                    .map_err(ensemble::of_member(i))
            })
            .collect::<PyResult<Vec<LieStart>>>()?;
        let m = starts.len();
        calls::check_memory(
            || format!("an ensemble of {m} members of {steps} steps (every state kept)"),
            (m as u128).saturating_mul(steps as u128 + 1),
            2 * self.row_bytes(),
        )?;
        let code = Arc::clone(&self.code);
        let rows = r.end_time.is_none().then_some(steps + 1);
        let (results, interrupt) = calls::interruptible(py, |cancel| {
            let job = Ensemble::new(cancel);
            collected(dirac_jit::run_lie!(&code, &params, &starts, &r, job))
        })?;
        ensemble::ensemble_dict(py, results, interrupt, rows, |flat| self.to_dict(py, flat))
    }

    fn __repr__(&self) -> String {
        let s = self.code.system();
        let coords: Vec<String> = s
            .coordinates
            .iter()
            .zip(self.code.kinds())
            .map(|(c, k)| format!("{} ({})", c.name, k.name()))
            .collect();
        format!(
            "<dirac.LieSystem {}: {}; parameters ({})>",
            s.name,
            coords.join(", "),
            s.parameters.join(", ")
        )
    }
}
