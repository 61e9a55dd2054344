//! # High order
//!
//! The discrete Lagrangians of the other chapters are second-order quadratures of `∫ L dt`, and
//! the compositions of [integrators](super::integrators) raise a self-adjoint step to order 4
//! or 6. For long, accurate runs — eccentric orbits, close encounters, error budgets near
//! machine precision — dirac also steps any continuous Lagrangian by the Gauss–Legendre
//! variational integrators of order `2s`, for any number of stages `s` up to 16: the Galerkin
//! discrete Lagrangian of `L` with polynomials of degree `s` and Gauss quadrature at `s` nodes,
//! which is the variational partitioned Runge–Kutta method of Gauss's coefficients (the
//! derivation is in [`crate::runtime::gauss`]).
//!
//! ## Running one
//!
//! Any system declared with `fn l(q: Config, v: Velocity, ..)` and a `rule = ..` (the rule is
//! the second-order step's; the Gauss step reads `L` itself) on at most 16 coordinates and
//! without constraints gets the stage derivatives the step needs, emitted as straight-line code
//! like everything else. [`GaussIntegrator::new`](crate::GaussIntegrator::new) takes the system,
//! the number of stages and the Newton options, and runs like every integrator:
//!
//! ```
//! use dirac::prelude::*;
//!
//! /// Kepler's problem in polar coordinates.
//! #[reduced_lagrangian(shape(r), group(theta), rule = midpoint)]
//! fn kepler(q: Config, v: Velocity, k: f64) -> f64 {
//!     0.5 * (v.r * v.r + q.r * q.r * v.theta * v.theta) + k / q.r
//! }
//!
//! // One orbit of eccentricity 0.5 (a = 1, period 2π) in 80 steps, order 8.
//! let period = 2.0 * std::f64::consts::PI;
//! let sys = Kepler { h: period / 80.0, k: 1.0 };
//! let start = sys.unreduced_state([0.5, 0.0], [0.0, 0.75f64.sqrt() / 0.25])?;
//! let gauss = GaussIntegrator::new(sys, 4, NewtonOptions::default())?;
//! let traj = gauss.run(start).end_time(period).collect()?;
//! let last = traj.states.last().unwrap();
//! // Back at periapsis after one period, to 1e-9 with 80 steps.
//! assert!((last.q[0] - 0.5).abs() < 1e-9 && (last.q[1] - period).abs() < 1e-9);
//! // The angular momentum, the momentum of the rotations, is kept bit for bit.
//! assert!(traj.states.iter().all(|s| s.p[1] == start.p[1]));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! The states are the unreduced `(q, p)` of [`UnreducedIntegrator`](crate::UnreducedIntegrator)
//! and the trajectories the same type, so energies, Parquet output, ensembles, step schedules
//! and exact end times work unchanged; controls and declared forces (`force = |dq| ..`) enter
//! each stage.
//!
//! ## Reduced states
//!
//! [`ReducedGaussIntegrator`](crate::ReducedGaussIntegrator) takes the same step on the reduced
//! states `(x, w, μ, g)` and trajectories of [`ReducedIntegrator`](crate::ReducedIntegrator),
//! for the (+) or the (−) reduced equations: the step reads the Lagrangian at `g = 0`, as the
//! reduced Lagrangians do, keeps `μ` by the momentum equation (bit for bit, even where the
//! Lagrangian reads a group coordinate it is invariant under only up to rounding), records the
//! side's group unknown and reconstructs `g`. Without constraints the two sides are the same
//! equations, and the two integrators give the same states:
//!
//! ```
//! use dirac::prelude::*;
//!
//! /// Kepler's problem in cylindrical coordinates, its shape momenta read through a connection.
//! #[reduced_lagrangian(shape(r, z), group(theta), connection = [[0.4, -0.3]], rule = midpoint)]
//! fn cylinder(q: Config, v: Velocity, k: f64) -> f64 {
//!     0.5 * (v.r * v.r + v.z * v.z + q.r * q.r * v.theta * v.theta)
//!         + k / (q.r * q.r + q.z * q.z).sqrt()
//! }
//!
//! let sys = Cylinder { h: 0.05, k: 1.0 };
//! let start = sys.trivialize(&sys.unreduced_state([1.0, 0.3, 0.0], [0.1, -0.2, 0.9])?);
//! let plus = ReducedGaussIntegrator::plus(sys, 4, NewtonOptions::default())?;
//! let minus = ReducedGaussIntegrator::minus(sys, 4, NewtonOptions::default())?;
//! let (a, b) = (
//!     plus.run(start).steps(200).collect()?,
//!     minus.run(start).steps(200).collect()?,
//! );
//! assert_eq!(a.states, b.states);
//! assert!(a.states.iter().all(|s| s.mu == start.mu));
//! // The group unknowns: g_k^+ on one side, g_{k+1}^- = −g_k^+ on the other.
//! assert_eq!(a.group_unknowns[7], -b.group_unknowns[7]);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! ## What is kept
//!
//! - **Symplecticity**: the step map is the discrete Legendre transform of a discrete Lagrangian
//!   ([`GaussIntegrator::step_jacobian`](crate::GaussIntegrator::step_jacobian) gives its
//!   Jacobian; its symplecticity defect is at round-off, checked in the tests).
//! - **Momenta of symmetries, bit for bit**: where `L` and the forces do not read a group
//!   coordinate, its force is the constant zero the compiler folds, and its momentum is copied
//!   from step to step — the discrete Noether theorem without rounding, for every order. The
//!   group coordinates themselves are reconstructed by the same sum as the others.
//! - **Order `2s` and self-adjointness**: observed in the tests at orders 2 to 12 on the
//!   harmonic oscillator, 2 to 8 on Kepler's problem, on a damped pendulum and on the paper's
//!   double spherical pendulum, and a step of `−h` undoing a step of `h` to round-off.
//! - **Adaptive steps at any order**: with `time(t), adapt = |q| g` the attribute's Lagrangian
//!   is the time-transformed one, and the Gauss step integrates it like any other: the
//!   fictitious step is fixed, the physical steps follow `g`, the energy level `p_t = −E` and
//!   every momentum are kept bit for bit.
//!
//! ```
//! use dirac::prelude::*;
//!
//! #[reduced_lagrangian(shape(r), group(theta, t), time(t), adapt = |q| q.r * q.r.sqrt(), rule = midpoint)]
//! fn kepler(q: Config, v: Velocity, k: f64) -> f64 {
//!     0.5 * (v.r * v.r + q.r * q.r * v.theta * v.theta) + k / q.r
//! }
//!
//! // Ten orbits at e = 0.9 at order 12, a fictitious step of 0.25 (about 34 steps an orbit).
//! let (e, r0) = (0.9f64, 0.1);
//! let sys = Kepler { h: 0.25, k: 1.0 };
//! let start = sys.unreduced_state([r0, 0.0, 0.0], [0.0, (1.0 - e * e).sqrt() / (r0 * r0), 1.0])?;
//! let gauss = GaussIntegrator::new(sys, 6, NewtonOptions::default())?;
//! let span = 10.0 * 2.0 * std::f64::consts::PI;
//! let traj = gauss.run(start).end_time(span).collect()?;
//! let last = traj.states.last().unwrap();
//! assert_eq!(last.q[2], span); // the physical time, landed on exactly
//! assert!((last.q[0] - r0).abs() < 1e-12); // at periapsis again
//! assert_eq!(last.p[2], start.p[2]); // p_t = −E, bit for bit
//! assert!(traj.step_count() < 400);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! ## Round-off
//!
//! At high order the step's truncation error falls below what the arithmetic resolves, and two
//! things decide the error floor instead:
//!
//! - **Newton's iteration.** The residual is accepted at `abs_tol + rel_tol · ρ`, `ρ` the size
//!   of the terms it balances (the momenta at the stages and the stages' forces times `h`, not
//!   only the momentum at the start). Past that, the step keeps correcting with the factors at
//!   hand as long as the corrections shrink (Hairer, McLachlan and Razakarivony's criterion), so
//!   the stage velocities are solved to round-off whatever the tolerance: a truncated iteration
//!   leaves an error of the same sign at every step, which over a long adaptive run is a linear
//!   energy drift (on Kepler's problem at e = 0.9 and order 12: 1.1e-11 after 1000 orbits
//!   without the extra corrections, 1.3e-14 with them). They cost one or two residual
//!   evaluations a step, with no Jacobian.
//! - **Summation.** Positions, momenta and the time coordinate are updated by adding increments
//!   with compensated summation (the rounding of each addition carried into the next step's
//!   increment), so a run of 10⁵ steps does not gather 10⁵ roundings of `|q|`.
//!
//! What is left is the rounding of each step: on Kepler's problem at e = 0.9 and order 12 the
//! energy error's mean over the first and last tenth of 1000 orbits is 5.7e-15 and 1.5e-14, and
//! over 10⁵ orbits it grows by about 6e-19 a step — below one rounding of the energy per step,
//! but a slow drift rather than the square-root growth of Brouwer's law (see the targets below).
//!
//! What remains is the conditioning of the problem itself: at e = 0.99 the energy of the start
//! (`v²/2 − 1/r`, 99.5 − 100) loses two digits to cancellation, which shifts the orbit's period
//! by about 1e-14 of itself — after 100 orbits a position error near 5e-10 at periapsis, for
//! any integrator started from the same rounded numbers (REBOUND's IAS15 included, see the
//! benchmark below).
//!
//! ## Against the integrators astronomers use
//!
//! `cargo run --release --example high_order` finds, for Kepler's problem at e = 0.9 and 0.99
//! over 10 and 100 orbits, the coarsest adaptive step of each order reaching a position error of
//! 1e-10 and counts its force evaluations (each Newton evaluation evaluates `∂L/∂q` at every
//! stage); `bash benches/rebound/run.sh` installs REBOUND in its own environment and runs its
//! IAS15 on the same problems beside it (without REBOUND the example says so and prints dirac's
//! figures alone). The figures are in [the benchmarks](super::benchmarks); the targets, each
//! met or not:
//!
//! - **e = 0.9, evaluations ≤ IAS15's for 1e-10 after 10 and 100 orbits:** met — order 12 uses
//!   0.60 and 0.57 of IAS15's, in 0.6–0.9 of its wall time, with errors far below the tolerance.
//! - **e = 0.99, ≤ 2 × IAS15's:** met after 10 orbits (0.98 ×, order 8). After 100 orbits
//!   neither integrator reaches 1e-10 (dirac's error stops at 7.5e-10, IAS15's at 8.6e-10): the
//!   conditioning of the start's energy described above bounds both.
//! - **10⁵ orbits at e = 0.9, the energy error of the last tenth within 1.2 × the first's:** not
//!   met — 25 to 27 × (IAS15: 19 ×). The error grows by about 6e-19 a step, below one rounding
//!   of the energy per step, after the corrections past the tolerance removed a drift 1000 times
//!   larger. It is not the rounding of the method's coefficients: applied as sums of two doubles
//!   they made the drift larger, not smaller (measured, and not kept); what is left is the
//!   rounding of the step's own arithmetic.
//! - **Fixed-step orders 2s ± 0.1 for s = 1…6 until the error reaches 1e-13:** met on the
//!   harmonic oscillator; on the paper's double spherical pendulum met for s = 1…4, and for
//!   s = 5 and 6 the slope over the whole range is 10.45 and 12.53 while single refinements
//!   scatter (9.5–13): from s = 5 the error falls from 1e-4 to the floor within a factor of 2 to
//!   3 in the step, before its leading term dominates
//!   (`cargo run --release --example high_order -- --pendulum`).
//! - **A stage costs ≤ 1.5 × the second-order step's residual evaluation:** met, 0.32 ×.
//!
//! ## Limits
//!
//! The Gauss step is available for systems on vector spaces on the dense backend (at most 16
//! coordinates) without constraints, on unreduced and reduced states: compiled in, given as text
//! (a `dirac_jit::JitSystem`, bit for bit as compiled in), from Python
//! (`system.run(params, steps, scheme="gauss", order=2s, ..)`) and from the command line
//! (`scheme = "gauss"` and `order = 2s` in a system file), at most 8 coordinates from those two
//! (their fixed-size instances). The others step at order 2, or at order 4 and 6 by
//! compositions:
//!
//! - **Holonomic constraints.** Gauss collocation of an index-3 system loses its order in the
//!   multipliers and positions; the structure-preserving high-order choice is the partitioned
//!   Lobatto IIIA–IIIB pair with the constraint at the end points (Jay's SPARK methods, and
//!   Hairer, Lubich & Wanner VII.5), a different family of stages not built here.
//! - **Rotation groups.** A Lie group Galerkin method interpolates in the Lie algebra through
//!   the exponential map, and its stage equations carry `dexp⁻¹` to the order of the method
//!   (Bogfjellmo & Marthinsen, "High-order symplectic partitioned Lie group methods"): the
//!   attribute's stage derivatives are for vector spaces, and this is not built either.
