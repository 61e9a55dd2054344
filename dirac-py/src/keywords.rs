//! The keywords of every run method, read once for every class: `run`, `write` and `ensemble`
//! of `System`, `LieSystem` and `ElementSystem` take their parameters and steps (and a path, a
//! class's sizes) by position or name, and everything else by keyword — the run's options
//! ([`OPTIONS`]: the equations, the order, Newton's tolerance, the end time, the schedule, the
//! energies), each with one name, one default and one type whatever the class, and the start.
//! [`Keywords::read`] takes them out of the method's `**keywords`, refuses one the method does
//! not take with a `TypeError` naming it (and the closest one it takes), and makes them the one
//! run request ([`Keywords::request`]).

use dirac_jit::{Compiled, RunRequest};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::calls;

/// The options a run method may take, besides its parameters, steps and start.
pub(crate) const OPTIONS: [&str; 7] = [
    "method", "order", "tol", "end_time", "schedule", "energies", "scheme",
];

/// The options of a collected run of a class without energies and of every ensemble.
pub(crate) const RUN: &[&str] = OPTIONS.split_at(5).0;
/// The options of a run written to Parquet: every option of [`RUN`] but the order (a written
/// run is the integrator itself, order 2).
pub(crate) const WRITE: &[&str] = &["method", "tol", "end_time", "schedule"];

/// A run method: its Python name, the arguments it takes by position or name (named in the
/// message of a keyword it does not take), and which of [`OPTIONS`] it takes.
pub(crate) struct Method<'a> {
    pub(crate) name: &'a str,
    pub(crate) positional: &'a [&'a str],
    pub(crate) options: &'a [&'a str],
}

/// The `RUN`, `WRITE` and `ENSEMBLE` [`Method`]s of the class `$class`: each takes the
/// parameters and the steps, `write` then the path, and then the arguments `$after` (a start's
/// vectors, the sizes); `run` takes the options `$run`, `ensemble` those of [`RUN`], `write`
/// those of [`WRITE`].
macro_rules! methods {
    ($class:literal, [$($after:literal),*], run = $run:expr) => {
        const RUN: $crate::keywords::Method = $crate::keywords::Method {
            name: concat!($class, ".run"),
            positional: &["parameters", "steps" $(, $after)*],
            options: $run,
        };
        const WRITE: $crate::keywords::Method = $crate::keywords::Method {
            name: concat!($class, ".write"),
            positional: &["parameters", "steps", "path" $(, $after)*],
            options: $crate::keywords::WRITE,
        };
        const ENSEMBLE: $crate::keywords::Method = $crate::keywords::Method {
            name: concat!($class, ".ensemble"),
            positional: &["parameters", "steps" $(, $after)*],
            options: $crate::keywords::RUN,
        };
    };
}

pub(crate) use methods;

/// A run method's options, read from its keywords (each its default when not given), and the
/// keywords left: the start.
pub(crate) struct Keywords<'py> {
    /// `method`: which equations, a word of the runtime's one vocabulary (default "plus").
    pub(crate) method: String,
    /// `order`: 2, 4 or 6 (default 2); by `scheme="gauss"` any even order from 2 to 32.
    pub(crate) order: u32,
    /// `scheme`: "composition" (default) or "gauss" (only `System.run` takes it).
    pub(crate) scheme: String,
    /// `tol`: Newton's absolute tolerance (default: Newton's own).
    pub(crate) tol: Option<f64>,
    /// `end_time`: the time the run ends at, reached exactly (default: none, `steps` steps).
    pub(crate) end_time: Option<f64>,
    /// `schedule`: the size of each step (default: the system's own).
    pub(crate) schedule: Option<Vec<f64>>,
    /// `energies`: the continuous energies of the states (default `False`).
    pub(crate) energies: bool,
    /// The keywords that are none of the method's options: the start's vectors.
    pub(crate) start: Bound<'py, PyDict>,
}

/// The value of the keyword argument `name`, of the type its option takes: else the
/// `TypeError` Python gives for an argument of the wrong type.
fn typed<'py, T: FromPyObject<'py>>(value: &Bound<'py, PyAny>, name: &str) -> PyResult<T> {
    value.extract().map_err(|e| {
        let why = e.value(value.py()).to_string();
        PyTypeError::new_err(format!("argument '{name}': {why}"))
    })
}

impl<'py> Keywords<'py> {
    /// Reads `given`, the keywords of `method` that its signature did not bind: each of its
    /// options, and the start's keywords `start` (any keyword that is no option, when `None`:
    /// the class checks them itself). A keyword that is neither is a `TypeError` naming it and
    /// the closest one the method takes.
    pub(crate) fn read(
        py: Python<'py>,
        method: &Method<'_>,
        given: Option<&Bound<'py, PyDict>>,
        start: Option<&[&str]>,
    ) -> PyResult<Self> {
        let mut k = Keywords {
            method: "plus".to_owned(),
            order: 2,
            scheme: "composition".to_owned(),
            tol: None,
            end_time: None,
            schedule: None,
            energies: false,
            start: PyDict::new(py),
        };
        let Some(given) = given else { return Ok(k) };
        for (key, value) in given.iter() {
            let name: String = key.extract()?;
            let name = name.as_str();
            if !method.options.contains(&name) {
                if start.is_none_or(|s| s.contains(&name)) {
                    k.start.set_item(name, value)?;
                    continue;
                }
                let accepted: Vec<&str> = method
                    .positional
                    .iter()
                    .chain(start.unwrap_or_default())
                    .chain(method.options)
                    .copied()
                    .collect();
                return Err(calls::unexpected_keyword(
                    method.name,
                    name,
                    &accepted,
                    None,
                ));
            }
            match name {
                "method" => k.method = typed(&value, name)?,
                "order" => k.order = typed(&value, name)?,
                "tol" => k.tol = typed(&value, name)?,
                "end_time" => k.end_time = typed(&value, name)?,
                "schedule" => k.schedule = typed(&value, name)?,
                "scheme" => k.scheme = typed(&value, name)?,
                _ => k.energies = typed(&value, name)?,
            }
        }
        Ok(k)
    }

    /// The run request these options make for `system` and `steps` (`dirac_jit::RunRequest`,
    /// checked against the system there): what the system cannot run is a `ValueError` saying
    /// what it accepts.
    pub(crate) fn request(&self, system: &Compiled, steps: usize) -> PyResult<RunRequest> {
        RunRequest::from_keywords(
            system,
            &self.method,
            &self.scheme,
            self.order,
            steps,
            self.tol,
        )
        .and_then(|r| r.with_end_time(self.end_time))
        .and_then(|r| r.with_schedule(self.schedule.clone()))
        .map_err(|e| PyValueError::new_err(e.to_string()))
    }

    /// [`Self::request`] for an ensemble, whose members run the integrators themselves (order
    /// 2).
    pub(crate) fn ensemble_request(&self, system: &Compiled, steps: usize) -> PyResult<RunRequest> {
        let r = self.request(system, steps)?;
        if r.order != 2 {
            return Err(PyValueError::new_err(
                "ensembles run the integrators themselves (order 2)",
            ));
        }
        Ok(r)
    }
}
