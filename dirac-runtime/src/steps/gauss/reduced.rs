//! The Gauss–Legendre step in the reduced coordinates `(x, w, μ, g)` of eq. (3.6), on either
//! side of the reduced equations.
//!
//! # Why the reduced step is the unreduced one, trivialized
//!
//! The Galerkin discrete Lagrangian of a Lagrangian that does not read the group coordinates
//! `g` (nor do its forces) is invariant under the translations, `L_d(x0, g0 + a, x1, g1 + a) =
//! L_d(x0, g0, x1, g1)`, since the translation moves the whole polynomial `q(·)` and every
//! stage with it. Its reduced Lagrangians are then (4.5) and (4.7),
//! `l_{d+}(x0, x1, u) = L_d(x0, 0, x1, u + h_d^0(x0, x1))` and `l_{d−}` the same with
//! `u = g_{k+1}^−`, and the reduced equations (4.6) / (4.8) are the discrete Lagrange–Dirac
//! equations of `L_d` read through the trivialization `w = p_x + Bᵀ p_g`, `μ = p_g`
//! (Theorems 4.6 and 4.9: the reduced and unreduced systems have the same solutions). In the
//! stage unknowns of the variational partitioned Runge–Kutta step this is explicit: the group
//! rows of `P_i = p0 + h Σ_j a_ij f_j` read `∂L/∂ġ(Q_i, V_i) = μ_k` at every stage (the
//! momentum equation, the reduced equations' last line), and `μ_{k+1} = μ_k + h Σ_j b_j · 0`.
//!
//! So a reduced step untrivializes `(x_k, w_k, μ_k)` at `g = 0` (eq. (3.7); the reduced
//! Lagrangians read `L_d` at `g_k = 0`), takes the Gauss step of [`GaussIntegrator`] from
//! there, and trivializes the result: `x_{k+1}`, `w_{k+1} = p_{x,k+1} + Bᵀ μ_{k+1}`, and
//! `μ_{k+1} = μ_k` bit for bit, the reduced equations' momentum line (where the Lagrangian reads
//! `g` and is invariant only up to rounding, as the paper's double spherical pendulum through
//! `cos(ϑ1 ∓ ϑ2)`, `∂L/∂g` need not round to `0`; the momentum line does not read it). The
//! group coordinate is reconstructed from the step's increment, `g_{k+1} = g_k + (g_{k+1} − g_k)`,
//! with the compensated summation of every coordinate, and
//! the group unknown the side names is read off the step: `u = g_k^+ = ω_d(q_k, q_{k+1})` for
//! (+) and `u = g_{k+1}^− = −ω_d(q_k, q_{k+1})` for (−) ([`crate::Side::group_increment`],
//! Definition 2.1). Without constraints the (+) and (−) discrete Lagrange–Dirac equations of
//! one `L_d` are the same equations (§2.3.2), and so are their reduced forms: both sides give
//! the same states, and those of the unreduced integrator to rounding. A run carries the
//! unreduced state at `g = 0` and the rounding errors between its steps (keyed, as the
//! unreduced step's, on the state it returned, bit for bit), so that a reduced run adds no
//! rounding of a trivialization and its inverse at every step.

use std::marker::PhantomData;

use nalgebra::SVector;

use super::{GaussIntegrator, GaussRule, GaussWorkspace};
use crate::continuous::StageDerivatives;
use crate::error::StepError;
use crate::newton::NewtonOptions;
use crate::reduced::{ReducedStep, Trajectory};
use crate::state::{ReducedState, UnreducedState};
use crate::stepper::{Collect, StepAt, Stepper};
use crate::system::{DiscreteLagrangian, Minus, Plus, Side, Variant};

/// The Gauss–Legendre integrator of order `2s` on the reduced states `(x, w, μ, g)` and
/// trajectories of [`crate::ReducedIntegrator`], for the (+) ([`Self::plus`]) or (−)
/// ([`Self::minus`]) reduced equations (see the [module documentation](self)).
#[derive(Clone, Debug)]
pub struct ReducedGaussIntegrator<L, D, const S: usize, const K: usize, const N: usize> {
    gauss: GaussIntegrator<L, S, K, N>,
    side: PhantomData<D>,
}

