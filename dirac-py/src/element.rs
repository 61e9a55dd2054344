//! Element-wise systems from Python (`dirac.ElementSystem`): sizes chosen per run, the start
//! given by coordinate (a vector or a grid each), runs of the element-wise integrator (both
//! sides, its compositions) or, with constraints, of the constrained one, trajectories as NumPy
//! arrays per coordinate. The integrators take their sizes at run time: no dispatch on
//! dimensions is needed.

use std::sync::Arc;

use dirac_compiler::text::ElementSystem as Text;
use dirac_jit::{Compiled, ElementCode, JitElement, RunRequest};
use dirac_runtime::element::{
    ElementConstrainedIntegrator, ElementConstrainedTrajectory, ElementIntegrator,
    ElementLagrangian, ElementState, ElementTrajectory,
};
use dirac_runtime::nalgebra::DVector;
use dirac_runtime::StepStats;
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::{PyDeprecationWarning, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use crate::calls;
use crate::ensemble;
use crate::keywords::{self, Keywords};
use crate::parquet::{self, ToParquet};
use crate::runs::{collected, Collect, Ensemble, Flatten};

// `ElementSystem.run`, `write` and `ensemble`: their arguments and options.
keywords::methods!("ElementSystem", ["sizes", "q", "p"], run = keywords::RUN);

/// What a run is asked for: the system at its sizes, and the run request of every class.
struct Request {
    sys: JitElement,
    run: RunRequest,
}

/// `value`, the keyword argument `name` of a run, which it needs.
fn required<'a, 'py>(
    name: &str,
    value: Option<&'a Bound<'py, PyAny>>,
) -> PyResult<&'a Bound<'py, PyAny>> {
    value.ok_or_else(|| PyTypeError::new_err(format!("missing the keyword argument '{name}'")))
}

/// The bytes one state of a collected run of `sys` costs until its arrays are returned: `q` and
/// `p` kept by the integrator (two vectors on the heap) and in the flattened copy, the momentum
/// map, the time, the step's statistics.
fn row_bytes(sys: &JitElement) -> u128 {
    let n = sys.dim() as u128;
    let translations = sys.translations().len() as u128;
    2 * 16 * n + 64 + 8 * translations + 16 + 64
}

impl Flatten for ElementIntegrator<JitElement> {
    type Flat = Flat;

    /// The states with the momentum map of the system's translations at each.
    fn flat_states(&self, states: &[ElementState], times: &[f64], stats: &[StepStats]) -> Flat {
        flat(self, states, times, stats)
    }

    fn flat(&self, t: &ElementTrajectory) -> Flat {
        self.flat_states(&t.states, &t.times, &t.stats)
    }
}

impl Flatten for ElementConstrainedIntegrator<JitElement> {
    type Flat = Flat;

    fn flat_states(&self, states: &[ElementState], times: &[f64], stats: &[StepStats]) -> Flat {
        flat(self, states, times, stats)
    }

    /// The states, and each step's multipliers `λ_k` and `‖φ(q_{k+1})‖∞`.
    fn flat(&self, t: &ElementConstrainedTrajectory) -> Flat {
        let mut f = self.flat_states(&t.states, &t.times, &t.stats);
        f.multipliers = Some((
            t.records
                .iter()
                .flat_map(|s| s.lambda.iter().copied())
                .collect(),
            t.records.iter().map(|s| s.constraint_residual).collect(),
        ));
        f
    }
}

/// What the element integrators read the momentum map `J(q, p)` of the system's translations
/// with.
trait MomentumMap {
    fn translations(&self) -> usize;
    fn momentum_map(&self, state: &ElementState) -> Vec<f64>;
}

impl MomentumMap for ElementIntegrator<JitElement> {
    fn translations(&self) -> usize {
        self.system().translations().len()
    }
    fn momentum_map(&self, state: &ElementState) -> Vec<f64> {
        ElementIntegrator::momentum_map(self, state).unwrap_or_default()
    }
}

impl MomentumMap for ElementConstrainedIntegrator<JitElement> {
    fn translations(&self) -> usize {
        self.system().translations().len()
    }
    fn momentum_map(&self, state: &ElementState) -> Vec<f64> {
        ElementConstrainedIntegrator::momentum_map(self, state).unwrap_or_default()
    }
}

/// A run's trajectory flattened for NumPy.
pub(crate) struct Flat {
    pub(crate) t: Vec<f64>,
    pub(crate) q: Vec<f64>,
    pub(crate) p: Vec<f64>,
    momentum_map: Vec<f64>,
    pub(crate) iterations: Vec<usize>,
    pub(crate) residuals: Vec<f64>,
    /// For a constrained run: `λ_k` per step, and `‖φ(q_{k+1})‖∞`.
    pub(crate) multipliers: Option<(Vec<f64>, Vec<f64>)>,
}

/// The states, times and statistics of a run of `integ`, flattened, with the momentum map at
/// each state.
fn flat(
    integ: &impl MomentumMap,
    states: &[ElementState],
    times: &[f64],
    stats: &[StepStats],
) -> Flat {
    let mut out = Flat {
        t: times.to_vec(),
        q: Vec::new(),
        p: Vec::new(),
        momentum_map: Vec::with_capacity(integ.translations() * states.len()),
        iterations: stats.iter().map(|s| s.iterations).collect(),
        residuals: stats.iter().map(|s| s.residual).collect(),
        multipliers: None,
    };
    for s in states {
        out.q.extend_from_slice(s.q.as_slice());
        out.p.extend_from_slice(s.p.as_slice());
        out.momentum_map.extend(integ.momentum_map(s));
    }
    out
}

/// An element-wise system given as text, compiled to machine code; its sizes are chosen per
/// run.
#[pyclass(frozen, module = "dirac._dirac")]
pub(crate) struct ElementSystem {
    code: Arc<ElementCode>,
}

impl ElementSystem {
    pub(crate) fn new(code: Arc<ElementCode>) -> ElementSystem {
        ElementSystem { code }
    }

    fn text(&self) -> &Text {
        self.code.system()
    }

    /// Reads and checks a run's request: the parameters, the steps and the sizes (by keyword;
    /// `positional` the arguments after the parameters, the steps or, deprecated, the sizes and
    /// the steps), the options `k` of `function` (an ensemble's: order 2); the system at these
    /// sizes.
    fn request(
        &self,
        function: &str,
        parameters: &Bound<'_, PyAny>,
        (positional, steps, sizes): (
            &Bound<'_, PyTuple>,
            Option<usize>,
            Option<&Bound<'_, PyAny>>,
        ),
        k: &Keywords<'_>,
    ) -> PyResult<Request> {
        let params = crate::inputs::values_of(&self.text().parameters, parameters)?;
        let (mut steps, mut sizes) = (steps, sizes.cloned());
        let mut sizes_positional = false;
        for arg in positional.iter() {
            match arg.extract::<usize>() {
                Ok(n) if steps.is_none() => steps = Some(n),
                Err(_) if sizes.is_none() => {
                    sizes = Some(arg);
                    sizes_positional = true;
                }
                _ => {
                    return Err(PyTypeError::new_err(format!(
                        "{function}() takes the parameters and the steps as positional \
                         arguments, the sizes as `sizes=`"
                    )))
                }
            }
        }
        if sizes_positional {
            let warnings = parameters.py().import("warnings")?;
            let category = parameters.py().get_type::<PyDeprecationWarning>();
            warnings.call_method1(
                "warn",
                (
                    format!(
                        "{function}(parameters, sizes, steps, ..) is deprecated: give the sizes \
                         by keyword, {function}(parameters, steps, sizes=.., ..)"
                    ),
                    category,
                    2,
                ),
            )?;
        }
        let steps = steps.ok_or_else(|| {
            PyTypeError::new_err(format!("{function}() missing the argument 'steps'"))
        })?;
        let sizes = sizes.ok_or_else(|| {
            PyTypeError::new_err(format!("{function}() missing the keyword argument 'sizes'"))
        })?;
        let sizes = self.size_values(&sizes)?;
        let system = Compiled::Element(Arc::clone(&self.code));
        let run = match function {
            "ElementSystem.ensemble" => k.ensemble_request(&system, steps)?,
            _ => k.request(&system, steps)?,
        };
        let sys = self
            .code
            .instantiate(&params, &sizes)
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        Ok(Request { sys, run })
    }

    /// The sizes from a mapping (by name) or a sequence (in order).
    fn size_values(&self, sizes: &Bound<'_, PyAny>) -> PyResult<Vec<usize>> {
        let names = &self.text().sizes;
        if let Ok(d) = sizes.downcast::<PyDict>() {
            for key in d.keys() {
                let key: String = key.extract()?;
                if !names.contains(&key) {
                    return Err(PyValueError::new_err(format!(
                        "no size `{key}`; declared: {}",
                        names.join(", ")
                    )));
                }
            }
            names
                .iter()
                .map(|n| {
                    d.get_item(n)?
                        .ok_or_else(|| {
                            PyValueError::new_err(format!(
                                "size `{n}` not given; declared: {}",
                                names.join(", ")
                            ))
                        })?
                        .extract::<usize>()
                })
                .collect()
        } else {
            let v: Vec<usize> = sizes.extract()?;
            if v.len() != names.len() {
                return Err(PyValueError::new_err(format!(
                    "{} sizes for {} ({})",
                    v.len(),
                    names.len(),
                    names.join(", ")
                )));
            }
            Ok(v)
        }
    }

    /// A configuration or momentum: a flat array of the system's length, or a mapping by
    /// coordinate (each an array of the coordinate's shape, a grid row by row).
    fn vector(
        &self,
        sys: &JitElement,
        what: &str,
        given: &Bound<'_, PyAny>,
    ) -> PyResult<DVector<f64>> {
        let np = given.py().import("numpy")?;
        let ravel = |v: &Bound<'_, PyAny>| -> PyResult<Vec<f64>> {
            np.call_method1("ravel", (np.call_method1("asarray", (v, "float64"))?,))?
                .extract()
        };
        let values: Vec<f64> = if let Ok(d) = given.downcast::<PyDict>() {
            let ranges = sys.coordinate_ranges();
            for key in d.keys() {
                let key: String = key.extract()?;
                if !ranges.iter().any(|(n, _)| *n == key) {
                    return Err(PyValueError::new_err(format!(
                        "`{what}` names `{key}`, not a coordinate"
                    )));
                }
            }
            let mut all = Vec::with_capacity(sys.dim());
            for (name, range) in ranges {
                let v = d
                    .get_item(name)?
                    .ok_or_else(|| PyValueError::new_err(format!("`{what}` needs `{name}`")))?;
                let v = ravel(&v)?;
                if v.len() != range.len() {
                    return Err(PyValueError::new_err(format!(
                        "`{what}[\"{name}\"]` has {} values; at these sizes it has {}",
                        v.len(),
                        range.len()
                    )));
                }
                all.extend(v);
            }
            all
        } else {
            ravel(given)?
        };
        if values.len() != sys.dim() {
            return Err(PyValueError::new_err(format!(
                "`{what}` has {} values; the system has {} at these sizes",
                values.len(),
                sys.dim()
            )));
        }
        if let Some(i) = values.iter().position(|x| !x.is_finite()) {
            return Err(PyValueError::new_err(format!(
                "`{what}[{i}]` = {} is not finite",
                values[i]
            )));
        }
        Ok(DVector::from_vec(values))
    }

    /// The dict of a run: `t`, `q` and `p` by coordinate, `momentum_map`, the statistics and,
    /// constrained, the multipliers.
    fn to_dict<'py>(
        &self,
        py: Python<'py>,
        sys: &JitElement,
        flat: Flat,
    ) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        let rows = flat.t.len();
        let n = sys.dim();
        let text = self.text();
        let sizes = sys.sizes();
        let z: Vec<i64> = sizes.iter().map(|&s| s as i64).collect();
        d.set_item("t", PyArray1::from_vec(py, flat.t))?;
        for (key, data) in [("q", flat.q), ("p", flat.p)] {
            let by_name = PyDict::new(py);
            for ((name, range), coord) in sys.coordinate_ranges().into_iter().zip(&text.coordinates)
            {
                let mut values = Vec::with_capacity(rows * range.len());
                for r in 0..rows {
                    values.extend_from_slice(&data[r * n + range.start..r * n + range.end]);
                }
                let mut shape = vec![rows];
                shape.extend(coord.dims.iter().map(|d| d.eval(&z).max(0) as usize));
                by_name.set_item(name, PyArray1::from_vec(py, values).reshape(shape)?)?;
            }
            d.set_item(key, by_name)?;
        }
        let t = sys.translations().len();
        d.set_item(
            "momentum_map",
            PyArray1::from_vec(py, flat.momentum_map).reshape([rows, t])?,
        )?;
        d.set_item("iterations", PyArray1::from_vec(py, flat.iterations))?;
        d.set_item("residuals", PyArray1::from_vec(py, flat.residuals))?;
        if let Some((lambda, residual)) = flat.multipliers {
            let steps = residual.len();
            let m = sys.constraint_count();
            d.set_item(
                "multipliers",
                PyArray1::from_vec(py, lambda).reshape([steps, m])?,
            )?;
            d.set_item("constraint_residuals", PyArray1::from_vec(py, residual))?;
        }
        Ok(d)
    }
}

