//! The unreduced integrator: the discrete Lagrange–Dirac equations on `Q` (Definitions
//! 2.7/2.8), the baseline that knows nothing of the symmetry, and the Jacobian of its step map.

use nalgebra::{SMatrix, SVector};

use crate::error::{StepError, Steps};
use crate::linalg::Lu;
use crate::newton::{self, inf_norm, NewtonOptions};
use crate::reduced::{flat_monitor, trajectory_accessors};
use crate::sensitivity::Sensitivity;
use crate::state::UnreducedState;
use crate::stepper::{
    check_inputs, flat_level_set, predicted_increment, step_error, system_at, Collect, History,
    LevelSet, StepAt, StepStats, StepStatsExt, Stepper,
};
use crate::system::{LagrangianHessian, Unreduced};

/// An unreduced trajectory `(q_k, p_k)`, `k = 0..=step_count()`.
#[derive(Clone, Debug, PartialEq)]
pub struct UnreducedTrajectory<const N: usize> {
    /// The integrator's time step `h` (the default step of a run; see [`Self::times`] for the
    /// time of each state).
    pub h: f64,
    /// `states[k]` is the state at `times[k]`.
    pub states: Vec<UnreducedState<N>>,
    /// `times[k] = t_k`, the time of `states[k]` (`k h` exactly for a fixed step).
    pub times: Vec<f64>,
    /// `step_sizes[k]` is the size step `k` was taken with, bit for bit as the run passed it to
    /// the step: `h` itself for a fixed step, `h_k` with a schedule (the last step shortened to
    /// land on an end time); with adaptive steps the fictitious step `ε_k` (the physical step is
    /// `times[k + 1] − times[k]`).
    pub step_sizes: Vec<f64>,
    /// Newton statistics of each step.
    pub stats: Vec<StepStats>,
}

impl<const N: usize> UnreducedTrajectory<N> {
    trajectory_accessors!(UnreducedState<N>);
}

impl<const N: usize> Steps for UnreducedTrajectory<N> {
    fn completed_steps(&self) -> usize {
        self.step_count()
    }
}

impl<L, const S: usize, const K: usize, const N: usize> Collect<UnreducedIntegrator<L, S, K, N>>
    for UnreducedTrajectory<N>
where
    L: Unreduced<S, K, N>,
{
    crate::stepper::collect_steps!(
        start(integrator: UnreducedIntegrator<L, S, K, N>) {
            h: integrator.system.time_step(),
        },
        UnreducedState<N>,
        StepStats,
        |stats| *stats
    );
}

/// The workspace of an unreduced run: the linear solver and the last two increments
/// `q_{j+1} − q_j`, newest first, that Newton's guess extrapolates ([`canonical_guess`]).
#[derive(Clone, Debug)]
pub struct UnreducedWorkspace<B, const N: usize> {
    /// The linear solver ([`Unreduced::UnreducedLinear`]).
    #[doc(hidden)]
    pub solver: B,
    /// The last two increments of the configuration.
    #[doc(hidden)]
    pub history: History<SVector<f64, N>>,
}

/// Integrates the unreduced discrete Lagrange–Dirac equations on `Q` (Definitions 2.7/2.8,
/// see [`Unreduced`]): the baseline that knows nothing of the symmetry.
#[derive(Clone, Debug)]
pub struct UnreducedIntegrator<L, const S: usize, const K: usize, const N: usize> {
    system: L,
    options: NewtonOptions,
}