impl<L, const S: usize, const K: usize, const N: usize> ReducedGaussIntegrator<L, Plus, S, K, N>
where
    L: DiscreteLagrangian<S, K, N> + StageDerivatives<N>,
{
    /// The reduced (+) integrator (eq. (4.6)) with `stages` stages; [`StepError::InvalidSize`]
    /// for `stages` outside `1..=`[`super::MAX_STAGES`].
    pub fn plus(system: L, stages: usize, options: NewtonOptions) -> Result<Self, StepError> {
        Self::new(system, stages, options)
    }
}

impl<L, const S: usize, const K: usize, const N: usize> ReducedGaussIntegrator<L, Minus, S, K, N>
where
    L: DiscreteLagrangian<S, K, N> + StageDerivatives<N>,
{
    /// The reduced (−) integrator (eq. (4.8), with the signs of Definition 2.8) with `stages`
    /// stages; [`StepError::InvalidSize`] for `stages` outside `1..=`[`super::MAX_STAGES`].
    pub fn minus(system: L, stages: usize, options: NewtonOptions) -> Result<Self, StepError> {
        Self::new(system, stages, options)
    }
}

impl<L, D, const S: usize, const K: usize, const N: usize> ReducedGaussIntegrator<L, D, S, K, N>
where
    D: Side,
    L: DiscreteLagrangian<S, K, N> + StageDerivatives<N>,
{
    /// The integrator of side `D`, for code generic over the side; a program names the side by
    /// its constructor, [`Self::plus`](ReducedGaussIntegrator::plus) or
    /// [`Self::minus`](ReducedGaussIntegrator::minus).
    #[doc(hidden)]
    pub fn new(system: L, stages: usize, options: NewtonOptions) -> Result<Self, StepError> {
        Ok(Self {
            gauss: GaussIntegrator::new(system, stages, options)?,
            side: PhantomData,
        })
    }

    /// The same integrator on unreduced states `(q, p)`.
    pub fn unreduced(&self) -> &GaussIntegrator<L, S, K, N> {
        &self.gauss
    }

    /// The system being integrated.
    pub fn system(&self) -> &L {
        self.gauss.system()
    }

    /// The rule.
    pub fn rule(&self) -> &GaussRule {
        self.gauss.rule()
    }

    /// The Newton options.
    pub fn options(&self) -> &NewtonOptions {
        self.gauss.options()
    }

    /// Which reduced equations are solved.
    pub fn variant(&self) -> Variant {
        D::VARIANT
    }

    /// The momentum map `μ` at `state`: constant along a run of a system without forces on its
    /// group coordinates, bit for bit. [`StepError::NonFinite`] for a `μ` that is not finite.
    pub fn momentum_map(&self, state: &ReducedState<S, K>) -> Result<SVector<f64, K>, StepError> {
        crate::stepper::finite_momentum_map(state.mu)
    }

    /// The continuous energy of a trajectory of this integrator at its nodes and midpoints
    /// ([`crate::reduced_continuous_energies`]).
    pub fn energies(
        &self,
        trajectory: &Trajectory<S, K>,
    ) -> Result<crate::ContinuousEnergies, crate::LegendreError> {
        crate::reduced_continuous_energies(self.gauss.system(), trajectory)
    }
}

/// The workspace of a reduced Gauss–Legendre run: the unreduced run's, and the last state the
/// run returned in both coordinates.
#[derive(Debug)]
pub struct ReducedGaussWorkspace<const S: usize, const K: usize, const N: usize> {
    gauss: GaussWorkspace<N>,
    /// The state returned, its unreduced form at `g = 0` and the rounding error of its `g`.
    last: Option<(ReducedState<S, K>, UnreducedState<N>, SVector<f64, K>)>,
}

