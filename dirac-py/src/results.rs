//! What a run returns to Python: its trajectory flattened for NumPy (`Flat`, from the states of
//! any trajectory type), the dict of arrays made of it, and a failed or interrupted run's
//! exception (`StepError`, `dirac.OutOfMemoryError`, `KeyboardInterrupt`) carrying the
//! trajectory so far.

use dirac_runtime::nalgebra::SVector;
use dirac_runtime::{
    DiscreteLagrangian, IntegrationError, ReducedState, StepError as RuntimeStepError, StepStats,
    Steps, UnreducedState,
};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::calls;
use crate::{OutOfMemoryError, StepError};

/// A trajectory flattened for NumPy: the times and, per state, the vectors of the state in a
/// fixed order (`x, w, mu, g` reduced; `q, p` unreduced), with their lengths.
#[derive(Default)]
pub(crate) struct Flat {
    pub(crate) t: Vec<f64>,
    pub(crate) parts: Vec<(&'static str, usize, Vec<f64>)>,
    pub(crate) iterations: Vec<usize>,
    pub(crate) residuals: Vec<f64>,
    /// For a constrained run: the number of constraints, each step's multipliers `λ_k` and its
    /// constraint residual.
    pub(crate) multipliers: Option<(usize, Vec<f64>, Vec<f64>)>,
    /// When asked for: the continuous energy at each state (through the inverse Legendre map)
    /// and at each step's midpoint, or why there is none.
    pub(crate) energies: Option<Energies>,
}

/// The continuous energies of a run at its states and midpoints, or why there are none.
pub(crate) type Energies = Result<(Vec<f64>, Vec<f64>), String>;

/// A failed run: the runtime's error and what was computed before it (a [`Flat`] trajectory,
/// or another kind's).
pub(crate) struct Failed<F = Flat> {
    pub(crate) error: RuntimeStepError,
    pub(crate) partial: F,
}

pub(crate) fn reduced_flat<const S: usize, const K: usize>(
    (states, times, stats): (&[ReducedState<S, K>], &[f64], &[StepStats]),
) -> Flat {
    let rows = states.len();
    let (mut x, mut w) = (Vec::with_capacity(rows * S), Vec::with_capacity(rows * S));
    let (mut mu, mut g) = (Vec::with_capacity(rows * K), Vec::with_capacity(rows * K));
    for s in states {
        x.extend_from_slice(s.x.as_slice());
        w.extend_from_slice(s.w.as_slice());
        mu.extend_from_slice(s.mu.as_slice());
        g.extend_from_slice(s.g.as_slice());
    }
    Flat {
        t: times.to_vec(),
        parts: vec![("x", S, x), ("w", S, w), ("mu", K, mu), ("g", K, g)],
        iterations: stats.iter().map(|s| s.iterations).collect(),
        residuals: stats.iter().map(|s| s.residual).collect(),
        multipliers: None,
        energies: None,
    }
}

pub(crate) fn unreduced_flat<const N: usize>(
    (states, times, stats): (&[UnreducedState<N>], &[f64], &[StepStats]),
) -> Flat {
    Flat {
        t: times.to_vec(),
        parts: vec![
            (
                "q",
                N,
                states.iter().flat_map(|s| s.q.iter().copied()).collect(),
            ),
            (
                "p",
                N,
                states.iter().flat_map(|s| s.p.iter().copied()).collect(),
            ),
        ],
        iterations: stats.iter().map(|s| s.iterations).collect(),
        residuals: stats.iter().map(|s| s.residual).collect(),
        multipliers: None,
        energies: None,
    }
}

/// A run's result flattened by `flat`: the trajectory, or the error with the states before it.
pub(crate) fn finish<T: Steps + std::fmt::Debug, F>(
    result: Result<T, Box<IntegrationError<T>>>,
    flat: impl Fn(&T) -> F,
) -> Result<F, Box<Failed<F>>> {
    match result {
        Ok(traj) => Ok(flat(&traj)),
        Err(e) => Err(Box::new(Failed {
            partial: flat(&e.trajectory),
            error: e.source,
        })),
    }
}

/// `rows` rows of `names.len()` values each (row-major) as a dict by name of `(rows,)` arrays,
/// one per coordinate: the form every class's run returns a configuration or momentum in.
fn by_coordinate<'py>(
    py: Python<'py>,
    names: &[String],
    data: &[f64],
    rows: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let n = names.len();
    for (i, name) in names.iter().enumerate() {
        let column: Vec<f64> = (0..rows).map(|r| data[r * n + i]).collect();
        d.set_item(name, PyArray1::from_vec(py, column))?;
    }
    Ok(d)
}

