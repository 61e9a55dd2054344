//! The continuous Lagrangian behind a discrete one: when the attribute is
//! given `L(q, v)` and a quadrature rule, it also emits the Legendre map `p = ∂L/∂v`, its
//! Jacobian `∂²L/∂v²` and the energy `E(q, v) = ⟨∂L/∂v, v⟩ − L` as straight-line code, and
//! implements [`ContinuousLagrangian`]. This module turns positions and velocities into the
//! integrators' initial states and reports the continuous energy along a trajectory.

use nalgebra::{SMatrix, SVector};

use crate::error::StepError;
use crate::linalg::{checked_rcond, LinearSolver};
use crate::newton::{self, inf_norm, NewtonFailure, NewtonOptions};
use crate::reduced::Trajectory;
use crate::state::{IntoVector, ReducedState, UnreducedState};
use crate::stepper::step_between as step;
use crate::system::DiscreteLagrangian;
use crate::unreduced::UnreducedTrajectory;

/// Solving the Legendre map `∂L/∂v (q, v) = p` for `v` failed.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum LegendreError {
    /// `∂²L/∂v²` is singular: the Lagrangian is degenerate (e.g. linear in the velocities), so
    /// the momentum does not determine the velocity.
    #[error("singular Legendre map at node {node}: ∂²L/∂v² has no inverse (a degenerate Lagrangian; the momentum does not determine the velocity)")]
    Singular {
        /// The trajectory node.
        node: usize,
    },
    /// Newton's method did not reach the tolerance.
    #[error("Legendre map at node {node}: no velocity found (residual {residual:.3e} after {iterations} iterations)")]
    NotConverged {
        /// The trajectory node.
        node: usize,
        /// `|∂L/∂v (q, v) − p|∞` at the last iterate.
        residual: f64,
        /// Newton iterations taken.
        iterations: usize,
    },
}

/// A Lagrangian `L(q, v)` on `TQ`, with its Legendre map and energy, emitted by the attribute for
/// a continuous Lagrangian (`fn l(q: Config, v: Velocity, ...)` with `rule = ...`).
pub trait ContinuousLagrangian<const N: usize> {
    /// The quadrature rule that forms `L_d` from `L`, e.g. "the midpoint rule L_d(q0, q1) =
    /// h L((q0 + q1)/2, (q1 − q0)/h)".
    const RULE: &'static str;

    /// `L(q, v)`.
    fn continuous_lagrangian(&self, q: &SVector<f64, N>, v: &SVector<f64, N>) -> f64;

    /// The Legendre map `p = ∂L/∂v (q, v)` (eq. (2.3) of the continuous theory, `FL`).
    fn legendre(&self, q: &SVector<f64, N>, v: &SVector<f64, N>) -> SVector<f64, N>;

    /// The linear algebra of the inverse Legendre map: dense [`crate::Lu`] for small systems, the sparse
    /// backend on the compile-time pattern of `∂²L/∂v²` above [`crate::DENSE_MAX`] (see
    /// [`crate::Reduced::Linear`]).
    type LegendreLinear: LinearSolver<Vector = SVector<f64, N>>;

    /// A workspace for [`Self::LegendreLinear`].
    fn legendre_solver(&self) -> Self::LegendreLinear;

    /// `∂L/∂v` and its Jacobian `∂²L/∂v²`, one straight line.
    fn legendre_jacobian(
        &self,
        q: &SVector<f64, N>,
        v: &SVector<f64, N>,
    ) -> (
        SVector<f64, N>,
        <Self::LegendreLinear as LinearSolver>::Matrix,
    );

    /// The energy `E(q, v) = ⟨∂L/∂v, v⟩ − L(q, v)`.
    fn energy(&self, q: &SVector<f64, N>, v: &SVector<f64, N>) -> f64;

