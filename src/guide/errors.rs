//! # Errors and what they mean
//!
//! A step that cannot be computed is never a panic and never a silent NaN: it is a typed
//! [`StepError`](crate::StepError) carrying the step index and the residual `‖R‖∞` at the last
//! iterate, and the run that contained it returns an error that keeps everything computed before
//! it. A mistake in an annotated function is a compile error that points at the token and says
//! what is accepted.
//!
//! ## A failed step
//!
//! | [`StepError`](crate::StepError) | what happened | what to try |
//! | --- | --- | --- |
//! | `NotConverged { step, iterations, residual }` | Newton's iteration reached `max_iterations` without meeting the tolerances | a smaller time step, or a larger iteration cap |
//! | `SingularJacobian { step, residual }` | the Jacobian of the step equations is singular: `L_d` is degenerate here, or the reduction is not valid here | coordinates where the symmetry acts freely; for a degenerate `L`, whether its discrete Legendre map is invertible |
//! | `IllConditioned { step, rcond, residual, tolerance }` | the step Jacobian's reciprocal condition estimate is below [`NewtonOptions::min_rcond`](crate::NewtonOptions::min_rcond): with `residual ≤ tolerance` the step converged but the result has few or no correct digits; with `residual > tolerance` it did not converge, the ill-conditioning the likely cause (the message says which) | another chart ([atlas](super::integrators#an-atlas-of-charts-6)); near a pole of spherical coordinates the action is not free (Remark 7.1) |
//! | `NonFinite { step, what, residual }` | a residual, Jacobian, correction or state component is NaN or infinite; `what` says which | the parameters, the initial state, and whether the motion left the domain of `L` (a square root or logarithm of a negative number) |
//! | `InvalidSize { reason }` | sizes that do not fit (nothing taken): a state or vector without the system's number of coordinates, a run-time-sized system's sizes against its stencils, or a workspace or trajectory of another integrator; `reason` has the figures | build the state from the system's own sizes, and pass each integrator its own workspace and trajectory |
//! | `OffManifold { reason }` | the initial state is not on its manifold: a rotation coordinate that is not a rotation matrix, a direction that is not a unit vector to `1e-9` ([`lie::UNIT_TOLERANCE`](crate::lie::UNIT_TOLERANCE): not normalized for you, compiled in or given as text) or without an orthonormal frame ([rotations](super::rotations)), or an [adaptive](super::adaptive_steps) start off its energy level set `p_t = −E` (relative [`LEVEL_SET_TOLERANCE`](crate::runtime::adaptive::LEVEL_SET_TOLERANCE)); `reason` names the coordinate and by how much | an orthonormal start: a rotation built as a [`Rotation3`](crate::nalgebra::Rotation3), a unit direction; an adaptive start from `sys.reduced_state(q, v)` |
//! | `OutOfDomain { step, initial, coordinate, value, bound }` | the state step `step` reached (or, with `initial`, the initial state) lies outside the domain the system declares, `domain(r > 0.0)`: `coordinate = value` violates `bound` (the states before it kept; see [below](#a-step-too-coarse-a-declared-domain)) | a smaller time step, or adaptive steps; a start inside the domain |
//! | `InvalidMonitor { step, value }` | the step monitor `g(q)` of a system with [adaptive steps](super::adaptive_steps) is not positive and finite at the state step `step` reached (0: the initial state), so `Δt ≈ ε g` would vanish or turn back | a floor in the monitor, e.g. `r.powf(1.5) + 1e-6` for a distance that vanishes at a collision |
//! | `TimeReversed { step, dt }` | an adaptive step solved for a physical time step `dt` without the sign of the fictitious step: Newton found the root that goes back in time | a smaller fictitious step `ε`, or a monitor that is smaller where the motion is fast |
//! | `InvalidTimeStep { h }` | the time step is not positive and finite (step 0, nothing taken) | a positive `h` |
//! | `InvalidStepSize { step, h }` | a step-size policy gave a size that is not positive and finite | the schedule |
//! | `ScheduleEnded { step }` | a precomputed [`StepSizes`](crate::StepSizes) has no size for step `step` | one size per step, or a shorter run |
//! | `InvalidRun { reason }` | the run has no length (`.steps(n)` or `.end_time(t)`), an end time before its start, a zero output stride, or a `.start_time(t0)` on a run with [adaptive steps](super::adaptive_steps) other than the initial state's own time, which is its clock (nothing computed) | the run's options; with adaptive steps, the time in the state |
//! | `ConstraintViolated { residual, tolerance }` | the initial configuration does not satisfy the holonomic [constraints](super::constraints): `‖φ(q₀)‖∞ = residual` exceeds `tolerance` (nothing taken) | start on the constraint manifold: solve `φ(q₀) = 0` for the initial configuration |
//! | `Unsupported { what }` | what was asked is not available for this system, and `what` says why: step sensitivities of a system compiled without its step partials, the energy of a discrete Lagrangian, a fictitious velocity of a system without adaptive steps, the (+) action's variables of a (−) trajectory | what `what` names: declare the system as it requires (e.g. `controls(...)` or `force = ...` for the partials, a continuous Lagrangian with a `rule` for an energy), or another method |
//! | `InvalidControls { step, expected, found }` | the controls given are not the ones the system declares in `controls(...)`: `found` values per step where it declares `expected`, or (with `found = expected`) a control sequence that has no row for step `step` | one value per declared control, and one row per step of the run |
//! | `NotSymmetric { defect, tolerance }` | a composition was asked of a rule that is not symmetric, so it would not reach its order | the midpoint or trapezoidal rule |
//! | `InvalidAtlas { reason }` | the charts or transitions of an atlas do not fit together | the atlas's construction |
//! | `StageFailed { stage, stages, substep, error }` | stage `stage` (from 0) of a composition, stepping with `substep`, failed with `error` (which has the macro step's index and the stage's residual) | what `error` suggests; a smaller macro step |
//! | `OutOfMemory { what, bytes }` | a run-time-sized system's workspace, or a collected run's trajectory, needs `bytes` bytes, which cannot be allocated (checked before allocating: a run of `.steps(n)` without a stop condition or an end time before its first step) | smaller sizes, fewer states kept (`.stream()` keeps none), or a machine with more memory |
//!
//! [`StepError::step`](crate::StepError::step), [`residual`](crate::StepError::residual) and
//! [`kind`](crate::StepError::kind) read the common fields; the enum is `#[non_exhaustive]`.
//!
//! ## The trajectory is kept
//!
//! `run(..).collect()` returns `Err(Box<IntegrationError<Trajectory>>)`: the
//! [`IntegrationError`](crate::IntegrationError) holds the `source` (the [`StepError`](crate::StepError)),
//! the `trajectory` up to the failed step, intact, and the number of steps `requested`. `run(..).stream()`
//! keeps the [`RunSummary`](crate::RunSummary) up to the failed step the same way. An ensemble
//! member that fails is an `Err` at its position; the other members are unaffected. The message
//! of an `IntegrationError` names the step, the kind of failure and how much was kept; the cause
//! with its figures is its [`source()`](std::error::Error::source) and is not repeated, so a
//! printed error chain shows each cause once — the output of the example below:
//!
//! ```text
//! integration stopped at step 1 (Newton did not converge): 1 of 100 steps completed, the trajectory so far kept
//! caused by: step 1: Newton iteration did not converge in 2 iterations (residual 2.689e-7); try a smaller time step or a larger iteration cap
//! ```
//!
//! ```
//! use dirac::paper::DoubleSphericalPendulum;
//! use dirac::prelude::*;
//! use std::error::Error;
//!
//! let sys = DoubleSphericalPendulum::paper();
//! let start = DoubleSphericalPendulum::paper_initial_state();
//!
//! // An iteration cap of two corrections: the first step that needs three fails, typed.
//! let tight = NewtonOptions { max_iterations: 2, ..NewtonOptions::default() };
//! let e = ReducedIntegrator::plus(sys, tight).run(start).steps(100).collect().unwrap_err();
//! let StepError::NotConverged { step, iterations, residual } = e.source else {
//!     panic!("expected NotConverged, got {}", e.source);
//! };
//! assert_eq!(iterations, 2);
//! assert_eq!(e.trajectory.step_count(), step); // every step before the failed one, kept
//! assert!(residual > 0.0 && e.requested == 100);
//! println!("{e}\ncaused by: {}", e.source().expect("the StepError"));
//!
//! // Remark 7.1: a bob 1e-7 from the vertical axis, where the rotation is not free.
//! let mut at_pole = start;
//! at_pole.x[0] = std::f64::consts::PI - 1e-7;
//! let integ = ReducedIntegrator::plus(sys, NewtonOptions::default());
//! let e = integ.run(at_pole).steps(100).observe(|_, _, _, _| {}).stream().unwrap_err();
//! assert_eq!((e.source.step(), e.trajectory.step_count), (0, 0)); // refused, nothing taken
//! println!("{}", e.source);
//!
//! // Inputs are checked before the first step.
//! let backwards = DoubleSphericalPendulum { h: -0.01, ..sys };
//! let e = ReducedIntegrator::plus(backwards, NewtonOptions::default())
//!     .run(start).steps(10).collect()
//!     .unwrap_err();
//! assert_eq!(e.source, StepError::InvalidTimeStep { h: -0.01 });
//! ```
//!
//! ## A step too coarse: a declared domain
//!
//! A variational step solves its equations `D2 L_d(q_{k−1}, q_k) + D1 L_d(q_k, q_{k+1}) = 0`
//! (Definition 2.7; eqs. (4.6)/(4.8) reduced) wherever they have a solution, and they know
//! nothing of where the Lagrangian means anything. Kepler's problem in polar coordinates,
//! `L = ½ (ṙ² + r² φ̇²) + k/r`, at `e = 0.9` and `h = 0.2` (about five steps for the periapsis
//! passage): the sixth step converges, residual at round-off, to `r = −0.63`, and the run goes
//! on outward through negative radii (`r = −55` after fifty steps) — every step converged, every
//! momentum conserved, nothing wrong that the step can see. What is wrong is the time step: it
//! is too coarse for the motion at periapsis. A coarse step shows as states that leave the
//! region where the coordinates mean something, an energy error that jumps at one passage, or
//! Newton needing many more iterations there (`stats[k].iterations`).
//!
//! Declare the domain and every integrator checks it: `domain(r > 0.0)` in the attribute (bounds
//! `<coordinate> <op> <number>` with `>`, `>=`, `<`, `<=`, several separated by commas, on shape
//! or group coordinates; a whole array coordinate bounds each component). The initial state is
//! checked before the first step and every new state after its step, by the plain steps, both
//! reduced sides, the unreduced and constrained steps and the compositions alike (and a system
//! given as text with the same key); the first state outside ends the run with
//! `StepError::OutOfDomain`, the states before it kept. Then take a smaller step, or adaptive
//! steps (`time(t), adapt = |q| q.r.powf(1.5)`, [adaptive steps](super::adaptive_steps)), which
//! shorten the step where the motion is fast. [`Kepler`](crate::systems::kepler::Kepler)
//! declares its domain:
//!
//! ```
//! use dirac::prelude::*;
//! use dirac::systems::kepler::Kepler;
//!
//! let coarse = Kepler::unit(0.2);
//! let start = coarse.periapsis_state(1.0, 0.9);
//! let e = ReducedIntegrator::plus(coarse, NewtonOptions::default())
//!     .run(start).steps(50).collect()
//!     .unwrap_err();
//! let StepError::OutOfDomain { step, ref coordinate, value, .. } = e.source else {
//!     panic!("expected OutOfDomain, got {}", e.source);
//! };
//! assert_eq!((step, coordinate.as_str()), (5, "r"));
//! assert!(value < 0.0);
//! assert_eq!(e.trajectory.states.len(), 6); // the start and five steps, all with r > 0
//!
//! // A step that resolves the passage runs on.
//! let fine = Kepler::unit(0.01);
//! let traj = ReducedIntegrator::plus(fine, NewtonOptions::default())
//!     .run(fine.periapsis_state(1.0, 0.9)).steps(700).collect()?;
//! assert!(traj.states.iter().all(|s| s.x[0] > 0.09));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! ## Compile errors
//!
//! The attributes check what they are given before they emit anything, and report every mistake
//! in one annotation at once, each at its token. The messages say what was found, what is
//! accepted, and where:
//!
//! * the attribute's keys (`shape`, `group`, `coordinates`, `translate`, `connection`, `step`,
//!   `name`, `ranges`, `rule`): an unknown or duplicate key, a malformed list;
//! * the signature: `q0: Config, q1: Config` (or `q: Config, v: Velocity` with a `rule`) and
//!   `f64` parameters;
//! * the body: any construct outside the body language (`if`, `match`, closures, macros,
//!   references, `return`, unknown names, loops over non-constant ranges), array indices out of
//!   range or not constant;
//! * the symmetry: a body that is not invariant under translation of a group coordinate (or a
//!   declared translation), with the coordinate, the sample point and the two values; a body
//!   that is not finite at any sample point;
//! * `#[chart_transition]`: a map that is not equivariant (`x' = ψ(x)`, `g' = g + c(x)`).
//!
//! A potential in the group coordinate itself is not invariant under its translation:
//!
//! ```compile_fail
//! use dirac::prelude::*;
//!
//! #[reduced_lagrangian(shape(x), group(theta))]
//! fn particle(q0: Config, q1: Config, h: f64, m: f64) -> f64 {
//!     let (dx, dg) = (q1.x - q0.x, q1.theta - q0.theta);
//!     0.5 * m / h * (dx * dx + dg * dg) - h * q0.theta.cos()
//! }
//! # fn main() {}
//! ```
//!
//! ```text
//! error: the discrete Lagrangian is not invariant under translation of the group coordinate `theta`:
//!        at q0 = (x = -0.367, theta = 1.5), q1 = (x = 1.67, theta = -1.67), h = 1.8, m = 1.9, shifting
//!        `theta` by 0.37 in both `q0` and `q1` changes L_d from 7.3662 to 8.0241; `#[reduced_lagrangian]`
//!        reduces by translations of the group coordinates, so L_d may depend on them only through
//!        differences such as `q1.theta - q0.theta`; if L_d depends on `theta` itself, declare it in
//!        `shape(...)`
//!  --> src/main.rs:3:38
//!   |
//! 3 | #[reduced_lagrangian(shape(x), group(theta))]
//!   |                                      ^^^^^
//! ```
//!
//! The workspace keeps one compile-fail case per mistake, with its expected message, under
//! `tests/ui/`.
