//! The Python module `dirac._dirac`, re-exported by the package `dirac`: a system given as text
//! (`compile`), its names, and runs of the reduced (+)/(−) and unreduced integrators (order 2, or
//! the compositions of order 4 and 6; with constraints, the constrained integrators) with NumPy
//! arrays in and out; ensembles on all cores; the runtime's typed errors as Python exceptions
//! carrying the step and the trajectory so far. Systems on rotation groups (`lie`) and
//! element-wise systems (`element`) are classes of their own, with the same surface: `run`,
//! `write` and `ensemble`, the same keywords, and results of one shape (`t`, `q` and `p` by
//! coordinate name, the step statistics, what the kind adds). Every run method refuses a
//! keyword it does not take, a trajectory that cannot be allocated, and ends at Ctrl-C with
//! what it computed (`calls`). A run's inputs are read and checked in `inputs`, its trajectory
//! or error made Python's in `results`, an ensemble's starts read and its members' results
//! stacked in `ensemble` (for every class), and runs streamed to Parquet in `parquet`.
//!
//! Systems on vector spaces run at any size, on one of two paths chosen by their dimensions
//! (`dirac_jit::Code::fixed_size`). The fixed-size integrators take the dimensions as type
//! parameters; the module dispatches a system's `(S, K)` at run time to one instance per pair
//! with `S + K ≤ 8` (`dirac_jit::with_dimensions`), with constraints per `(S, K, M)` with
//! `S + K ≤ 6`, `K ≤ 1`, `M ≤ 3` (`dirac_jit::with_constrained_dimensions`): those sizes step
//! bit for bit as the system compiled in, with the fixed-size stack-only steps. Every other
//! size runs on the system's element view (`sizes`: the element integrators, sized at run time,
//! the same trajectory to round-off by the paper's Lemma: the reduced (+)/(−) equations (4.6),
//! (4.8) are the element (+)/(−) sides in another basis). Results have the same shape on both.

use std::sync::Arc;

mod calls;
mod element;
mod ensemble;
mod inputs;
mod keywords;
mod lie;
mod multibody;
mod parquet;
mod results;
mod runs;
mod sizes;

use inputs::{control_names, parameter_values, Inputs};
use keywords::{Keywords, Method, OPTIONS};
use parquet::{written_dict, ToParquet};
use results::{finish_run, to_dict};
use runs::{collected, Collect, Ensemble, Timed};

