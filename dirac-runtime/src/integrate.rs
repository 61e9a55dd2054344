//! Marching the reduced (+) equations (4.6) step by step.

use nalgebra::SVector;

use crate::error::{IntegrationError, StepError};
use crate::newton::{self, NewtonFailure, NewtonOptions};
use crate::state::ReducedState;
use crate::system::{join, split, ReducedPlus};

/// What one step cost.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepStats {
    /// Newton corrections (linear solves) taken.
    pub iterations: usize,
    /// `‖R‖∞` at the accepted solution.
    pub residual: f64,
}

/// A computed trajectory: states `0..=steps()` at times `t_k = k h`, and for each step the
/// solved group increment `g_k^+` and the Newton statistics.
#[derive(Clone, Debug, PartialEq)]
pub struct Trajectory<const S: usize, const K: usize> {
    /// The time step `h`.
    pub h: f64,
    /// `states[k]` is the state at `t_k`.
    pub states: Vec<ReducedState<S, K>>,
    /// `increments[k] = g_k^+`, the reduced group unknown of step `k` (eq. (4.6)).
    pub increments: Vec<SVector<f64, K>>,
    /// Newton statistics of each step.
    pub stats: Vec<StepStats>,
}

impl<const S: usize, const K: usize> Trajectory<S, K> {
    fn start(h: f64, initial: ReducedState<S, K>, capacity: usize) -> Self {
        let mut states = Vec::with_capacity(capacity + 1);
        states.push(initial);
        Self {
            h,
            states,
            increments: Vec::with_capacity(capacity),
            stats: Vec::with_capacity(capacity),
        }
    }

    /// Number of completed steps.
    pub fn steps(&self) -> usize {
        self.states.len() - 1
    }

    /// The time of state `k`.
    pub fn time(&self, k: usize) -> f64 {
        k as f64 * self.h
    }

    /// The last state.
    pub fn last(&self) -> &ReducedState<S, K> {
        self.states
            .last()
            .expect("a trajectory holds its initial state")
    }

    /// Mean Newton corrections per step (0 for an empty trajectory).
    pub fn mean_iterations(&self) -> f64 {
        if self.stats.is_empty() {
            return 0.0;
        }
        self.stats.iter().map(|s| s.iterations as f64).sum::<f64>() / self.stats.len() as f64
    }

    /// Largest accepted residual over the steps.
    pub fn max_residual(&self) -> f64 {
        self.stats.iter().map(|s| s.residual).fold(0.0, f64::max)
    }
}

/// Integrates a system with the reduced (+) discrete Lagrange–Poincaré–Dirac equations (4.6).
///
/// Each step solves `R(z) = (∂l_{d+}/∂x0 + w_k, ∂l_{d+}/∂g1 − μ_k) = 0` for
/// `z = (x_{k+1}, g_k^+)` by Newton's method (see [`ReducedPlus`]), then updates
/// `w_{k+1} = ∂l_{d+}/∂x1`, `μ_{k+1} = μ_k` exactly, and reconstructs the absolute group
/// coordinate `g_{k+1} = g_k + g_k^+ + B (x_{k+1} − x_k)` (last line of (4.6)).
#[derive(Clone, Debug)]
pub struct ReducedIntegrator<L, const S: usize, const K: usize, const N: usize> {
    system: L,
    options: NewtonOptions,
}

impl<L, const S: usize, const K: usize, const N: usize> ReducedIntegrator<L, S, K, N>
where
    L: ReducedPlus<S, K, N>,
{
    /// The (+) integrator of eq. (4.6).
    pub fn plus(system: L, options: NewtonOptions) -> Self {
        Self { system, options }
    }

    /// The system being integrated.
    pub fn system(&self) -> &L {
        &self.system
    }

    /// The Newton options.
    pub fn options(&self) -> &NewtonOptions {
        &self.options
    }

    /// Takes step `k` from `state`, starting Newton at `guess` for `z = (x_{k+1}, g_k^+)`.
    /// Returns the new state, the solved `g_k^+` and the step's statistics.
    pub fn step(
        &self,
        k: usize,
        state: &ReducedState<S, K>,
        guess: &SVector<f64, N>,
    ) -> Result<(ReducedState<S, K>, SVector<f64, K>, StepStats), StepError> {
        let sys = &self.system;
        let (w, mu) = (state.w, state.mu);
        let rho = newton::inf_norm(&w).max(newton::inf_norm(&mu));
        let solution = newton::solve(
            *guess,
            rho,
            &self.options,
            |z| sys.plus_residual(&state.x, &w, &mu, z),
            |z| sys.plus_residual_jacobian(&state.x, &w, &mu, z),
        )
        .map_err(|failure| match failure {
            NewtonFailure::NotConverged {
                iterations,
                residual,
            } => StepError::NotConverged {
                step: k,
                iterations,
                residual,
            },
            NewtonFailure::Singular { residual } => {
                StepError::SingularJacobian { step: k, residual }
            }
            NewtonFailure::NonFinite { residual } => StepError::NonFinite {
                step: k,
                what: "the step equations",
                residual,
            },
        })?;
        let (x1, g_plus) = split::<S, K, N>(&solution.z);
        let next = ReducedState {
            x: x1,
            w: sys.plus_momentum(&state.x, &solution.z),
            mu,
            g: state.g + g_plus + sys.connection() * (x1 - state.x),
        };
        if !next.is_finite() {
            return Err(StepError::NonFinite {
                step: k,
                what: "the updated state",
                residual: solution.residual,
            });
        }
        let stats = StepStats {
            iterations: solution.iterations,
            residual: solution.residual,
        };
        Ok((next, g_plus, stats))
    }

    /// Integrates `steps` steps from `initial`.
    ///
    /// Newton starts each step from a linear extrapolation of the last two shape points and the
    /// last group increment. On failure the error holds the trajectory computed so far.
    pub fn integrate(
        &mut self,
        initial: ReducedState<S, K>,
        steps: usize,
    ) -> Result<Trajectory<S, K>, Box<IntegrationError<S, K>>> {
        let h = self.system.time_step();
        let mut trajectory = Trajectory::start(h, initial, steps);
        let fail = |source, trajectory| {
            Box::new(IntegrationError {
                source,
                trajectory,
                requested: steps,
            })
        };
        if !(h.is_finite() && h > 0.0) {
            return Err(fail(StepError::InvalidTimeStep { h }, trajectory));
        }
        if !initial.is_finite() {
            let source = StepError::NonFinite {
                step: 0,
                what: "the initial state",
                residual: f64::INFINITY,
            };
            return Err(fail(source, trajectory));
        }
        if self
            .system
            .parameter_values()
            .iter()
            .any(|p| !p.is_finite())
        {
            let source = StepError::NonFinite {
                step: 0,
                what: "the parameters",
                residual: f64::INFINITY,
            };
            return Err(fail(source, trajectory));
        }
        let mut state = initial;
        let mut previous: Option<(SVector<f64, S>, SVector<f64, K>)> = None;
        for k in 0..steps {
            let guess = match previous {
                Some((x_prev, g_plus)) => join::<S, K, N>(&(2.0 * state.x - x_prev), &g_plus),
                None => join::<S, K, N>(&state.x, &SVector::zeros()),
            };
            match self.step(k, &state, &guess) {
                Ok((next, g_plus, stats)) => {
                    previous = Some((state.x, g_plus));
                    trajectory.states.push(next);
                    trajectory.increments.push(g_plus);
                    trajectory.stats.push(stats);
                    state = next;
                }
                Err(source) => return Err(fail(source, trajectory)),
            }
        }
        Ok(trajectory)
    }
}