impl<L, const S: usize, const K: usize, const N: usize> UnreducedIntegrator<L, S, K, N>
where
    L: Unreduced<S, K, N>,
{
    /// The (+) discrete Lagrange–Dirac equations (Definition 2.7). Unconstrained, the (−)
    /// equations of Definition 2.8 (with `q_{k+1}^− = q_k`) are the same equations, so this one
    /// integrator serves both.
    pub fn new(system: L, options: NewtonOptions) -> Self {
        Self { system, options }
    }

    /// The system being integrated.
    pub fn system(&self) -> &L {
        &self.system
    }

    /// The momentum map `J(q, p) = p_g` of the declared translations at `state`. A `Result` as
    /// on every integrator: [`StepError::NonFinite`] for a state that is not finite.
    pub fn momentum_map(&self, state: &UnreducedState<N>) -> Result<SVector<f64, K>, StepError> {
        crate::stepper::finite_momentum_map(self.system.momentum_map(state))
    }

    /// The continuous energy of a trajectory of this integrator at its nodes and midpoints
    /// ([`crate::continuous_energies`]).
    pub fn energies(
        &self,
        trajectory: &UnreducedTrajectory<N>,
    ) -> Result<crate::ContinuousEnergies, crate::LegendreError>
    where
        L: crate::ContinuousLagrangian<N>,
    {
        crate::continuous_energies(&self.system, trajectory)
    }

    /// The Newton options.
    pub fn options(&self) -> &NewtonOptions {
        &self.options
    }

    /// Takes step `k` from `state`, Newton starting at `guess` for `q_{k+1}`, in a fresh
    /// workspace. Runs use [`Stepper::step_in`], which keeps one workspace and extrapolates the
    /// guess ([`canonical_guess`]).
    pub fn step_from(
        &self,
        k: usize,
        state: &UnreducedState<N>,
        guess: &SVector<f64, N>,
    ) -> Result<(UnreducedState<N>, StepStats), StepError> {
        self.solve_step(
            &mut self.system.unreduced_linear_solver(),
            StepAt::new(k, self.system.time_step()),
            state,
            guess,
        )
    }

    /// The step `at` (its size `h`, its controls `u`: empty, the system's own) from `state`,
    /// Newton starting at `guess`, in the linear solver `solver`.
    fn solve_step(
        &self,
        solver: &mut L::UnreducedLinear,
        at: StepAt<'_>,
        state: &UnreducedState<N>,
        guess: &SVector<f64, N>,
    ) -> Result<(UnreducedState<N>, StepStats), StepError> {
        let StepAt { k, h, u } = at;
        let owned = system_at(&self.system, k, h, u)?;
        let sys = owned.as_ref().unwrap_or(&self.system);
        let (q, p) = (&state.q, &state.p);
        let rho = inf_norm(p);
        let solution = newton::solve_with(
            solver,
            *guess,
            rho,
            &self.options,
            |z| sys.unreduced_residual(q, p, z),
            |z| sys.unreduced_residual_jacobian(q, p, z),
        )
        .map_err(|failure| step_error(k, failure))?;
        let next = UnreducedState {
            q: solution.z,
            p: sys.unreduced_momentum(q, &solution.z),
        };
        if !next.is_finite() {
            return Err(StepError::NonFinite {
                step: k,
                what: "the updated state",
                residual: solution.residual,
            });
        }
        Ok((
            next,
            StepStats::from_solution(&solution, self.options.residual_tolerance(rho)),
        ))
    }
}

/// The [`Stepper`] methods about the state of an integrator on unreduced states `(q, p)` of a
/// flat system in the field `system` (written once for the second-order step and the
/// Gauss–Legendre steps): the checks of the start and of the domain, the physical time and
/// level set of adaptive steps, the monitor `g(x)` at the shape `x`, the first `S` coordinates.
macro_rules! unreduced_checks {
    () => {
        fn check(&self, initial: &UnreducedState<N>) -> Result<(), StepError> {
            check_inputs(
                self.system.time_step(),
                &self.system.parameter_values(),
                initial.is_finite(),
            )?;
            // The domain: outside it the monitor (checked next by the run) need not be defined.
            crate::domain::check_system(&self.system, 0, true, |i| initial.q.get(i).copied())
        }

        fn check_domain(&self, k: usize, state: &UnreducedState<N>) -> Result<(), StepError> {
            crate::domain::check_system(&self.system, k, false, |i| state.q.get(i).copied())
        }

        fn physical_time(&self, state: &UnreducedState<N>) -> Option<f64> {
            self.system.time_index().map(|j| state.q[S + j])
        }

        fn level_set(&self, state: &UnreducedState<N>) -> Option<LevelSet> {
            flat_level_set(&self.system, &state.q, &state.p)
        }

        /// `g(x)` at the shape `x`, the first `S` coordinates of `q`.
        fn monitor(
            &self,
            at: StepAt<'_>,
            state: &UnreducedState<N>,
        ) -> Result<Option<f64>, StepError> {
            flat_monitor(&self.system, at, &state.q.fixed_rows::<S>(0).into_owned())
        }
    };
}
pub(crate) use unreduced_checks;

