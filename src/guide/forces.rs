//! # Forces and controls
//!
//! A force enters the attribute as its **virtual work**: a closure, linear in the virtual
//! displacement, written in the body language (the configurations, the velocities of a
//! continuous Lagrangian and the parameters are in scope). It is differentiated at compile time
//! like the Lagrangian.
//!
//! * Continuous Lagrangian: `force = |dq| ⟨F(q, v), dq⟩`, e.g. `|dq| -c * v.x * dq.x`; the
//!   declared rule forms the discrete forces (midpoint: `f_d^− = f_d^+ = (h/2) F((q0+q1)/2, v)`;
//!   trapezoid, left and right as derived in the compiler's `ir::force`).
//! * Discrete Lagrangian: `force = |dq0, dq1| ⟨f_d^−, dq0⟩ + ⟨f_d^+, dq1⟩`.
//!
//! Each step then solves the forced discrete Lagrange–Dirac equations (Marsden & West's discrete
//! Lagrange–d'Alembert principle in position–momentum form)
//! `p_k = −D1 L_d − f_d^−`, `p_{k+1} = D2 L_d + f_d^+`, unreduced or reduced. For the reduction
//! the forces must be invariant under the symmetry, as the Lagrangian is (the compiler samples
//! it and rejects a force that is not, with its span). Then `μ` is no longer conserved: it obeys
//! the **forced discrete Noether balance** `μ_{k+1} − μ_k = f_{d,g}^− + f_{d,g}^+`, the group
//! component of the step's discrete impulse, applied explicitly by the reduced step so that it
//! holds to round-off at every step. Without a force on the group coordinates `μ` stays bit for
//! bit constant, and a system whose forces vanish integrates bit for bit as the same system
//! without `force`.
//!
//! **Controls** are parameters named in `controls(...)`: a run can set them before every step,
//! from a feedback law `.feedback(|k, t, state, u| …)` or a sequence
//! `.controls(`[`ControlSequence`](crate::ControlSequence)`::rows(&us))`, options of the one
//! configured [`Drive::run`](crate::Drive::run). Without a law a run uses
//! the values the system holds, like any parameter.
//!
//! **Sensitivities.** For a system with forces or controls, `sensitivity` and
//! `step_sensitivity` on the reduced and unreduced integrators give the derivative of one step
//! with respect to the state and the controls, `∂s_{k+1}/∂(s_k, u_k)`, by the implicit-function
//! theorem on the step residual with partial derivatives differentiated at compile time (dense
//! and sparse backends): what a linear-quadratic regulator, a Kalman filter or a trajectory
//! optimisation needs. The state is ordered `(x, w, μ, g)` reduced and `(q, p)` unreduced.
//!
//! ```
//! use dirac::prelude::*;
//!
//! /// A turntable (angle `phi`, a group coordinate) carrying a pendulum (angle `x`) with
//! /// damping, driven by a torque `tau` on the table: a control.
//! #[reduced_lagrangian(shape(x), group(phi), rule = midpoint, controls(tau),
//!     force = |dq| tau * dq.phi - c * v.x * dq.x)]
//! fn turntable(q: Config, v: Velocity, m: f64, l: f64, c: f64, tau: f64) -> f64 {
//!     let r = l * q.x.sin();
//!     0.5 * v.phi * v.phi + 0.5 * m * (l * l * v.x * v.x + r * r * v.phi * v.phi)
//!         + 9.81 * m * l * q.x.cos()
//! }
//!
//! let h = 0.01;
//! let sys = Turntable { h, m: 1.0, l: 0.5, c: 0.2, tau: 0.0 };
//! let integ = ReducedIntegrator::plus(sys, NewtonOptions::default());
//! let s0 = ReducedState::new([0.3], [0.0], [0.5], [0.0]);
//!
//! // A feedback law: a torque against the table's momentum.
//! let traj = integ
//!     .run(s0)
//!     .steps(1000)
//!     .feedback(|_k, _t, s, u| u[0] = -0.8 * s.mu[0])
//!     .collect()
//!     .unwrap();
//! // The forced Noether balance: μ changes by exactly the applied impulse h τ_k.
//! for pair in traj.states.windows(2) {
//!     let impulse = h * (-0.8 * pair[0].mu[0]);
//!     assert!((pair[1].mu[0] - pair[0].mu[0] - impulse).abs() < 1e-15);
//! }
//!
//! // The linearisation of one step, e.g. for an LQR design.
//! let (_, _, lin) = integ.step_sensitivity(0, &s0, &[0.1]).unwrap();
//! assert_eq!(lin.state.shape(), (4, 4)); // ∂(x, w, μ, g)_{1} / ∂(x, w, μ, g)_0
//! assert_eq!(lin.control.shape(), (4, 1)); // ∂(x, w, μ, g)_{1} / ∂τ_0
//! assert!((lin.control[(2, 0)] - h).abs() < 1e-15); // ∂μ_1/∂τ_0 = h
//! ```
//!
//! Limits: compositions take the stages' forces at each stage's time step (a symmetric rule's
//! forced step is self-adjoint when its forces are, as the midpoint rule's are); an atlas takes
//! each chart's forces in that chart's coordinates (a virtual work written the same way in every
//! chart is the cotangent lift of one force); the step-map Jacobian from the Hessian of `L_d`
//! ([`UnreducedIntegrator::step_jacobian`](crate::UnreducedIntegrator::step_jacobian)) is only
//! for systems without forces — a forced system uses the sensitivities.
//!
//! The examples:
//!
//! ```sh
//! cargo run --release --example forced        # damped, driven oscillator (order 2); a torque on a rotor: μ moves by h τ_k exactly
//! cargo run --release --example cartpole_lqr  # LQR designed on the step sensitivities stabilises the upright cart-pole
//! cargo run --release --example dmoc_cartpole -- --casadi  # DMOC swing-up against CasADi + IPOPT, same discrete problem
//! ```
