//! # Systems sized at run time
//!
//! Lattices, chains, discretised strings and membranes, particle systems: the systems that
//! bring many degrees of freedom are sums of one small term over many elements. Give the
//! function `usize` arguments — the *sizes* — and declare coordinates whose lengths are sizes;
//! then the body is compiled element by element, and one build serves every size:
//!
//! ```
//! use dirac::prelude::*;
//! use dirac::runtime::element::ElementIntegrator;
//!
//! /// The periodic Toda lattice of `n` particles, `x_n ≡ x_0 + n d`.
//! #[reduced_lagrangian(coordinates(x[n]), translate(x), rule = midpoint)]
//! fn toda(q: Config, v: Velocity, m: f64, d: f64, n: usize) -> f64 {
//!     let mut l = 0.0;
//!     for i in 0..n {
//!         l += 0.5 * m * v.x[i] * v.x[i];
//!     }
//!     for i in 0..n - 1 {
//!         l -= (-(q.x[i + 1] - q.x[i] - d)).exp();
//!     }
//!     l - (-(q.x[0] + n as f64 * d - q.x[n - 1] - d)).exp()
//! }
//!
//! for n in [10, 1000] {
//!     let sys = Toda { m: 1.0, d: 1.0, h: 0.05, n };
//!     let integ = ElementIntegrator::new(sys, NewtonOptions::default());
//!     let q = DVector::from_fn(n, |i, _| i as f64 + 0.1 * (i as f64).sin());
//!     let p = DVector::from_fn(n, |i, _| 0.3 * (0.5 * i as f64).cos());
//!     let start = ElementState::new(q, p);
//!     let mu0 = integ.momentum_map(&start)?[0];
//!     let summary = integ.run(start).steps(100).observe(|_, _, _, _| ()).stream()?;
//!     // The total momentum of the declared translation is kept exactly (to round-off).
//!     let mu = integ.momentum_map(&summary.last)?[0];
//!     assert!((mu - mu0).abs() < 1e-10);
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! ## The body
//!
//! The compiler splits the body into *families* of elements. Every `for` loop over sizes whose
//! body adds to the accumulator (`l += ..`, `l -= ..`) is a family, one element per iteration;
//! nested loops — pairs `for j in i + 1..n`, grids `for i in 0..nx { for j in 0..ny { .. } }` —
//! are families of their own, one element per iteration of the whole nest; the terms outside
//! loops (the accumulator's initial value, `l += ..` at the top level, the tail `l ± ..`) form
//! one family of a single element. `let` bindings before the loops are visible to every
//! element, those in a loop body to the elements of that loop and of the loops nested in it.
//!
//! * **Coordinates**: `coordinates(x[n], y[n], u[nx][ny], c)` — one- and two-dimensional arrays
//!   whose lengths are sizes (or integer literals, or a literal times a size, `x[3 * n]`), and
//!   scalars. A two-dimensional coordinate is read `q.u[i][j]` and stored row by row.
//! * **Points in 3-D as one array**: `coordinates(x[3 * n])` stores point `i` at `x[3 * i]`,
//!   `x[3 * i + 1]`, `x[3 * i + 2]`; a loop over a constant range inside an element,
//!   `for d in 0..3 { r2 += (q.x[3 * j + d] - q.x[3 * i + d]).powi(2); }`, is unrolled before
//!   the element's reads become its stencil (so the element reads all of them). Particles joined
//!   by springs written this way follow the same particles written as three arrays to 1e-12
//!   (tested).
//! * **Indices** are integer code in the sizes, the loop indices and literals, affine in the
//!   loop indices: `x[i]`, `x[i + 1]`, `x[(i + 1) % n]`, `u[i][(j + 1) % ny]`, `x[n - 1]`. A
//!   product of loop indices, a division, or anything else is a compile error pointing at the
//!   index. Every read must stay inside its coordinate for every size from some smallest size
//!   on: the compiler evaluates the stencils on sample sizes and reports an escaping read
//!   (`x[i + 1]` in `for i in 0..n`) or a `usize` underflow (`x[(i - 1) % n]`: write
//!   `x[(i + n - 1) % n]`) with the sizes and indices where it happens; the smallest valid size
//!   is the system's [`MIN_SIZE`](crate::runtime::element::ElementLagrangian::MIN_SIZE), and the
//!   runtime checks the sizes it is given against it, and every stencil against the dimension,
//!   before the first step (a typed [`StepError::InvalidSize`](crate::StepError::InvalidSize)).
//! * **Loop bounds** are built the same way: `0..n`, `1..n - 1`, `i + 1..n`, `0..=n - 2`; an
//!   integer `let` names an index (`let j = (i + 1) % n;` then `x[j]`).
//! * **Sizes and loop indices as values**: `n as f64`, `i as f64` (e.g. a spatially varying
//!   coefficient); a bare integer in an f64 expression is an error that says so.
//! * The rest of the body language is that of [Writing a Lagrangian](super::lagrangians):
//!   `let`, arithmetic, the f64 functions. A discrete Lagrangian `fn(q0: Config, q1: Config, h:
//!   f64, ..)` works the same way, element by element.
//! * Keys: `coordinates`, `translate`, `rule`, `force`, `controls`, `name`, `step`.
//!   Constraints, connections and sampling ranges are not available for systems sized at run
//!   time (a compile error says so).
//!
//! ## Forces
//!
//! `force = |dq| W` (or `|dq0, dq1|` with a discrete Lagrangian) is the virtual work written like
//! the body — an accumulator, loops over sizes, terms outside loops — and linear in the virtual
//! displacements `dq.x[i]`:
//!
//! ```
//! use dirac::prelude::*;
//! use dirac::runtime::element::ElementIntegrator;
//!
//! /// A chain of unit masses and springs, damped on every particle and pushed at its ends.
//! #[reduced_lagrangian(coordinates(x[n]), translate(x), rule = midpoint,
//!     force = |dq| {
//!         let mut w = 0.0;
//!         for i in 0..n {
//!             w -= c * v.x[i] * dq.x[i];
//!         }
//!         w + a * (dq.x[0] - dq.x[n - 1])
//!     })]
//! fn chain(q: Config, v: Velocity, c: f64, a: f64, n: usize) -> f64 {
//!     let mut l = 0.0;
//!     for i in 0..n {
//!         l += 0.5 * v.x[i] * v.x[i];
//!     }
//!     for i in 0..n - 1 {
//!         l -= 0.5 * (q.x[i + 1] - q.x[i]).powi(2);
//!     }
//!     l
//! }
//!
//! let sys = Chain { c: 0.2, a: 0.5, h: 0.05, n: 100 };
//! let integ = ElementIntegrator::new(sys, NewtonOptions::default());
//! let start = ElementState::new(DVector::from_fn(100, |i, _| i as f64), DVector::from_element(100, 1.0));
//! let traj = integ.run(start).steps(200).collect()?;
//! // The forced Noether balance: the total momentum changes by the impulse of the damping
//! // (the pushes at the ends cancel), −c Σ_i (x_i(t) − x_i(0)).
//! let (first, last) = (&traj.states[0], traj.last());
//! let impulse = -0.2 * (&last.q - &first.q).sum();
//! let change = integ.momentum_map(last)?[0] - integ.momentum_map(first)?[0];
//! assert!((change - impulse).abs() < 1e-10);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! The compiler splits the virtual work into families as it splits the body, and each family's
//! element yields its discrete forces by the rule, as for fixed sizes (midpoint:
//! `f_d^{e±} = (h/2) F^e(q̄, v)`): the assembly adds `f_d^{e−}` to the residual, its derivative
//! in `q_{k+1}` to the Jacobian and `f_d^{e+}` to the next momentum. With `translate(..)`
//! declared, each step keeps the forced discrete Noether balance `μ_{k+1} = μ_k + Σ (f_d^− +
//! f_d^+)` over the translation's orbit to round-off. A virtual work that is not linear in the
//! displacements, or has a term without one, is a compile error; the stencils of the forces are
//! checked like the body's. Tested against the unrolled code of the same lattice (a damped Toda
//! lattice at `n = 16`, 300 steps, to 1e-10) and of a driven chain with discrete forces.
//!
//! `controls(a, ..)` names parameters that a run sets before every step, from a feedback law or
//! a sequence (`run(..).feedback(..)`, `.controls(..)`), as for fixed sizes: the step then uses
//! a copy of the system with the controls set (parameters only, no heap memory). The driven chain
//! above under a feedback drive follows the unrolled code to 1e-12.
//!
//! ## Constraints
//!
//! Holonomic constraints `φ(q) = 0` of a continuous Lagrangian are written row by row, as the
//! fixed-size `constraints = |q| [..]` are, with the constraint vector's length an integer
//! expression in the sizes and each row assigned once — in a loop over sizes (one row per
//! element) or outside loops:
//!
//! ```
//! use dirac::prelude::*;
//!
//! /// A cart on a rail carrying a chain of `n` rigid links in maximal coordinates.
//! #[reduced_lagrangian(coordinates(c, x[n], y[n]), rule = midpoint,
//!     constraints = |q| {
//!         let mut phi = vec![0.0; n];
//!         phi[0] = (q.x[0] - q.c) * (q.x[0] - q.c) + q.y[0] * q.y[0] - l * l;
//!         for i in 1..n {
//!             let (dx, dy) = (q.x[i] - q.x[i - 1], q.y[i] - q.y[i - 1]);
//!             phi[i] = dx * dx + dy * dy - l * l;
//!         }
//!         phi
//!     })]
//! fn chain(q: Config, v: Velocity, m: f64, l: f64, g: f64, n: usize) -> f64 {
//!     let mut t = 0.5 * m * v.c * v.c;
//!     for i in 0..n {
//!         t += 0.5 * m * (v.x[i] * v.x[i] + v.y[i] * v.y[i]) - m * g * q.y[i];
//!     }
//!     t
//! }
//!
//! let n = 50;
//! let sys = Chain { m: 1.0, l: 1.0, g: 9.81, h: 0.01, n };
//! // The chain hanging at small angles from the cart, at rest.
//! let mut q = DVector::zeros(2 * n + 1);
//! let (mut x, mut y) = (0.0, 0.0);
//! for i in 0..n {
//!     let th = 0.3 * ((i + 1) as f64).sin();
//!     (x, y) = (x + th.sin(), y - th.cos());
//!     (q[1 + i], q[1 + n + i]) = (x, y);
//! }
//! let integ = ElementConstrainedIntegrator::new(sys, NewtonOptions::default());
//! let traj = integ.run(ElementState::new(q, DVector::zeros(2 * n + 1))).steps(100).collect()?;
//! assert!(traj.max_constraint_residual() < 1e-10); // every link at its length, every step
//! let tension = &traj.records[99].lambda; // the multipliers λ_k, one per link
//! assert_eq!(tension.len(), n);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Each assignment is a family of rows: its element is `φ` over the coordinates it reads (a
//! stencil, as for the body), differentiated at compile time into `φ^e` and `∇φ^e`; its row is
//! an affine index in the loop indices. A run checks that every row is assigned exactly once and
//! that the start satisfies the constraints (typed errors). [`ElementConstrainedIntegrator`](crate::runtime::element::ElementConstrainedIntegrator)
//! takes the RATTLE step of the fixed-size constrained integrators — SHAKE for the positions,
//! the projection of the momenta onto the constraints' cotangent space — as two Newton solves on
//! saddle-point systems `[[J, −A(q_k)ᵀ], [A(q_{k+1}), 0]]` and `[[∂²L/∂v², −Aᵀ], [A, 0]]` of
//! `n + m` unknowns, assembled element by element and row by row into one pattern built per run
//! and factored by the banded LU (a chain's saddle-point systems are a narrow band once
//! reordered) or the sparse LU (chord iterations reuse the factors). Each step reports its
//! multipliers `λ_k`, `ν_{k+1}` and `‖φ(q_{k+1})‖∞`; forces and controls enter as without
//! constraints; `ElementConstrainedIntegrator::minus` solves the (−) equations. A constraint
//! that is not invariant under a declared translation is a compile error (for an invariant one
//! the constraint forces have no component along the orbit, and the momentum map stays exact).
//! Tested against the unrolled chain of four links (states and multipliers, with and without a
//! damping force and a feedback control on the cart, to 1e-10), a free chain's two momentum maps
//! (to 1e-13), and the (−) side; `examples/maximal_chain` runs the chain against the unrolled one
//! at n = 16 … 128 and up to n = 10⁴.
//!
//! ## What is emitted
//!
//! The system type has a field per parameter and per size, and `dim()`, `config(&q)` and
//! `vector(&config)` to go between the flat vector `q` and the coordinates (`<Type>Config`, with
//! `Vec`s); your function stays callable on configurations (it is the reference the tests
//! compare against). For each family the compiler differentiates **one element** with respect
//! to its stencil and emits straight-line kernels — `D_1 L_d^e` with `D_2 L_d^e` (one function:
//! they share subexpressions), the same with `D_1 D_2 L_d^e` — and the stencil as integer code.
//! `GENERATED` states the families and their operation counts. Nothing depends on the sizes'
//! values: the toda lattice above builds in the same time for n = 10 and n = 10⁶.
//!
//! ## The integrator
//!
//! [`ElementIntegrator`](crate::runtime::element::ElementIntegrator) solves the (+) equations in
//! position–momentum form, `p_k + D_1 L_d(q_k, q_{k+1}) = 0`, `p_{k+1} = D_2 L_d(q_k, q_{k+1})`,
//! with the residual and Jacobian assembled from the elements, on the one driver (`run`,
//! the configured `run`, stop conditions, ensembles) and the one Newton iteration (chord iterations on a
//! pattern built once per run). The step Jacobian is solved by a banded LU when a reverse
//! Cuthill–McKee ordering makes its pattern a band at most
//! [`BANDED_MAX_WIDTH`](crate::runtime::element::BANDED_MAX_WIDTH) wide (chains, lattices,
//! rings, several arrays coupled site by site), by a dense LU with partial pivoting when the
//! pattern is wider but small and dense (at most
//! [`DENSE_MAX_DIM`](crate::runtime::element::DENSE_MAX_DIM) unknowns, as an element reading
//! every coordinate), by faer's sparse LU otherwise — or, for large
//! fields on grids (at least [`ITERATIVE_MIN_DIM`](crate::runtime::element::ITERATIVE_MIN_DIM)
//! unknowns and five entries per row), by conjugate gradients with a Jacobi preconditioner,
//! which needs no factorization and no fill and falls back to the LU when the Jacobian is not
//! symmetric; choose with
//! [`with_solver`](crate::runtime::element::ElementIntegrator::with_solver). States are
//! [`ElementState`](crate::runtime::element::ElementState)s of `DVector`s; a run allocates its
//! workspace once and nothing per step. With `translate(..)` declared, the momentum map of each
//! translation is kept exactly, as the reduced integrator keeps `μ` (the equations are the
//! reduced (+) equations (4.6) in another basis; see the
//! [module documentation](crate::runtime::element)).
//!
//! **Compositions.** `Composition::new(ElementIntegrator::new(sys, options), method)` raises a
//! symmetric rule (midpoint, trapezoid) to order 4 (`TRIPLE_JUMP`) or 6 (`YOSHIDA_6`,
//! `KAHAN_LI_6`): each stage is the system at `γ_i h`, assembled and solved like the base step,
//! in a workspace of its own. On the Toda lattice at `n = 16` the composed run-time-sized
//! lattice follows the composed unrolled code to 1e-12 and shows orders 3.9 and 5.9 (tested).
//!
//! **The (−) side.** [`ElementIntegrator::minus`](crate::runtime::element::ElementIntegrator::minus)
//! solves the (−) equations `p_k = −D_1 L_d(q_{k+1}^−, q_{k+1})`, `q_{k+1}^− = q_k`, for the
//! backward increment `Δ = q_k − q_{k+1}` (with a translation, its component along the orbit is
//! the group unknown `g_{k+1}^−` of the reduced (−) equations), on the same assembly with the
//! Jacobian negated. It computes the (+) trajectory to round-off — with translations, forces,
//! feedback controls and compositions (tested); `traj.variant` records the side.
//!
//! **Sensitivities.** [`step_sensitivity`](crate::runtime::element::ElementIntegrator::step_sensitivity)
//! (or `sensitivity(k, &state, &next, &u)`) returns an
//! [`ElementSensitivity`](crate::runtime::element::ElementSensitivity): the step's partial
//! derivatives in `q_k`, `q_{k+1}` and the controls, each element's differentiated at compile
//! time and assembled into the stencils' sparse pattern
//! ([`CscMatrix`](crate::runtime::element::CscMatrix)), with the sparse LU of the step Jacobian.
//! The step map's derivative is dense (`J⁻¹` couples every coordinate), so it is applied rather
//! than formed: `apply(&dq, &dp, &du)` (one solve) for tangents, `apply_transpose(&λq, &λp)`
//! (one transposed solve) for adjoint gradients; `to_dense()` gives the whole
//! [`Sensitivity`](crate::runtime::sensitivity::Sensitivity) of a small system. Tested against
//! central differences, the unrolled fixed-size system's sensitivity (to 1e-12), symplecticity
//! of a conservative step, and `⟨λ', dΦ v⟩ = ⟨dΦᵀ λ', v⟩` at `n = 2000`.
//!
//! **Parallel assembly.** Above [`PARALLEL_MIN_ENTRIES`](crate::runtime::element::PARALLEL_MIN_ENTRIES)
//! Jacobian block entries the elements are evaluated on rayon's pool, each row block evaluating
//! the elements that touch its rows and writing only its rows: the result is the serial one,
//! bit for bit, on any number of threads (tested). Choose with
//! [`with_parallel`](crate::runtime::element::ElementIntegrator::with_parallel).
//!
//! ## Examples and figures
//!
//! * `cargo run --release --example toda_n -- --n 200,1000,10000,100000`: one build, every n;
//!   time per step against the hand-written `O(n)` Newton step, parallel assembly, memory.
//! * `cargo run --release --example wave2d`: a 2-D nonlinear wave equation on 316 × 316 nodes
//!   (`--linear direct` for the sparse LU instead of conjugate gradients).
//! * `cargo run --release --example cluster`: a Lennard-Jones cluster, pairs, n = 64 … 256,
//!   and the same cluster written with strided indices.
//! * `cargo run --release --example driven_lattice`: a damped Toda lattice of 1000 particles
//!   driven by a control; its energy changes by the injected minus the dissipated work up to a
//!   residual of order 2 (1.1e-4 of the injected work at `h = 0.02`, falling by 4.00 at
//!   `h = 0.01`), and its total momentum by the forces' impulse to 2e-16 per step.
//! * `cargo run --release --example maximal_chain`: a chain of rigid links with its size at run
//!   time, up to n = 10⁴.
//!
//! The targets for systems sized at run time, three runs each on 2 cores:
//!
//! | target | measured | |
//! | --- | --- | --- |
//! | one build of the lattice serves every n, ≤ 5 s (release) | 1.5–2.5 s | met |
//! | n = 10⁵ in ≤ 200 MB; step time linear in n (slope 1 ± 0.1, 10³ … 10⁵) | 70–73 MiB; 1.02–1.03 | met |
//! | step ≤ 1.5 × a hand-written banded Newton step, n = 200 / 10⁴ | 1.87–1.88 / 0.79–0.80 (1.65–2.38 / 0.79–1.03 on a noisy machine, 2026-11-26) | not met / met |
//! | residual + Jacobian at n = 10⁴ ≤ 1.0 × CasADi's `map`-generated C | 0.64–0.65 (0.55–1.15 under load) | met |
//! | parallel assembly at n = 10⁵ ≥ 1.7× on 2 threads | 1.58–1.64 | not met |
//! | dense chain: R+J ≤ 1.0 × CasADi at n = 8 … 64; n = 64 builds in ≤ 60 s | 0.55–0.58; 27.6 s | met |
//! | link chain with constraints sized at run time: step time linear in n (slope 1 ± 0.1, 10² … 10⁴) | 0.90–0.97 | met |
//! | forced step ≤ 1.3 × unforced; constrained step ≤ 1.3 × the same chain on stiff springs | 1.08–1.26 (once 1.38); 2.14–2.85 | met; not met |
//! | whole step at n = 10⁶ on 2 threads ≥ 1.5 × 1 thread | 1.10 | not met |
//!
//! The measured figures, with the figure of step and R+J time against n for one build beside
//! CasADi's `map`, are in [Benchmarks](super::benchmarks#systems-sized-at-run-time).
//!
//! ## Limits
//!
//! Both sides of the position–momentum step and their compositions, with forces, controls,
//! sensitivities and holonomic constraints: no nonholonomic constraints, no sensitivities or
//! compositions of a constrained step, no atlases of element-wise systems; the sensitivity's
//! blocks are assembled serially and its Jacobian factored by the sparse LU whatever solver the
//! run uses; a constrained step's saddle-point systems are factored whole (no Schur complement
//! on the multipliers), banded when narrow and by the sparse LU otherwise; a strided coordinate
//! `x[3 * n]` declares one translation, moving all its components together; integer `let`s are index
//! aliases (`let j = (i + 1) % n;`) and cannot be read as values. At small sizes the chord iterations' linear convergence costs
//! corrections that a hand-written Newton step on a tridiagonal system does not pay (see
//! [Benchmarks](super::benchmarks#systems-sized-at-run-time)).
