//! # Symmetries
//!
//! The symmetry dirac reduces by is an abelian group `G = R^K` acting by translation of
//! coordinates: `Q = Σ × G`, with shape coordinates `x ∈ Σ = R^S` and group coordinates
//! `g ∈ G`. Its conserved momentum `μ ∈ g*` is an unknown of the reduced equations that they
//! update by `μ_{k+1} = μ_k`, so it is conserved exactly, not to a tolerance. A rotation about
//! an axis is a translation of an angle; a common translation of particles is a translation of
//! their positions, which you can declare without choosing coordinates yourself.
//!
//! ## Group coordinates
//!
//! `shape(...)` and `group(...)` split your coordinates: the Lagrangian may depend on the group
//! coordinates only through differences (`q1.theta - q0.theta`), and the attribute checks this
//! at compile time (see [Writing a Lagrangian](super::lagrangians#the-attribute)). A state of
//! the reduced integrators is a [`ReducedState`](crate::ReducedState) `{ x, w, mu, g }`: the
//! shape, the reduced momentum `w ∈ Σ*`, the momentum `μ` of the symmetry and the group
//! coordinate, which the integrator reconstructs along the way,
//! `g_{k+1} = g_k + g_k^+ + B (x_{k+1} − x_k)`.
//!
//! ## Connections
//!
//! The reduction uses a linear discrete connection `ω_d(q0, q1) = (g1 − g0) − B (x1 − x0)`,
//! with a constant `K × S` matrix `B` (`connection = [[...], ...]`, one row per group
//! coordinate; entries are f64 literals or parameters; `B = 0` when omitted). It fixes how
//! canonical momenta are split into `(w, μ)`, the trivialization (3.6):
//! `w = p_x + Bᵀ p_g`, `μ = p_g`, and back (3.7): `p = (w − Bᵀ μ, μ)`
//! ([`DiscreteLagrangian::trivialize`](crate::DiscreteLagrangian::trivialize),
//! [`untrivialize`](crate::DiscreteLagrangian::untrivialize)). Any `B` gives the same physical
//! motion, as the example below shows; the group unknown `g_k^+` of a step is the part of the
//! group step that `B (x_{k+1} − x_k)` does not account for.
//!
//! ## Indexed coordinates
//!
//! A coordinate may be an array of constant length: `shape(x[199], y)`, `group(c[3])`,
//! `coordinates(x[4], y[4])`. Its components enter the configuration vector in order (names
//! `"x[0]"`, `"x[1]"`, … in [`SHAPE`](crate::DiscreteLagrangian::SHAPE) and
//! [`GROUP`](crate::DiscreteLagrangian::GROUP)), `<Name>Config` gets the field
//! `pub x: [f64; 199]` (and so does `Velocity`), and the body reads `q0.x[i]` with an index known
//! at compile time: an integer literal, a loop index of an unrolled `for` loop (up to 4096
//! iterations), or `+ - * / %` on those (`q0.x[(i + 1) % n]`). An index out of range, an f64
//! index, indexing a scalar and reading an array without an index are compile errors;
//! `ranges(x = (lo, hi))` applies to every component of `x`. `shape(x[3])` and
//! `shape(x0, x1, x2)` give the same code.
//!
//! ## Declared translations
//!
//! Instead of choosing shape and group coordinates, an N-body or lattice Lagrangian can be
//! written in the particles' own positions and declare the symmetry: `coordinates(...)` lists
//! your coordinates, and each `translate(a, b, ...)` is one group dimension, adding the same
//! amount to every component of the listed coordinates (a coordinate belongs to at most one
//! `translate`; no `shape`, `group` or `connection` with them). The compiler builds adapted
//! coordinates, the trivialization `Σ × G` of §2.2.1: the group coordinate of
//! `translate(a, ...)` is `a[0]`, and every other translated component `c` becomes the shape
//! coordinate `c − a[0]` (named `"x[3] - x[0]"`); untranslated coordinates stay as they are;
//! shape coordinates come in the order of your components, then one group coordinate per
//! `translate`. So `q_user = T q` with `T` unimodular, `B = 0`, and the invariance check, the
//! derivatives and the reduction run in adapted coordinates unchanged (a body that is not
//! invariant under the declared translation is a compile error naming it).
//!
//! The system's vectors are adapted; your function and `<Name>Config` stay in your coordinates.
//! [`AdaptedCoordinates`](crate::AdaptedCoordinates) (emitted for every system, the identity
//! without `translate`) converts: `to_adapted` (`q = T⁻¹ q_user`, also for velocities),
//! `from_adapted` (`T`), `momentum_to_adapted` (`p = Tᵀ p_user`: the group momentum is the
//! total momentum of the translated components, so `μ` is the conserved total momentum) and
//! `momentum_from_adapted` (`T⁻ᵀ`), and whole states with `adapted_state` /
//! `from_adapted_state`. `cargo run --release --example n_body` declares one translation per
//! axis for four bodies in space: `μ` is the total linear momentum, exact over 50,000 steps (the
//! unreduced integrator from the same annotation: `|J − J₀| ≤ 2.5e-11`).
//!
//! ## Both ways
//!
//! The paper's charged particle with a nonzero connection, and a periodic Toda lattice of six
//! particles written in their positions with the translation declared:
//!
//! ```
//! use dirac::paper::ChargedParticle;
//! use dirac::prelude::*;
//!
//! /// The paper's charged particle with the connection B = (0.3, −0.7, b): same L_d.
//! #[reduced_lagrangian(shape(x, y, z), group(theta), connection = [[0.3, -0.7, b]])]
//! fn connected_particle(q0: Config, q1: Config, h: f64, m: f64, b0: f64, b: f64) -> f64 {
//!     let (dx, dy, dz) = (q1.x - q0.x, q1.y - q0.y, q1.z - q0.z);
//!     let a_dot_dq = 0.5 * b0 * (-q0.y * dx + q0.x * dy);
//!     let s = a_dot_dq + (q1.theta - q0.theta);
//!     0.5 * m / h * (dx * dx + dy * dy + dz * dz) + 0.5 / h * s * s
//! }
//!
//! /// The periodic Toda lattice in the particles' positions; the symmetry is a common translation.
//! #[reduced_lagrangian(coordinates(x[6]), translate(x), rule = midpoint)]
//! fn toda(q: Config, v: Velocity, m: f64) -> f64 {
//!     let mut l = 0.0;
//!     for i in 0..6 {
//!         l += 0.5 * m * v.x[i] * v.x[i] - (q.x[i] - q.x[(i + 1) % 6]).exp();
//!     }
//!     l
//! }
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! // The same canonical initial state, split by two connections: the same motion.
//! let paper = ChargedParticle { h: 0.2, m: 1.0, b0: 1.0 };
//! let connected = ConnectedParticle { h: 0.2, m: 1.0, b0: 1.0, b: 0.4 };
//! let canonical = paper.untrivialize(&ChargedParticle::paper_initial_state());
//! let a = ReducedIntegrator::plus(paper, NewtonOptions::default())
//!     .run(paper.trivialize(&canonical)).steps(50).collect()?;
//! let b = ReducedIntegrator::plus(connected, NewtonOptions::default())
//!     .run(connected.trivialize(&canonical)).steps(50).collect()?;
//! let (qa, qb) = (paper.untrivialize(a.last()).q, connected.untrivialize(b.last()).q);
//! assert!((qa - qb).amax() < 1e-10);
//!
//! // The lattice: adapted coordinates x[i] − x[0] and the group coordinate x[0].
//! let sys = Toda { m: 1.0, h: 0.05 };
//! assert_eq!(<Toda as DiscreteLagrangian<5, 1, 6>>::SHAPE[2], "x[3] - x[0]");
//! // Positions and momenta of the particles, in your coordinates.
//! let q = SVector::from([0.0, 0.9, 2.1, 2.8, 4.2, 5.0]);
//! let p = SVector::from([0.5, -0.3, 0.8, -0.6, 0.1, -0.13]);
//! let start = sys.trivialize(&Toda::adapted_state(&q, &p)); // (3.6) in adapted coordinates
//! assert!((start.mu[0] - p.sum()).abs() < 1e-15); // μ is the total momentum
//! let traj = ReducedIntegrator::plus(sys, NewtonOptions::default()).run(start).steps(100).collect()?;
//! assert_eq!(traj.last().mu, start.mu); // exactly
//! let end = Toda::from_adapted_state(&sys.untrivialize(traj.last())); // back to your coordinates
//! println!("positions after 100 steps: {}", end.q);
//! # Ok(())
//! # }
//! ```