impl<L, const S: usize, const K: usize, const N: usize> Stepper for UnreducedIntegrator<L, S, K, N>
where
    L: Unreduced<S, K, N>,
{
    type State = UnreducedState<N>;
    type Record = StepStats;
    type Workspace = UnreducedWorkspace<L::UnreducedLinear, N>;
    type Trajectory = UnreducedTrajectory<N>;

    fn time_step(&self) -> f64 {
        self.system.time_step()
    }

    unreduced_checks!();

    fn workspace(&self) -> Self::Workspace {
        UnreducedWorkspace {
            solver: self.system.unreduced_linear_solver(),
            history: History::default(),
        }
    }

    fn control_dim(&self) -> usize {
        self.system.control_count()
    }

    /// Newton starts from [`canonical_guess`], a quadratic extrapolation of the last
    /// configurations.
    fn step_with(
        &self,
        workspace: &mut Self::Workspace,
        at: StepAt<'_>,
        state: &UnreducedState<N>,
    ) -> Result<(UnreducedState<N>, StepStats), StepError> {
        let h = at.h;
        let mut guess = canonical_guess(&state.q, &workspace.history, h);
        // Adaptive steps: a run's first step starts from the motion in fictitious time, not rest.
        if workspace.history.last.is_none() && self.system.time_index().is_some() {
            if let Some(dq) = self.system.adaptive_increment(&state.q, &state.p, h) {
                guess = state.q + dq;
            }
        }
        let (next, stats) = self.solve_step(&mut workspace.solver, at, state, &guess)?;
        workspace.history.push(next.q - state.q, h);
        Ok((next, stats))
    }
}

/// Newton's initial guess for `q_{k+1}` over a step of size `h` in the unreduced equations from
/// the last two increments `q_{j+1} − q_j` and their step sizes, newest first: `q`,
/// `q + Δ_{k−1}`, then `q + 2 Δ_{k−1} − Δ_{k−2}` on a uniform grid (see
/// [`crate::reduced::reduced_guess`]).
#[doc(hidden)]
pub fn canonical_guess<const N: usize>(
    q: &SVector<f64, N>,
    history: &History<SVector<f64, N>>,
    h: f64,
) -> SVector<f64, N> {
    predicted_increment(history, h).map_or(*q, |dq| q + dq)
}

impl<L, const S: usize, const K: usize, const N: usize> UnreducedIntegrator<L, S, K, N>
where
    L: LagrangianHessian<S, K, N>,
{
    /// The Jacobian of the step map `(q_k, p_k) ↦ (q_{k+1}, p_{k+1})` at a computed step, from the
    /// implicit-function theorem on `D1 L_d(q_k, q_{k+1}) + p_k = 0` and
    /// `p_{k+1} = D2 L_d(q_k, q_{k+1})` with the generated second derivatives: with
    /// `A = D12 L_d`,
    ///
    /// ```text
    /// ∂q_{k+1}/∂q_k = −A⁻¹ D11 L_d      ∂q_{k+1}/∂p_k = −A⁻¹
    /// ∂p_{k+1}/∂q_k = D21 L_d + D22 L_d ∂q_{k+1}/∂q_k      ∂p_{k+1}/∂p_k = D22 L_d ∂q_{k+1}/∂p_k
    /// ```
    ///
    /// The result is the [`Sensitivity`] of the step with no control columns: the same
    /// derivative that [`Self::sensitivity`] computes from the step partials, here from the
    /// Hessian of `L_d` alone, so it needs no forces or controls to have been declared.
    ///
    /// The step map of a variational integrator is symplectic, `Mᵀ Ω M = Ω` (see
    /// [`Sensitivity::symplecticity_defect`]). Control and estimation use `M` to propagate
    /// sensitivities and covariances along a trajectory.
    ///
    /// `k` is the index of the step `from → to`, for the error: a singular `D12 L_d`
    /// (`StepError::SingularJacobian`, with no residual to report: NaN), or second derivatives
    /// that are not finite (`StepError::NonFinite`: outside the Lagrangian's domain, or a system
    /// given at run time whose Hessian was not compiled, one with forces).
    pub fn step_jacobian(
        &self,
        k: usize,
        from: &UnreducedState<N>,
        to: &UnreducedState<N>,
    ) -> Result<Sensitivity, StepError> {
        let (d11, d12, d22) = self.system.lagrangian_hessian(&from.q, &to.q);
        if ![&d11, &d12, &d22]
            .iter()
            .all(|m| m.iter().all(|v| v.is_finite()))
        {
            return Err(StepError::NonFinite {
                step: k,
                what: "the second derivatives of L_d",
                residual: f64::NAN,
            });
        }
        let lu = Lu::new(d12).ok_or(StepError::SingularJacobian {
            step: k,
            residual: f64::NAN,
        })?;
        let solve_columns = |m: &SMatrix<f64, N, N>| {
            let mut out = SMatrix::<f64, N, N>::zeros();
            for (c, column) in m.column_iter().enumerate() {
                out.set_column(c, &lu.solve(&column.into_owned()));
            }
            out
        };
        let dq_dq = -solve_columns(&d11);
        let dq_dp = -solve_columns(&SMatrix::identity());
        Ok(Sensitivity::from_blocks(
            &dq_dq,
            &dq_dp,
            &(d12.transpose() + d22 * dq_dq),
            &(d22 * dq_dp),
        ))
    }
}