use dirac_jit::run::{constrained, flat, gauss};
use dirac_jit::Code;
use dirac_runtime::{Equations, Form, StepStats};
use numpy::PyArray1;
use pyo3::exceptions::{PyException, PyMemoryError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

pyo3::create_exception!(
    _dirac,
    CompileError,
    PyException,
    "The text of a system has mistakes: `diagnostics` lists (message, line, column)."
);
pyo3::create_exception!(
    _dirac,
    StepError,
    PyException,
    "A step failed: `step` is its index, `residual` the residual norm, `trajectory` the states computed before it."
);
pyo3::create_exception!(
    _dirac,
    OutOfMemoryError,
    PyMemoryError,
    "A run needs more memory than can be allocated, refused before it is allocated: `what` needs `bytes` bytes."
);

/// The error of a size the fixed-size instances do not have, which a system of that size never
/// asks of them (`Code::fixed_size`: it runs on its element view).
fn off_the_tables() -> dirac_jit::Error {
    dirac_jit::Error::Request {
        reason: "no fixed-size instance at these sizes (other sizes run on the element view)"
            .to_owned(),
    }
}

// `System.run`, `ensemble`, `write` and the benchmark's run: their arguments and options.
keywords::methods!("System", [], run = &OPTIONS);
const CORE: Method = Method {
    name: "System._core_seconds",
    positional: &["parameters", "steps"],
    options: &[],
};

/// A system given as text, compiled to machine code.
#[pyclass(frozen, module = "dirac._dirac")]
struct System {
    code: Arc<Code>,
}

impl System {
    /// The number of constraints (0 without).
    fn constraint_count(&self) -> usize {
        self.code.system().constrained.as_ref().map_or(0, |c| c.m)
    }

    /// One of the maps of the adapted coordinates on a vector of the system's length.
    fn adapted_map<'py>(
        &self,
        py: Python<'py>,
        v: Vec<f64>,
        map: fn(&Code, &[f64], &mut [f64]),
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let (s, k) = self.dims();
        if v.len() != s + k {
            return Err(PyValueError::new_err(format!(
                "a vector of {} values; the system has {}",
                v.len(),
                s + k
            )));
        }
        let mut out = vec![0.0; s + k];
        map(&self.code, &v, &mut out);
        Ok(PyArray1::from_vec(py, out))
    }

    fn dims(&self) -> (usize, usize) {
        let s = self.code.system();
        (s.shape.len(), s.group.len())
    }

    /// The names and lengths of a start's vectors for `method`.
    fn start_parts(&self, method: Equations) -> Vec<(&'static str, usize)> {
        let (s, k) = self.dims();
        match method.form {
            Form::Unreduced => vec![("q", s + k), ("p", s + k)],
            Form::Reduced => vec![("x", s), ("w", s), ("mu", k), ("g", k)],
        }
    }

    /// The bytes one state of a collected run costs until its arrays are returned: the
    /// trajectory the integrator keeps (the state, its time, the step's statistics) and its
    /// flattened copy (the state, its time, the iterations and residual); with `energies` the
    /// unreduced state and two energies; with constraints each step's multipliers and residual,
    /// twice.
    fn row_bytes(&self, energies: bool) -> u128 {
        let (s, k) = self.dims();
        // `x, w, μ, g` or `q, p`: 2 (S + K) numbers either way.
        let words = 2 * (s + k) as u128;
        let mut bytes = 2 * (8 * words + 8) + std::mem::size_of::<StepStats>() as u128 + 16;
        if energies {
            bytes += 16 * (s + k) as u128 + 16;
        }
        bytes + 2 * 8 * (self.constraint_count() as u128 + 1)
    }
}

#[pymethods]
impl System {
    /// The type name the attribute would emit.
    #[getter]
    fn name(&self) -> String {
        self.code.system().name.clone()
    }

    /// The shape coordinates, in the order of `x`.
    #[getter]
    fn shape(&self) -> Vec<String> {
        self.code.system().shape.clone()
    }

    /// The group coordinates, in the order of `g`.
    #[getter]
    fn group(&self) -> Vec<String> {
        self.code.system().group.clone()
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
        control_names(&s.parameters, &s.controls)
    }

    /// The number of constraints (`constraints = ..` or `nonholonomic = ..`), 0 without.
    #[getter]
    fn constraints(&self) -> usize {
        self.constraint_count()
    }

    /// Whether the constraints are holonomic (`None` without constraints).
    #[getter]
    fn holonomic(&self) -> Option<bool> {
        self.code.system().constrained.as_ref().map(|c| c.holonomic)
    }

    /// Whether the symmetry is declared on the user's coordinates (`coordinates(..),
    /// translate(..)`): then the system's vectors (`x`, `g` of `run`) are adapted coordinates,
    /// which `to_adapted` and `from_adapted` convert from and to the user's.
    #[getter]
    fn adapted(&self) -> bool {
        self.code.system().adapted.is_some()
    }

