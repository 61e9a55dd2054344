//! What every class's `ensemble` shares: the members' starts read from the keyword arrays (each
//! with a leading member axis; member `i`'s start is row `i` of each, read as `run` reads a
//! start), and the members' outcomes returned as one dict (the dict of `run`, stacked along a
//! leading member axis by `dirac._ensemble.stack`), the failed members listed as `failed`, the
//! first failure raised with the stacked dict as `ensemble`, Ctrl-C with the states so far.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::calls;
use crate::results::{raise, Failed};

/// A member's outcome: its trajectory, or its error with what it computed before.
pub(crate) type Member<F> = Result<F, Box<Failed<F>>>;

/// The number of members of the start arrays `given` (the length of their leading axis, the
/// same for all of them; a mapping by coordinate counts by its arrays), and member `i`'s start:
/// the keywords with row `i` of every array (of every array of a mapping).
pub(crate) fn member_starts<'py>(
    py: Python<'py>,
    given: &Bound<'py, PyDict>,
) -> PyResult<Vec<Bound<'py, PyDict>>> {
    let np = py.import("numpy")?;
    let mut members: Option<(String, usize)> = None;
    let mut count = |name: String, v: &Bound<'py, PyAny>| -> PyResult<()> {
        let shape: Vec<usize> = np.call_method1("shape", (v,))?.extract()?;
        let Some(&m) = shape.first() else {
            return Err(PyValueError::new_err(format!(
                "`{name}` is one value; an ensemble's starts have one row per member"
            )));
        };
        match &members {
            None => members = Some((name, m)),
            Some((first, n)) if *n != m => {
                return Err(PyValueError::new_err(format!(
                    "`{name}` has {m} rows, `{first}` {n}: one per member"
                )))
            }
            Some(_) => {}
        }
        Ok(())
    };
    for (key, value) in given.iter() {
        let key: String = key.extract()?;
        match value.downcast::<PyDict>() {
            Ok(by_name) => {
                for (name, v) in by_name.iter() {
                    count(format!("{key}[\"{}\"]", name.extract::<String>()?), &v)?;
                }
            }
            Err(_) => count(key, &value)?,
        }
    }
    let m = members.map_or(0, |(_, m)| m);
    (0..m)
        .map(|i| {
            let start = PyDict::new(py);
            for (key, value) in given.iter() {
                let row = match value.downcast::<PyDict>() {
                    Ok(by_name) => {
                        let rows = PyDict::new(py);
                        for (name, v) in by_name.iter() {
                            rows.set_item(name, v.get_item(i)?)?;
                        }
                        rows.into_any()
                    }
                    Err(_) => value.get_item(i)?,
                };
                start.set_item(key, row)?;
            }
            Ok(start)
        })
        .collect()
}

/// A member's error for its start, prefixed by the member.
pub(crate) fn of_member(i: usize) -> impl Fn(PyErr) -> PyErr {
    move |e| Python::with_gil(|py| PyValueError::new_err(format!("member {i}: {}", e.value(py))))
}

/// What `ensemble` returns: the members' dicts (`dict` of each outcome, a failed member's what
/// it computed) stacked, `rows` rows (as many as the longest member reached when `rows` is
/// `None`, as for a run up to an end time, or when Ctrl-C ended the ensemble), with `failed` the list of `(member, step, message)`; the first failed
/// member's `StepError` (with `member`, its own `trajectory` and the stacked `ensemble`) after
/// all have run; at Ctrl-C the interrupt with `ensemble`.
pub(crate) fn ensemble_dict<'py, F>(
    py: Python<'py>,
    results: Result<Vec<Member<F>>, String>,
    interrupt: Option<PyErr>,
    rows: Option<usize>,
    dict: impl Fn(F) -> PyResult<Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let results = match (results, interrupt.is_some()) {
        (Err(why), false) => return Err(PyValueError::new_err(why)),
        (Err(_), true) => return Err(interrupt.expect("the interrupt")),
        (Ok(results), _) => results,
    };
    let members = PyList::empty(py);
    let failures = PyList::empty(py);
    let mut first_failure = None;
    for (i, result) in results.into_iter().enumerate() {
        match result {
            Ok(flat) => members.append(dict(flat)?)?,
            Err(failed) => {
                let Failed { error, partial } = *failed;
                failures.append((i, error.step(), error.to_string()))?;
                let partial = dict(partial)?;
                members.append(&partial)?;
                if first_failure.is_none() {
                    first_failure = Some((i, error, partial));
                }
            }
        }
    }
    let rows = match (&interrupt, rows) {
        (None, Some(rows)) => rows,
        _ => members
            .iter()
            .map(|m| m.get_item("t").and_then(|t| t.len()))
            .collect::<PyResult<Vec<usize>>>()?
            .into_iter()
            .max()
            .unwrap_or(0),
    };
    let stacked = py
        .import("dirac._ensemble")?
        .getattr("stack")?
        .call1((members, rows))?
        .downcast_into::<PyDict>()?;
    stacked.set_item("failed", failures)?;
    if let Some(interrupt) = interrupt {
        return Err(calls::interrupted(py, interrupt, "ensemble", stacked));
    }
    if let Some((i, error, trajectory)) = first_failure {
        let err = raise(py, &error, trajectory, Some(i))?;
        err.value(py).setattr("ensemble", stacked)?;
        return Err(err);
    }
    Ok(stacked)
}
