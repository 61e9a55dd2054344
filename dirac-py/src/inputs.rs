//! A run's inputs read from Python and checked: the parameter values (by name or in order), the
//! method and order, the start's vectors (their lengths, finite), and no keyword the run
//! method does not take.

use std::sync::Arc;

use dirac_jit::{Code, Compiled, RunRequest};
use dirac_runtime::{Equations, Form};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::calls;
use crate::keywords::{Keywords, Method};
use crate::System;

/// The parameter values in declaration order, from a mapping (by name) or a sequence.
pub(crate) fn parameter_values(code: &Code, params: &Bound<'_, PyAny>) -> PyResult<Vec<f64>> {
    values_of(&code.system().parameters, params)
}

/// The names of the controls, given as indices into the parameters.
pub(crate) fn control_names(parameters: &[String], controls: &[usize]) -> Vec<String> {
    controls.iter().map(|&i| parameters[i].clone()).collect()
}

/// The values of the parameters `names`, in declaration order, from a mapping (by name) or a
/// sequence.
pub(crate) fn values_of(names: &[String], params: &Bound<'_, PyAny>) -> PyResult<Vec<f64>> {
    if let Ok(d) = params.downcast::<PyDict>() {
        let mut values = Vec::with_capacity(names.len());
        for name in names {
            let v = d.get_item(name)?.ok_or_else(|| {
                PyValueError::new_err(format!(
                    "parameter `{name}` not given; declared: {}",
                    names.join(", ")
                ))
            })?;
            values.push(v.extract::<f64>()?);
        }
        for key in d.keys() {
            let key: String = key.extract()?;
            if !names.contains(&key) {
                return Err(PyValueError::new_err(format!(
                    "no parameter `{key}`; declared: {}",
                    names.join(", ")
                )));
            }
        }
        Ok(values)
    } else {
        params.extract::<Vec<f64>>()
    }
}

/// One start's vectors, each of its length, from keyword arrays: each vector an array of its
/// length or a mapping by coordinate (`names` gives each vector's coordinates, in order).
fn vectors(
    parts: &[(&'static str, usize)],
    names: impl Fn(&str) -> Vec<String>,
    given: &Bound<'_, PyDict>,
) -> PyResult<Vec<Vec<f64>>> {
    parts
        .iter()
        .map(|&(name, len)| {
            let v: Vec<f64> = match given.get_item(name)? {
                Some(d) if d.downcast::<PyDict>().is_ok() => {
                    by_name(name, &names(name), d.downcast::<PyDict>()?)?
                }
                Some(v) => v.extract()?,
                None if len == 0 => Vec::new(),
                None => {
                    return Err(PyValueError::new_err(format!(
                        "the start needs `{name}` ({len} values)"
                    )))
                }
            };
            if v.len() != len {
                return Err(PyValueError::new_err(format!(
                    "`{name}` has {} values; the system has {len}",
                    v.len()
                )));
            }
            if let Some(i) = v.iter().position(|x| !x.is_finite()) {
                return Err(PyValueError::new_err(format!(
                    "`{name}[{i}]` = {} is not finite",
                    v[i]
                )));
            }
            Ok(v)
        })
        .collect()
}

/// The vector `what` from a mapping by coordinate: a value for each of `names`, in order, and
/// no other key.
fn by_name(what: &str, names: &[String], d: &Bound<'_, PyDict>) -> PyResult<Vec<f64>> {
    for key in d.keys() {
        let key: String = key.extract()?;
        if !names.contains(&key) {
            return Err(PyValueError::new_err(format!(
                "`{what}` names `{key}`, not one of its coordinates ({})",
                names.join(", ")
            )));
        }
    }
    names
        .iter()
        .map(|n| {
            d.get_item(n)?
                .ok_or_else(|| PyValueError::new_err(format!("`{what}` needs `{n}`")))?
                .extract::<f64>()
        })
        .collect()
}

impl System {
    /// The system as the run request checks it.
    pub(crate) fn compiled(&self) -> Compiled {
        Compiled::Flat(Arc::clone(&self.code))
    }

    /// A `TypeError` for a keyword of `given` (the start's vectors) that is none of the start's
    /// vectors of `method`; `fixed` are the function's other keywords. A vector of the other
    /// kind of start (`q` for a reduced run) is named as such.
    pub(crate) fn check_start_keywords(
        &self,
        function: &Method<'_>,
        method: Equations,
        given: &Bound<'_, PyDict>,
    ) -> PyResult<()> {
        let parts = self.start_parts(method);
        let names: Vec<&str> = parts.iter().map(|&(name, _)| name).collect();
        let accepted: Vec<&str> = (function.positional.iter())
            .chain(function.options)
            .chain(&names)
            .copied()
            .collect();
        let this = format!("\"{}\"", method.keyword(Form::Reduced));
        let (other, other_names) = match method.form {
            Form::Unreduced => ("\"plus\" or \"minus\"", "x, w, mu, g"),
            Form::Reduced => ("\"unreduced\"", "q, p"),
        };
        calls::no_other_keywords(function.name, Some(given), &names, &accepted, |key| {
            let elsewhere = match method.form {
                Form::Unreduced => ["x", "w", "mu", "g"].contains(&key),
                Form::Reduced => ["q", "p"].contains(&key),
            };
            elsewhere.then(|| {
                format!(
                    "`{key}` starts a run of method {other} ({other_names}), and method \
                     {this} starts from {}",
                    names.join(", ")
                )
            })
        })
    }
}

impl System {
    /// The coordinates of a start's vector `part`: `x`, `w` the shape coordinates, `mu`, `g`
    /// the group ones, `q`, `p` both.
    pub(crate) fn part_names(&self, part: &str) -> Vec<String> {
        let s = self.code.system();
        match part {
            "x" | "w" => s.shape.clone(),
            "mu" | "g" => s.group.clone(),
            _ => s.shape.iter().chain(&s.group).cloned().collect(),
        }
    }

    /// One member's start of an ensemble, read as `run` reads a start.
    pub(crate) fn member_start(
        &self,
        method: Equations,
        given: &Bound<'_, PyDict>,
    ) -> PyResult<Vec<Vec<f64>>> {
        vectors(
            &self.start_parts(method),
            |part| self.part_names(part),
            given,
        )
    }
}

/// A run's inputs read from Python: the parameter values, the request, the start's vectors.
pub(crate) struct Inputs {
    pub(crate) params: Vec<f64>,
    pub(crate) request: RunRequest,
    pub(crate) start: Vec<Vec<f64>>,
}

impl System {
    /// Reads and checks one run's inputs (the parameters, the request its options `k` make,
    /// the start, no keyword that `function` does not take).
    pub(crate) fn inputs(
        &self,
        function: &Method<'_>,
        parameters: &Bound<'_, PyAny>,
        k: &Keywords<'_>,
        steps: usize,
    ) -> PyResult<Inputs> {
        let request = k.request(&self.compiled(), steps)?;
        self.check_start_keywords(function, request.equations, &k.start)?;
        let params = parameter_values(&self.code, parameters)?;
        let start = vectors(
            &self.start_parts(request.equations),
            |part| self.part_names(part),
            &k.start,
        )?;
        Ok(Inputs {
            params,
            request,
            start,
        })
    }
}
