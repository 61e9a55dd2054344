//! # Adaptive steps
//!
//! On an eccentric orbit, a close encounter or a pendulum passing near a pole, the time scale of
//! the motion changes by orders of magnitude along the run: a fixed step is too small for most
//! of it or too large where it matters. Feeding a variational step to an error controller breaks
//! what makes it worth using (the step map is no longer symplectic, the energy drifts). dirac
//! adapts the step the structure-preserving way: by a change of the time variable, made part of
//! the Lagrangian, so that a fixed step in a fictitious time `τ` is a variable step in physical
//! time and every integrator steps the result unchanged.
//!
//! ## Declaring it
//!
//! Declare physical time as a group coordinate `t` the body does not read, name it with
//! `time(t)`, and give the monitor `g(q) > 0` — the physical duration of a unit of fictitious
//! time, `dt = g(q) dτ` — with `adapt = |q| ..`, a function of the shape coordinates (and
//! parameters). The step parameter `h` is then the fictitious step `ε`:
//!
//! ```
//! use dirac::prelude::*;
//!
//! /// Kepler's problem in polar coordinates, the step following the free-fall time `r^{3/2}`.
//! #[reduced_lagrangian(shape(r), group(theta, t), time(t), adapt = |q| q.r.powf(1.5), rule = midpoint)]
//! fn kepler(q: Config, v: Velocity, k: f64) -> f64 {
//!     0.5 * (v.r * v.r + q.r * q.r * v.theta * v.theta) + k / q.r
//! }
//!
//! let sys = Kepler { h: 0.05, k: 1.0 };
//! // Periapsis of the orbit with e = 0.9 (semi-major axis 1): position (r, θ, t) and the
//! // physical velocity (ṙ, θ̇, 1). The state is put on the energy level, p_t = −E.
//! let (e, r0): (f64, f64) = (0.9, 0.1);
//! let start = sys.reduced_state([r0, 0.0, 0.0], [0.0, (1.0 - e * e).sqrt() / (r0 * r0), 1.0])?;
//! let period = 2.0 * std::f64::consts::PI;
//! let traj = ReducedIntegrator::plus(sys, NewtonOptions::default())
//!     .run(start)
//!     .end_time(period) // a physical time, landed on exactly
//!     .collect()?;
//! let last = traj.last();
//! assert!((last.g[1] - period).abs() < 1e-14);
//! // The angular momentum and p_t = −E are momenta of symmetries: copied bit for bit.
//! assert_eq!(last.mu, start.mu);
//! assert!((start.mu[1] - 0.5).abs() < 1e-12); // E = −1/(2a)
//! // The run's clock is physical time: short steps at periapsis, long ones at apoapsis.
//! assert_eq!(traj.times[3], traj.states[3].g[1]);
//! let dt = |k: usize| traj.times[k + 1] - traj.times[k]; // the physical steps Δt_k
//! assert!(dt(traj.step_count() / 2) > 20.0 * dt(0));
//! assert_eq!(traj.step_sizes[0], sys.h); // the fictitious step ε
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! The state's `g[1]` is the physical time `t_k` (reconstructed like any group coordinate), and
//! it is the run's clock: observers, stop conditions and a collected trajectory's `times[k]` see
//! the physical `t_k` (so `times[k + 1] − times[k]` is the physical step `Δt_k`), while its
//! `step_sizes[k]` are the fictitious steps `ε_k` the steps were taken with, as are the sizes a
//! `.schedule` gives; a run starts at the state's time (a `.start_time` other than it is
//! refused, with [`StepError::InvalidRun`](crate::StepError::InvalidRun): the state sets the
//! clock), and `.end_time(T)` is a physical time. The step that passes `T` is taken again with
//! the fictitious step that lands on it (found by the secant method, to a few ulp:
//! [`adaptive::land_at`](crate::runtime::adaptive::land_at), which you can also call yourself) —
//! a step of the same integrator, so the momenta stay exact. A monitor that
//! reads a group coordinate (it would break that symmetry and make steps depend on the origin of
//! time), a body that reads `t` (not autonomous) and a discrete Lagrangian are compile errors,
//! each at its token.
//!
//! With the symmetry declared on your own coordinates (`coordinates(..)`, `translate(..)`),
//! physical time is a coordinate translated alone, `coordinates(x[2], y[2], t), translate(x),
//! translate(y), translate(t), time(t)`, and the monitor may read anything the translations
//! leave unchanged (`q.x[1] - q.x[0]`), checked at sample points. States are built in the
//! adapted coordinates: `sys.reduced_state(Sys::to_adapted(&q), Sys::to_adapted(&u))`
//! (the map is linear, so it takes velocities too). Two bodies in the plane declared this way
//! keep their total momentum and `p_t` bit for bit and have order 2 against Kepler's equation
//! for their relative orbit.
//!
//! Constraints carry over unchanged: `φ(q) = 0` does not involve time, and `A(q) q̇ = 0` is
//! `A(q) q' = 0` in fictitious time. A pendulum held by a rod in Cartesian coordinates
//! (`constraints = |q| [q.x * q.x + q.y * q.y - 1.0]`, monitor `1.5 + y`) keeps its rod to
//! 1e-12, `p_t` bit for bit, and has order 2 against a tight solve of `θ'' = −g sin θ`; a skate
//! (`nonholonomic = |q, v| [q.theta.sin() * v.x - q.theta.cos() * v.y]`) follows its circle with
//! order 2, `p_t` kept to round-off (the constraint's impulse on the group momenta passes through
//! the step's residual).
//!
//! A `force = |dq| ..` (and controls) is transformed with the Lagrangian: the physical virtual
//! work `F·δq dt`, on a path whose time is varied too (`δq_phys = δq − q̇ δt`), is
//! `(t' F·δq − (F·q') δt) dτ`, so the force in fictitious time is `t' F(q, q'/t')` on the
//! coordinates and `−F·q'` — the power it delivers — on the time coordinate: `p_t = −E` then
//! changes by the work done, step by step (a damped oscillator keeps `−p_t` within `O(ε²)` of
//! its draining energy and has order 2 against its closed form). A force may not read `t` or act
//! on it.
//!
//! ## On rotation groups
//!
//! Rotations and directions take adaptive steps the same way, with a continuous Lagrangian in
//! the body angular velocity (`rule = trapezoid`, `left` or `right`): the compiler transforms
//! `L(q, v)` into `L₂` before the rule, with `v/t'` in place of each velocity (a rotation's body
//! angular velocity `Ω = cay⁻¹(R_kᵀ R_{k+1})/Δt` over the step's own physical duration), and the
//! Lie group step solves for the chart coordinates of the rotations and the time increment
//! together. The monitor may read rotations and directions — invariant under a declared
//! `symmetry(..)`, checked at compile time, so that the symmetry's momentum is kept:
//!
//! ```
//! use dirac::prelude::*;
//!
//! /// A spherical pendulum, its steps shorter near the bottom where it is fastest.
//! #[reduced_lagrangian(direction(n), group(t), rule = trapezoid, symmetry(n, axis = z),
//!     time(t), adapt = |q| 1.5 + q.n.z)]
//! fn swinging(q: Config, v: Velocity, g: f64) -> f64 {
//!     0.5 * v.n.dot(&v.n) - g * q.n.z
//! }
//!
//! let sys = Swinging { h: 0.02, g: 1.0 };
//! let (s, c) = 1.2_f64.sin_cos();
//! // The state at a physical position and velocity, on the energy level (p_t = −E).
//! let start = sys.unreduced_state(
//!     &SwingingConfig { n: Vector3::new(s, 0.0, -c), t: 0.0 },
//!     &SwingingVelocity { n: Vector3::new(0.0, 0.8, 0.0), t: 1.0 },
//! )?;
//! let integ = ReducedLieIntegrator::new(sys, NewtonOptions::default());
//! let traj = integ.run(integ.reduce(&start)).steps(500).collect()?;
//! let last = traj.last();
//! // The angular momentum about the vertical and p_t, bit for bit.
//! assert_eq!(last.mu, integ.reduce(&start).mu);
//! assert_eq!(last.p[2], start.p[2]);
//! assert!(sys.config(&last.unreduced()).t > 5.0); // physical time reached
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! `unreduced_state(q, v)`, emitted for such a system (the name and the `Result` of every
//! system's state from a position and a velocity), puts the physical configuration and
//! velocity on the level set: the momenta `∂L/∂v` (a rotation's body momentum, a direction's in
//! its tangent frame) and `p_t = −E(q, v)`. A run's first step starts Newton from the motion at
//! the physical step `ε g(q)` (the step's own equations solved with the time increment held),
//! since no motion is singular for `Δt L(q, ξ/Δt)`. Measured (`tests/adaptive_rotations.rs`): a
//! rigid body on a Kepler orbit with `e = 0.9` (its step following `r^{3/2}`) has order 2 and 4
//! (triple jump) against Kepler's equation and a tight Runge–Kutta solve of the attitude at the
//! physical time reached, `p_t` and the spatial angular momentum `π` bit for bit in the reduced
//! run (reduced and unreduced agree to 1e-9), forward then backward returns to the start, the
//! (−) steps equal the (+) ones; a spherical pendulum has order 2 with `μ` and `p_t` bit for bit,
//! and damped by `force = |dq| -c * v.n.dot(&dq.n)` has order 2 with `−p_t` within `O(ε²)` of its
//! draining energy.
//!
//! ## The time transformation
//!
//! With `dt = g(q) dτ`, the Poincaré Hamiltonian `K = g(q) (H(q, p) + p_t)` in the extended phase
//! space `(q, t, p, p_t)` has, on its level set `K = 0`, the physical solutions reparametrized:
//! `t' = g`, `p_t = −H` (Hairer 1997, "Variable time step integration with symplectic methods";
//! Duruisseaux, Schmitt & Leok 2021 for the variational form). `K` is degenerate in `p_t` and has
//! no Lagrangian; the regularization `K₂ = g (H + p_t) + ½ g (H + p_t)²` keeps the level set,
//! invariant and with the same flow on it (the added term vanishes there to second order), and
//! is regular. Its Legendre transform — the supremum over `p_t`, then over `p` — is
//!
//! ```text
//! L₂(q, t, q', t') = t' L(q, q'/t') + (t' − g(q))² / (2 g(q)),
//! ```
//!
//! which the compiler builds from your `L` and discretizes with your rule at the fictitious step
//! `ε`; for the midpoint rule, `L_d = Δt L(q̄, Δq/Δt) + (Δt − ε g(q̄))² / (2 ε g(q̄))`: the physical
//! discrete Lagrangian over a step of its own size `Δt`, and a term that holds `Δt` at `ε g`.
//! What is preserved follows from `L₂` being an ordinary Lagrangian on `(q, t)`:
//!
//! * the step map is symplectic in the extended phase space;
//! * a symmetric rule (midpoint, trapezoid) gives a symmetric, time-reversible step (forward
//!   then backward returns to the start to round-off), of order 2 in `ε`, raised to 4 and 6 by
//!   the compositions — against Kepler's closed form at `e = 0.9`, errors fall by 4.0 and 16 per
//!   halving of `ε`;
//! * `L₂` does not read `t`, so `p_t` is a conserved momentum, kept bit for bit by the reduced
//!   integrators, and every symmetry of `L` that `g` respects keeps its momentum the same way
//!   (the angular momentum above);
//! * the momenta conjugate to `q` are the physical ones, `∂L/∂v`, and the physical energy
//!   oscillates about `−p_t` without drift (its mean over the last tenth of a 40-orbit run lies
//!   within the spread of the first tenth). With the default Newton tolerance
//!   (`abs_tol = rel_tol = 1e-12`) this holds for the step itself over 1000 orbits of Kepler's
//!   problem at `e = 0.9` and `e = 0.99`, at `ε = 0.05` and down to `ε = 0.002` (the largest
//!   energy error of the last tenth within 1% of the first tenth's). A composition at a small
//!   `ε`, whose own energy error is far smaller, shows what each step leaves of Newton's
//!   tolerance: at `e = 0.99`, `ε = 0.01`, order 4, the largest error of the last tenth is 5.7
//!   times the first tenth's at `1e-12`, 1.3 times at `1e-14`. For long runs of a composition
//!   take `NewtonOptions { abs_tol: 1e-14, rel_tol: 1e-14, ..NewtonOptions::default() }`, as
//!   `examples/adaptive_kepler.rs` does (`tests/adaptive_drift.rs` measures all of these).
//!
//! A run must start on the level set `p_t = −E`:
//! [`sys.unreduced_state(q, v)`](crate::runtime::ContinuousLagrangian::unreduced_state) and
//! `sys.reduced_state(q, v)` build it from the physical position and velocity (for a system
//! with adaptive steps; the same calls start any system with a continuous Lagrangian). A start
//! off the level set would integrate another orbit, so every run checks it before the first
//! step, whatever the integrator, and refuses one farther from it than
//! [`LEVEL_SET_TOLERANCE`](crate::runtime::adaptive::LEVEL_SET_TOLERANCE) (`1e-8` relative to
//! the energy's terms) with [`StepError::OffManifold`](crate::StepError::OffManifold). Each new state's monitor must be positive and finite, or the
//! run ends with [`StepError::InvalidMonitor`](crate::StepError::InvalidMonitor) carrying the step
//! index (the states before it kept); and each step must move physical time forward: the step
//! equations also have roots with `Δt < 0`, which Newton can find when the fictitious step is
//! too large where the monitor is small, and such a step ends the run with
//! [`StepError::TimeReversed`](crate::StepError::TimeReversed).
//!
//! `cargo run --release --example adaptive_kepler` sets adaptive against fixed steps on Kepler's
//! problem at `e = 0.9` and `0.99`, orders 2 and 4: at `e = 0.9`, 100 orbits to a phase error of
//! 1e-6 take the adaptive triple jump 1.9·10⁶ force evaluations; the fixed one has not reached it
//! with 9.7·10⁷.
//!
//! `cargo run --release --example three_body` runs Burrau's Pythagorean problem (masses 3, 4, 5
//! at rest on a 3-4-5 triangle): with `g = (Σ 1/r_ij³)^{−1/2}` and `ε = 0.0005` it passes the
//! close encounters (down to `r = 4.1e-4`, physical steps from 2.7e-9 to 2.0e-3) to `t = 20` in
//! 60,527 steps with the energy within 2.6e-2 and `p_t` exact, where the fixed step with as many
//! steps fails at the first encounter (`t ≈ 1.88`).
//!
//! ## Choosing the monitor and the step
//!
//! The monitor is the time scale of the motion where the system is: `r^{3/2}` (the free-fall
//! time) or `r` for Kepler-like encounters, the distance to a pole for a pendulum in angles, a
//! minimum pair distance for close encounters. Scale it to be about 1 where the motion is
//! typical; then `ε` plays the role of a fixed step there, and halving it halves every physical
//! step (the error falls by `2^p` for a method of order `p`). A floor (`r.powf(1.5) + 1e-6`)
//! keeps the monitor positive through collisions.
//!
//! To ask for an accuracy rather than a step,
//! [`adaptive::step_for_tolerance`](crate::runtime::adaptive::step_for_tolerance) runs a pilot
//! — your closure, at `ε0` and `ε0/2`, returning what should be accurate — estimates the error
//! by Richardson extrapolation and scales the step for the method's order; on Kepler at
//! `e = 0.9` over one orbit the step it picks for 1e-4 (order 2) and 1e-6 (order 4) meets both.
//! Below a phase error of about 10⁻⁶ per hundred orbits of a very eccentric orbit (`e = 0.99`),
//! round-off in the position differences of short steps, not the step, limits the accuracy.
//!
//! ## Limits
//!
//! Not yet: systems sized at run time. The step
//! sizes a schedule gives (`.schedule(..)`) are fictitious steps. On rotation groups the Lagrangian must
//! be continuous (the transformation needs `L(q, v)`), as on flat coordinates.
