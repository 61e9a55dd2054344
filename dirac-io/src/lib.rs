//! Results that leave the process: runs and ensembles of [`dirac`] integrators written to
//! Apache Parquet, ensembles split into shards that run anywhere (a Slurm array job, several
//! machines, one machine in several sittings) and restart where they stopped, and progress bars.
//!
//! * [`ParquetObserver`]: an observer for [`Drive::run`](dirac::Drive::run) that streams states
//!   into a Parquet file, one bounded row group at a time, encoded on a thread of its own
//!   ([`Options::rows_per_file`] splits a long run into parts, so that not even the footer grows
//!   with it); [`write_ensemble`] for ensembles (one file per member, or one file with a
//!   `member` column);
//! * [`table`]: an ensemble as a table of initial states and parameters (CSV or Parquet);
//! * [`shard`]: shard `i` of `n` of such an ensemble, written atomically and skipped when already
//!   complete, failed members recorded with their typed error; [`shard::merge`] gives one table;
//! * [`progress`]: indicatif progress bars, drawn only when standard error is a terminal.
//!
//! # The trajectory schema
//!
//! One row per written state, in step order:
//!
//! | column | type | meaning |
//! | --- | --- | --- |
//! | `member` | u64 | the ensemble member (only in ensemble files written to one file) |
//! | `step` | u64 | `k`, from 0 (the initial state) |
//! | `t` | f64 | `k · h` |
//! | `x_<name>`, `w_<name>`, `mu_<name>`, `g_<name>` | f64 | a [`ReducedState`](dirac::ReducedState): shape `x`, momenta `w`, `μ`, group `g`, one column per coordinate named in the annotation |
//! | `q_<name>`, `p_<name>` | f64 | a [`CanonicalState`](dirac::CanonicalState) instead |
//! | `iterations` | u32, null at step 0 | Newton corrections of the step that produced the state |
//! | `residual` | f64, null at step 0 | its accepted `‖R‖∞` |
//! | `rcond` | f64, nullable | its reciprocal condition estimate (null when no Jacobian was factored) |
//! | extra names | f64 | [`Options::extra`]: energies or other functions of the state |
//!
//! The file's key-value metadata describes the run ([`RunInfo::key_values`]): `dirac.h`,
//! `dirac.parameters` (names, comma-separated) and `dirac.parameter.<name>` (value),
//! `dirac.shape`, `dirac.group`, `dirac.integrator`, `dirac.newton.{abs_tol, rel_tol,
//! max_iterations, min_rcond}`, `dirac.every`, and after [`ParquetObserver::finish_with`]
//! `dirac.outcome`, `dirac.steps` and for a failed run `dirac.error.{kind, step, residual,
//! message}`. Floats are written in Rust's shortest round-trip form. Values are written with
//! plain encoding and no compression by default ([`Options::snappy`]), so a reader gets the
//! run's bits exactly.
//!
//! ```
//! use dirac::paper::DoubleSphericalPendulum;
//! use dirac::prelude::*;
//! use dirac_io::{Describe, Options, ParquetObserver};
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let sys = DoubleSphericalPendulum::paper();
//! let integ = ReducedIntegrator::plus(sys, NewtonOptions::default());
//! let path = std::env::temp_dir().join(format!("dsp-lib-doc-{}.parquet", std::process::id()));
//! // Every state, and the energy at each state beside it.
//! let options = Options::new().extra(&["x_sum"], |_, s: &ReducedState<3, 1>, out| {
//!     out[0] = s.x.sum();
//! });
//! let mut out = ParquetObserver::create(&path, integ.describe(), options)?;
//! integ.run(DoubleSphericalPendulum::paper_initial_state(), 1000, out.observer())?;
//! out.finish()?;
//! # std::fs::remove_file(path)?;
//! # Ok(())
//! # }
//! ```
#![warn(missing_docs)]

pub mod columns;
pub mod ensemble;
pub mod error;
pub mod observer;
pub mod progress;
pub mod read;
pub mod shard;
pub mod table;

pub use columns::{Describe, RunInfo, StateColumns};
pub use ensemble::{write_ensemble, EnsembleOutput};
pub use error::{Error, Result};
pub use observer::{Options, ParquetObserver};
