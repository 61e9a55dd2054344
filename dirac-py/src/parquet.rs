//! Runs written to Apache Parquet: a run streamed into the workspace's writer, ended early by
//! Ctrl-C, and what `write` returns to Python (or raises) once it has ended.

use std::sync::atomic::AtomicBool;

use dirac_jit::RunRequest;
use dirac_runtime::{StepError as RuntimeStepError, StepStats};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::calls::span;
use crate::results::exception_of;

/// What a run written to Parquet ended with: its steps, its final time and the path; or the
/// failed step's error, the states before it on disk.
pub(crate) type Written =
    Result<(usize, f64, std::path::PathBuf), (RuntimeStepError, std::path::PathBuf)>;

/// The run `request` asks (its steps, end time, schedule and Newton's options) streamed into Parquet at `path` by the workspace's writer (the run's
/// observer, [`dirac_io::ParquetObserver`]), that ends after the step in progress once `cancel` is
/// set (the file then holds the states so far, its outcome "stopped"): what it ended with, as
/// [`Written`]; the writer's own failure is the outer `Err`.
pub(crate) fn to_parquet<I>(
    integ: &I,
    start: I::State,
    request: &RunRequest,
    path: &std::path::Path,
    cancel: &AtomicBool,
) -> Result<Written, String>
where
    I: dirac_io::Describe + dirac_runtime::Drive,
    I::State: dirac_io::StateColumns,
    I::Record: AsRef<StepStats>,
{
    let info = integ.describe().with_newton(&request.newton);
    let mut writer = dirac_io::ParquetObserver::create(path, info, dirac_io::Options::new())
        .map_err(|e| e.to_string())?;
    let result = span!(integ.run(start), request, cancel, observe(writer.observer()) => stream);
    let path = writer.finish_with(&result).map_err(|e| e.to_string())?;
    Ok(match result {
        Ok(summary) => Ok((summary.step_count, summary.t, path)),
        Err(e) => Err((e.source, path)),
    })
}

/// What `write` returns: `steps`, `t` and `path`; or the `StepError` of the failed step with
/// `step`, `residual` and `path`; or the interrupt that ended the run (Ctrl-C) with `steps`,
/// `t` and `path` of what was written.
pub(crate) fn written_dict(
    py: Python<'_>,
    written: Result<Written, String>,
    interrupt: Option<PyErr>,
) -> PyResult<Bound<'_, PyDict>> {
    let written = match (written, interrupt) {
        (Err(why), None) => return Err(PyValueError::new_err(why)),
        (Err(_), Some(interrupt)) => return Err(interrupt),
        (Ok(Ok((steps, t, path))), Some(interrupt)) => {
            let value = interrupt.value(py);
            value.setattr("steps", steps)?;
            value.setattr("t", t)?;
            value.setattr("path", path)?;
            return Err(interrupt);
        }
        (Ok(Err((_, path))), Some(interrupt)) => {
            interrupt.value(py).setattr("path", path)?;
            return Err(interrupt);
        }
        (Ok(written), None) => written,
    };
    match written {
        Ok((steps, t, path)) => {
            let d = PyDict::new(py);
            d.set_item("steps", steps)?;
            d.set_item("t", t)?;
            d.set_item("path", path)?;
            Ok(d)
        }
        Err((error, path)) => {
            let err = exception_of(
                py,
                &error,
                format!(
                    "{error}; the states before it are written to {}",
                    path.display()
                ),
            )?;
            let value = err.value(py);
            value.setattr("step", error.step())?;
            value.setattr("residual", error.residual())?;
            value.setattr("path", path)?;
            Err(err)
        }
    }
}
