//! Systems given at run time: a discrete (or continuous) Lagrangian written as text — the same
//! attribute and function a Rust program compiles in with `#[reduced_lagrangian]` — compiled by
//! the same compiler (`dirac-compiler`: parsing, the invariance check, differentiation, the
//! paper's reduction) and by Cranelift to straight-line machine code, behind the runtime's traits.
//! Every integrator for systems on vector spaces then runs it: the reduced (+) and (−) steps of
//! eqs. (4.6) and (4.8), the unreduced step, compositions, and forces and controls.
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
//! What the text may declare is what the attribute accepts for a system on vector spaces of at
//! most 16 coordinates: `shape(..)`, `group(..)` (or `coordinates(..)` with `translate(..)`), a
//! connection, `step = ..`, a continuous Lagrangian with its `rule`, forces and controls. Systems
//! on rotation groups, element-wise systems, constraints and adaptive steps are compiled in.
//! A mistake in the text gets the attribute's message, with its line and column.
//!
//! The dimensions are type parameters, as for a compiled-in system ([`Code::instantiate`] checks
//! them against the text's), so a step runs the same fixed-size code with no allocation: the
//! kernels read and write the integrators' stack vectors directly.

#![warn(missing_docs)]

mod codegen;
mod error;
mod system;

pub use error::Error;
pub use system::{compile, Code, JitSystem, MAX_PARAMETERS};
