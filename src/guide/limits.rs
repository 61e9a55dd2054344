//! # Limits
//!
//! What the integrators do not do, and where their guarantees end.
//!
//! **Step sizes follow the dynamics only through a monitor.** A run takes the system's step `h`
//! or the sizes a schedule gives ([step sizes per step](super::integrators#step-sizes-per-step));
//! a schedule that depends on the state is not variational (the energy may drift). The
//! structure-preserving way is [adaptive steps](super::adaptive_steps) (`time(t), adapt = |q| g`):
//! the step follows a monitor you choose, not an error estimate, and is not yet available with
//! run-time sizes. Near a singularity of the coordinates (spherical coordinates at
//! a pole, Remark 7.1) a step can solve the discrete equations and still be physically
//! meaningless when `h` is too coarse there; the conditioning threshold catches degenerate
//! Jacobians, not coarse steps. In the paper's chart alone, the double spherical pendulum
//! started from the paper's initial state creeps ever closer to the poles and stops with a typed
//! error after 725,521 steps at `h = 0.01` (`t ≈ 7255`); on its atlas of three charts it runs 10⁶ steps from
//! the same state. The switching threshold of an atlas is a user choice: for the pendulum, lower
//! thresholds (0.1, 0.05) let steps pass close to a chart's pole and cost energy accuracy
//! ([`SWITCH_BELOW`](crate::paper::atlas::SWITCH_BELOW)). Chart transitions take no parameters.
//!
//! **Symmetries.** Groups act by translation of coordinates: abelian, with a linear connection
//! of constant `B`. The momentum-level elimination applies for `K ≤ 3` group coordinates.
//! [Rotation and direction coordinates](super::rotations#limits) are stepped on their group and
//! [reduced by rotations](super::rotation_reduction) (every rotation of one attitude, or the
//! rotations about a coordinate axis), have no constraints yet, and step
//! sensitivities up to 16 dimensions (of the unreduced step). The reduced step is not faster
//! than the unreduced Lie group step, which already solves in the chart at the current attitude.
//!
//! **The body language** is smooth by design: no branches, no calls to your own functions, no
//! run-time loop bounds or indices (see [Writing a Lagrangian](super::lagrangians#the-attribute)),
//! except in [systems sized at run time](super::run_time_sizes), whose loops over sizes are
//! compiled element by element (with that chapter's own limits).
//!
//! **Large systems** (more than [`DENSE_MAX`](crate::runtime::linalg::DENSE_MAX) = 16
//! coordinates, the sparse backend): no momentum-level elimination, no emitted Hessian blocks of
//! `L_d` (so no step-map Jacobian), and the conditioning check of a chord step applies to the
//! Jacobian whose factors it used, which may be an earlier step's. Compile time grows with the
//! size: a 64-link chain (dense 65 × 65 Jacobian, 21 k operations by reverse accumulation) takes
//! ≈ 30 s to build in release; a 1000-particle lattice ≈ 2 minutes. The lattice step is ≈ 2.4×
//! a hand-written `O(n)` solver ([Benchmarks](super::benchmarks#scaling-with-the-size-of-the-system)).
//!
//! **Forces and constraints.** Forces must be invariant under the symmetry for the reduced
//! steps (checked); a forced system has no step-map Jacobian from the Hessian of `L_d` (its
//! step sensitivities serve instead). Constraints need a continuous Lagrangian; constrained
//! integrators are neither compositions' stages nor atlas charts, and have no sensitivities; on
//! the sparse backend the saddle-point LU's pivoting makes long chains scale slightly worse than
//! linearly (slope 1.17 from 16 to 128 links). Systems sized at run time take holonomic
//! constraints on both sides, with forces and controls, but no nonholonomic ones. A long chain
//! hanging under gravity stiffens as it grows (its fastest transverse wave has `ω ∝ √n`): at
//! `h = 0.01` Newton stops converging from the extrapolated guess beyond a few hundred unit
//! links (a typed `NotConverged`), and `h ω` must be held (`h ∝ 1/√n`).
//!
//! **Speed against the paper.** The reduced stepper is 10–30% faster than the unreduced one on
//! the double spherical pendulum, not the paper's 75%: both solve four unknowns per step with
//! the same number of Newton iterations, and the reduced residual and Jacobian are 14% smaller.
//!
//! **Signed zeros.** The simplifier folds `−0.0` to `+0` and `x · 0` to `+0`; this can change
//! the *value* of `atan2` exactly on its branch cut (`x < 0`, `y = ±0`) by `2π` relative to IEEE
//! evaluation of the same expression. Derivatives are unaffected.
//!
//! **Newton tolerances.** With the default tolerances (`1e-12` on the momentum residual) each
//! stage of a composition leaves up to `1e-12` of momentum error, which floors long order-6 runs
//! near `1e-9`; tighter tolerances (`abs_tol = rel_tol = 1e-15`) move the floor to round-off.