/// The dict of a run of a system on vector spaces: `t`; `q` and `p`, dicts by coordinate
/// (`names`: the shape coordinates, then the group ones), the configuration and the momenta of
/// every state (of a reduced run, `x` and `g`, and `p` by eq. (3.7)); a reduced run's state `x,
/// w, mu, g` besides, as arrays (rows, length); per step `iterations` and `residuals`; the
/// multipliers and the energies when there are.
pub(crate) fn to_dict<'py>(
    py: Python<'py>,
    flat: Flat,
    names: &[String],
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let rows = flat.t.len();
    let part = |name: &str| {
        flat.parts
            .iter()
            .find(|(n, _, _)| *n == name)
            .map(|(_, len, data)| (*len, data.as_slice()))
    };
    let q: Vec<f64> = match (part("q"), part("x"), part("g")) {
        (Some((_, q)), _, _) => q.to_vec(),
        (None, Some((s, x)), Some((k, g))) => (0..rows)
            .flat_map(|r| x[r * s..(r + 1) * s].iter().chain(&g[r * k..(r + 1) * k]))
            .copied()
            .collect(),
        _ => Vec::new(),
    };
    d.set_item("t", PyArray1::from_vec(py, flat.t.clone()))?;
    d.set_item("q", by_coordinate(py, names, &q, rows)?)?;
    if let Some((_, p)) = part("p") {
        d.set_item("p", by_coordinate(py, names, p, rows)?)?;
    }
    for (name, len, data) in flat.parts {
        if name == "q" || name == "p" {
            continue;
        }
        let a = PyArray1::from_vec(py, data).reshape([rows, len])?;
        d.set_item(name, a)?;
    }
    d.set_item("iterations", PyArray1::from_vec(py, flat.iterations))?;
    d.set_item("residuals", PyArray1::from_vec(py, flat.residuals))?;
    if let Some((m, lambda, residual)) = flat.multipliers {
        let steps = residual.len();
        d.set_item(
            "multipliers",
            PyArray1::from_vec(py, lambda).reshape([steps, m])?,
        )?;
        d.set_item("constraint_residuals", PyArray1::from_vec(py, residual))?;
    }
    match flat.energies {
        None => {}
        Some(Ok((nodes, midpoints))) => {
            d.set_item("energy", PyArray1::from_vec(py, nodes))?;
            d.set_item("energy_midpoints", PyArray1::from_vec(py, midpoints))?;
        }
        Some(Err(why)) => return Err(PyValueError::new_err(format!("energies: {why}"))),
    }
    Ok(d)
}

/// A reduced run's states with their momenta `p = (w − Bᵀ μ, μ)`, eq. (3.7)
/// ([`DiscreteLagrangian::untrivialize`]), as the part `p`; an unreduced run's unchanged.
pub(crate) fn with_momenta<L, const S: usize, const K: usize, const N: usize>(
    sys: &L,
    mut flat: Flat,
) -> Flat
where
    L: DiscreteLagrangian<S, K, N>,
{
    let part = |name: &str| {
        flat.parts
            .iter()
            .find(|(n, _, _)| *n == name)
            .map(|(_, _, data)| data.as_slice())
    };
    let (Some(x), Some(w), Some(mu), Some(g)) = (part("x"), part("w"), part("mu"), part("g"))
    else {
        return flat;
    };
    let p: Vec<f64> = (0..flat.t.len())
        .flat_map(|k| {
            let state = ReducedState {
                x: SVector::from_column_slice(&x[k * S..(k + 1) * S]),
                w: SVector::from_column_slice(&w[k * S..(k + 1) * S]),
                mu: SVector::from_column_slice(&mu[k * K..(k + 1) * K]),
                g: SVector::from_column_slice(&g[k * K..(k + 1) * K]),
            };
            sys.untrivialize(&state)
                .p
                .iter()
                .copied()
                .collect::<Vec<_>>()
        })
        .collect();
    flat.parts.push(("p", N, p));
    flat
}

/// The `StepError` of a failed step: its message (prefixed by the member of an ensemble),
/// `step`, `residual`, `member` and `trajectory`, the dict of the states before it. A run
/// refused for its memory (the runtime's `OutOfMemory`) is a `dirac.OutOfMemoryError` with the
/// same attributes and `what` and `bytes`.
pub(crate) fn raise(
    py: Python<'_>,
    error: &RuntimeStepError,
    trajectory: Bound<'_, PyDict>,
    member: Option<usize>,
) -> PyResult<PyErr> {
    let message = match member {
        Some(m) => format!("member {m}: {error}"),
        None => error.to_string(),
    };
    let err = exception_of(py, error, message)?;
    let value = err.value(py);
    value.setattr("step", error.step())?;
    value.setattr("residual", error.residual())?;
    value.setattr("member", member)?;
    value.setattr("trajectory", trajectory)?;
    Ok(err)
}

/// The Python exception of the runtime's `error` with `message`: `dirac.OutOfMemoryError` (with
/// `what` and `bytes`) for a run refused for its memory, `dirac.StepError` for the others.
pub(crate) fn exception_of(
    py: Python<'_>,
    error: &RuntimeStepError,
    message: String,
) -> PyResult<PyErr> {
    Ok(match error {
        RuntimeStepError::OutOfMemory { what, bytes } => {
            let err = OutOfMemoryError::new_err(message);
            err.value(py).setattr("what", what)?;
            err.value(py).setattr("bytes", *bytes)?;
            err
        }
        _ => StepError::new_err(message),
    })
}

/// What a run returns to Python: the dict of its trajectory (`dict`); `StepError` with the
/// trajectory so far when a step failed; or, when Ctrl-C (or another signal handler) ended it
/// ([`calls::interruptible`]), that exception with the trajectory so far as `trajectory`.
pub(crate) fn finish_run<'py, F>(
    py: Python<'py>,
    result: Result<Result<F, Box<Failed<F>>>, String>,
    interrupt: Option<PyErr>,
    dict: impl Fn(F) -> PyResult<Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let result = match (result, interrupt) {
        (Err(why), None) => return Err(PyValueError::new_err(why)),
        (Err(_), Some(interrupt)) => return Err(interrupt),
        (Ok(run), Some(interrupt)) => {
            let partial = match run {
                Ok(flat) => flat,
                Err(failed) => failed.partial,
            };
            return Err(calls::interrupted(
                py,
                interrupt,
                "trajectory",
                dict(partial)?,
            ));
        }
        (Ok(run), None) => run,
    };
    match result {
        Ok(flat) => dict(flat),
        Err(failed) => {
            let Failed { error, partial } = *failed;
            Err(raise(py, &error, dict(partial)?, None)?)
        }
    }
}
