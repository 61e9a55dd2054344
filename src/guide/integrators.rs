//! # Integrators and the driver
//!
//! One annotated system gives four integrators, and every one of them is a
//! [`Stepper`](crate::Stepper): the one driver, [`Drive`](crate::Drive), gives all of them the
//! same configured run (`run(initial)`: steps or an end time, step sizes per step, stop
//! conditions, observers; collected or streamed) and ensembles.
//!
//! | integrator | state | what a step reports |
//! | --- | --- | --- |
//! | [`ReducedIntegrator::plus`](crate::ReducedIntegrator::plus) / [`minus`](crate::ReducedIntegrator::minus) | [`ReducedState`](crate::ReducedState) | [`ReducedStep`](crate::ReducedStep) `{ group_unknown, stats }` |
//! | [`UnreducedIntegrator::new`](crate::UnreducedIntegrator::new) | [`UnreducedState`](crate::UnreducedState) | [`StepStats`](crate::StepStats) |
//! | [`Composition::new`](crate::Composition::new)`(base, method)` | the base's | [`StepStats`](crate::StepStats), summed over the stages |
//! | [`AtlasIntegrator`](crate::AtlasIntegrator) | `(chart, ReducedState)` | [`AtlasStep`](crate::AtlasStep) `{ stats, rescue, switch }` |
//!
//! The constrained integrators ([Constraints](super::constraints)) and the integrator of
//! systems sized at run time ([Run-time sizes](super::run_time_sizes)) follow the same rules:
//!
//! * **Construction.** `new(system, options)` builds every integrator; where the paper has two
//!   sides, `plus` and `minus` name the side instead
//!   ([`ReducedIntegrator`](crate::ReducedIntegrator),
//!   [`ReducedConstrainedIntegrator`](crate::ReducedConstrainedIntegrator)). Wrappers take
//!   what they wrap: `Composition::new(base, method)`.
//! * **Initial states.** Every state constructor, and the systems'
//!   [`reduced_state(q, v)`](crate::ContinuousLagrangian::reduced_state) and
//!   [`unreduced_state(q, v)`](crate::ContinuousLagrangian::unreduced_state), takes arrays and
//!   nalgebra vectors alike; a state sized at run time also slices and `Vec`s
//!   ([`IntoVector`](crate::IntoVector)). Coordinates are listed in the order of the system's
//!   [`SHAPE`](crate::DiscreteLagrangian::SHAPE) followed by its
//!   [`GROUP`](crate::DiscreteLagrangian::GROUP).
//! * **Quantities.** `integ.momentum_map(&state)?` and `integ.energies(&traj)` (node and
//!   midpoint energies of a continuous Lagrangian, the nodes through the inverse Legendre map)
//!   on every integrator, constrained ones and those sized at run time included.
//! * **Derivatives of a step.** One type, [`Sensitivity`](crate::Sensitivity) (`∂s_{k+1}/∂s_k`
//!   and `∂s_{k+1}/∂u_k`), whether it comes from the step partials (`sensitivity`) or from the
//!   Hessian of `L_d` (`step_jacobian`).
//!
//! ## The reduced integrators: eqs. (4.6) and (4.8)
//!
//! `ReducedIntegrator::plus(system, options)` marches the reduced (+) discrete
//! Lagrange–Poincaré–Dirac equations (4.6), `::minus` the (−) ones (4.8). Each step solves for
//! the next shape `x_{k+1}` and a group unknown (`g_k^+`, resp. `g_{k+1}^−`) by Newton's method
//! on fixed-size nalgebra types, sets `μ_{k+1} = μ_k` exactly and reconstructs the group
//! coordinate. Newton starts from a guess extrapolated from the last steps (quadratic in the
//! shape, linear in the group unknown), with the tolerances and iteration cap of
//! [`NewtonOptions`](crate::NewtonOptions): by default `abs_tol = 1e-12`, `rel_tol = 1e-12`
//! (against the size of the momenta), `max_iterations = 50`, and `min_rcond = 1e-13`, the
//! smallest reciprocal condition number of a step Jacobian that is accepted (see
//! [Errors](super::errors)). The defaults sit near machine precision: loosening them trades the
//! structure (momentum, symplecticity) for speed.
//!
//! **A sign in the paper.** Equation (4.8) and the (−) action (2.12) carry the opposite momentum
//! sign to Definition 2.8 and Propositions 3.10, 4.4 (`p_k = +D1 L_d` against `−D1 L_d`). Taken
//! literally, (4.8) integrates the motion with reversed momenta. dirac's (−) stepper uses
//! Definition 2.8's signs: `w_k = −∂l_{d−}/∂x0`, `μ_k = −∂l_{d−}/∂g0`, `w_{k+1} = ∂l_{d−}/∂x1`.
//! With these, the (+) and (−) steppers give the same physical trajectory, the discrete
//! Euler–Lagrange solution, as the paper says they must. The derivation is in the
//! documentation of [`Minus`](crate::Minus).
//!
//! ## The unreduced integrator
//!
//! `UnreducedIntegrator::new(system, options)` integrates the discrete Lagrange–Dirac equations
//! on `Q` (Definitions 2.7/2.8; unconstrained, the (+) and (−) forms are the same equations) in
//! canonical coordinates `(q, p)`: the baseline that knows nothing of the symmetry, from the same
//! annotation. Its momentum map is conserved to the Newton tolerance per step, not exactly.
//! [`step_jacobian`](crate::UnreducedIntegrator::step_jacobian) gives the Jacobian of the step
//! map `(q_k, p_k) ↦ (q_{k+1}, p_{k+1})`, which is symplectic.
//!
//! ## Symmetric compositions: order 4 and 6
//!
//! A symmetric discrete Lagrangian, `L_d(q0, q1; −h) = −L_d(q1, q0; h)` (the midpoint and
//! trapezoidal rules), has a self-adjoint step of order 2.
//! [`Composition`](crate::Composition) composes it with substeps `γ_i h` into order 4
//! ([`CompositionMethod::TRIPLE_JUMP`](crate::CompositionMethod::TRIPLE_JUMP)) or 6 (Yoshida's
//! 7-stage [`YOSHIDA_6`](crate::CompositionMethod::YOSHIDA_6) and Kahan–Li's 9-stage
//! [`KAHAN_LI_6`](crate::CompositionMethod::KAHAN_LI_6)), for the reduced (+) and (−) and the
//! unreduced integrators alike; every stage is a variational step, so `μ` stays exact and the
//! step map symplectic
//! ([`Composition::step_with_jacobian`](crate::Composition::step_with_jacobian) multiplies the
//! stage Jacobians).
//!
//! Some `γ_i` are negative (the triple jump's −1.70): inside a composition a stage steps
//! backwards, which for a symmetric `L_d` is the inverse step. The user-facing step must still
//! be positive ([`StepError::InvalidTimeStep`](crate::StepError::InvalidTimeStep)). A
//! composition of a non-symmetric rule stays at the rule's order, so a run first checks
//! `L_d(q0, q1; −h) + L_d(q1, q0; h) = 0` at sample points near the initial state and fails with
//! [`StepError::NotSymmetric`](crate::StepError::NotSymmetric) otherwise. (The paper's charged
//! particle passes: its left-point rule is symmetric, because the vector potential of a constant
//! field is linear and antisymmetric — which is why Table 1 shows order 2.)
//!
//! Observed orders on Kepler (`e = 0.5`, one period, against Kepler's equation): 1.992, 3.991
//! (triple jump), 5.949 (Yoshida), 5.966 (Kahan–Li); with the trapezoidal rule 1.955, 3.975,
//! 5.957. `cargo run --release --example work_precision` plots error against wall time for both
//! paper-size test systems ([Benchmarks](super::benchmarks#compositions-error-against-wall-time)).
//!
//! ```
//! use dirac::systems::kepler::Kepler; // L = ½(ṙ² + r²φ̇²) + k/r, midpoint rule, φ the group coordinate
//! use dirac::paper::DoubleSphericalPendulum;
//! use dirac::prelude::*;
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! // (+) and (−): the same physical trajectory.
//! let sys = DoubleSphericalPendulum::paper();
//! let start = DoubleSphericalPendulum::paper_initial_state();
//! let plus = ReducedIntegrator::plus(sys, NewtonOptions::default()).run(start).steps(200).collect()?;
//! let minus = ReducedIntegrator::minus(sys, NewtonOptions::default()).run(start).steps(200).collect()?;
//! assert!((plus.last().x - minus.last().x).amax() < 1e-9);
//!
//! // One step from an explicit Newton guess, outside a run.
//! let integ = ReducedIntegrator::plus(sys, NewtonOptions::default());
//! let guess = SVector::from([2.25, 2.0, 3.0, 0.0]); // (x_{k+1}, g_k^+)
//! let (next, record) = integ.step_from(0, &start, &guess)?;
//! assert!((next.x - plus.states[1].x).amax() < 1e-12); // the step the run took, to round-off
//! println!("{} Newton corrections, residual {:e}", record.stats.iterations, record.stats.residual);
//!
//! // Order 6 on Kepler: one period of the e = 0.5 orbit in 100 steps.
//! let kepler = Kepler::unit(2.0 * std::f64::consts::PI / 100.0);
//! let order6 = Composition::new(
//!     ReducedIntegrator::plus(kepler, NewtonOptions::default()),
//!     CompositionMethod::KAHAN_LI_6,
//! );
//! let initial = kepler.periapsis_state(1.0, 0.5);
//! let traj = order6.run(initial).steps(100).collect()?;
//! assert!((traj.last().x[0] - 0.5).abs() < 1e-6); // back at periapsis
//! assert_eq!(traj.last().mu, initial.mu); // μ exact through negative substeps too
//!
//! // The unreduced composition, and its symplectic step map.
//! let unreduced = Composition::new(
//!     UnreducedIntegrator::new(kepler, NewtonOptions::default()),
//!     CompositionMethod::TRIPLE_JUMP,
//! );
//! let (_, m) = unreduced.step_with_jacobian(0, &kepler.untrivialize(&initial))?;
//! assert!(m.symplecticity_defect() < 1e-12);
//! # Ok(())
//! # }
//! ```
//!
//! ## An atlas of charts (§6)
//!
//! One chart of `S² × S²` cannot hold the double spherical pendulum: in the paper's coordinates
//! it stops at step 725,521 (Remark 7.1). §6 of the paper says to change chart "whenever it is
//! necessary". Each chart is an annotated Lagrangian in its own coordinates with the same group
//! acting by translation; a change of chart is a Rust function annotated with
//! `#[chart_transition]`, compiled like a Lagrangian into straight-line code for `φ` and `Dφ`, and
//! checked at compile time to be equivariant (`x' = ψ(x)`, `g' = g + c(x)`; a compile error
//! otherwise):
//!
//! ```text
//! #[chart_transition(
//!     from(shape(phi1, a2, b2), group(th1)),     // the old chart's coordinates
//!     to(shape(phi1, vt2, phi2), group(vt1)),    // the new chart's, same numbers S and K
//!     name = Bob1FrameToPaper,                   // optional (default: CamelCase of the fn name)
//! )]
//! fn bob1_frame_to_paper(q: Config) -> (f64, f64, f64, f64) { /* new coordinates, in order */ }
//! ```
//!
//! A switch maps the state by the cotangent lift `p' = Dφ^{-T} p`: in the reduced variables
//! `x' = ψ(x)`, `μ' = μ` (copied), `w' = Dψ^{-T}(w − B_oldᵀμ − Dcᵀμ) + B_newᵀμ`, `g' = g + c(x)`
//! (derivation in [`crate::runtime::atlas`]). [`AtlasIntegrator`](crate::AtlasIntegrator)
//! switches when a user-supplied quality indicator falls below a threshold
//! ([`with_quality`](crate::AtlasIntegrator::with_quality); for the pendulum the distance to the
//! chart's singular set, below [`SWITCH_BELOW`](crate::paper::atlas::SWITCH_BELOW) = 0.3), or,
//! without one, when the step Jacobian's conditioning does
//! ([`with_conditioning`](crate::AtlasIntegrator::with_conditioning)); it records every switch
//! ([`Switch`](crate::Switch): step, from, to, the state before and after), retries a failed step
//! in another chart, and keeps the typed-error guarantee. Its state is `(chart, state)`.
//!
//! [`crate::paper::atlas`] is the pendulum on three charts: the paper's, and two that take the
//! azimuth of one link as the group coordinate and measure the other link's direction in that
//! link's rotating frame from a horizontal pole, so they are regular where the paper's chart is
//! not; where both links are vertical the action is not free and the step is a typed error.
//! From the paper's own initial state it runs 10⁶ steps at `h = 0.01` with 933 switches and no
//! failed step (`cargo run --release --example double_spherical_pendulum_atlas`; the measured
//! figures are in [Benchmarks](super::benchmarks#the-double-spherical-pendulum-on-its-atlas)).
//!
//! ```
//! use dirac::paper::atlas::PAPER;
//! use dirac::paper::DoubleSphericalPendulum;
//! use dirac::prelude::*;
//!
//! /// Link-1 frame → the paper's chart (dirac::paper::atlas has all six transitions).
//! #[chart_transition(from(shape(phi1, a2, b2), group(th1)), to(shape(phi1, vt2, phi2), group(vt1)))]
//! fn bob1_frame_to_paper(q: Config) -> (f64, f64, f64, f64) {
//!     let u = [q.a2.sin() * q.b2.cos(), q.a2.cos(), q.a2.sin() * q.b2.sin()];
//!     let d = u[1].atan2(u[0]);
//!     (q.phi1, 0.5 * d, (u[0] * u[0] + u[1] * u[1]).sqrt().atan2(u[2]), q.th1 + 0.5 * d)
//! }
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let sys = DoubleSphericalPendulum::paper();
//! let atlas = sys.atlas(NewtonOptions::default()); // three charts, six transitions
//! let traj = atlas.run((PAPER, DoubleSphericalPendulum::paper_initial_state())).steps(1000).collect()?;
//! assert!(traj.switches.iter().all(|s| s.after.mu == s.before.mu)); // μ carried over exactly
//! let (chart, last) = traj.last();
//! println!("after 1000 steps: chart {chart}, {} switches, x = {}", traj.switches.len(), last.x);
//! let _: &dyn ChartTransition<3, 1, 4> = &Bob1FrameToPaper; // what the attribute emits
//! # Ok(())
//! # }
//! ```
//!
//! ## The driver: one run, configured
//!
//! [`Drive::run`](crate::Drive::run) is the one entry of every integrator (reduced, unreduced,
//! composed, atlas, constrained, element-wise). It returns a [`Run`](crate::Run), configured by
//! options and finished in one of two ways:
//!
//! * a length: `.steps(n)`, `.end_time(t)` (reached exactly: the last step is shortened to land
//!   on it) or both (whichever comes first); `.start_time(t0)` sets the clock of the initial
//!   state (default 0);
//! * the size of each step, one way for each kind of input: a list with
//!   `.step_size(StepSizes(&hs))`, a closure computed as the run goes with
//!   `.schedule(|k, t, state| h_k)` (see below; default [`Fixed`](crate::Fixed), the system's
//!   own `h`);
//! * `.feedback(|k, t, state, u| ..)` or `.controls(ControlSequence::rows(&us))`: the controls of
//!   each step, for a system that declares them (see [Forces and controls](super::forces));
//! * `.stop(|k, t, state| ..)`: end after the first state `k` where it holds (the result then
//!   has `stopped` set);
//! * `.observe(|k, t, state, record| ..)`: every state as it is computed, at its time `t`, with
//!   the record of the step that produced it (`None` for the initial state); `.every(k)` shows
//!   the observer every `k`-th state and the last;
//! * `.collect()` keeps every state and every step's record, with the time of each state
//!   (`traj.times[k]`); `.stream()` keeps nothing, so memory does not grow with the number of
//!   steps, and returns a [`RunSummary`](crate::RunSummary): the last state and its time,
//!   Newton corrections and factorizations, the largest residual, the worst conditioning.
//!
//! [`Drive::ensemble`](crate::Drive::ensemble)`(&initials)` runs many initial states the same
//! way on rayon's thread pool (`.threads(n)` for a pool of its own), one workspace per member,
//! each member with its own typed result in input order, bit for bit the member's own run;
//! [`parameters`](crate::runtime::driver::parameters)`(&params, |p| (integrator, initial))` is
//! the ensemble over parameter sets. Both take the options above that apply to every member
//! and finish with `.collect()` or `.stream(|member| observer)`.
//!
//! A run checks its inputs first (a length, a positive finite time step, finite parameters and
//! state, a symmetric rule for a composition), builds one workspace (the linear-solver
//! workspaces and the memory Newton's guess extrapolates from) and steps in it, so after the
//! first step no step allocates. A failed step ends the run with a typed error that keeps what
//! was computed: see [Errors](super::errors).
//!
//! ```
//! use dirac::systems::kepler::Kepler;
//! use dirac::prelude::*;
//! use dirac::runtime::driver::parameters;
//! use std::sync::Mutex;
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let sys = Kepler::unit(0.01);
//! let integ = Composition::new(
//!     ReducedIntegrator::plus(sys, NewtonOptions::default()),
//!     CompositionMethod::TRIPLE_JUMP,
//! );
//! let start = sys.periapsis_state(1.0, 0.5);
//!
//! // Streamed: the largest radius seen, in constant memory.
//! let mut r_max = 0.0_f64;
//! let summary = integ
//!     .run(start)
//!     .steps(1000)
//!     .observe(|_, _, state, _| r_max = r_max.max(state.x[0]))
//!     .stream()?;
//! assert!((r_max - 1.5).abs() < 1e-3); // apoapsis a (1 + e)
//! assert_eq!((summary.step_count, summary.t), (1000, 1000.0 * 0.01));
//! println!("{:.2} Newton corrections per step", summary.mean_iterations());
//!
//! // Stop at the first state past apoapsis (p_r = w turns negative).
//! let half = integ.run(start).steps(1000).stop(|_, _, s| s.w[0] < 0.0).collect()?;
//! assert!((half.times[half.step_count()] - std::f64::consts::PI).abs() < 0.02);
//!
//! // Up to t = 1.005 exactly: 100 steps of h and a last one of 0.005.
//! let to_end = integ.run(start).end_time(1.005).collect()?;
//! assert_eq!((to_end.step_count(), *to_end.times.last().unwrap()), (101, 1.005));
//!
//! // Ensembles: three eccentricities in parallel, each its own result, in input order.
//! let starts: Vec<_> = [0.1, 0.3, 0.5].iter().map(|&e| sys.periapsis_state(1.0, e)).collect();
//! let members = integ.ensemble(&starts).steps(100).collect();
//! assert!(members.iter().all(|m| m.is_ok()));
//! // Streamed members: each observer gets its member's index and writes to its own slot.
//! let r_min: Vec<Mutex<f64>> = starts.iter().map(|_| Mutex::new(f64::INFINITY)).collect();
//! let summaries = integ.ensemble(&starts).steps(1000).threads(2).stream(|member| {
//!     let slot = &r_min[member];
//!     move |_: usize, _: f64, s: &ReducedState<1, 1>, _: Option<&StepStats>| {
//!         let mut r = slot.lock().unwrap();
//!         *r = r.min(s.x[0]);
//!     }
//! });
//! assert!(summaries.iter().all(|(_, summary)| summary.is_ok()));
//! for (r, e) in r_min.iter().zip([0.1, 0.3, 0.5]) {
//!     assert!((*r.lock().unwrap() - (1.0 - e)).abs() < 1e-6); // periapsis a (1 − e)
//! }
//!
//! // An ensemble over parameters: one system per force constant k.
//! let results = parameters(&[0.5, 1.0, 2.0], |&k| {
//!     let sys = Kepler { h: 0.01, k };
//!     (ReducedIntegrator::plus(sys, NewtonOptions::default()), sys.periapsis_state(1.0, 0.2))
//! })
//! .steps(100)
//! .collect();
//! assert!(results.iter().all(|r| r.is_ok()));
//! # Ok(())
//! # }
//! ```
//!
//! ## Step sizes per step
//!
//! The time step `h` of a system is the default size of its steps. A run may give each step its
//! own size `h_k`: a precomputed [`StepSizes`](crate::StepSizes)`(&sizes)` or a closure
//! `.schedule(|k, t, state| h_k)`; state `k` is then at `t_k = t_0 + Σ_{j<k} h_j` (with the
//! default, `t_k = t_0 + k h` exactly, and the run is the fixed-step run bit for bit).
//!
//! Step `k` is the step of the discrete Lagrangian at that size, `L_d(q_k, q_{k+1}; h_k)`: the
//! system with its time-step parameter set to `h_k`. What a variational step keeps, it keeps for
//! every `h_k`:
//!
//! * **symplecticity**: the map `(q_k, p_k) ↦ (q_{k+1}, p_{k+1})` defined by
//!   `p_k = −D_1 L_d(q_k, q_{k+1}; h_k)`, `p_{k+1} = D_2 L_d(q_k, q_{k+1}; h_k)` has the
//!   generating function `L_d(·, ·; h_k)`, so it preserves the canonical symplectic form; a
//!   sequence of such maps is a composition of symplectic maps;
//! * **momentum maps**: a symmetry of `L_d(·, ·; h)` for every `h` gives discrete Noether's
//!   theorem step by step, whatever the sizes; in the reduced equations `μ_{k+1} = μ_k` is one of
//!   the equations, so `μ` stays constant bit for bit;
//! * **order**: a schedule `h_k = h σ(t_k)` with smooth `σ` keeps the order of the method (each
//!   step's local error is `O(h_k^{r+1})`; a composition scales its stages `γ_i h_k`).
//!
//! What it does not keep in general is the long-time behaviour of the energy. The bounded energy
//! error of a fixed step comes from one modified Hamiltonian that every step preserves exactly
//! (backward error analysis); steps of different sizes preserve different ones, so a schedule
//! chosen independently of the dynamics may show an energy drift, and a step size that depends
//! on the state is not variational at all without a time transformation of the Lagrangian. A
//! smooth periodic schedule is harmless in practice.
//!
//! ```
//! use dirac::systems::kepler::Kepler;
//! use dirac::prelude::*;
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let (h, period) = (0.01, 2.0 * std::f64::consts::PI);
//! let sys = Kepler::unit(h);
//! let start = sys.periapsis_state(1.0, 0.5);
//! let traj = ReducedIntegrator::plus(sys, NewtonOptions::default())
//!     .run(start)
//!     .end_time(period)
//!     .schedule(|_, t, _| h * (1.0 + 0.5 * (t / period * 2.0 * std::f64::consts::PI).sin()))
//!     .collect()?;
//! assert_eq!(*traj.times.last().unwrap(), period); // the end time, exactly
//! assert!(traj.states.iter().all(|s| s.mu == start.mu)); // μ, bit for bit
//! println!("{} steps of sizes {} .. {}", traj.step_count(), traj.step_sizes[0], traj.step_sizes[300]);
//! # Ok(())
//! # }
//! ```