    /// `q = T⁻¹ q_user`: a configuration in the user's coordinates (the function's, in the
    /// order of its `coordinates(..)`) in the system's adapted ones, the `q` of
    /// `run(method="unreduced")` (shape first, then group).
    fn to_adapted<'py>(
        &self,
        py: Python<'py>,
        q_user: Vec<f64>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.adapted_map(py, q_user, Code::to_adapted)
    }

    /// `q_user = T q`, the inverse of `to_adapted`.
    #[allow(
        clippy::wrong_self_convention,
        reason = "the Python name of AdaptedCoordinates::from_adapted, answered by the system"
    )]
    fn from_adapted<'py>(
        &self,
        py: Python<'py>,
        q: Vec<f64>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.adapted_map(py, q, Code::from_adapted)
    }

    /// `p = Tᵀ p_user`: momenta (and forces) transform as covectors; a group coordinate's is the
    /// total momentum of the components its translation moves.
    fn momentum_to_adapted<'py>(
        &self,
        py: Python<'py>,
        p_user: Vec<f64>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.adapted_map(py, p_user, Code::momentum_to_adapted)
    }

    /// `p_user = T⁻ᵀ p`, the inverse of `momentum_to_adapted`.
    fn momentum_from_adapted<'py>(
        &self,
        py: Python<'py>,
        p: Vec<f64>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.adapted_map(py, p, Code::momentum_from_adapted)
    }

    /// Whether forces are declared.
    #[getter]
    fn forced(&self) -> bool {
        self.code.system().forced
    }

    /// Seconds from text to machine code.
    #[getter]
    fn compile_time(&self) -> f64 {
        self.code.compile_time().as_secs_f64()
    }

    /// Integrates `steps` steps (with `end_time`, up to that time, reached exactly, and at most
    /// `steps`; with `schedule`, a list of at least `steps` sizes, step `k` of size `schedule[k]`)
    /// from one start (`x, w, mu, g` for "plus", "minus" and "reduced",
    /// `q, p` for "unreduced": each an array in coordinate order or a dict by coordinate) and
    /// returns a dict of NumPy arrays: `t` (steps+1); `q` and `p`, dicts by coordinate of
    /// (steps+1,) arrays (a reduced run's `q` is `x` then `g`, its `p` `(w − Bᵀ μ, μ)` by eq.
    /// (3.7)); a reduced run's `x, w, mu, g`, each (steps+1, length); per step `iterations` and
    /// `residuals`; with `energies=True` (a continuous Lagrangian) `energy` at each state and
    /// `energy_midpoints`. The keywords besides the start: `method="plus"`, `order=2`,
    /// `tol=None`, `end_time=None`, `schedule=None`, `energies=False`, `scheme="composition"`
    /// (orders 2, 4, 6: the integrator and its compositions) or `scheme="gauss"` (the
    /// Gauss–Legendre variational integrator of any even order from 2 to 32, for a continuous
    /// Lagrangian without constraints on at most 8 coordinates; the momenta `mu` kept bit for
    /// bit). Raises `StepError`
    /// with the trajectory so far when a step fails, `KeyboardInterrupt` with the trajectory
    /// so far at Ctrl-C, `OutOfMemoryError` (before running) when the trajectory cannot be
    /// allocated, and `TypeError` for a keyword it does not take.
    #[pyo3(signature = (parameters, steps, **keywords))]
    fn run<'py>(
        &self,
        py: Python<'py>,
        parameters: &Bound<'py, PyAny>,
        steps: usize,
        keywords: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let kw = Keywords::read(py, &RUN, keywords, None)?;
        let energies = kw.energies;
        let Inputs {
            params,
            request: r,
            start,
        } = self.inputs(&RUN, parameters, &kw, steps)?;
        if energies && self.code.system().continuous.is_none() {
            return Err(PyValueError::new_err(
                "energies: a discrete Lagrangian has no continuous energy; write \
                 `fn l(q: Config, v: Velocity, ..)` with a `rule`",
            ));
        }
        if energies && self.constraint_count() > 0 {
            return Err(PyValueError::new_err(
                "energies: for a system without constraints (from Rust, the constrained integrators' `energies`)",
            ));
        }
        let m = self.constraint_count();
        calls::check_memory(
            || format!("a run of {steps} steps (every state kept)"),
            steps as u128 + 1,
            self.row_bytes(energies),
        )?;
        let (s, k) = self.dims();
        let code = Arc::clone(&self.code);
        let starts = std::slice::from_ref(&start);
        let (result, interrupt) = calls::interruptible(py, |cancel| {
            let job = Collect::new(cancel, energies);
            match m {
                _ if !code.fixed_size() => {
                    sizes::run_one(&code, &params, &start, r, energies, cancel)
                }
                0 if r.scheme == dirac_jit::Scheme::Gauss => {
                    collected(dirac_jit::with_dimensions!(
                        s,
                        k,
                        gauss::<_>(&code, &params, starts, &r, job) else Err(off_the_tables())
                    ))
                }
                0 => collected(dirac_jit::with_dimensions!(
                    s,
                    k,
                    flat::<_>(&code, &params, starts, &r, job) else Err(off_the_tables())
                )),
                m => collected(dirac_jit::with_constrained_dimensions!(
                    s,
                    k,
                    m,
                    constrained::<_>(&code, &params, starts, &r, job) else Err(off_the_tables())
                )),
            }
        })?;
        let names = self.part_names("q");
        finish_run(py, result, interrupt, |flat| to_dict(py, flat, &names))
    }

    /// An ensemble: one run per row of the start arrays (each `(members, length)`, or a dict by
    /// coordinate of `(members,)` arrays), in parallel on all cores, with the keywords of `run`
    /// but `energies`. Returns the same dict as `run` with one more leading axis and `failed`,
    /// the list of `(member, step, message)`; the first failed member raises `StepError` (with
    /// `member` set) after all have run. Ctrl-C ends every member after its current step and
    /// raises `KeyboardInterrupt` with `ensemble`, the dict of the states so far (NaN after
    /// each member's last).
    #[pyo3(signature = (parameters, steps, **keywords))]
    fn ensemble<'py>(
        &self,
        py: Python<'py>,
        parameters: &Bound<'py, PyAny>,
        steps: usize,
        keywords: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let kw = Keywords::read(py, &ENSEMBLE, keywords, None)?;
        let r = kw.ensemble_request(&self.compiled(), steps)?;
        self.check_start_keywords(&ENSEMBLE, r.equations, &kw.start)?;
        let params = parameter_values(&self.code, parameters)?;
        let per_member: Vec<Vec<Vec<f64>>> = ensemble::member_starts(py, &kw.start)?
            .iter()
            .enumerate()
            .map(|(i, start)| {
                self.member_start(r.equations, start)
                    .map_err(ensemble::of_member(i))
            })
            .collect::<PyResult<_>>()?;
        let m = per_member.len();
        // Each member's trajectory and its flattened copy, and its rows of the stacked arrays.
        let words = 2 * (self.dims().0 + self.dims().1) as u128;
        calls::check_memory(
            || format!("an ensemble of {m} members of {steps} steps (every state kept)"),
            (m as u128).saturating_mul(steps as u128 + 1),
            self.row_bytes(false) + 8 * words + 8,
        )?;
        let (s, k) = self.dims();
        let code = Arc::clone(&self.code);
        let rows = r.end_time.is_none().then_some(steps + 1);
        let (results, interrupt) = calls::interruptible(py, |cancel| {
            let job = Ensemble::new(cancel);
            match self.constraint_count() {
                _ if !code.fixed_size() => sizes::run_many(&code, &params, &per_member, r, cancel),
                0 => collected(dirac_jit::with_dimensions!(
                    s,
                    k,
                    flat::<_>(&code, &params, &per_member, &r, job) else Err(off_the_tables())
                )),
                m => collected(dirac_jit::with_constrained_dimensions!(
                    s,
                    k,
                    m,
                    constrained::<_>(&code, &params, &per_member, &r, job)
                        else Err(off_the_tables())
                )),
            }
        })?;
        let names = self.part_names("q");
        ensemble::ensemble_dict(py, results, interrupt, rows, |flat| {
            to_dict(py, flat, &names)
        })
    }

    /// Integrates `steps` steps from one start and writes every state to Apache Parquet at
    /// `path` (a directory of parts; the columns named after the coordinates, the parameters and
    /// the Newton options in the metadata), streaming, in constant memory, with the keywords of
    /// `run` but `order` and `energies`. Returns a dict with `steps`, `t` (the final time) and
    /// `path`. A failed step raises `StepError` with `step`, `residual` and `path`, the states
    /// before it written; Ctrl-C ends the run after the step in progress and raises
    /// `KeyboardInterrupt` with `steps`, `t` and `path`, the states so far written.
    #[pyo3(signature = (parameters, steps, path, **keywords))]
    fn write<'py>(
        &self,
        py: Python<'py>,
        parameters: &Bound<'py, PyAny>,
        steps: usize,
        path: std::path::PathBuf,
        keywords: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let kw = Keywords::read(py, &WRITE, keywords, None)?;
        let Inputs {
            params,
            request: r,
            start,
        } = self.inputs(&WRITE, parameters, &kw, steps)?;
        let (written, interrupt) = calls::interruptible(py, |cancel| {
            let out = ToParquet {
                path: &path,
                cancel,
            };
            parquet::written(dirac_jit::run_flat!(
                &self.code,
                &params,
                std::slice::from_ref(&start),
                &r,
                out
            ))
        })?;
        written_dict(py, written, interrupt)
    }

    /// Benchmarks only: the seconds of the same reduced (+) run as `run`, timed inside Rust
    /// around the integrator alone (no arrays).
    #[pyo3(signature = (parameters, steps, **start))]
    fn _core_seconds<'py>(
        &self,
        py: Python<'py>,
        parameters: &Bound<'py, PyAny>,
        steps: usize,
        start: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<f64> {
        let kw = Keywords::read(py, &CORE, start, None)?;
        let Inputs {
            params,
            request: r,
            start,
        } = self.inputs(&CORE, parameters, &kw, steps)?;
        let (s, k) = self.dims();
        let starts = std::slice::from_ref(&start);
        py.allow_threads(|| {
            collected(dirac_jit::with_dimensions!(
                s,
                k,
                flat::<_>(&self.code, &params, starts, &r, Timed) else Err(off_the_tables())
            ))
        })
        .map_err(PyValueError::new_err)
    }

    fn __repr__(&self) -> String {
        let s = self.code.system();
        format!(
            "<dirac.System {}: shape ({}), group ({}), parameters ({})>",
            s.name,
            s.shape.join(", "),
            s.group.join(", "),
            s.parameters.join(", ")
        )
    }
}

