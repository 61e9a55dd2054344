//! # Reduction by rotations
//!
//! A body in empty space does not care how it is turned; a top in a vertical field does not care
//! how it is turned about the vertical. Declared with `symmetry(..)`, such a rotation symmetry is
//! checked at compile time, and the same annotation gives two integrators: the
//! [unreduced](super::rotations) Lie group step ([`LieIntegrator`](crate::LieIntegrator)) and
//! the reduced one ([`ReducedLieIntegrator`](crate::ReducedLieIntegrator)), whose conserved
//! momentum is a parameter of the run, as the paper's reduced integrators carry `μ`. The paper
//! reduces by translations and leaves nonabelian groups to future work; this is that step for the
//! rotation group.
//!
//! ## Declaring the symmetry
//!
//! * `symmetry(R)`: every rotation `R ↦ g R` of one rotation coordinate (`SO(3)`, acting on the
//!   left: rotating the body in space). The other coordinates — scalars, other rotations and
//!   directions — are not moved: the configuration space is `Q = SO(3) × S`.
//! * `symmetry(R, n1, .., axis = z)`: the rotations about a coordinate axis of every listed
//!   rotation and direction together (`SO(2)`): a body in a field along that axis, pendula on a
//!   pivot.
//! * `symmetry(X)` for a pose `X`: every rigid motion `(A, a)·(R, x) = (A R, A x + a)`
//!   (`SE(3)`): a body, or a tree carried by a floating base, in empty space. The reduced
//!   integrator carries its spatial momentum `(π, p) = (R Π + x × p, p)` — `π` as `mu`, `p`
//!   copied bit for bit in the state's momentum (see
//!   [`dirac::runtime::lie::reduced`](crate::runtime::lie::reduced)).
//!
//! ```
//! use dirac::prelude::*;
//!
//! /// The free rigid body, reduced by every rotation of its attitude.
//! #[reduced_lagrangian(rotation(r), symmetry(r))]
//! fn body(q0: Config, q1: Config, h: f64, j1: f64, j2: f64, j3: f64) -> f64 {
//!     let jd = Matrix3::from_diagonal(&Vector3::new(j2 + j3 - j1, j1 + j3 - j2, j1 + j2 - j3)) * 0.5;
//!     let f = q0.r.transpose() * q1.r;
//!     ((Matrix3::identity() - f) * jd).trace() / h
//! }
//!
//! let sys = Body { h: 0.01, j1: 1.0, j2: 2.0, j3: 3.0 };
//! let start = sys.state(
//!     &BodyConfig { r: Matrix3::identity() },
//!     &BodyMomentum { r: Vector3::new(0.3, 1.0, -0.2) },
//! );
//! let reduced = ReducedLieIntegrator::new(sys, NewtonOptions::default());
//! let unreduced = LieIntegrator::new(sys, NewtonOptions::default());
//! let a = reduced.run(reduced.reduce(&start)).steps(1000).collect().unwrap();
//! let b = unreduced.run(start).steps(1000).collect().unwrap();
//! // The spatial momentum π is the reduced run's parameter, and its attitude, reconstructed,
//! // is the unreduced run's.
//! let last = a.last();
//! assert_eq!(last.mu, a.states[0].mu);
//! assert!((reduced.momentum_map(&last.unreduced()).unwrap() - last.mu).norm() < 1e-15);
//! assert!((last.q - b.last().q).amax() < 1e-12);
//! ```
//!
//! The compiler rotates sample configurations by a sample rotation and requires `L_d` and the
//! forces to be unchanged (a torque in the body frame is; a direction's force must turn with
//! it). A top in a field declared `symmetry(r)`, a field along `x` declared `axis = z`, or a
//! list that leaves out a coordinate the body compares with a listed one, are compile errors at
//! the symmetry's first coordinate.
//!
//! ## The reduced equations
//!
//! *Every rotation.* Invariance gives the reduced Lagrangian
//! `l_d(F, s0, s1) = L_d(I, s0, F, s1)`, `F = R0ᵀ R1` (the discrete connection `R1 R0⁻¹`
//! identifies `(Q × Q)/SO(3)` with `SO(3) × S × S`). With `δR_k = R_k η̂_k`, `F_k` varies by
//! `−η̂_k F_k + F_k η̂_{k+1}` (Marsden, Pekarsky & Shkoller 1999; Leok, Marsden & Weinstein
//! 2005), and the reduced Hamilton–Pontryagin principle gives the discrete
//! Lagrange–Poincaré–Dirac equations in position–momentum form
//!
//! ```text
//! Π_k · η     = ⟨D_F l_d, η̂ F_k⟩         w_k     = −D_{s0} l_d
//! Π_{k+1} · η = ⟨D_F l_d, F_k η̂⟩         w_{k+1} =  D_{s1} l_d
//! R_{k+1}     = R_k F_k                   (reconstruction)
//! ```
//!
//! — the discrete Euler–Poincaré equations `h Π_k = vee(F_k J_d − J_d F_kᵀ)` for the free rigid
//! body, the discrete Lagrange–Poincaré equations with shapes (a satellite's wheel). They are
//! the unreduced step with `R_k` replaced by the identity, and the compiler emits them that way,
//! so a step solves for `F_k = cay(z)` and the shapes without reading the attitude. Because
//! `F η̂ = (F η)^ F`, the two `Π` lines give `Π_{k+1} = F_kᵀ Π_k = Ad*_{F_k} Π_k`: the discrete
//! Lie–Poisson equation, whose solutions stay on the coadjoint orbit `|Π| = |π|` and keep
//! `π = R Π`. The reduced integrator carries `π` and, after each step, scales `Π` onto that orbit
//! and turns the reconstructed attitude by the smallest rotation that gives `R Π = π`, with one
//! Newton–Schulz step `R (3I − RᵀR)/2` to keep it on `SO(3)`: corrections of the size of the
//! step's round-off, which stop the random walks of `π` and `RᵀR` (over 10⁶ free-body steps:
//! `|π_k − π_0|/|π_0| ≤ 6.3e-16` and `|RᵀR − I| ≤ 6.7e-16` reduced, against 5.7e-13 and 3.2e-13
//! unreduced).
//!
//! *About an axis `e`.* An abelian group on a nonlinear space (the paper's §6 setting, here with
//! the group's own retraction). Its generator in the chart at `q` is
//! `ζ(q) = (Rᵀ e, ((e × n)·e_1, (e × n)·e_2), 0)` and its momentum `μ = ⟨p, ζ⟩ = e · π`. A
//! reduced step reads the shape part of the momentum with the group part `μ`, so the group
//! component of its residual is the equation `⟨D1 L̃, ζ⟩ + μ = 0` of the paper's (4.6); by
//! invariance the step reads the configuration through its orbit only (`Rᵀ e` for the heavy top),
//! the stored phase about `e` being the reconstruction. `μ` is copied from step to step: bit
//! for bit.
//!
//! *The (−) side.* [`ReducedLieIntegrator::minus`](crate::ReducedLieIntegrator::minus) (and
//! [`LieIntegrator::minus`](crate::LieIntegrator::minus)) solve Definition 2.8's (−) equations,
//! trivialized at the next point: the unknown is the coordinate `w` of `q_k` in the chart
//! centred at `q_{k+1}`, and for every rotation the reduced (−) Lagrangian is
//! `l_{d−}(G, s0, s1) = L_d(G, s0, I, s1)`, `G = R_{k+1}ᵀ R_k`. Each chart here is inverted by
//! a sign (`cay(w)ᵀ = cay(−w)`, and the sphere's shortest-arc rotation `M(w)ᵀ = M(−w)`), so
//! `l_{d−}(G) = l_{d+}(G⁻¹)` and the (−) equations are the (+) ones at `z = −w`: the two sides
//! take the same steps, bit for bit, as the paper's (+) and (−) equations do for an
//! unconstrained system (end of its §2.3.2).
//!
//! With forces that act on a coordinate the symmetry moves, the momentum obeys the forced
//! balance and is recomputed from each new state. The derivation in full is in
//! [`crate::lie::reduced`].
//!
//! ## What is kept
//!
//! The reduced step is the unreduced step of the same `L_d` up to round-off: tested against it
//! (reconstructed) for the free body, the satellite under a feedback torque, the heavy top and
//! the paper's pendulum on `S² × S²`, and against Euler's equations `Π̇ = Π × J⁻¹Π` solved by
//! Runge–Kutta (order 2, and 4 for its triple jump). So the reduced flow is symplectic on the
//! reduced space — Lie–Poisson on `so(3)*` for the free body, on each coadjoint orbit
//! symplectic — and a symmetric `L_d` gives order 2, composed 4 and 6, the energy oscillating
//! without drift. [`ReducedLieIntegrator::dirac_residuals`](crate::ReducedLieIntegrator::dirac_residuals),
//! `discrete_energies` and `discrete_action` are the paper's diagnostics for these steps (also on
//! [`LieIntegrator`](crate::LieIntegrator)): the paper's run of its pendulum on `S² × S²`,
//! reduced about the vertical, gives the discrete generalized energy of its Figure 4 within
//! 1.3e-11 of the unreduced run, with `μ` unchanged over all 10⁴ steps.
//!
//! `cargo run --release --example rotation_reduction` runs the free body, the satellite, the
//! heavy top and the paper's pendulum reduced, and times each reduced step against its unreduced
//! one.
//!
//! ## Cost, and what is not reduced
//!
//! The unreduced Lie group step already solves in the chart centred at the current attitude, so
//! for these systems it solves the reduced step's unknowns (3 for the free body) and the reduced
//! step is not cheaper: it adds the momentum-level reconstruction (measured in
//! [Benchmarks](super::benchmarks)). Choose it for what it keeps — `π` or `μ` as exact
//! parameters, the attitude on `SO(3)` at round-off — not for speed. Not yet available:
//! constraints, step sensitivities of the reduced step (those of the unreduced step apply to
//! its trajectories), the rotations of several bodies at once by every rotation (about an axis
//! they are available), and dropping the reconstruction altogether.
