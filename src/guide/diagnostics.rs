//! # Diagnostics
//!
//! A run reports how each step was solved, and [`crate::runtime::diagnostics`] evaluates the
//! paper's geometry along a computed trajectory, so you can see that the structure the
//! integrator is built on holds for your system, not only that the numbers look plausible.
//!
//! ## What each step reports
//!
//! Every step records its [`StepStats`](crate::StepStats): the Newton corrections taken
//! (`iterations`), the Jacobians factored (`factorizations`; on the sparse backend chord steps
//! reuse earlier factors), the residual `‖R‖∞` at the accepted solution and the tolerance it was
//! accepted against (`abs_tol + rel_tol · ρ`, `ρ` the size of the momenta; a step accepted on a
//! small Newton correction has a residual at round-off level, below its tolerance), and `rcond`,
//! a reciprocal condition estimate of the last Jacobian factored (`None` when the initial guess
//! already solved the step). Trajectories summarize them
//! ([`mean_iterations`](crate::runtime::reduced::Trajectory::mean_iterations),
//! [`max_residual`](crate::runtime::reduced::Trajectory::max_residual),
//! [`worst_rcond`](crate::runtime::reduced::Trajectory::worst_rcond), also
//! [`StepStatsExt`](crate::StepStatsExt) on a slice), and so does the
//! [`RunSummary`](crate::RunSummary) of a streamed run.
//!
//! **The conditioning** is checked on every step with a guaranteed lower bound on the
//! reciprocal 1-norm condition number (comparison matrices of the LU factors, one extra solve);
//! only when that bound does not clear `min_rcond` (by a factor 2) does Hager's estimator run.
//! Since Hager's estimate is never below the true value (up to its own round-off) and the bound
//! never above it, a step is refused exactly when Hager's estimate is below `min_rcond`, as if
//! the estimator ran on every step; the recorded figure is the bound on healthy steps and
//! Hager's estimate otherwise. A small `rcond` is the first sign of coordinates approaching a
//! singularity (for the pendulum, a bob near the vertical axis).
//!
//! ## The paper's geometry along a trajectory
//!
//! * [`trajectory_energies`](crate::trajectory_energies): the discrete energy
//!   `(E_d)_k = L_d(q_k, q_{k+1})` of each step, the generalized energy (5.7) on solutions.
//! * [`dirac_membership_residuals`](crate::runtime::diagnostics::dirac_membership_residuals):
//!   for every step, how far the step is from lying in the reduced discrete Dirac structure
//!   (Propositions 3.8, 3.10 with the reduced Dirac differentials of Propositions 4.3, 4.4); of
//!   the order of the Newton residual along a computed trajectory.
//! * [`ReducedActionPlus`](crate::runtime::diagnostics::ReducedActionPlus): the reduced (+)
//!   discrete action of Theorem 5.2 and its gradient in all its variables, which vanishes along
//!   a computed trajectory (the variational route to the same equations).
//! * [`reduced_energy_plus`](crate::runtime::diagnostics::reduced_energy_plus) /
//!   [`reduced_energy_minus`](crate::runtime::diagnostics::reduced_energy_minus): the reduced
//!   discrete generalized energies `e_{d±}` (Lemmas 5.1, 5.4).
//! * For a continuous Lagrangian, [`continuous_energies`](crate::continuous_energies) and
//!   [`reduced_continuous_energies`](crate::reduced_continuous_energies): the energy
//!   `E(q, v)` at the nodes and the midpoints (see
//!   [Writing a Lagrangian](super::lagrangians#continuous-lagrangians-with-a-rule)).
//! * [`UnreducedIntegrator::step_jacobian`](crate::UnreducedIntegrator::step_jacobian): the
//!   Jacobian of the step map, for sensitivities and covariance propagation, and its
//!   [`symplecticity_defect`](crate::Sensitivity::symplecticity_defect).
//! * `<Name>::GENERATED`: the operation counts of everything the attribute emitted for a system.
//!
//! ```
//! use dirac::paper::DoubleSphericalPendulum;
//! use dirac::prelude::*;
//! use dirac::runtime::diagnostics::{dirac_membership_residuals, ReducedActionPlus};
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let sys = DoubleSphericalPendulum::paper();
//! let start = DoubleSphericalPendulum::paper_initial_state();
//! let traj = ReducedIntegrator::plus(sys, NewtonOptions::default()).run(start).steps(500).collect()?;
//!
//! // How the steps were solved.
//! let (step, rcond) = traj.worst_rcond().expect("Newton corrected at least once");
//! println!(
//!     "{:.2} corrections per step, largest residual {:.1e}, worst rcond {rcond:.1e} at step {step}",
//!     traj.mean_iterations(),
//!     traj.max_residual(),
//! );
//!
//! // The discrete energy of each step, and the physical energy T + V at the step midpoints.
//! let e_d = trajectory_energies(&sys, &traj);
//! assert_eq!(e_d.len(), 500);
//! let q: Vec<_> = traj.states.iter().map(|s| sys.untrivialize(s).q).collect();
//! let energy: Vec<f64> = q.windows(2).map(|w| sys.physical_energy(&w[0], &w[1])).collect();
//! let spread = energy.iter().fold(f64::NEG_INFINITY, |a, &b| a.max(b))
//!     - energy.iter().fold(f64::INFINITY, |a, &b| a.min(b));
//! assert!(spread < 1e-6 * energy[0].abs()); // 4e-8 relative over these 500 steps
//!
//! // The Dirac structure and the variational principle hold along the computed steps, to the
//! // Newton residual the steps were accepted with (and round-off in the size of the state).
//! let scale = traj.states.iter().map(|s| s.w.amax().max(s.x.amax())).fold(1.0, f64::max);
//! let bound = 4.0 * traj.max_residual() + 1e-14 * scale;
//! let membership = dirac_membership_residuals(&sys, &traj);
//! assert!(membership.iter().all(|&r| r <= bound));
//! let gradient = ReducedActionPlus::from_trajectory(&traj)?.gradient(&sys).max_abs();
//! assert!(gradient <= bound);
//!
//! // The step map of the unreduced integrator is symplectic.
//! let unreduced = UnreducedIntegrator::new(sys, NewtonOptions::default());
//! let from = sys.untrivialize(&start);
//! let (to, _) = unreduced.step_from(0, &from, &from.q)?;
//! assert!(unreduced.step_jacobian(0, &from, &to)?.symplecticity_defect() < 1e-10);
//!
//! println!("{}", DoubleSphericalPendulum::GENERATED);
//! # Ok(())
//! # }
//! ```
