//! The runs of systems on vector spaces without constraints, at dimensions `S`, `K`,
//! `N = S + K` (what `dirac_jit::with_dimensions` dispatches to): one run, one written to
//! Parquet, an ensemble, and the benchmark's bare run.

use std::sync::atomic::AtomicBool;
use std::sync::Arc;

use dirac_jit::{Code, JitSystem};
use dirac_runtime::nalgebra::SVector;
use dirac_runtime::{
    continuous_energies, DiscreteLagrangian, Drive, Equations, Form, ReducedIntegrator,
    ReducedState, System, UnreducedIntegrator, UnreducedState, UnreducedTrajectory, Variant,
};

use crate::calls::span;
use crate::inputs::{reduced_start, unreduced_start};
use crate::parquet::{to_parquet, Written};
use crate::results::by_order;
use crate::results::{finish, parts, reduced_flat, unreduced_flat, with_momenta_of, Failed, Flat};
use dirac_jit::RunRequest;

/// One run of a system of `S` shape and `K` group coordinates from `start` (`x, w, mu, g` or
/// `q, p`, by the method).
pub(crate) fn run_one<const S: usize, const K: usize, const N: usize>(
    code: &Arc<Code>,
    params: &[f64],
    start: &[Vec<f64>],
    r: RunRequest,
    energies: bool,
    cancel: &AtomicBool,
) -> Result<Result<Flat, Box<Failed>>, String> {
    let sys = code
        .instantiate::<S, K, N>(params)
        .map_err(|e| e.to_string())?;
    let o = r.newton;
    let energies = energies.then(|| sys.clone());
    let momenta = sys.clone();
    let result = match (r.equations.form, r.equations.side) {
        (Form::Unreduced, _) => {
            let s0 = unreduced_start(start);
            by_order!(UnreducedIntegrator::new(sys, o), s0, r, cancel, |t| {
                unreduced_flat(parts!(t))
            })
        }
        (Form::Reduced, side) => {
            let s0 = reduced_start(start);
            if side == Variant::Plus {
                by_order!(ReducedIntegrator::plus(sys, o), s0, r, cancel, |t| {
                    reduced_flat(parts!(t))
                })
            } else {
                by_order!(ReducedIntegrator::minus(sys, o), s0, r, cancel, |t| {
                    reduced_flat(parts!(t))
                })
            }
        }
    };
    let result = with_momenta_of(&momenta, result);
    Ok(match (energies, result) {
        (Some(sys), Ok(flat)) => Ok(with_energies(&sys, flat, r.equations)),
        (_, result) => result,
    })
}

/// `flat` with the continuous energies of its states (`ContinuousLagrangian`: the inverse
/// Legendre map at each node, the midpoint rule between), reduced states mapped back to
/// `(q, p)` by eq. (3.7).
fn with_energies<const S: usize, const K: usize, const N: usize>(
    sys: &JitSystem<S, K, N>,
    mut flat: Flat,
    method: Equations,
) -> Flat {
    let column = |name: &str| {
        flat.parts
            .iter()
            .find(|(n, _, _)| *n == name)
            .map_or(&[][..], |(_, _, data)| data.as_slice())
    };
    let rows = flat.t.len();
    let states: Vec<UnreducedState<N>> = (0..rows)
        .map(|k| match method.form {
            Form::Unreduced => UnreducedState {
                q: SVector::from_column_slice(&column("q")[k * N..(k + 1) * N]),
                p: SVector::from_column_slice(&column("p")[k * N..(k + 1) * N]),
            },
            Form::Reduced => sys.untrivialize(&ReducedState {
                x: SVector::from_column_slice(&column("x")[k * S..(k + 1) * S]),
                w: SVector::from_column_slice(&column("w")[k * S..(k + 1) * S]),
                mu: SVector::from_column_slice(&column("mu")[k * K..(k + 1) * K]),
                g: SVector::from_column_slice(&column("g")[k * K..(k + 1) * K]),
            }),
        })
        .collect();
    let trajectory = UnreducedTrajectory {
        h: sys.time_step(),
        states,
        times: flat.t.clone(),
        // Python's runs take the system's own step.
        step_sizes: vec![sys.time_step(); rows.saturating_sub(1)],
        stats: Vec::new(),
    };
    flat.energies = Some(
        continuous_energies(sys, &trajectory)
            .map(|e| (e.nodes, e.midpoints))
            .map_err(|e| e.to_string()),
    );
    flat
}

