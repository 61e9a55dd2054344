//! Systems on vector spaces with holonomic or nonholonomic constraints, from Python: the same
//! `System.run` as without them, stepped by the constrained integrators (RATTLE form: a
//! position step, then a projection), unreduced on `(q, p)` or reduced on either side on
//! `(x, w, μ, g)`, and the multipliers and constraint residuals of every step beside the states.
//!
//! The integrators take the dimensions and the number of constraints as type parameters; the
//! module has an instance per `(S, K, M)` with at most one group coordinate, `S + K ≤ 6` and
//! `M ≤ 3` ([`with_constrained!`]).

use std::sync::Arc;

use dirac_jit::Code;
use dirac_runtime::{
    ConstrainedIntegrator, ConstrainedTrajectory, Drive, ReducedConstrainedIntegrator,
    ReducedState, UnreducedState,
};

use crate::{finish, parts, reduced_flat, reduced_start, unreduced_flat, unreduced_start};
use crate::{Failed, Flat, Method, Request};

/// The most constraints, coordinates and group coordinates of a constrained system the module
/// has integrators for.
pub(crate) const MAX: (usize, usize, usize) = (3, 6, 1);

/// Calls `f::<S, K, N, M, Z>(args)` for a system's `(S, K, M)`, `N = S + K`, `Z = N + M`.
macro_rules! with_constrained {
    ($s:expr, $k:expr, $m:expr, $f:ident $args:tt) => {
        $crate::constrained::with_constrained!(@arms ($s, $k, $m), $f $args;
            (1,0,1) (2,0,1) (3,0,1) (4,0,1) (5,0,1) (6,0,1)
            (0,1,1) (1,1,1) (2,1,1) (3,1,1) (4,1,1) (5,1,1)
            (1,0,2) (2,0,2) (3,0,2) (4,0,2) (5,0,2) (6,0,2)
            (0,1,2) (1,1,2) (2,1,2) (3,1,2) (4,1,2) (5,1,2)
            (1,0,3) (2,0,3) (3,0,3) (4,0,3) (5,0,3) (6,0,3)
            (0,1,3) (1,1,3) (2,1,3) (3,1,3) (4,1,3) (5,1,3))
    };
    (@arms $skm:expr, $f:ident $args:tt; $(($s:literal, $k:literal, $m:literal))*) => {
        match $skm {
            $(($s, $k, $m) => $f::<$s, $k, { $s + $k }, $m, { $s + $k + $m }> $args,)*
            (s, k, m) => ::core::result::Result::Err(::std::format!(
                "{s} shape and {k} group coordinates with {m} constraints: the Python module integrates constrained systems of at most {} coordinates, {} of them group coordinates, and {} constraints",
                $crate::constrained::MAX.1,
                $crate::constrained::MAX.2,
                $crate::constrained::MAX.0
            )),
        }
    };
}

pub(crate) use with_constrained;

/// The states of a constrained run, flattened, with each step's multipliers `λ_k` and
/// constraint residual.
fn with_multipliers<St, const M: usize>(
    t: &ConstrainedTrajectory<St, M>,
    states: impl Fn(&ConstrainedTrajectory<St, M>) -> Flat,
) -> Flat {
    let mut flat = states(t);
    flat.multipliers = Some((
        M,
        t.steps
            .iter()
            .flat_map(|s| s.lambda.iter().copied())
            .collect(),
        t.steps.iter().map(|s| s.constraint_residual).collect(),
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
    r: Request,
) -> Result<Result<Flat, Box<Failed>>, String> {
    let sys = code
        .instantiate_constrained::<S, K, N, M, Z>(params)
        .map_err(|e| e.to_string())?;
    let (n, o) = (r.steps, r.options);
    Ok(match r.method {
        Method::Unreduced => {
            let s0: UnreducedState<N> = unreduced_start(start);
            let integ = ConstrainedIntegrator::new(sys, o);
            finish(integ.run(s0).steps(n).collect(), |t| {
                with_multipliers(t, |t| unreduced_flat(parts!(t)))
            })
        }
        side => {
            let s0: ReducedState<S, K> = reduced_start(start);
            if side == Method::Plus {
                let integ = ReducedConstrainedIntegrator::plus(sys, o);
                finish(integ.run(s0).steps(n).collect(), |t| {
                    with_multipliers(t, |t| reduced_flat(parts!(t)))
                })
            } else {
                let integ = ReducedConstrainedIntegrator::minus(sys, o);
                finish(integ.run(s0).steps(n).collect(), |t| {
                    with_multipliers(t, |t| reduced_flat(parts!(t)))
                })
            }
        }
    })
}
