//! Element-wise systems from Python (`dirac.ElementSystem`): sizes chosen per run, the start
//! given by coordinate (a vector or a grid each), runs of the element-wise integrator (both
//! sides, its compositions) or, with constraints, of the constrained one, trajectories as NumPy
//! arrays per coordinate. The integrators take their sizes at run time: no dispatch on
//! dimensions is needed.

use std::sync::atomic::AtomicBool;
use std::sync::Arc;

use dirac_compiler::text::ElementSystem as Text;
use dirac_jit::{ElementCode, JitElement};
use dirac_runtime::element::{
    ElementConstrainedIntegrator, ElementConstrainedTrajectory, ElementIntegrator,
    ElementLagrangian, ElementState, ElementTrajectory,
};
use dirac_runtime::nalgebra::DVector;
use dirac_runtime::{Composition, Drive, Equations, Form, NewtonOptions, Variant};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::calls::{self, until};
use crate::composition;
use crate::results::{finish, Failed};

/// The keywords of `ElementSystem.run`.
const RUN_KEYWORDS: &[&str] = &[
    "parameters",
    "sizes",
    "steps",
    "q",
    "p",
    "method",
    "order",
    "tol",
];

/// A run's trajectory flattened for NumPy.
struct Flat {
    t: Vec<f64>,
    q: Vec<f64>,
    p: Vec<f64>,
    momentum_map: Vec<f64>,
    iterations: Vec<usize>,
    residuals: Vec<f64>,
    /// For a constrained run: `λ_k` per step, and `‖φ(q_{k+1})‖∞`.
    multipliers: Option<(Vec<f64>, Vec<f64>)>,
}

fn flat(
    translations: usize,
    states: &[ElementState],
    times: &[f64],
    stats: impl Iterator<Item = (usize, f64)>,
    momentum_map: impl Fn(&ElementState) -> Vec<f64>,
) -> Flat {
    let (iterations, residuals) = stats.unzip();
    let mut out = Flat {
        t: times.to_vec(),
        q: Vec::new(),
        p: Vec::new(),
        momentum_map: Vec::with_capacity(translations * states.len()),
        iterations,
        residuals,
        multipliers: None,
    };
    for s in states {
        out.q.extend_from_slice(s.q.as_slice());
        out.p.extend_from_slice(s.p.as_slice());
        out.momentum_map.extend(momentum_map(s));
    }
    out
}

