//! # The paper's two systems
//!
//! dirac implements Rodríguez Abella & Leok, *Discrete Dirac reduction of implicit Lagrangian
//! systems with abelian symmetry groups*. Its §7 integrates two systems; both are in
//! [`crate::paper`], written with `#[reduced_lagrangian]` exactly as a user would write them, and
//! one command reproduces every table and figure of that section:
//!
//! ```sh
//! cargo run --release --example paper            # Table 1, Figures 1, 3, 4 and the summaries
//! cargo run --release --example paper -- --out DIR   # figures under DIR instead of target/dirac-figures
//! ```
//!
//! `cargo run --release --example charged_particle` and `... --example double_spherical_pendulum`
//! run one system each.
//!
//! What of the paper dirac implements: the reduced (+) and (−) discrete
//! Lagrange–Poincaré–Dirac equations (eqs. (4.6), (4.8)), the unreduced discrete Lagrange–Dirac
//! equations (Definitions 2.7, 2.8), the reduced Dirac structures, energies and action of §§3–5 as
//! [diagnostics](super::diagnostics), and the change of charts of §6; the example reproduces §7:
//! Table 1 to the printed digits and Figures 1, 3 and 4. Where the paper's (−) equations carry a
//! sign that reverses the momenta, dirac follows its Definition 2.8
//! ([Integrators](super::integrators) says why).
//!
//! ## The charged particle (§7.1, Table 1)
//!
//! A particle of mass `m` in the constant magnetic field `B = b0 ∂_z`, in Kaluza–Klein form: the
//! configuration is `(x, y, z, θ)`, the group `S¹` translates `θ`, and the conserved momentum `μ`
//! is the charge. [`ChargedParticle`](crate::paper::ChargedParticle) is the left-point rule of the
//! paper; [`ChargedParticle::paper`](crate::paper::ChargedParticle::paper) gives the paper's
//! parameters (`m = 1`, `b0 = 1`, `T = 20`) for a number of steps. The example prints Table 1:
//!
//! ```text
//!     N        h   |q(T) - q_N|      paper   order  Newton it.
//!    10   2.0000      1.67814e0     1.6781       -        1.00
//!    50   0.4000     2.59709e-1    0.25971   1.159        1.00
//!   100   0.2000     6.62574e-2    0.06626   1.971        1.00
//!   200   0.1000     1.66415e-2    0.01664   1.993        1.00
//!   400   0.0500     4.16510e-3          -   1.998        1.00
//!   800   0.0250     1.04157e-3          -   2.000        1.00
//! ```
//!
//! and writes `figure1.csv` and `figure1.svg` (exact and discrete trajectories, `N = 100`). One
//! Newton correction per step: the momentum equation is affine in the group unknown, so the
//! compiler solves it in closed form and each step is a linear system in the shape unknowns (see
//! [Writing a Lagrangian](super::lagrangians#how-the-code-is-generated)).
//!
//! ## The double spherical pendulum (§7.2, Figures 3–4)
//!
//! Two bobs on rigid links in a uniform field; the rotation about the vertical axis is the
//! symmetry. [`DoubleSphericalPendulum`](crate::paper::DoubleSphericalPendulum) is the midpoint
//! rule of the Lagrangian derived from the Cartesian positions of the bobs (the kinetic energy
//! printed in the paper has typesetting errors), in the paper's coordinates: shape
//! `(φ1, ϑ2, φ2)`, group `ϑ1`. The paper's run is `T = 100`, `N = 10⁴`, `m1 = 20`, `m2 = 35`,
//! `l1 = 500`, `l2 = 800`, `g = 9.8`, `q0 = (ϑ1, φ1, ϑ2, φ2) = (0, 9/4, 2, 3)`,
//! `(μ0, w0) = (0, 0, 1, 1)`. The example runs it with the reduced and with the unreduced
//! equations and writes Figure 3 (φ1; the second bob's XY trace) and Figure 4 (the discrete
//! energy, the physical energy `T + V`, and reduced minus unreduced discrete energy) as SVG and
//! CSV. Its summary:
//!
//! ```text
//!   discrete energy (E_d)_k = L_d(q_k, q_k+1) = h (T - V)
//!     spread max - min                             2.0434e3 (relative to |mean|: 3.836e-1)
//!   physical energy T + V at the step midpoints
//!     spread max - min                             4.6395e3 (relative to |mean|: 1.052e-2)
//!     drift: mean(last 10%) - mean(first 10%)      -3.4248e0 (-0.001 x spread)
//!   max |mu_k - mu_0|                              0
//!   Newton iterations per step                     mean 1.504, max 4
//!   min rcond of the step Jacobian                 5.719e-7 (step 6603, t = 66.03)
//!   max |q_reduced - q_unreduced|                  2.736e-8 (relative to max |q|: 3.330e-9)
//!   max |E_d reduced - E_d unreduced|              1.209e-6
//!   max |J(q_k, p_k) - J(q_0, p_0)| unreduced      4.267e-5 (reduced: exactly 0)
//!   wall time ratio unreduced / reduced            1.306 (best of 5 alternating runs each)
//! ```
//!
//! The discrete energy `L_d(q_k, q_{k+1}) = h (T − V)` oscillates with the motion, as in the
//! paper's Figure 4; the physical energy shows no drift, and its spread (dominated by the passages
//! within `|sin φ2| ≈ 1.6e-3` of the pole) shrinks as `h²`. The reduced integrator keeps `μ`
//! exactly — `μ_{k+1} = μ_k` is one of its equations — while the unreduced one lets its momentum
//! map drift by `4e-5`. The reduced stepper is 10–30% faster than the unreduced one here, not
//! the paper's 75%: both solve four unknowns per step with the same number of Newton
//! iterations, and the reduced residual and Jacobian are 14% smaller (745 against 862
//! operations). See [Benchmarks](super::benchmarks).
//!
//! In the paper's chart the pendulum cannot run for ever: from the paper's initial state it
//! creeps towards the poles of its spherical coordinates, where the rotation is not free
//! (Remark 7.1), and stops with a typed error after 725,521 steps (`t ≈ 7255`; the step where it
//! breaks depends on round-off, the motion being chaotic). On an atlas of three charts
//! ([`crate::paper::atlas`], see [Integrators](super::integrators#an-atlas-of-charts-6)) it runs
//! 10⁶ steps from the same state.
//!
//! ## Both systems in a few lines
//!
//! A row of Table 1, and 1000 steps of the pendulum with the reduced and the unreduced equations:
//!
//! ```
//! use dirac::paper::{ChargedParticle, DoubleSphericalPendulum, CHARGED_PARTICLE_T, TABLE_1};
//! use dirac::prelude::*;
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! // Table 1, N = 100: |q(T) − q_N| to the digits the paper prints.
//! let (n, printed) = TABLE_1[2];
//! let integ = ReducedIntegrator::plus(ChargedParticle::paper(n), NewtonOptions::default());
//! let traj = integ.run(ChargedParticle::paper_initial_state()).steps(n).collect()?;
//! let exact = ChargedParticle::exact_position(CHARGED_PARTICLE_T);
//! let error = (0..3).map(|i| (traj.last().x[i] - exact[i]).powi(2)).sum::<f64>().sqrt();
//! assert!((error - printed).abs() < 5e-6, "|q(T) − q_N| = {error}");
//! assert_eq!(traj.mean_iterations(), 1.0); // the group unknown is eliminated: one correction
//!
//! // The pendulum: the reduced run keeps μ exactly, the unreduced one to round-off per step.
//! let sys = DoubleSphericalPendulum::paper();
//! let start = DoubleSphericalPendulum::paper_initial_state();
//! let reduced = ReducedIntegrator::plus(sys, NewtonOptions::default()).run(start).steps(1000).collect()?;
//! let unreduced =
//!     UnreducedIntegrator::new(sys, NewtonOptions::default()).run(sys.untrivialize(&start)).steps(1000).collect()?;
//! assert!(reduced.states.iter().all(|s| s.mu == start.mu));
//! // The same motion: the reduced states mapped back by (3.7) are the unreduced ones.
//! for (r, u) in reduced.states.iter().zip(&unreduced.states) {
//!     let q = sys.untrivialize(r).q;
//!     assert!((q - u.q).amax() < 1e-7);
//! }
//! let j0 = sys.momentum_map(&unreduced.states[0]);
//! let drift = unreduced.states.iter().map(|s| (sys.momentum_map(s) - j0).amax()).fold(0.0, f64::max);
//! println!("unreduced momentum-map drift over 1000 steps: {drift:e}");
//! # Ok(())
//! # }
//! ```