#[pymethods]
impl ElementSystem {
    /// The type name the attribute would emit.
    #[getter]
    fn name(&self) -> String {
        self.text().name.clone()
    }

    /// The sizes' names, in declaration order.
    #[getter]
    fn sizes(&self) -> Vec<String> {
        self.text().sizes.clone()
    }

    /// The coordinates, in the order of the flat configuration vector.
    #[getter]
    fn coordinates(&self) -> Vec<String> {
        self.text()
            .coordinates
            .iter()
            .map(|c| c.name.clone())
            .collect()
    }

    /// The parameters, in declaration order.
    #[getter]
    fn parameters(&self) -> Vec<String> {
        self.text().parameters.clone()
    }

    /// The controls' names.
    #[getter]
    fn controls(&self) -> Vec<String> {
        let s = self.text();
        crate::inputs::control_names(&s.parameters, &s.controls)
    }

    /// Whether the system has holonomic constraints (then it runs the constrained integrator).
    #[getter]
    fn constrained(&self) -> bool {
        self.text().constraints.is_some()
    }

    /// Seconds from text to machine code.
    #[getter]
    fn compile_time(&self) -> f64 {
        self.code.compile_time().as_secs_f64()
    }

    /// Integrates `steps` steps (with `end_time`, up to that time, reached exactly, and at most
    /// `steps`; with `schedule`, a list of at least `steps` sizes, step `k` of size `schedule[k]`)
    /// at `sizes` (a dict by name or a sequence in order) from `q` and
    /// `p` (each a flat array of the system's length at these sizes, or a dict by coordinate of
    /// arrays of each coordinate's shape). `method` is "plus" or "minus" (or "unreduced", the
    /// "plus"); `order` 2, 4 or 6 (a constrained system: 2). Returns a dict of NumPy arrays: `t`,
    /// `q` and `p` (dicts by coordinate, one leading row per state), `momentum_map` (one column
    /// per declared translation), per step `iterations` and `residuals`, and for a constrained
    /// system `multipliers` (steps, rows) and `constraint_residuals`. Raises `StepError` with
    /// the trajectory so far, `KeyboardInterrupt` with the trajectory so far at Ctrl-C,
    /// `OutOfMemoryError` (before running) when the trajectory cannot be allocated, and
    /// `TypeError` for a keyword it does not take. The sizes given before the steps, as
    /// positional arguments (`run(parameters, sizes, steps, ..)`), are read with a
    /// `DeprecationWarning`.
    #[pyo3(signature = (parameters, *positional, steps = None, sizes = None, q = None, p = None, **keywords))]
    #[allow(clippy::too_many_arguments, reason = "the Python arguments, one each")]
    fn run<'py>(
        &self,
        py: Python<'py>,
        parameters: &Bound<'py, PyAny>,
        positional: &Bound<'py, PyTuple>,
        steps: Option<usize>,
        sizes: Option<&Bound<'py, PyAny>>,
        q: Option<&Bound<'py, PyAny>>,
        p: Option<&Bound<'py, PyAny>>,
        keywords: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let kw = Keywords::read(py, &RUN, keywords, Some(&[]))?;
        let r = self.request(RUN.name, parameters, (positional, steps, sizes), &kw)?;
        let start = ElementState::new(
            self.vector(&r.sys, "q", required("q", q)?)?,
            self.vector(&r.sys, "p", required("p", p)?)?,
        );
        let steps = r.run.steps;
        calls::check_memory(
            || {
                format!(
                    "a run of {steps} steps of {} coordinates (every state kept, and its copy)",
                    r.sys.dim()
                )
            },
            steps as u128 + 1,
            row_bytes(&r.sys),
        )?;
        let runner = r.sys.clone();
        let run = r.run;
        let (result, interrupt) = calls::interruptible(py, move |cancel| {
            collected(dirac_jit::run::element(
                runner,
                vec![start],
                &run,
                Collect::new(cancel, false),
            ))
        })?;
        crate::results::finish_run(py, result, interrupt, |flat| self.to_dict(py, &r.sys, flat))
    }

    /// Integrates `steps` steps (order 2) from the start of `run` and writes every state to
    /// Apache Parquet at `path` (a directory of parts: columns `q_<i>` and `p_<i>` by index in
    /// the flat vector, the coordinate arrays and the sizes in the metadata), streaming, in
    /// constant memory. Returns a dict with `steps`, `t` and `path`; a failed step raises
    /// `StepError` with `step`, `residual` and `path`, the states before it written; Ctrl-C
    /// raises `KeyboardInterrupt` with `steps`, `t` and `path`, the states so far written.
    #[pyo3(signature = (parameters, steps, path, sizes, q, p, **keywords))]
    #[allow(clippy::too_many_arguments, reason = "the Python arguments, one each")]
    fn write<'py>(
        &self,
        py: Python<'py>,
        parameters: &Bound<'py, PyAny>,
        steps: usize,
        path: std::path::PathBuf,
        sizes: &Bound<'py, PyAny>,
        q: &Bound<'py, PyAny>,
        p: &Bound<'py, PyAny>,
        keywords: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let kw = Keywords::read(py, &WRITE, keywords, Some(&[]))?;
        let no_more = PyTuple::empty(py);
        let r = self.request(
            WRITE.name,
            parameters,
            (&no_more, Some(steps), Some(sizes)),
            &kw,
        )?;
        let start = ElementState::new(self.vector(&r.sys, "q", q)?, self.vector(&r.sys, "p", p)?);
        let (written, interrupt) = calls::interruptible(py, move |cancel| {
            let out = ToParquet {
                path: &path,
                cancel,
            };
            parquet::written(dirac_jit::run::element(r.sys, vec![start], &r.run, out))
        })?;
        crate::parquet::written_dict(py, written, interrupt)
    }

    /// An ensemble: one run (order 2) per member at the same `sizes`, in parallel on all cores,
    /// from the starts of `run` with a leading member axis (`q` an array (members, length) or a
    /// dict by coordinate of arrays (members, shape..)). Returns the dict of `run` with one
    /// more leading axis and `failed`, the list of `(member, step, message)`; the first failed
    /// member raises `StepError` (with `member` and `ensemble`) after all have run; Ctrl-C
    /// raises `KeyboardInterrupt` with `ensemble`, the states so far (NaN after each member's
    /// last).
    #[pyo3(signature = (parameters, steps, sizes, q, p, **keywords))]
    #[allow(clippy::too_many_arguments, reason = "the Python arguments, one each")]
    fn ensemble<'py>(
        &self,
        py: Python<'py>,
        parameters: &Bound<'py, PyAny>,
        steps: usize,
        sizes: &Bound<'py, PyAny>,
        q: &Bound<'py, PyAny>,
        p: &Bound<'py, PyAny>,
        keywords: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let kw = Keywords::read(py, &ENSEMBLE, keywords, Some(&[]))?;
        let no_more = PyTuple::empty(py);
        let r = self.request(
            ENSEMBLE.name,
            parameters,
            (&no_more, Some(steps), Some(sizes)),
            &kw,
        )?;
        let given = PyDict::new(py);
        given.set_item("q", q)?;
        given.set_item("p", p)?;
        let starts = ensemble::member_starts(py, &given)?
            .iter()
            .enumerate()
            .map(|(i, start)| {
                let part = |key: &str| -> PyResult<DVector<f64>> {
                    let v = start.get_item(key)?.expect("q and p are given");
                    self.vector(&r.sys, key, &v)
                };
                (|| Ok(ElementState::new(part("q")?, part("p")?)))().map_err(ensemble::of_member(i))
            })
            .collect::<PyResult<Vec<ElementState>>>()?;
        let m = starts.len();
        calls::check_memory(
            || format!("an ensemble of {m} members of {steps} steps (every state kept)"),
            (m as u128).saturating_mul(steps as u128 + 1),
            2 * row_bytes(&r.sys),
        )?;
        let rows = r.run.end_time.is_none().then_some(steps + 1);
        let (sys, run) = (r.sys.clone(), r.run);
        let (results, interrupt) = calls::interruptible(py, move |cancel| {
            collected(dirac_jit::run::element(
                sys,
                starts,
                &run,
                Ensemble::new(cancel),
            ))
        })?;
        ensemble::ensemble_dict(py, results, interrupt, rows, |flat| {
            self.to_dict(py, &r.sys, flat)
        })
    }

    fn __repr__(&self) -> String {
        let s = self.text();
        let coords: Vec<&str> = s.coordinates.iter().map(|c| c.name.as_str()).collect();
        format!(
            "<dirac.ElementSystem {}: coordinates ({}), sizes ({}), parameters ({})>",
            s.name,
            coords.join(", "),
            s.sizes.join(", "),
            s.parameters.join(", ")
        )
    }
}