    /// The unreduced state `(q, ∂L/∂v (q, v))` from a position and a velocity (arrays or
    /// nalgebra vectors): the one way to start a run from them, for every system with a
    /// continuous Lagrangian. For a degenerate Lagrangian this is the point of the primary
    /// constraint `p = ∂L/∂v` over `q`.
    ///
    /// `q` and `v` list the system's own coordinates in the order of
    /// [`DiscreteLagrangian::SHAPE`] followed by [`DiscreteLagrangian::GROUP`]: for a system with a declared
    /// translation (`coordinates(..), translate(..)`) these are the *adapted* coordinates
    /// `(x, g)` of [`crate::adapted`], not the user's; convert user coordinates first with
    /// [`crate::AdaptedCoordinates::to_adapted`] (velocities transform like positions).
    ///
    /// With adaptive steps (`time(t), adapt = |q| g`, [`crate::adaptive`]) `q` is the physical
    /// position (its time coordinate the physical time) and `v` the *physical* velocity (the
    /// time coordinate's entry is ignored: its rate is 1); the state is put on the level set
    /// `p_t = −E(q, v)` where the transformed system's solutions are the physical ones: the
    /// momenta of `L₂` at the velocity in fictitious time `g(x) v`, with `t' = g(x)`
    /// ([`fictitious_velocity`]).
    ///
    /// `Err` with [`StepError::InvalidMonitor`] where the monitor of a system with adaptive
    /// steps is not positive and finite at `q`, and [`StepError::NonFinite`] for a position or
    /// a momentum that is not finite.
    fn unreduced_state<const S: usize, const K: usize>(
        &self,
        q: impl IntoVector<SVector<f64, N>>,
        v: impl IntoVector<SVector<f64, N>>,
    ) -> Result<UnreducedState<N>, StepError>
    where
        Self: Sized + DiscreteLagrangian<S, K, N>,
    {
        let (q, mut v) = (q.into_vector(), v.into_vector());
        if self.time_index().is_some() {
            v = fictitious_velocity(self, &q, &v)?;
        }
        let p = self.legendre(&q, &v);
        if !q.iter().chain(p.iter()).all(|x| x.is_finite()) {
            return Err(StepError::NonFinite {
                step: 0,
                what: "the state from a position and velocity (the position or ∂L/∂v)",
                residual: f64::NAN,
            });
        }
        Ok(UnreducedState { q, p })
    }

    /// The reduced state `(x, w, μ, g)` from a position and a velocity: the unreduced state of
    /// [`Self::unreduced_state`] (the same coordinates, the same adaptive level set, the same
    /// errors) trivialized by eq. (3.6).
    fn reduced_state<const S: usize, const K: usize>(
        &self,
        q: impl IntoVector<SVector<f64, N>>,
        v: impl IntoVector<SVector<f64, N>>,
    ) -> Result<ReducedState<S, K>, StepError>
    where
        Self: Sized + DiscreteLagrangian<S, K, N>,
    {
        Ok(self.trivialize(&self.unreduced_state(q, v)?))
    }

    /// Solves the Legendre map `∂L/∂v (q, v) = p` for `v` (the inverse Legendre map) by the
    /// Newton driver of the steps, from `guess`, with the default [`NewtonOptions`] (`node`
    /// labels errors). See [`Self::velocity_with`].
    fn velocity(
        &self,
        node: usize,
        q: &SVector<f64, N>,
        p: &SVector<f64, N>,
        guess: SVector<f64, N>,
    ) -> Result<SVector<f64, N>, LegendreError> {
        self.velocity_with(node, q, p, guess, &NewtonOptions::default())
    }

    /// [`Self::velocity`] with the given options: the residual `∂L/∂v (q, v) − p` is accepted at
    /// `abs_tol + rel_tol ‖p‖∞` (or on a correction below `rel_tol`, see [`NewtonOptions`]), and
    /// `∂²L/∂v²` is checked as a step Jacobian is, with [`checked_rcond`] against `min_rcond`.
    ///
    /// The conditioning is checked even when the guess already solves the map: for a degenerate
    /// Lagrangian every velocity satisfies the Legendre map at a momentum on the primary
    /// constraint, so a small residual proves nothing; `∂²L/∂v²` is singular there in exact
    /// arithmetic (in floating point the rounded Hessian can keep a tiny pivot, which the
    /// reciprocal condition figure catches). Errors: [`LegendreError::Singular`] for a
    /// degenerate Lagrangian (a zero pivot or a condition figure below `min_rcond`),
    /// [`LegendreError::NotConverged`] otherwise.
    fn velocity_with(
        &self,
        node: usize,
        q: &SVector<f64, N>,
        p: &SVector<f64, N>,
        guess: SVector<f64, N>,
        options: &NewtonOptions,
    ) -> Result<SVector<f64, N>, LegendreError> {
        let mut solver = self.legendre_solver();
        let solution = newton::solve_with(
            &mut solver,
            guess,
            inf_norm(p),
            options,
            |v| self.legendre(q, v) - p,
            |v| {
                let (pv, jacobian) = self.legendre_jacobian(q, v);
                (pv - p, jacobian)
            },
        )
        .map_err(|failure| match failure {
            NewtonFailure::NotConverged {
                iterations,
                residual,
            } => LegendreError::NotConverged {
                node,
                residual,
                iterations,
            },
            NewtonFailure::NonFinite { residual } => LegendreError::NotConverged {
                node,
                residual,
                iterations: 0,
            },
            _ => LegendreError::Singular { node },
        })?;
        if solution.rcond.is_none() {
            // The guess solved the map without a factorization: check ∂²L/∂v² there.
            let (_, jacobian) = self.legendre_jacobian(q, &solution.z);
            if solver.factor(&jacobian).is_err()
                || checked_rcond(&mut solver, options.min_rcond) < options.min_rcond
            {
                return Err(LegendreError::Singular { node });
            }
        }
        Ok(solution.z)
    }
}

