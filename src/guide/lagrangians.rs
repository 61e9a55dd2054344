//! # Writing a Lagrangian
//!
//! A system is one Rust function annotated with `#[reduced_lagrangian(...)]`: it takes two
//! configurations and the parameters and returns the discrete Lagrangian `L_d(q0, q1)`, or takes
//! a configuration and a velocity and returns the Lagrangian `L(q, q̇)` together with a
//! quadrature rule. The attribute differentiates the body at compile time and emits a type that
//! every integrator of [`crate::runtime`] accepts.
//!
//! ## The attribute
//!
//! ```text
//! #[reduced_lagrangian(
//!     shape(x, y, z),               // shape coordinates x ∈ Σ (may be empty: `shape()`)
//!     group(theta),                 // group coordinates g ∈ G = R^K, translated by the symmetry
//!                                   //   (may be empty: `group()`, a system without symmetry)
//!     connection = [[0.0, b, 0.0]], // optional K × S matrix B: ω_d(q0, q1) = (g1 − g0) − B (x1 − x0)
//!     step = h,                     // optional: the time-step parameter (default: the one named `h`)
//!     name = ChargedParticle,       // optional: the emitted type (default: CamelCase of the fn name)
//!     ranges(h = (0.001, 0.1)),     // optional: where the invariance check samples a parameter
//!                                   //   or coordinate
//!     rule = midpoint,              // only for a continuous L(q: Config, v: Velocity, ...)
//! )]
//! fn name(q0: Config, q1: Config, h: f64, /* more f64 parameters */) -> f64 { /* L_d(q0, q1) */ }
//! ```
//!
//! Instead of `shape(...)`/`group(...)`, the symmetry may be declared on your own coordinates,
//! `coordinates(x[4], y[4]), translate(x), translate(y)`, and a coordinate may be an array,
//! `shape(x[3])`, read as `q0.x[i]`: see [Symmetries](super::symmetries).
//!
//! **The body** is a smooth subset of Rust: f64 literals, parameters, coordinates (`q0.x`),
//! `let` (with tuple destructuring, and `let mut` with `= += -= *= /=`), `+ - * /`, unary `-`,
//! blocks, tuples, arrays with constant indices, `for` loops over constant ranges (unrolled),
//! `as f64` on loop indices, `f64::consts`, and the f64 functions
//! `sin cos tan asin acos atan exp ln sqrt sinh cosh tanh recip powi powf atan2`, as methods
//! (`x.sin()`) or paths (`f64::sin(x)`). Anything else is a compile error that points at the
//! offending token and says what is accepted; every mistake in one annotation is reported at once
//! (see [Errors](super::errors#compile-errors)).
//!
//! **The symmetry is checked.** The Lagrangian must be invariant under translation of the group
//! coordinates: they may appear only through differences such as `q1.theta - q0.theta`. The
//! attribute evaluates the body at 16 fixed pseudo-random points (coordinates in `[−2, 2]`,
//! parameters in `[0.5, 2]`), translates one group coordinate at a time, and rejects a body that
//! changes, naming the coordinate and the point. Points where the body is not finite are skipped;
//! if it is defined only elsewhere, say where with `ranges(name = (lo, hi), ...)` (f64 literals,
//! for parameters or coordinates). The connection matrix must be finite at the sampled
//! parameters.
//!
//! ## Discrete Lagrangians, and systems without symmetry
//!
//! Write `L_d(q0, q1)` directly when you want to choose the discretization yourself — the
//! paper's charged particle ([`crate::paper::charged_particle`]) is written this way. The function
//! stays callable, with `Config` replaced by the emitted struct `<Name>Config`.
//!
//! `group()` declares no symmetry (`K = 0`): the same annotation then gives a plain variational
//! integrator for any Lagrangian — the unreduced stepper, the diagnostics, the step-map
//! Jacobian. The reduced steppers stay available and are the same equations (with `K = 0`,
//! eq. (4.6) is Definition 2.7 with `w = p`).
//!
//! ## Continuous Lagrangians with a rule
//!
//! Write the physics, `L(q, q̇)`, and name the quadrature rule; the attribute forms `L_d` on its
//! expression graph and everything downstream is unchanged. The second argument is
//! `v: Velocity` (fields as in `Config`), and `rule` is one of
//!
//! | `rule =` | `L_d(q0, q1)`, with `v = (q1 − q0)/h` |
//! | --- | --- |
//! | `midpoint` | `h L((q0 + q1)/2, v)` |
//! | `trapezoid` | `h/2 (L(q0, v) + L(q1, v))` |
//! | `left` | `h L(q0, v)` |
//! | `right` | `h L(q1, v)` |
//!
//! `L` need not take the time step; the emitted type has the field `h` either way (or the one
//! named by `step = ...`). The type also implements
//! [`ContinuousLagrangian`](crate::ContinuousLagrangian): the Legendre map `p = ∂L/∂v` and its
//! Jacobian, the energy `E(q, v) = ⟨∂L/∂v, v⟩ − L` (straight-line code, differentiated at compile
//! time), initial states from positions and velocities
//! ([`unreduced_state`](crate::ContinuousLagrangian::unreduced_state), and
//! [`reduced_state`](crate::ContinuousLagrangian::reduced_state), trivialized by (3.6)), and the
//! inverse Legendre map by Newton ([`velocity`](crate::ContinuousLagrangian::velocity)).
//! [`continuous_energies`](crate::continuous_energies) and
//! [`reduced_continuous_energies`](crate::reduced_continuous_energies) report `E` along a
//! trajectory, at the nodes (from the discrete momenta) and at the midpoints.
//!
//! [`crate::paper`] has both forms of the paper's systems:
//! [`charged_particle_continuous`](crate::paper::charged_particle_continuous) (left-point rule;
//! its steps agree with the hand-written `L_d` to a few ulps, because `h·½m(Δx/h)²` rounds
//! differently from `½m/h·Δx²`) and
//! [`double_spherical_pendulum_continuous`](crate::paper::double_spherical_pendulum_continuous)
//! (midpoint rule; the generated code and every step are bit for bit those of the hand-written
//! `L_d`).
//!
//! ## Degenerate Lagrangians
//!
//! A Lagrangian linear in the velocities goes through the same annotation; its momenta come from
//! positions alone (`p = ∂L/∂v` does not depend on `v`). Two point vortices reduced by rotations
//! (`cargo run --release --example point_vortices`) converge at the midpoint rule's order 2
//! against the exact rigid rotation, with the angular impulse `μ` exact. Where the discrete
//! Legendre map is singular (a massless charged particle in the Landau gauge with the left-point
//! rule) the step fails with a typed [`StepError`](crate::StepError); the inverse continuous
//! Legendre map fails with [`LegendreError::Singular`](crate::LegendreError::Singular).
//!
//! ## Three systems
//!
//! A discrete Lagrangian without symmetry (Hénon–Heiles), a degenerate continuous one with the
//! midpoint rule (two point vortices, reduced by rotations), and the paper's charged particle as
//! `L(q, q̇)` started from a velocity:
//!
//! ```
//! use dirac::paper::ChargedParticleContinuous;
//! use dirac::prelude::*;
//! use dirac::reduced_continuous_energies;
//!
//! /// The Hénon–Heiles system, midpoint rule, written as L_d; no symmetry.
//! #[reduced_lagrangian(shape(x, y), group())]
//! fn henon_heiles(q0: Config, q1: Config, h: f64) -> f64 {
//!     let (x, y) = (0.5 * (q0.x + q1.x), 0.5 * (q0.y + q1.y));
//!     let (vx, vy) = ((q1.x - q0.x) / h, (q1.y - q0.y) / h);
//!     h * (0.5 * (vx * vx + vy * vy) - 0.5 * (x * x + y * y) - x * x * y + y * y * y / 3.0)
//! }
//!
//! /// Two point vortices, L = −½ Σ Γ_j r_j² θ̇_j − H: linear in the velocities (degenerate).
//! /// θ1 = vt is translated by rotations; θ2 = vt + phi.
//! #[reduced_lagrangian(shape(r1, r2, phi), group(vt), rule = midpoint)]
//! fn vortex_pair(q: Config, v: Velocity, gamma1: f64, gamma2: f64) -> f64 {
//!     let d2 = q.r1 * q.r1 + q.r2 * q.r2 - 2.0 * q.r1 * q.r2 * q.phi.cos();
//!     let impulse_rate = gamma1 * q.r1 * q.r1 * v.vt + gamma2 * q.r2 * q.r2 * (v.vt + v.phi);
//!     -0.5 * impulse_rate + gamma1 * gamma2 / (4.0 * std::f64::consts::PI) * d2.ln()
//! }
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! // No symmetry: the plain variational integrator, and the Jacobian of its step map.
//! let integ = UnreducedIntegrator::new(HenonHeiles { h: 0.05 }, NewtonOptions::default());
//! let start = UnreducedState::new([0.1, -0.2], [0.3, 0.25]);
//! let traj = integ.run(start).steps(1000).collect()?;
//! let m = integ.step_jacobian(0, &traj.states[0], &traj.states[1])?;
//! assert!(m.symplecticity_defect() < 1e-12);
//! // The function stays callable, on the emitted configuration struct.
//! let origin = HenonHeilesConfig::default();
//! assert_eq!(henon_heiles(origin, origin, 0.05), 0.0);
//!
//! // Degenerate: the momenta come from the positions alone, so the velocity passed is unused.
//! let vortices = VortexPair { gamma1: 1.0, gamma2: 2.0, h: 0.05 };
//! let q = SVector::from([1.0, 0.8, 2.0, 0.3]);
//! let initial: ReducedState<3, 1> = vortices.reduced_state(q, SVector::zeros())?;
//! let traj = ReducedIntegrator::plus(vortices, NewtonOptions::default()).run(initial).steps(100).collect()?;
//! assert_eq!(traj.last().mu, initial.mu); // the angular impulse, exactly
//!
//! // The paper's charged particle as L_K(q, q̇) with the left-point rule: from q = 0 and
//! // q̇ = (1, 0, 1), θ̇ = 1, the paper's (w0, μ0) = ((1, 0, 1), 1).
//! let sys = ChargedParticleContinuous { m: 1.0, b0: 1.0, h: 0.1 };
//! let initial: ReducedState<3, 1> =
//!     sys.reduced_state(SVector::zeros(), SVector::from([1.0, 0.0, 1.0, 1.0]))?;
//! assert_eq!(initial, dirac::paper::ChargedParticle::paper_initial_state());
//! let traj = ReducedIntegrator::plus(sys, NewtonOptions::default()).run(initial).steps(200).collect()?;
//! let e = reduced_continuous_energies(&sys, &traj)?;
//! assert!((e.nodes[200] - e.nodes[0]).abs() < 1e-12); // E = ½|q̇|² + ½μ², conserved here
//! # Ok(())
//! # }
//! ```
//!
//! ## What the attribute emits
//!
//! Next to your function (which stays callable, with `Config` replaced by `<Name>Config`):
//!
//! * `<Name>Config` — one `f64` field per coordinate (`[f64; n]` for an array), shape first, then
//!   group (or your `coordinates(...)` in order);
//! * `<Name>` — one `f64` field per parameter, and `<Name>::GENERATED`, the operation counts of
//!   everything emitted;
//! * `impl` [`System`](crate::System) — what every system answers, whatever its kind: the
//!   parameters' names and values, the time step and the system at another
//!   (`with_time_step`), the controls and the system with them set (`with_controls`), the time
//!   coordinate of adaptive steps, the domain and the coordinates' names; a system on rotation
//!   groups, one sized at run time and one given as text answer the same trait;
//! * `impl` [`DiscreteLagrangian`](crate::DiscreteLagrangian) — the Lagrangian on vectors, the
//!   connection matrix, the trivialization of momenta (3.6)/(3.7) `trivialize`/`untrivialize`,
//!   the momentum map `J`, the discrete generalized energy (5.7);
//! * `impl` [`AdaptedCoordinates`](crate::AdaptedCoordinates) — the conversions of declared
//!   translations (the identity without `translate`);
//! * `impl` [`Reduced`](crate::Reduced)`<`[`Plus`](crate::Plus)`>` — the reduced Lagrangian
//!   `l_{d+}` (4.5), the residual of (4.6) in the unknowns `z = (x_{k+1}, g_k^+)` and its exact
//!   Jacobian from one straight-line function, the momentum update `w_{k+1} = ∂l_{d+}/∂x1`;
//!   `impl Reduced<`[`Minus`](crate::Minus)`>` the same for the (−) equations (4.7)–(4.8), in
//!   the unknowns `(x_{k+1}, g_{k+1}^−)`;
//! * `impl` [`Unreduced`](crate::Unreduced) — the unreduced discrete Lagrange–Dirac equations
//!   on `Q` (Definitions 2.7/2.8), and for systems of at most
//!   [`DENSE_MAX`](crate::runtime::linalg::DENSE_MAX) coordinates `impl`
//!   [`LagrangianHessian`](crate::LagrangianHessian), from which
//!   [`UnreducedIntegrator::step_jacobian`](crate::UnreducedIntegrator::step_jacobian) gives the
//!   Jacobian of the step map;
//! * for a continuous Lagrangian, `<Name>Velocity` and `impl`
//!   [`ContinuousLagrangian`](crate::ContinuousLagrangian).
//!
//! ## How the code is generated
//!
//! The body is lowered to a hash-consed expression graph (equal subexpressions are one node),
//! differentiated at compile time — in forward mode, or, for a system of 5 or more coordinates
//! whose gradient is clearly shorter that way (densely coupled ones, such as a chain of links),
//! by reverse accumulation with the Jacobians forward over reverse — and emitted as one
//! straight-line function per quantity; constants are folded, exact identities (`x + 0`, `x · 1`,
//! `c·x + (−c)·x = 0`, …) applied, structurally zero Jacobian entries never computed, and the
//! body's own arithmetic is never reassociated, so its value rounds as the expression you wrote. At run time there are no dual numbers, tapes,
//! interpreters or heap allocations in a step.
//!
//! Two optimizations go beyond the paper. (1) By G-invariance the reduced Lagrangian is the same
//! function whichever configuration carries the group origin; the compiler builds it at the
//! start, the midpoint and the end of the step and keeps the cheapest (for the double spherical
//! pendulum the midpoint: 745 instead of 863 operations for residual and Jacobian).
//! (2) *Momentum-level elimination*: when the momentum equations are affine in the group
//! unknowns — detected structurally, as for both paper examples — the compiler solves them in
//! closed form and Newton runs on the shape unknowns alone
//! ([`Reduced::ELIMINATES_GROUP`](crate::Reduced::ELIMINATES_GROUP)). It is the default where it
//! does not cost more code ([`Reduced::ELIMINATION_PAYS`](crate::Reduced::ELIMINATION_PAYS); for
//! the charged particle each step becomes linear, for the pendulum the eliminated system costs
//! 913 operations and the general path is kept); either path can be forced with
//! [`ReducedIntegrator::with_elimination`](crate::ReducedIntegrator::with_elimination), and both
//! give the same trajectory to round-off.
//!
//! ## Strict user crates
//!
//! The emitted items carry the lint allowances they need, each with its reason: folded constants
//! such as `2.0 * PI` are printed as `6.283185307179586`, which `clippy::approx_constant` flags
//! even inside macro output. A crate under `#![deny(warnings, clippy::all, clippy::pedantic)]`
//! that uses π, long literals and many parameters builds clean; the workspace checks one
//! (`tests/lint_clean/`, a workspace member):
//!
//! ```sh
//! cargo clippy --workspace -- -D warnings
//! ```