/// One run written to Parquet at `path` by the workspace's writer.
pub(crate) fn write_one<const S: usize, const K: usize, const N: usize>(
    code: &Arc<Code>,
    params: &[f64],
    start: &[Vec<f64>],
    r: RunRequest,
    path: &std::path::Path,
    cancel: &AtomicBool,
) -> Result<Written, String> {
    let sys = code
        .instantiate::<S, K, N>(params)
        .map_err(|e| e.to_string())?;
    let o = r.newton;
    Ok(match (r.equations.form, r.equations.side) {
        (Form::Unreduced, _) => {
            let s0 = unreduced_start(start);
            to_parquet(&UnreducedIntegrator::new(sys, o), s0, &r, path, cancel)?
        }
        (Form::Reduced, side) => {
            let s0 = reduced_start(start);
            if side == Variant::Plus {
                to_parquet(&ReducedIntegrator::plus(sys, o), s0, &r, path, cancel)?
            } else {
                to_parquet(&ReducedIntegrator::minus(sys, o), s0, &r, path, cancel)?
            }
        }
    })
}

/// Seconds of the reduced (+) run alone (collected, no arrays): the baseline of the Python
/// overhead benchmark (`dirac-py/examples/overhead.py`).
pub(crate) fn time_one<const S: usize, const K: usize, const N: usize>(
    code: &Arc<Code>,
    params: &[f64],
    start: &[Vec<f64>],
    r: RunRequest,
) -> Result<f64, String> {
    let sys = code
        .instantiate::<S, K, N>(params)
        .map_err(|e| e.to_string())?;
    let s0 = reduced_start(start);
    let t = std::time::Instant::now();
    let traj = ReducedIntegrator::plus(sys, r.newton)
        .run(s0)
        .steps(r.steps)
        .collect()
        .map_err(|e| e.to_string())?;
    let elapsed = t.elapsed().as_secs_f64();
    drop(traj);
    Ok(elapsed)
}

/// An ensemble: one run per start, on all cores.
pub(crate) fn run_many<const S: usize, const K: usize, const N: usize>(
    code: &Arc<Code>,
    params: &[f64],
    starts: &[Vec<Vec<f64>>],
    r: RunRequest,
    cancel: &AtomicBool,
) -> Result<Vec<Result<Flat, Box<Failed>>>, String> {
    let sys = code
        .instantiate::<S, K, N>(params)
        .map_err(|e| e.to_string())?;
    let o = r.newton;
    Ok(match (r.equations.form, r.equations.side) {
        (Form::Unreduced, _) => {
            let s0: Vec<_> = starts.iter().map(|s| unreduced_start(s)).collect();
            let integ = UnreducedIntegrator::new(sys, o);
            span!(integ.ensemble(&s0), r, cancel => collect)
                .into_iter()
                .map(|m| finish(m, |t| unreduced_flat(parts!(t))))
                .collect()
        }
        (Form::Reduced, side) => {
            let s0: Vec<_> = starts.iter().map(|s| reduced_start(s)).collect();
            let momenta = sys.clone();
            let members = if side == Variant::Plus {
                let integ = ReducedIntegrator::plus(sys, o);
                span!(integ.ensemble(&s0), r, cancel => collect)
            } else {
                let integ = ReducedIntegrator::minus(sys, o);
                span!(integ.ensemble(&s0), r, cancel => collect)
            };
            members
                .into_iter()
                .map(|m| with_momenta_of(&momenta, finish(m, |t| reduced_flat(parts!(t)))))
                .collect()
        }
    })
}
