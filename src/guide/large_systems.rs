//! # Large systems
//!
//! Nothing changes in how a large system is written: an array coordinate and a `for` loop
//! (see [Symmetries](super::symmetries#indexed-coordinates)) describe a lattice of 200
//! particles as briefly as one of six. What changes is the linear algebra of a step, which the
//! compiler chooses by size, and how a run is kept: streamed instead of stored.
//!
//! ```sh
//! cargo run --release --example lattice   # 200-particle periodic Toda lattice, translate(x)
//! cargo run --release --example n_body    # four bodies in space, translate(x), translate(y), translate(z)
//! ```
//!
//! ## Two backends, one Newton driver
//!
//! Up to [`DENSE_MAX`](crate::runtime::linalg::DENSE_MAX) = 16 configuration coordinates a
//! step's Jacobian is a fixed-size `SMatrix` factored by the unrolled dense
//! [`Lu`](crate::runtime::linalg::Lu) (everything on the stack). Above it the compiler emits the
//! Jacobian's structural sparsity pattern as a static compressed-sparse-column pattern and the
//! Jacobian as the values of its nonzero entries alone (never a dense matrix), factored by faer's
//! sparse LU with partial pivoting ([`SparseLu`](crate::runtime::linalg::SparseLu): a COLAMD
//! ordering once per run, faer's simplicial numeric LU into preallocated memory). Each system
//! names its solver ([`Reduced::Linear`](crate::Reduced::Linear),
//! [`Unreduced::UnreducedLinear`](crate::Unreduced::UnreducedLinear),
//! [`ContinuousLagrangian::LegendreLinear`](crate::ContinuousLagrangian::LegendreLinear)), and
//! one Newton driver ([`crate::runtime::newton`]) serves both: a linear solver is a workspace
//! that computes its ordering and scratch once per run, so no step allocates after the first
//! factorization.
//!
//! On the sparse backend the momentum-level elimination is not used (its shape Jacobian is
//! dense), and the Hessian blocks of `L_d` ([`LagrangianHessian`](crate::LagrangianHessian), what
//! the step-map Jacobian needs) are not emitted: the step-map Jacobian of a large system is a
//! dense `2N × 2N` matrix.
//!
//! ## Chord iterations
//!
//! On the sparse backend a factorization costs many residual evaluations, so a step of a run
//! first corrects with the factors of an earlier step, evaluating residuals alone, as long as
//! each correction shrinks the residual by a factor of at least 10; the first correction that
//! does not hands the rest of the step to Newton's iteration with a fresh Jacobian, whose
//! factors the next steps then reuse. Acceptance is the same residual test, so a chord step is
//! the step Newton accepts, to round-off. [`StepStats::factorizations`](crate::StepStats) and
//! [`RunSummary::factorizations`](crate::RunSummary) count the Jacobians factored. The dense
//! backend never reuses factors (a 4 × 4 factorization costs less than a residual). The
//! conditioning check is the dense one — a guaranteed bound read from the factors, Hager's
//! estimator only when the bound does not clear `min_rcond` — applied to the Jacobian whose
//! factors the step used: for a chord step, an earlier step's. A Jacobian that degrades along
//! the run stops the old factors from contracting, and the fresh one is checked.
//!
//! ## Streaming and ensembles
//!
//! A streamed run ([`Run::stream`](crate::Run::stream)) calls the observer for every state as it
//! is computed and keeps nothing: keep every `k`-th state (`.every(k)`), accumulate statistics,
//! write a file, in memory independent of the number of steps.
//! [`Drive::ensemble`](crate::Drive::ensemble) and
//! [`parameters`](crate::runtime::driver::parameters) spread members over rayon's thread pool
//! (`.threads(n)` for a pool of its own). A composition keeps one workspace per stage and an atlas
//! one per chart, so a composed sparse run allocates nothing after its first macro step either.
//!
//! A lattice of 20 particles, sparse, streamed, and an ensemble of four:
//!
//! ```
//! use dirac::prelude::*;
//!
//! /// The periodic Toda lattice of 20 particles: 20 unknowns per step, above DENSE_MAX.
//! #[reduced_lagrangian(coordinates(x[20]), translate(x), rule = midpoint)]
//! fn toda(q: Config, v: Velocity, m: f64) -> f64 {
//!     let mut l = 0.0;
//!     for i in 0..20 {
//!         l += 0.5 * m * v.x[i] * v.x[i] - (q.x[i] - q.x[(i + 1) % 20]).exp();
//!     }
//!     l
//! }
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let sys = Toda { m: 1.0, h: 0.05 };
//! let phase = |i: usize| 2.0 * std::f64::consts::PI * i as f64 / 20.0;
//! let q = SVector::<f64, 20>::from_fn(|i, _| 0.1 * phase(i).sin());
//! let p = SVector::<f64, 20>::from_fn(|i, _| 0.05 + 0.2 * phase(i).cos());
//! let start = sys.trivialize(&Toda::adapted_state(&q, &p));
//! let integ = ReducedIntegrator::plus(sys, NewtonOptions::default());
//!
//! // Streamed: the energy spread at the step midpoints, nothing stored.
//! let (mut e_min, mut e_max) = (f64::INFINITY, f64::NEG_INFINITY);
//! let mut previous = start;
//! let summary = integ.run(start).steps(400).observe(|k, _, state, _| {
//!     if k > 0 {
//!         let (a, b) = (sys.untrivialize(&previous).q, sys.untrivialize(state).q);
//!         let e = sys.energy(&(0.5 * (a + b)), &((b - a) / sys.h));
//!         (e_min, e_max) = (e_min.min(e), e_max.max(e));
//!     }
//!     previous = *state;
//! }).stream()?;
//! assert_eq!(summary.last.mu, start.mu); // the total momentum, exactly
//! assert!(summary.factorizations < summary.step_count / 4); // chord steps reuse factors
//! println!(
//!     "{} steps, {:.2} corrections and {} factorizations in all, energy spread {:.1e}",
//!     summary.step_count, summary.mean_iterations(), summary.factorizations, e_max - e_min
//! );
//!
//! // Four members in parallel, each bit for bit its sequential run.
//! let starts: Vec<_> = (0..4)
//!     .map(|j| {
//!         let p = p.map(|pi| pi * (1.0 + 0.1 * j as f64));
//!         sys.trivialize(&Toda::adapted_state(&q, &p))
//!     })
//!     .collect();
//! let members = integ.ensemble(&starts).steps(50).collect();
//! let sequential = integ.run(starts[3]).steps(50).collect()?;
//! assert_eq!(members[3].as_ref().ok(), Some(&sequential));
//! # Ok(())
//! # }
//! ```
//!
//! ## The 200-particle lattice
//!
//! `cargo run --release --example lattice -- --steps 20000` prints (one run; the figures of other
//! runs, and the time per step across runs, are in
//! [Benchmarks](super::benchmarks#the-200-particle-lattice)):
//!
//! ```text
//! periodic Toda lattice, n = 200, h = 0.05, midpoint rule, reduced (+) equations: 200 unknowns per step
//!   20000 steps (T = 1000): 35.0 µs per step, 2.287 corrections per step (max 3), 2 Jacobians factored, worst rcond 6.27e-6
//!   total momentum μ = 10.000000000000002: max |μ_k − μ_0| = 0e0 (exact)
//!   energy at the midpoints: spread 1.293e-3 (6.31e-6 relative), drift (last tenth − first tenth) -1.22e-3 (-0.947 × spread)
//!   peak memory of the process: 3.3 MiB (the states are streamed, not stored)
//!   ensemble of 8 members × 2000 steps: 8/8 ok on 1 thread in 0.29 s, 8/8 ok on 2 threads in 0.15 s: speed-up 1.91, parallel efficiency 96%
//! ```
//!
//! ## Build the attribute optimized
//!
//! Cargo builds procedural macros at `opt-level = 0` by default; the expansion of the
//! 200-particle lattice then takes ≈ 27 s instead of ≈ 3 s. A crate with large systems wants
//! these lines in its `Cargo.toml` (this workspace has them):
//!
//! ```toml
//! [profile.dev.package.dirac-compiler]
//! opt-level = 3
//! [profile.release.package.dirac-compiler]
//! opt-level = 3
//! ```
//!
//! A crate with the 200-particle lattice of `examples/lattice.rs` then rebuilds in 10–11 s
//! instead of 32–41 s (2 cores).
//!
//! Compile time grows with the couplings of the system: the step Jacobian of a chain of `n`
//! links hanging from a cart is dense, and a 64-link chain (a 65 × 65 Jacobian, 157 k
//! operations) builds in ≈ 3 minutes in release; the Toda lattice's Jacobian is cyclic
//! tridiagonal with a dense border, and 1000 particles build in ≈ 2 minutes. The
//! [scaling table](super::benchmarks#scaling-with-the-size-of-the-system) has the figures for
//! each size. Large systems declare their emitted locals 64 per `let`, so a debug build of a
//! system with 10⁵ operations does not exhaust rustc's stack.
