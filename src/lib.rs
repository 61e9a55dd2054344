//! # dirac
//!
//! Structure-preserving variational integrators reduced by an abelian symmetry, derived at
//! compile time from a discrete Lagrangian written as ordinary Rust. The method is Rodríguez
//! Abella & Leok, *Discrete Dirac reduction of implicit Lagrangian systems with abelian symmetry
//! groups*: the reduced (+) discrete Lagrange–Poincaré–Dirac equations, eq. (4.6).
//!
//! The [guide] explains, chapter by chapter, how to write a system, integrate it, read its
//! diagnostics and handle its errors; this page is the reference.
//!
//! ```
//! use dirac::prelude::*;
//!
//! /// Charged particle in a magnetic field, Kaluza–Klein form (paper §7.1), left-point rule.
//! #[reduced_lagrangian(shape(x, y, z), group(theta))]
//! fn charged_particle(q0: Config, q1: Config, h: f64, m: f64, b0: f64) -> f64 {
//!     let (dx, dy, dz) = (q1.x - q0.x, q1.y - q0.y, q1.z - q0.z);
//!     let a_dot_dq = 0.5 * b0 * (-q0.y * dx + q0.x * dy);
//!     let s = a_dot_dq + (q1.theta - q0.theta);
//!     0.5 * m / h * (dx * dx + dy * dy + dz * dz) + 0.5 / h * s * s
//! }
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let sys = ChargedParticle { h: 0.2, m: 1.0, b0: 1.0 };
//! let initial = ReducedState::new([0.0; 3], [1.0, 0.0, 1.0], [1.0], [0.0]);
//! let integ = ReducedIntegrator::plus(sys, NewtonOptions::default());
//! let traj = integ.run(initial).steps(100).collect()?;
//! assert_eq!(traj.step_count(), 100);
//! assert_eq!(traj.last().mu, initial.mu); // μ_{k+1} = μ_k, exactly
//! # Ok(())
//! # }
//! ```
//!
//! ## The attribute
//!
//! ```text
//! #[reduced_lagrangian(
//!     shape(x, y, z),               // shape coordinates x ∈ Σ (may be empty: `shape()`)
//!     group(theta),                 // group coordinates g ∈ G = R^K, translated by the symmetry
//!     connection = [[0.0, b, 0.0]], // optional K × S matrix B: ω_d = (g1 − g0) − B (x1 − x0)
//!     step = h,                     // optional: the time-step parameter (default: the one named `h`)
//!     name = ChargedParticle,       // optional: the emitted type (default: CamelCase of the fn name)
//! )]
//! ```
//!
//! A coordinate may be an array of constant length, `shape(x[3])`, read as `q0.x[i]` with an
//! index known at compile time. Instead of `shape`/`group`, the symmetry may be declared on the
//! user's own coordinates, `coordinates(x[4], y[4]), translate(x), translate(y)`: the compiler
//! builds the adapted coordinates of §2.2.1 (`g = x[0]`, `x[i] − x[0]`), and
//! [`AdaptedCoordinates`] converts states (see the guide's chapter on [symmetries](guide::symmetries)).
//!
//! The function takes the two configurations `q0: Config, q1: Config` (coordinates are read as
//! fields, `q0.x`) and scalar `f64` parameters, and returns `L_d(q0, q1)`. It stays callable,
//! with `Config` replaced by the emitted struct `<Name>Config`. The macro emits:
//!
//! * `<Name>Config`, the configuration with one `f64` field per coordinate (shape, then group);
//! * `<Name>`, a struct with one `f64` field per parameter;
//! * implementations of [`DiscreteLagrangian`] (the Lagrangian, the connection matrix,
//!   trivialization (3.6)/(3.7) and the momentum map) and [`Reduced`] for each [`Side`]
//!   ([`Plus`]: eq. (4.6), [`Minus`]: eq. (4.8)) — the straight-line residual, its exact
//!   Jacobian, the momentum update and, where the group unknowns enter affinely, the eliminated
//!   stepper — and [`Unreduced`] (Definitions 2.7/2.8); for systems of at most
//!   [`runtime::DENSE_MAX`] coordinates also [`LagrangianHessian`] (the Hessian of `L_d`, for the
//!   step-map Jacobian). Small systems solve their steps with the dense fixed-size [`runtime::Lu`],
//!   larger ones with [`runtime::SparseLu`] on the Jacobian's compile-time sparsity pattern.
//!
//! The body language is a smooth subset of Rust: f64 literals, parameters, coordinates, `let`
//! (with tuple destructuring and `mut`), `+ - * /`, unary `-`, blocks, tuples, arrays with constant
//! indices, `for` loops over constant ranges (unrolled), and the f64 functions `sin cos tan asin
//! acos atan exp ln sqrt sinh cosh tanh recip powi powf atan2`, as methods or `f64::` paths.
//! Anything else is a compile error pointing at the offending token.
//!
//! ## Charts and transitions (§6)
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
//! The body reads the old coordinates as `q.name`, in the body language above, and returns the
//! tuple of new coordinates (shape, then group). The attribute emits a unit struct implementing
//! [`runtime::atlas::ChartTransition`] with straight-line code for `φ` and `Dφ`, after checking
//! on the derivative graph that the map is equivariant, `x' = ψ(x)` and `g' = g + c(x)` (a
//! compile error otherwise). [`runtime::atlas::AtlasIntegrator`] steps in one chart and changes
//! chart through the cotangent lift; [`paper::atlas`] is the double spherical pendulum on three
//! charts.

#![warn(missing_docs)]

// Emitted code names `::dirac::…`; this lets the crate's own `paper` module use the attribute.
extern crate self as dirac;

pub mod guide;
pub mod paper;
pub mod systems;

pub use dirac_macros::{chart_transition, reduced_lagrangian};
/// Articulated rigid bodies as data: models read from URDF, kinematics, energies, momenta.
pub use dirac_multibody as multibody;
pub use dirac_runtime as runtime;
pub use dirac_runtime::lie;
pub use dirac_runtime::nalgebra;
pub use dirac_runtime::prelude::*;

/// Everything a user of the attribute needs in scope: the runtime's one list
/// ([`runtime::prelude`], which the crate root re-exports too), plus the two attributes and
/// nalgebra's vectors and matrices (which the root reaches as [`nalgebra`]), with the `Matrix3`
/// and `Vector3` that rotation and direction coordinates are, and [`lie::hat`] / [`lie::vee`].
pub mod prelude {
    pub use crate::lie::{hat, vee};
    pub use crate::nalgebra::{DVector, Matrix3, SMatrix, SVector, Vector3};
    pub use crate::runtime::prelude::*;
    pub use crate::{chart_transition, reduced_lagrangian};
}

/// The README's example, compiled and run as a doctest so it cannot go stale.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
