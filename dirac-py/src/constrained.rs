//! Systems on vector spaces with holonomic or nonholonomic constraints, from Python: the same
//! `System.run` as without them, stepped by the constrained integrators (RATTLE form: a
//! position step, then a projection), unreduced on `(q, p)` or reduced on either side on
//! `(x, w, μ, g)`, and the multipliers and constraint residuals of every step beside the states.
//!
//! The integrators take the dimensions and the number of constraints as type parameters; the
//! module has an instance per `(S, K, M)` with at most one group coordinate, `S + K ≤ 6` and
//! `M ≤ 3` (`dirac_jit::with_constrained_dimensions`), which runs, writes and ensembles of those
//! sizes take (bit for bit as the integrators compiled in); larger constrained systems run on
//! their element view (`sizes`).

use std::sync::atomic::AtomicBool;
use std::sync::Arc;

use dirac_jit::Code;
use dirac_runtime::{
    ConstrainedIntegrator, ConstrainedTrajectory, Drive, Form, ReducedConstrainedIntegrator,
    ReducedState, UnreducedState, Variant,
};

use crate::calls::span;
use crate::ensemble::Member;
use crate::inputs::{reduced_start, unreduced_start};
use crate::parquet::{to_parquet, Written};
use crate::results::{finish, parts, reduced_flat, unreduced_flat, with_momenta_of, Failed, Flat};
use dirac_jit::RunRequest;

pub(crate) use dirac_jit::with_constrained_dimensions as with_constrained;

/// The states of a constrained run, flattened, with each step's multipliers `λ_k` and
/// constraint residual.
fn with_multipliers<St, const M: usize>(
    t: &ConstrainedTrajectory<St, M>,
    states: impl Fn(&ConstrainedTrajectory<St, M>) -> Flat,
) -> Flat {
    let mut flat = states(t);
    flat.multipliers = Some((
        M,
        t.records
            .iter()
            .flat_map(|s| s.lambda.iter().copied())
            .collect(),
        t.records.iter().map(|s| s.constraint_residual).collect(),
    ));
    flat
}

/// One run of a constrained system of `S` shape and `K` group coordinates and `M` constraints.
pub(crate) fn run_constrained<
    const S: usize,
    const K: usize,
    const N: usize,
    const M: usize,
    const Z: usize,
>(
    code: &Arc<Code>,
    params: &[f64],
    start: &[Vec<f64>],
    r: RunRequest,
    cancel: &AtomicBool,
) -> Result<Result<Flat, Box<Failed>>, String> {
    let sys = code
        .instantiate_constrained::<S, K, N, M, Z>(params)
        .map_err(|e| e.to_string())?;
    let o = r.newton;
    Ok(match (r.equations.form, r.equations.side) {
        (Form::Unreduced, _) => {
            let s0: UnreducedState<N> = unreduced_start(start);
            let integ = ConstrainedIntegrator::new(sys, o);
            finish(span!(integ.run(s0), r, cancel => collect), |t| {
                with_multipliers(t, |t| unreduced_flat(parts!(t)))
            })
        }
        (Form::Reduced, side) => {
            let s0: ReducedState<S, K> = reduced_start(start);
            let momenta = sys.clone();
            let result = if side == Variant::Plus {
                let integ = ReducedConstrainedIntegrator::plus(sys, o);
                finish(span!(integ.run(s0), r, cancel => collect), |t| {
                    with_multipliers(t, |t| reduced_flat(parts!(t)))
                })
            } else {
                let integ = ReducedConstrainedIntegrator::minus(sys, o);
                finish(span!(integ.run(s0), r, cancel => collect), |t| {
                    with_multipliers(t, |t| reduced_flat(parts!(t)))
                })
            };
            with_momenta_of(&momenta, result)
        }
    })
}

/// An ensemble of a constrained system of `S` shape and `K` group coordinates and `M`
/// constraints (order 2), one member per start, on all cores: each member the run
/// [`run_constrained`] takes from its start, bit for bit.
pub(crate) fn run_many_constrained<
    const S: usize,
    const K: usize,
    const N: usize,
    const M: usize,
    const Z: usize,
>(
    code: &Arc<Code>,
    params: &[f64],
    starts: &[Vec<Vec<f64>>],
    r: RunRequest,
    cancel: &AtomicBool,
) -> Result<Vec<Member<Flat>>, String> {
    let sys = code
        .instantiate_constrained::<S, K, N, M, Z>(params)
        .map_err(|e| e.to_string())?;
    let o = r.newton;
    Ok(match (r.equations.form, r.equations.side) {
        (Form::Unreduced, _) => {
            let s0: Vec<UnreducedState<N>> = starts.iter().map(|s| unreduced_start(s)).collect();
            let integ = ConstrainedIntegrator::new(sys, o);
            span!(integ.ensemble(&s0), r, cancel => collect)
                .into_iter()
                .map(|m| finish(m, |t| with_multipliers(t, |t| unreduced_flat(parts!(t)))))
                .collect()
        }
        (Form::Reduced, side) => {
            let s0: Vec<ReducedState<S, K>> = starts.iter().map(|s| reduced_start(s)).collect();
            let momenta = sys.clone();
            let flat = |t: &ConstrainedTrajectory<ReducedState<S, K>, M>| {
                with_multipliers(t, |t| reduced_flat(parts!(t)))
            };
            let members: Vec<Member<Flat>> = if side == Variant::Plus {
                let integ = ReducedConstrainedIntegrator::plus(sys, o);
                span!(integ.ensemble(&s0), r, cancel => collect)
                    .into_iter()
                    .map(|m| finish(m, flat))
                    .collect()
            } else {
                let integ = ReducedConstrainedIntegrator::minus(sys, o);
                span!(integ.ensemble(&s0), r, cancel => collect)
                    .into_iter()
                    .map(|m| finish(m, flat))
                    .collect()
            };
            members
                .into_iter()
                .map(|m| with_momenta_of(&momenta, m))
                .collect()
        }
    })
}

/// One constrained run written to Parquet at `path` (the states; the multipliers are not
/// columns).
pub(crate) fn write_constrained<
    const S: usize,
    const K: usize,
    const N: usize,
    const M: usize,
    const Z: usize,
>(
    code: &Arc<Code>,
    params: &[f64],
    start: &[Vec<f64>],
    r: RunRequest,
    path: &std::path::Path,
    cancel: &AtomicBool,
) -> Result<Written, String> {
    let sys = code
        .instantiate_constrained::<S, K, N, M, Z>(params)
        .map_err(|e| e.to_string())?;
    let o = r.newton;
    // The start of the equations' form, and their side.
    let (unreduced, reduced) = (
        || -> UnreducedState<N> { unreduced_start(start) },
        || -> ReducedState<S, K> { reduced_start(start) },
    );
    Ok(match (r.equations.form, r.equations.side) {
        (Form::Unreduced, _) => {
            let integ = ConstrainedIntegrator::new(sys, o);
            to_parquet(&integ, unreduced(), &r, path, cancel)?
        }
        (Form::Reduced, Variant::Plus) => {
            let integ = ReducedConstrainedIntegrator::plus(sys, o);
            to_parquet(&integ, reduced(), &r, path, cancel)?
        }
        (Form::Reduced, Variant::Minus) => {
            let integ = ReducedConstrainedIntegrator::minus(sys, o);
            to_parquet(&integ, reduced(), &r, path, cancel)?
        }
    })
}