/// Compiles a system given as text (a function carrying `#[reduced_lagrangian(..)]`). Raises
/// `CompileError` with the attribute's messages, lines and columns.
#[pyfunction]
fn compile(py: Python<'_>, text: &str) -> PyResult<PyObject> {
    let compiled = py.allow_threads(|| dirac_jit::compile_any(text));
    system_object(py, compiled.map_err(|e| compile_error(py, e))?)
}

/// The Python class of a compiled system: `System`, `LieSystem` or `ElementSystem`.
pub(crate) fn system_object(py: Python<'_>, compiled: dirac_jit::Compiled) -> PyResult<PyObject> {
    match compiled {
        dirac_jit::Compiled::Lie(code) => Ok(Py::new(py, lie::LieSystem::new(code)?)?.into_any()),
        dirac_jit::Compiled::Element(code) => {
            Ok(Py::new(py, element::ElementSystem::new(code))?.into_any())
        }
        dirac_jit::Compiled::Flat(code) => Ok(Py::new(py, System { code })?.into_any()),
    }
}

/// `CompileError` for a text's mistakes (with their messages, lines and columns), or for any
/// other error of the front end.
pub(crate) fn compile_error(py: Python<'_>, error: dirac_jit::Error) -> PyErr {
    let dirac_jit::Error::Text(e) = error else {
        return CompileError::new_err(error.to_string());
    };
    let err = CompileError::new_err(e.to_string());
    let diagnostics: Vec<(String, usize, usize)> = e
        .diagnostics
        .iter()
        .map(|d| (d.message.clone(), d.line, d.column))
        .collect();
    if let Err(set) = err.value(py).setattr("diagnostics", diagnostics) {
        return set;
    }
    err
}

#[pymodule]
fn _dirac(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(compile, m)?)?;
    m.add_function(wrap_pyfunction!(multibody::from_urdf, m)?)?;
    m.add_class::<multibody::Model>()?;
    m.add_class::<System>()?;
    m.add_class::<lie::LieSystem>()?;
    m.add_class::<element::ElementSystem>()?;
    m.add("CompileError", m.py().get_type::<CompileError>())?;
    m.add("StepError", m.py().get_type::<StepError>())?;
    m.add("OutOfMemoryError", m.py().get_type::<OutOfMemoryError>())?;
    Ok(())
}