/// Whether two reduced states are the same bit for bit.
fn same_bits<const S: usize, const K: usize>(
    a: &ReducedState<S, K>,
    b: &ReducedState<S, K>,
) -> bool {
    a.x.iter()
        .chain(&a.w)
        .chain(&a.mu)
        .chain(&a.g)
        .zip(b.x.iter().chain(&b.w).chain(&b.mu).chain(&b.g))
        .all(|(x, y)| x.to_bits() == y.to_bits())
}

impl<L, D, const S: usize, const K: usize, const N: usize>
    Collect<ReducedGaussIntegrator<L, D, S, K, N>> for Trajectory<S, K>
where
    D: Side,
    L: DiscreteLagrangian<S, K, N> + StageDerivatives<N>,
{
    crate::stepper::collect_steps!(
        start(integrator: ReducedGaussIntegrator<L, D, S, K, N>) {
            h: integrator.system().time_step(),
            variant: D::VARIANT,
        },
        ReducedState<S, K>,
        ReducedStep<K>,
        |step| step.stats,
        group_unknowns: "group unknowns" = step.group_unknown
    );
}

impl<L, D, const S: usize, const K: usize, const N: usize> Stepper
    for ReducedGaussIntegrator<L, D, S, K, N>
where
    D: Side,
    L: DiscreteLagrangian<S, K, N> + StageDerivatives<N>,
{
    type State = ReducedState<S, K>;
    type Record = ReducedStep<K>;
    type Workspace = ReducedGaussWorkspace<S, K, N>;
    type Trajectory = Trajectory<S, K>;

    fn time_step(&self) -> f64 {
        self.system().time_step()
    }

    crate::reduced::reduced_checks!();

    fn workspace(&self) -> Self::Workspace {
        ReducedGaussWorkspace {
            gauss: self.gauss.workspace(),
            last: None,
        }
    }

    fn control_dim(&self) -> usize {
        self.system().control_count()
    }

    fn step_with(
        &self,
        ws: &mut Self::Workspace,
        at: StepAt<'_>,
        state: &ReducedState<S, K>,
    ) -> Result<(ReducedState<S, K>, ReducedStep<K>), StepError> {
        let sys = self.system();
        // `(q, p)` at `g = 0`: the reduced Lagrangian's `L_d(x0, 0, x1, ·)` (eqs. (4.5), (4.7)).
        let (from, carry_g) = match &ws.last {
            Some((reduced, unreduced, carry_g)) if same_bits(reduced, state) => {
                (*unreduced, *carry_g)
            }
            _ => {
                let at_zero = ReducedState {
                    g: SVector::zeros(),
                    ..*state
                };
                (sys.untrivialize(&at_zero), SVector::zeros())
            }
        };
        let mut next = from;
        let stats = self.gauss.step_into(&mut ws.gauss, at, &from, &mut next)?;
        let (mut dg, mut carry_g) = (SVector::<f64, K>::zeros(), carry_g);
        let mut g = state.g;
        // `update` leaves the rounding errors of the step it took (always, on success).
        let (key, cq, cp) =
            ws.gauss
                .carry
                .get_or_insert((next, SVector::zeros(), SVector::zeros()));
        for j in 0..K {
            // The increment `g_{k+1} − g_k` (from `g = 0`) and its rounding, added to `g_k` with
            // the same compensated summation as every coordinate.
            dg[j] = next.q[S + j];
            (g[j], carry_g[j]) = super::two_sum(state.g[j], dg[j] + cq[S + j] + carry_g[j]);
            (next.q[S + j], cq[S + j]) = (0.0, 0.0);
            // The momentum equation of the reduced equations: `μ_{k+1} = μ_k`.
            (next.p[S + j], cp[S + j]) = (state.mu[j], 0.0);
        }
        *key = next;
        let (x0, x1) = (state.x, next.q.fixed_rows::<S>(0).into_owned());
        let reduced = ReducedState {
            x: x1,
            w: next.p.fixed_rows::<S>(0) + sys.connection().transpose() * state.mu,
            mu: state.mu,
            g,
        };
        let step = ReducedStep {
            group_unknown: D::group_increment(dg - sys.h_d0(&x0, &x1)),
            stats,
        };
        ws.last = Some((reduced, next, carry_g));
        Ok((reduced, step))
    }
}