/// The continuous energy along a trajectory.
#[derive(Clone, Debug, PartialEq)]
pub struct ContinuousEnergies {
    /// `E(q_k, v_k)` at each node, with `v_k` solving the Legendre map `∂L/∂v (q_k, v_k) = p_k`
    /// for the discrete momentum `p_k` (so the node values need a regular Lagrangian).
    pub nodes: Vec<f64>,
    /// `E((q_k + q_{k+1})/2, (q_{k+1} − q_k)/h)` at each step's midpoint.
    pub midpoints: Vec<f64>,
}

/// The energy at each step's midpoint, `E((q_k + q_{k+1})/2, (q_{k+1} − q_k)/h)`. Needs only the
/// positions, so it is defined for degenerate Lagrangians too.
pub fn midpoint_energies<L, const N: usize>(sys: &L, q: &[SVector<f64, N>], h: f64) -> Vec<f64>
where
    L: ContinuousLagrangian<N>,
{
    unreduced_midpoints(sys, q, &[], h)
}

/// The continuous energy of an unreduced trajectory at its nodes (from the discrete momenta) and
/// at its midpoints; [`UnreducedIntegrator::energies`](crate::UnreducedIntegrator::energies)
/// and the other integrators' `energies` call it. Newton for each node's velocity starts from
/// the adjacent difference quotient.
pub fn continuous_energies<L, const N: usize>(
    sys: &L,
    trajectory: &UnreducedTrajectory<N>,
) -> Result<ContinuousEnergies, LegendreError>
where
    L: ContinuousLagrangian<N>,
{
    unreduced_energies(sys, &trajectory.states, &trajectory.times, trajectory.h)
}

/// [`continuous_energies`] of a reduced trajectory, mapped back to `T*Q` by eq. (3.7).
pub fn reduced_continuous_energies<L, const S: usize, const K: usize, const N: usize>(
    sys: &L,
    trajectory: &Trajectory<S, K>,
) -> Result<ContinuousEnergies, LegendreError>
where
    L: ContinuousLagrangian<N> + DiscreteLagrangian<S, K, N>,
{
    let unreduced: Vec<UnreducedState<N>> = trajectory
        .states
        .iter()
        .map(|s| sys.untrivialize(s))
        .collect();
    unreduced_energies(sys, &unreduced, &trajectory.times, trajectory.h)
}

/// The node and midpoint energies of `states` at `times` (step `k` of size `t_{k+1} − t_k`;
/// `h` where a hand-built trajectory has no times).
pub(crate) fn unreduced_energies<L, const N: usize>(
    sys: &L,
    states: &[UnreducedState<N>],
    times: &[f64],
    h: f64,
) -> Result<ContinuousEnergies, LegendreError>
where
    L: ContinuousLagrangian<N>,
{
    let q: Vec<SVector<f64, N>> = states.iter().map(|s| s.q).collect();
    let mut nodes = Vec::with_capacity(q.len());
    for k in 0..q.len() {
        let guess = match (k.checked_sub(1), q.get(k + 1)) {
            (_, Some(next)) => (next - q[k]) / step(times, k, h),
            (Some(prev), None) => (q[k] - q[prev]) / step(times, prev, h),
            (None, None) => SVector::zeros(),
        };
        let v = sys.velocity(k, &q[k], &states[k].p, guess)?;
        nodes.push(sys.energy(&q[k], &v));
    }
    Ok(ContinuousEnergies {
        nodes,
        midpoints: unreduced_midpoints(sys, &q, times, h),
    })
}

