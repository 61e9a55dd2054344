//! # Constraints
//!
//! The paper treats only unconstrained systems (`Δ_Q = TQ`); dirac adds the two kinds of
//! constraints that discrete Dirac mechanics was built for (Leok & Ohsawa's discrete Dirac
//! structures with a constraint distribution), on continuous Lagrangians:
//!
//! * **Holonomic**, `constraints = |q| [φ_1, …, φ_m]` with `φ(q) = 0`: a pendulum in Cartesian
//!   coordinates, a closed kinematic loop, a multibody chain in maximal coordinates.
//! * **Nonholonomic**, `nonholonomic = |q, v| [A_1(q) v, …]`, linear in the velocities (checked at
//!   compile time): a rolling disk, a Chaplygin sleigh, a knife edge.
//!
//! Each step solves two saddle-point (KKT) systems by the one Newton driver, on the dense or the
//! sparse backend by size:
//!
//! ```text
//! position    p_k + D1 L_d(q_k, q_{k+1}) + f_d^− − A(q_k)ᵀ λ_k = 0,   c(q_k, q_{k+1}) = 0
//! momentum    p̃ = D2 L_d(q_k, q_{k+1}) + f_d^+
//! projection  ∂L/∂v(q_{k+1}, v) − A(q_{k+1})ᵀ ν = p̃,   A(q_{k+1}) v = 0,   p_{k+1} = ∂L/∂v(q_{k+1}, v)
//! ```
//!
//! with `A = Dφ` and `c = φ(q_{k+1})` for holonomic constraints (SHAKE for the positions,
//! RATTLE's projection for the momenta, Marsden & West §3.5), and for nonholonomic ones the
//! discrete constraint imposed at the midpoint, `c = A((q_k + q_{k+1})/2) (q_{k+1} − q_k)/h`
//! (McLachlan & Perlmutter's discrete Lagrange–d'Alembert integrator): symmetric, so the step is
//! time-reversible and of order 2, and exact for constraints that do not depend on `q`. The
//! projection does not change the positions (a multiple of `A(q_k)ᵀ` in `p_k` is absorbed by
//! `λ_k`): it picks the momentum whose velocity satisfies the constraints, so energies and
//! velocities read from the state are those of the constrained motion.
//!
//! [`ConstrainedIntegrator`](crate::ConstrainedIntegrator) integrates the unreduced equations;
//! [`ReducedConstrainedIntegrator`](crate::ReducedConstrainedIntegrator) the reduced (+) and (−)
//! ones, for constraints invariant under the symmetry (the compiler samples the invariance, as
//! for the Lagrangian). A holonomic invariant constraint has no group component, so `μ` stays
//! bit for bit constant (or follows the forced Noether balance); a nonholonomic one generally
//! does, and `μ` then follows the **discrete nonholonomic momentum equation**: it changes by the
//! group component of the constraint impulses (it is conserved when the symmetry is
//! horizontal). Each step reports its multipliers `λ_k`, `ν_{k+1}` and its constraint residual;
//! a holonomic run checks `φ(q_0) = 0` first ([`StepError::ConstraintViolated`](crate::StepError)).
//!
//! ```
//! use dirac::prelude::*;
//!
//! /// A pendulum in Cartesian coordinates.
//! #[reduced_lagrangian(shape(x, y), group(), rule = midpoint,
//!     constraints = |q| [q.x * q.x + q.y * q.y - l * l])]
//! fn pendulum(q: Config, v: Velocity, m: f64, l: f64) -> f64 {
//!     0.5 * m * (v.x * v.x + v.y * v.y) - 9.81 * m * q.y
//! }
//!
//! let sys = Pendulum { h: 0.01, m: 1.0, l: 1.0 };
//! let start = UnreducedState::new([1.0, 0.0], [0.0, 0.0]);
//! let traj = ConstrainedIntegrator::new(sys, NewtonOptions::default())
//!     .run(start).steps(1000).collect()
//!     .unwrap();
//! assert!(traj.max_constraint_residual() < 1e-10); // on the circle at every step, to the Newton tolerance
//! let tension = traj.records[500].lambda[0]; // the rod's multiplier at step 500
//! assert!(tension.is_finite());
//!
//! /// The Chaplygin sleigh: no sideways slip at a knife edge `a` behind the centre of mass.
//! #[reduced_lagrangian(shape(theta), group(x, y), rule = midpoint,
//!     nonholonomic = |q, v| [-q.theta.sin() * v.x + q.theta.cos() * v.y - a * v.theta])]
//! fn sleigh(_q: Config, v: Velocity, m: f64, i: f64, a: f64) -> f64 {
//!     0.5 * m * (v.x * v.x + v.y * v.y) + 0.5 * i * v.theta * v.theta
//! }
//!
//! let sys = Sleigh { h: 0.01, m: 1.0, i: 0.2, a: 0.5 };
//! let start = sys.trivialize(&UnreducedState::new([0.0; 3], [0.4, 0.2, 1.0]));
//! let traj = ReducedConstrainedIntegrator::plus(sys, NewtonOptions::default())
//!     .run(start).steps(2000).collect()
//!     .unwrap();
//! // The rotation dies out (ω = p_θ / I).
//! assert!((traj.last().w[0] / sys.i).abs() < 1e-3);
//! ```
//!
//! The examples: `cargo run --release --example cartesian_dsp` (the paper's double spherical
//! pendulum in Cartesian coordinates against the atlas run), `--example maximal_chain` (the
//! scaling chain in maximal coordinates, sparse), `--example nonholonomic` (the rolling disk at
//! order 2; the Chaplygin sleigh).
//!
//! Limits: constraints need a continuous Lagrangian (the projection uses its Legendre map);
//! compositions and the atlas take unconstrained steppers only (a constrained integrator is
//! neither [`SelfAdjoint`](crate::SelfAdjoint) nor a chart, so asking for one is a compile
//! error); step sensitivities are for unconstrained steps; the saddle-point systems are solved
//! by the general LU (on the sparse backend its pivoting limits how well long chains scale,
//! see `BENCHMARKS.md`).