/// One run: the unconstrained integrator (order 2, 4 or 6), or the constrained one.
fn run_one(
    sys: JitElement,
    start: ElementState,
    plus: bool,
    order: u32,
    steps: usize,
    options: NewtonOptions,
    cancel: &AtomicBool,
) -> Result<Flat, Box<Failed<Flat>>> {
    let translations = sys.translations().len();
    if sys.constrained() {
        let integ = if plus {
            ElementConstrainedIntegrator::new(sys, options)
        } else {
            ElementConstrainedIntegrator::minus(sys, options)
        };
        let to_flat = |t: &ElementConstrainedTrajectory| {
            let mut f = flat(
                translations,
                &t.states,
                &t.times,
                t.stats.iter().map(|s| (s.iterations, s.residual)),
                |s| integ.momentum_map(s).unwrap_or_default(),
            );
            f.multipliers = Some((
                t.records
                    .iter()
                    .flat_map(|s| s.lambda.iter().copied())
                    .collect(),
                t.records.iter().map(|s| s.constraint_residual).collect(),
            ));
            f
        };
        return finish(
            integ.run(start).steps(steps).stop(until(cancel)).collect(),
            to_flat,
        );
    }
    let integ = if plus {
        ElementIntegrator::new(sys, options)
    } else {
        ElementIntegrator::minus(sys, options)
    };
    let to_flat = |t: &ElementTrajectory| {
        flat(
            translations,
            &t.states,
            &t.times,
            t.stats.iter().map(|s| (s.iterations, s.residual)),
            |s| integ.momentum_map(s).unwrap_or_default(),
        )
    };
    if order == 2 {
        finish(
            integ.run(start).steps(steps).stop(until(cancel)).collect(),
            to_flat,
        )
    } else {
        let c = Composition::new(integ.clone(), composition(order));
        finish(
            c.run(start).steps(steps).stop(until(cancel)).collect(),
            |t| {
                flat(
                    translations,
                    &t.states,
                    &t.times,
                    t.stats.iter().map(|s| (s.iterations, s.residual)),
                    |s| integ.momentum_map(s).unwrap_or_default(),
                )
            },
        )
    }
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

    /// Integrates `steps` steps at `sizes` (a dict by name or a sequence) from `q` and `p`
    /// (each a flat array of the system's length at these sizes, or a dict by coordinate of
    /// arrays of each coordinate's shape). `method` is "plus" or "minus"; `order` 2, 4 or 6 (a
    /// constrained system: 2). Returns a dict of NumPy arrays: `t`, `q` and `p` (dicts by
    /// coordinate, one leading row per state), `momentum_map` (one column per declared
    /// translation), per step `iterations` and `residuals`, and for a constrained system
    /// `multipliers` (steps, rows) and `constraint_residuals`. Raises `StepError` with the
    /// trajectory so far, `KeyboardInterrupt` with the trajectory so far at Ctrl-C,
    /// `OutOfMemoryError` (before running) when the trajectory cannot be allocated, and
    /// `TypeError` for a keyword it does not take.
    #[pyo3(signature = (parameters, sizes, steps, q, p, method = "plus", order = 2, tol = None, **other))]
    #[allow(
        clippy::too_many_arguments,
        reason = "the Python keyword arguments, one each"
    )]
    fn run<'py>(
        &self,
        py: Python<'py>,
        parameters: &Bound<'py, PyAny>,
        sizes: &Bound<'py, PyAny>,
        steps: usize,
        q: &Bound<'py, PyAny>,
        p: &Bound<'py, PyAny>,
        method: &str,
        order: u32,
        tol: Option<f64>,
        other: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        calls::no_other_keywords("ElementSystem.run", other, &[], RUN_KEYWORDS, |_| None)?;
        let params = crate::inputs::values_of(&self.text().parameters, parameters)?;
        let sizes = self.size_values(sizes)?;
        // The runtime's one vocabulary: an element-wise system's equations are the unreduced
        // ones, on either side.
        let plus = match Equations::from_keyword(method, Form::Unreduced)
            .filter(|_| ["plus", "minus"].contains(&method))
        {
            Some(e) => e.side == Variant::Plus,
            None => {
                return Err(PyValueError::new_err(format!(
                    "unknown method `{method}`; accepted: \"plus\", \"minus\""
                )))
            }
        };
        if ![2, 4, 6].contains(&order) || (order != 2 && self.constrained()) {
            return Err(PyValueError::new_err(format!(
                "order {order}: accepted 2 (the integrator itself), 4 (triple jump), 6 (Kahan–Li); \
                 2 for a system with constraints"
            )));
        }
        let sys = self
            .code
            .instantiate(&params, &sizes)
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        let start = ElementState::new(self.vector(&sys, "q", q)?, self.vector(&sys, "p", p)?);
        // Per state: `q` and `p` kept by the integrator (two vectors on the heap) and in the
        // flattened copy, the momentum map, the time, the step's statistics.
        let n = start.q.len() as u128;
        let translations = sys.translations().len() as u128;
        calls::check_memory(
            || {
                format!(
                    "a run of {steps} steps of {n} coordinates (every state kept, and its copy)"
                )
            },
            steps as u128 + 1,
            2 * 16 * n + 64 + 8 * translations + 16 + 64,
        )?;
        let mut options = NewtonOptions::default();
        if let Some(t) = tol {
            options.abs_tol = t;
        }
        let runner = sys.clone();
        let (result, interrupt) = calls::interruptible(py, move |cancel| {
            run_one(runner, start, plus, order, steps, options, cancel)
        })?;
        crate::results::finish_run(py, Ok(result), interrupt, |flat| {
            self.to_dict(py, &sys, flat)
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