/// The midpoint energies of the configurations `q` at `times`: step `k` uses its own size.
pub(crate) fn unreduced_midpoints<L, const N: usize>(
    sys: &L,
    q: &[SVector<f64, N>],
    times: &[f64],
    h: f64,
) -> Vec<f64>
where
    L: ContinuousLagrangian<N>,
{
    q.windows(2)
        .enumerate()
        .map(|(k, w)| sys.energy(&(0.5 * (w[0] + w[1])), &((w[1] - w[0]) / step(times, k, h))))
        .collect()
}

/// The velocity in fictitious time of a physical velocity `u` at `q`: `v = g(x) u`, with the
/// time coordinate's rate set to `g(x)` (its physical rate is 1). `Err` for a monitor that is
/// not positive and finite at `q`, or a system without adaptive steps.
pub fn fictitious_velocity<L, const S: usize, const K: usize, const N: usize>(
    sys: &L,
    q: &SVector<f64, N>,
    u: &SVector<f64, N>,
) -> Result<SVector<f64, N>, StepError>
where
    L: DiscreteLagrangian<S, K, N>,
{
    let (Some(j), Some(g)) = (
        sys.time_index(),
        sys.monitor(&q.fixed_rows::<S>(0).into_owned()),
    ) else {
        return Err(StepError::Unsupported {
            what: "a fictitious velocity: the system is not declared with `time(t), adapt = |q| g`",
        });
    };
    crate::stepper::check_monitor(0, g)?;
    let mut v = u * g;
    v[S + j] = g;
    Ok(v)
}

/// What a stage `(Q_i, V_i)` of a Gauss–Legendre step reads, with its Jacobians
/// ([`StageDerivatives::stage_jacobian`]): the force `f = ∂L/∂q + F(q, v)` (the Lagrangian's
/// and the declared forces'), the momentum `p = ∂L/∂v`, and their derivatives in `q` and `v`.
///
/// Laid out as its fields in order (`repr(C)`, each vector and column-major matrix a run of
/// `f64`s), the layout in which machine code compiled at run time writes it.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C)]
pub struct StageJacobian<const N: usize> {
    /// `f = ∂L/∂q + F`.
    pub f: SVector<f64, N>,
    /// `p = ∂L/∂v`.
    pub p: SVector<f64, N>,
    /// `∂f/∂q`.
    pub f_q: SMatrix<f64, N, N>,
    /// `∂f/∂v`.
    pub f_v: SMatrix<f64, N, N>,
    /// `∂p/∂q`.
    pub p_q: SMatrix<f64, N, N>,
    /// `∂p/∂v = ∂²L/∂v²`.
    pub p_v: SMatrix<f64, N, N>,
}

impl<const N: usize> Default for StageJacobian<N> {
    fn default() -> Self {
        Self {
            f: SVector::zeros(),
            p: SVector::zeros(),
            f_q: SMatrix::zeros(),
            f_v: SMatrix::zeros(),
            p_q: SMatrix::zeros(),
            p_v: SMatrix::zeros(),
        }
    }
}

/// The stage derivatives of a continuous Lagrangian, emitted by the attribute as straight-line
/// code for a system with `L(q, v)` and a rule on the dense backend (at most
/// [`crate::DENSE_MAX`] coordinates) without constraints: what the Gauss–Legendre integrators
/// of any order ([`crate::gauss`]) evaluate at their stages.
pub trait StageDerivatives<const N: usize>: ContinuousLagrangian<N> {
    /// `(f, p)` at `(q, v)`: the force `∂L/∂q + F(q, v)` and the momentum `∂L/∂v`.
    fn stage(&self, q: &SVector<f64, N>, v: &SVector<f64, N>)
        -> (SVector<f64, N>, SVector<f64, N>);

    /// `f`, `p` and their Jacobians in `q` and `v` at `(q, v)`, one straight line.
    fn stage_jacobian(&self, q: &SVector<f64, N>, v: &SVector<f64, N>) -> StageJacobian<N>;
}
