//! Systems given at run time: a discrete (or continuous) Lagrangian written as text — the same
//! attribute and function a Rust program compiles in with `#[reduced_lagrangian]` — compiled by
//! the same compiler (`dirac-compiler`: parsing, the invariance check, differentiation, the
//! paper's reduction) and by Cranelift to straight-line machine code, behind the runtime's traits.
//! Every integrator then runs it: the reduced (+) and (−) steps of eqs. (4.6) and (4.8), the
//! unreduced step, compositions, forces and controls, constraints, adaptive steps, and on rotation
//! groups the Lie group variational step and its reduction by rotations.
//!
//! ```
//! use dirac_jit::compile;
//! use dirac_runtime::prelude::*;
//!
//! let code = compile(
//!     "#[reduced_lagrangian(shape(r), group(theta))]
//!      fn kepler(q0: Config, q1: Config, h: f64) -> f64 {
//!          let (dr, dth) = (q1.r - q0.r, q1.theta - q0.theta);
//!          let r = 0.5 * (q0.r + q1.r);
//!          0.5 / h * (dr * dr + r * r * dth * dth) + h / r
//!      }",
//! )?;
//! let kepler = code.instantiate::<1, 1, 2>(&[0.01])?;
//! let integ = ReducedIntegrator::plus(kepler, NewtonOptions::default());
//! let start = ReducedState::new([1.0], [0.0], [1.0], [0.0]);
//! let traj = integ.run(start).steps(100).collect()?;
//! assert_eq!(traj.last().mu, start.mu); // the angular momentum, exactly
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! A system given as text steps as its compiled-in version does, bit for bit when the operations
//! are the same and in the same order — here Kepler's problem against the facade's
//! `Kepler` (`dirac::systems::kepler::Kepler`):
//!
//! ```
//! use dirac::prelude::*;
//! use dirac::systems::kepler::Kepler;
//!
//! let text = "
//!     #[reduced_lagrangian(shape(r), group(phi))]
//!     fn kepler(q0: Config, q1: Config, h: f64, k: f64) -> f64 {
//!         let r = 0.5 * (q0.r + q1.r);
//!         let (dr, dphi) = ((q1.r - q0.r) / h, (q1.phi - q0.phi) / h);
//!         h * (0.5 * (dr * dr + r * r * dphi * dphi) + k / r)
//!     }";
//! let code = dirac_jit::compile(text)?;
//! assert_eq!(code.system().parameters, ["h", "k"]);
//!
//! // The dimensions are type parameters, checked against the text's: S = 1, K = 1, N = 2.
//! let given = code.instantiate_named::<1, 1, 2>(&[("h", 0.01), ("k", 1.0)])?;
//! let compiled = Kepler::unit(0.01);
//! let start = compiled.periapsis_state(1.0, 0.5);
//!
//! let a = ReducedIntegrator::plus(given, NewtonOptions::default()).run(start).steps(1000).collect()?;
//! let b = ReducedIntegrator::plus(compiled, NewtonOptions::default()).run(start).steps(1000).collect()?;
//! assert_eq!(a.states, b.states);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! A mistake in the text gets the attribute's own message, at the line and column of the
//! offending token, with the source line and a caret when printed:
//!
//! ```
//! let text = "#[reduced_lagrangian(shape(r), group(phi))]\n\
//!             fn f(q0: Config, q1: Config, h: f64) -> f64 { q0.r.floor() }";
//! let e = dirac_jit::compile(text).unwrap_err();
//! let shown = e.to_string();
//! assert!(shown.contains("unsupported method `floor`"), "{shown}");
//! assert!(shown.contains(" --> 2:52"), "{shown}");
//! ```
//!
//! What the text may declare is what the attribute accepts for a system on vector spaces:
//! `shape(..)`, `group(..)` (or `coordinates(..)` with `translate(..)`, array coordinates such
//! as `x[200]`), a connection, `step = ..`, a continuous Lagrangian with its `rule`, forces,
//! controls, holonomic or nonholonomic constraints ([`Code::instantiate_constrained`]: the
//! constrained integrators, unreduced and reduced), and adaptive steps (`time(t), adapt = |q| g`).
//! Systems on rotation groups (`rotation(..)`, `direction(..)`, `pose(..)`) compile with
//! [`compile_lie`] into a [`LieCode`], whose systems the Lie group variational integrator and,
//! reduced by their declared symmetry, `ReducedLieIntegrator` run: at fixed sizes a [`JitLie`],
//! at the sizes the text declares — any number of rotations, directions, poses and scalars — a
//! [`DynJitLie`] (`LieIntegratorOf<_, Dyn, Dyn>`, its vectors allocated once per run);
//! [`compile_any`] takes either kind.
//! Element-wise systems sized at run time (a function with `usize` sizes) compile with
//! [`compile_element`] into an [`ElementCode`], instantiated at any sizes as a [`JitElement`]
//! that `ElementIntegrator` (and, with constraints, `ElementConstrainedIntegrator`) runs. What a
//! front end is asked to run of any of them — the equations in the runtime's one vocabulary,
//! the order, the steps, Newton's tolerance — is one [`RunRequest`], checked against the
//! [`Compiled`] system in one place.
//!
//! A pendulum in Cartesian coordinates, its rod a holonomic constraint (`M = 1`, so each solve
//! has `Z = N + M = 3` unknowns):
//!
//! ```
//! use dirac_runtime::prelude::*;
//!
//! let code = dirac_jit::compile(
//!     "#[reduced_lagrangian(shape(x, y), group(), rule = midpoint,
//!          constraints = |q| [q.x * q.x + q.y * q.y - l * l])]
//!      fn pendulum(q: Config, v: Velocity, m: f64, l: f64) -> f64 {
//!          0.5 * m * (v.x * v.x + v.y * v.y) - 9.81 * m * q.y
//!      }",
//! )?;
//! assert_eq!(code.system().parameters, ["m", "l", "h"]);
//! let pendulum = code.instantiate_constrained::<2, 0, 2, 1, 3>(&[1.0, 1.5, 0.01])?;
//! let start = UnreducedState::new([1.5, 0.0], [0.0, 0.0]); // horizontal, at rest
//! let traj = ConstrainedIntegrator::new(pendulum, NewtonOptions::default())
//!     .run(start)
//!     .steps(500)
//!     .collect()?;
//! assert!(traj.max_constraint_residual() < 1e-9); // on its circle at every step
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! The dimensions are type parameters, as for a compiled-in system ([`Code::instantiate`] checks
//! them against the text's), so a step runs the same fixed-size code with no allocation: the
//! kernels read and write the integrators' stack vectors directly. The backend is the one the
//! attribute would choose: up to 16 coordinates the dense fixed-size LU
//! ([`Code::instantiate`]); above, the sparse LU on the step Jacobian's structural nonzeros
//! ([`Code::instantiate_sparse`]), whose kernels write only those entries, into a buffer that a
//! run reuses. A 200-particle lattice given as text steps bit for bit as the compiled-in one.
//!
//! # Sizes: two paths
//!
//! A program that takes systems at run time (the Python package, the command line) cannot name
//! the dimensions as type parameters. It takes one of two paths, by size
//! ([`Code::fixed_size`]):
//!
//! - the fixed-size instances, [`with_dimensions!`] (`S + K ≤` [`MAX_DISPATCHED`]) and
//!   [`with_constrained_dimensions!`] ([`MAX_DISPATCHED_CONSTRAINED`]): stack-only steps,
//!   bit for bit as the system compiled in, for the small systems where a step's cost is a few
//!   hundred operations and an allocation or a sparse solve would dominate it;
//! - every other size, the system's element view ([`Code::element_view`],
//!   [`compile_flat_elements`]): its `L_d` one element reading every coordinate, each group
//!   coordinate a translation whose momentum `μ = p_g` the element integrators keep exact, each
//!   constraint row a constraint family, on `ElementIntegrator` and
//!   `ElementConstrainedIntegrator`, which take their sizes at run time. Its (+)/(−) sides
//!   solve the reduced (+)/(−) equations (4.6), (4.8) in another basis (Definitions 2.7/2.8 in
//!   the coordinates `q = (x, g)`, `p = (w − Bᵀ μ, μ)`, eq. (3.7)): the same trajectory to
//!   round-off, not bit for bit (other unknowns, another linear solver).

#![warn(missing_docs)]

mod codegen;
mod element;
mod error;
mod lie;
mod model;
mod multibody;
mod request;
pub mod run;
mod system;

pub use element::{compile_element, compile_flat_elements, ElementCode, JitElement, MAX_SIZES};
pub use error::Error;
pub use lie::{compile_lie, DynJitLie, JitLie, LieCode, LieFront, Reduced, Reduction, Unreduced};
pub use multibody::{compile_model, ModelCode};
pub use request::{RunRequest, Scheme, ORDERS};

/// The runtime, for the macros' expansions in other crates ([`span!`]).
#[doc(hidden)]
pub use dirac_runtime as __runtime;
pub use system::{
    compile, Backend, Code, Dense, JitConstrained, JitSystem, LegendreLu, LegendreMatrix, Sparse,
    Variant, WithConstraints, MAX_PARAMETERS,
};

/// A system given as text and compiled to machine code, of any kind.
#[derive(Clone, Debug)]
pub enum Compiled {
    /// A system on vector spaces ([`compile`]).
    Flat(std::sync::Arc<Code>),
    /// A system on rotation groups ([`compile_lie`]).
    Lie(std::sync::Arc<LieCode>),
    /// An element-wise system sized at run time ([`compile_element`]).
    Element(std::sync::Arc<ElementCode>),
}

/// Compiles a system given as text, whichever its kind (see
/// [`dirac_compiler::text::compile_any`]): on rotation groups when it declares a `rotation(..)`
/// or `direction(..)` coordinate, on vector spaces otherwise. What a program that takes any
/// system (a Python module, a command line) calls.
pub fn compile_any(source: &str) -> Result<Compiled, Error> {
    let start = std::time::Instant::now();
    match dirac_compiler::text::compile_any(source)? {
        dirac_compiler::text::AnySystem::Flat(system) => {
            system::Code::from_system(*system, source, start).map(Compiled::Flat)
        }
        dirac_compiler::text::AnySystem::Lie(system) => {
            LieCode::from_system(*system, start).map(Compiled::Lie)
        }
        dirac_compiler::text::AnySystem::Element(system) => {
            ElementCode::from_system(*system, start).map(Compiled::Element)
        }
    }
}

/// The largest `N = S + K` that [`with_dimensions!`] has an instance for.
pub const MAX_DISPATCHED: usize = 8;

/// Calls a function generic over the dimensions, `f::<S, K, N>(args)`, for dimensions known
/// only at run time: one instance per split `(S, K)` with `1 ≤ S + K ≤` [`MAX_DISPATCHED`]
/// (44 instances). The function returns `Result<_, String>`; other dimensions are an `Err`
/// saying so. What a program that takes systems at run time (a Python module, a command line)
/// uses to reach the integrators, which take the dimensions as type parameters.
///
/// ```
/// fn dims<const S: usize, const K: usize, const N: usize>(scale: usize) -> Result<usize, String> {
///     Ok(scale * (10 * S + K) + N)
/// }
/// assert_eq!(dirac_jit::with_dimensions!(3, 1, dims(2)), Ok(66));
/// assert!(dirac_jit::with_dimensions!(9, 1, dims(2)).is_err());
/// ```
///
/// A function with one more type parameter (a [`run::Job`]'s type, inferred) is called as
/// `f::<_>(args)`, with the expression evaluated for any other dimensions after `else`:
///
/// ```
/// fn scaled<const S: usize, const K: usize, const N: usize, T: Into<f64>>(x: T) -> f64 {
///     x.into() * N as f64
/// }
/// assert_eq!(dirac_jit::with_dimensions!(3, 1, scaled::<_>(2.0f32) else 0.0), 8.0);
/// assert_eq!(dirac_jit::with_dimensions!(9, 1, scaled::<_>(2.0f32) else 0.0), 0.0);
/// ```
#[macro_export]
macro_rules! with_dimensions {
    ($s:expr, $k:expr, $f:ident $args:tt) => {
        $crate::with_dimensions!(@table ($s, $k), $f [] $args,
            (s, k) => ::core::result::Result::Err(::std::format!(
                "{s} shape and {k} group coordinates: the fixed-size instances have at most {} coordinates (other sizes run on the element view, `Code::element_view`)",
                $crate::MAX_DISPATCHED
            )),
        )
    };
    ($s:expr, $k:expr, $f:ident::<_> $args:tt else $fallback:expr) => {
        $crate::with_dimensions!(@table ($s, $k), $f [, _] $args, _ => $fallback,)
    };
    (@table $sk:expr, $f:ident $tail:tt $args:tt, $($fallback:tt)*) => {
        $crate::with_dimensions!(@arms $sk, $f $tail $args, [$($fallback)*];
            (0,1) (1,0)
            (0,2) (1,1) (2,0)
            (0,3) (1,2) (2,1) (3,0)
            (0,4) (1,3) (2,2) (3,1) (4,0)
            (0,5) (1,4) (2,3) (3,2) (4,1) (5,0)
            (0,6) (1,5) (2,4) (3,3) (4,2) (5,1) (6,0)
            (0,7) (1,6) (2,5) (3,4) (4,3) (5,2) (6,1) (7,0)
            (0,8) (1,7) (2,6) (3,5) (4,4) (5,3) (6,2) (7,1) (8,0))
    };
    (@arms $sk:expr, $f:ident [] $args:tt, [$($fallback:tt)*];
        $(($s:literal, $k:literal))*) => {
        match $sk {
            $(($s, $k) => $f::<$s, $k, { $s + $k }> $args,)*
            $($fallback)*
        }
    };
    (@arms $sk:expr, $f:ident [, _] $args:tt, [$($fallback:tt)*];
        $(($s:literal, $k:literal))*) => {
        match $sk {
            $(($s, $k) => $f::<$s, $k, { $s + $k }, _> $args,)*
            $($fallback)*
        }
    };
}

/// Calls a function generic over the dimensions of a system on rotation groups, `f::<P, N>(args)`,
/// for the small dimensions of its fixed-size instances, and evaluates `fallback` for any other:
/// one instance per `(P, N)` of a system with at most two rotation and direction coordinates and
/// `N ≤` [`MAX_DISPATCHED`] (25 instances), whose steps run on stack vectors and the dense LU.
/// A system of any other size runs at the sizes its text declares ([`DynJitLie`], by
/// `LieIntegratorOf<_, Dyn, Dyn>`): the fallback. The fixed-size instances are kept for the small
/// systems because their steps are faster than the run-time-sized step there (see the
/// [`DynJitLie`] documentation).
///
/// ```
/// fn dims<const P: usize, const N: usize>() -> Result<usize, String> {
///     Ok(100 * P + N)
/// }
/// assert_eq!(dirac_jit::with_lie_dimensions!(18, 4, dims() else Ok(0)), Ok(1804));
/// assert_eq!(dirac_jit::with_lie_dimensions!(72, 24, dims() else Ok(0)), Ok(0));
/// ```
#[macro_export]
macro_rules! with_lie_dimensions {
    ($p:expr, $n:expr, $f:ident $args:tt else $fallback:expr) => {
        $crate::with_lie_dimensions!(@table ($p, $n), $f [] $args, $fallback)
    };
    // `f::<_>(args)`: a function with one more type parameter, inferred.
    ($p:expr, $n:expr, $f:ident::<_> $args:tt else $fallback:expr) => {
        $crate::with_lie_dimensions!(@table ($p, $n), $f [, _] $args, $fallback)
    };
    (@table $pn:expr, $f:ident $tail:tt $args:tt, $fallback:expr) => {
        $crate::with_lie_dimensions!(@arms $pn, $f $tail $args, $fallback;
            (9,2) (9,3) (10,3) (10,4) (11,4) (11,5) (12,5) (12,6) (13,6) (13,7) (14,7) (14,8) (15,8) (18,4) (18,5) (18,6) (19,5) (19,6) (19,7) (20,6) (20,7) (20,8) (21,7) (21,8) (22,8))
    };
    (@arms $pn:expr, $f:ident [] $args:tt, $fallback:expr; $(($p:literal, $n:literal))*) => {
        match $pn {
            $(($p, $n) => $f::<$p, $n> $args,)*
            _ => $fallback,
        }
    };
    (@arms $pn:expr, $f:ident [, _] $args:tt, $fallback:expr; $(($p:literal, $n:literal))*) => {
        match $pn {
            $(($p, $n) => $f::<$p, $n, _> $args,)*
            _ => $fallback,
        }
    };
}

/// The most constraints `M`, coordinates `N` and group coordinates `K` of a constrained system
/// that [`with_constrained_dimensions!`] has an instance for.
pub const MAX_DISPATCHED_CONSTRAINED: (usize, usize, usize) = (3, 6, 1);

/// Calls a function generic over the dimensions of a system with constraints,
/// `f::<S, K, N, M, Z>(args)` with `N = S + K` and `Z = N + M`, for dimensions known only at run
/// time: one instance per `(S, K, M)` with `S + K ≤ 6`, `K ≤ 1` and `M ≤ 3`
/// ([`MAX_DISPATCHED_CONSTRAINED`], 36 instances). The function returns `Result<_, String>`;
/// other dimensions are an `Err` saying so.
///
/// ```
/// fn dims<const S: usize, const K: usize, const N: usize, const M: usize, const Z: usize>(
/// ) -> Result<[usize; 5], String> {
///     Ok([S, K, N, M, Z])
/// }
/// assert_eq!(dirac_jit::with_constrained_dimensions!(2, 0, 1, dims()), Ok([2, 0, 2, 1, 3]));
/// assert!(dirac_jit::with_constrained_dimensions!(2, 0, 4, dims()).is_err());
/// ```
#[macro_export]
macro_rules! with_constrained_dimensions {
    ($s:expr, $k:expr, $m:expr, $f:ident $args:tt) => {
        $crate::with_constrained_dimensions!(@table ($s, $k, $m), $f [] $args,
            (s, k, m) => ::core::result::Result::Err(::std::format!(
                "{s} shape and {k} group coordinates with {m} constraints: the fixed-size constrained instances have at most {} coordinates, {} of them group coordinates, and {} constraints (other sizes run on the element view, `Code::element_view`)",
                $crate::MAX_DISPATCHED_CONSTRAINED.1,
                $crate::MAX_DISPATCHED_CONSTRAINED.2,
                $crate::MAX_DISPATCHED_CONSTRAINED.0
            )),
        )
    };
    // `f::<_>(args)`: a function with one more type parameter, inferred.
    ($s:expr, $k:expr, $m:expr, $f:ident::<_> $args:tt else $fallback:expr) => {
        $crate::with_constrained_dimensions!(@table ($s, $k, $m), $f [, _] $args, _ => $fallback,)
    };
    (@table $skm:expr, $f:ident $tail:tt $args:tt, $($fallback:tt)*) => {
        $crate::with_constrained_dimensions!(@arms $skm, $f $tail $args, [$($fallback)*];
            (1,0,1) (2,0,1) (3,0,1) (4,0,1) (5,0,1) (6,0,1)
            (0,1,1) (1,1,1) (2,1,1) (3,1,1) (4,1,1) (5,1,1)
            (1,0,2) (2,0,2) (3,0,2) (4,0,2) (5,0,2) (6,0,2)
            (0,1,2) (1,1,2) (2,1,2) (3,1,2) (4,1,2) (5,1,2)
            (1,0,3) (2,0,3) (3,0,3) (4,0,3) (5,0,3) (6,0,3)
            (0,1,3) (1,1,3) (2,1,3) (3,1,3) (4,1,3) (5,1,3))
    };
    (@arms $skm:expr, $f:ident [] $args:tt, [$($fallback:tt)*];
        $(($s:literal, $k:literal, $m:literal))*) => {
        match $skm {
            $(($s, $k, $m) => $f::<$s, $k, { $s + $k }, $m, { $s + $k + $m }> $args,)*
            $($fallback)*
        }
    };
    (@arms $skm:expr, $f:ident [, _] $args:tt, [$($fallback:tt)*];
        $(($s:literal, $k:literal, $m:literal))*) => {
        match $skm {
            $(($s, $k, $m) => $f::<$s, $k, { $s + $k }, $m, { $s + $k + $m }, _> $args,)*
            $($fallback)*
        }
    };
}
