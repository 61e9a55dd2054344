//! Runs written to Apache Parquet: a run streamed into the workspace's writer, ended early by
//! Ctrl-C, and what `write` returns to Python (or raises) once it has ended.

use std::sync::atomic::AtomicBool;

use dirac_jit::run::{Finish, Job};
use dirac_jit::RunRequest;
use dirac_runtime::{StepError as RuntimeStepError, StepStats};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::calls::until;
use crate::results::exception_of;

/// What a run written to Parquet ended with: its steps, its final time and the path; or the
/// failed step's error, the states before it on disk.
pub(crate) type Written =
    Result<(usize, f64, std::path::PathBuf), (RuntimeStepError, std::path::PathBuf)>;

/// A run streamed into Parquet at `path` by the workspace's writer (the run's observer,
/// [`dirac_io::ParquetObserver`]): the run its request asks (its steps, end time, schedule and
/// Newton's options), ended after the step in progress once `cancel` is set (the file then holds
/// the states so far, its outcome "stopped"). What every class's `write` hands the integrator
/// its request chose to (`dirac_jit::run`).
#[derive(Clone, Copy)]
pub(crate) struct ToParquet<'a> {
    pub(crate) path: &'a std::path::Path,
    pub(crate) cancel: &'a AtomicBool,
}

impl Job for ToParquet<'_> {
    /// What the run ended with, as [`Written`]; the writer's own failure is the `Err`.
    type Output = Result<Written, String>;
}

impl<I> Finish<I> for ToParquet<'_>
where
    I: dirac_io::Describe + dirac_runtime::Drive,
    I::State: dirac_io::StateColumns,
    I::Record: AsRef<StepStats>,
{
    fn finish(self, integ: I, starts: Vec<I::State>, request: &RunRequest) -> Self::Output {
        let start = starts.into_iter().next().ok_or("a run needs its start")?;
        let info = integ.describe().with_newton(&request.newton);
        let mut writer =
            dirac_io::ParquetObserver::create(self.path, info, dirac_io::Options::new())
                .map_err(|e| e.to_string())?;
        let result = dirac_jit::span!(
            integ.run(start),
            request,
            stop(until(self.cancel)),
            observe(writer.observer()) => stream
        );
        let path = writer.finish_with(&result).map_err(|e| e.to_string())?;
        Ok(match result {
            Ok(summary) => Ok((summary.step_count, summary.t, path)),
            Err(e) => Err((e.source, path)),
        })
    }
}

/// What a run written by [`ToParquet`] ended with: the system, request or start refused is the
/// `Err`, as the writer's own failure is.
pub(crate) fn written(
    run: Result<Result<Written, String>, dirac_jit::Error>,
) -> Result<Written, String> {
    run.map_err(|e| e.to_string())?
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
