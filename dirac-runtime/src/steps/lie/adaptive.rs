//! Adaptive steps on rotation groups (`time(t), adapt = |q| g` with a continuous Lagrangian on
//! rotations, directions and scalars; see [`crate::adaptive`]): the time transformation is the
//! compiler's, so a step is an ordinary step of the transformed discrete Lagrangian; what the
//! integrators add is a run's first guess and the checks after each step.

use nalgebra::allocator::Allocator;
use nalgebra::{DMatrix, DVector, DefaultAllocator, Dim, OVector};

use super::integrator::StepEquations;
use super::{blocks, LieModel};
use crate::stepper::check_monitor;

/// Newton's guess for the chart coordinate `z` of a run's first step of fictitious size `h`
/// from `(q, p)`, written into `z`: the time coordinate's entry `h g(q)` (the step's physical
/// size on the level set, where `t' = g`), the others solving the step's own equations with it
/// held — the discrete Legendre transform at the physical step `Δt = h g` — by Newton iterations
/// with a difference-quotient Jacobian (a guess, once per run). Starting from no motion instead,
/// the transformed Lagrangian's `Δt L(q, ξ/Δt)` is singular at `Δt = 0`. No motion when the
/// monitor is not positive and finite (the run's checks report it).
pub(super) fn first_increment<L, P: Dim, N: Dim>(
    sys: &L,
    q: &OVector<f64, P>,
    p: &OVector<f64, N>,
    h: f64,
    equations: &StepEquations<L, P, N>,
    z: &mut OVector<f64, N>,
) where
    L: LieModel<P, N>,
    DefaultAllocator: Allocator<P> + Allocator<N>,
{
    z.fill(0.0);
    let (Some(time), Some(g)) = (sys.time_index(), sys.monitor(q)) else {
        return;
    };
    if check_monitor(0, g).is_err() {
        return;
    }
    let Some(at) = blocks(sys).nth(time).map(|b| b.chart) else {
        return;
    };
    z[at] = h * g;
    let n = z.len();
    let rows: Vec<usize> = (0..n).filter(|&i| i != at).collect();
    let scale = p.amax().max(1.0);
    let (mut r0, mut r1) = (z.clone(), z.clone());
    for _ in 0..8 {
        (equations.residual)(sys, q, p, z, &mut r0);
        if rows.iter().all(|&i| r0[i].abs() <= 1e-13 * scale) {
            break;
        }
        let mut jacobian = DMatrix::<f64>::zeros(rows.len(), rows.len());
        for (c, &i) in rows.iter().enumerate() {
            let step = 1e-7 * z[i].abs().max(h.abs() * g).max(f64::MIN_POSITIVE);
            let mut w = z.clone();
            w[i] += step;
            (equations.residual)(sys, q, p, &w, &mut r1);
            for (r, &k) in rows.iter().enumerate() {
                jacobian[(r, c)] = (r1[k] - r0[k]) / step;
            }
        }
        let rhs = DVector::from_iterator(rows.len(), rows.iter().map(|&k| r0[k]));
        let Some(delta) = jacobian.lu().solve(&rhs) else {
            break;
        };
        let mut next = z.clone();
        for (c, &i) in rows.iter().enumerate() {
            next[i] -= delta[c];
        }
        if !next.iter().all(|x| x.is_finite()) {
            break;
        }
        z.copy_from(&next);
    }
}

/// The physical time stored in the point `q` of a system with adaptive steps.
pub(super) fn time_of<L, P: Dim, N: Dim>(sys: &L, q: &OVector<f64, P>) -> Option<f64>
where
    L: LieModel<P, N>,
    DefaultAllocator: Allocator<P> + Allocator<N>,
{
    let time = sys.time_index()?;
    blocks(sys).nth(time).map(|b| q[b.point])
}
