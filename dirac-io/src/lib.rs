//! Results that leave the process: runs and ensembles of [`dirac`] integrators written to
//! Apache Parquet, ensembles split into shards that run anywhere (a Slurm array job, several
//! machines, one machine in several sittings) and restart where they stopped, and progress bars.
//!
//! * [`Output`]: an observer for [`Drive::run`](dirac::Drive::run) that turns every state of a
//!   run — flat, on rotation groups, element-wise, or an ensemble's members — into a row of
//!   named `f64` columns (named by the system's description, [`Describe`]) and streams the rows,
//!   one bounded block at a time, written on a thread of its own, into a [`Sink`]: a directory
//!   of parts each published complete when full ([`Options::rows_per_file`]), so that a killed
//!   run keeps every part it finished and memory does not grow with the run. The sink is the
//!   format; [`Parquet`] is the one this crate writes ([`ParquetObserver`]), in [`parquet`].
//!   [`write_ensemble`] for ensembles (one file per member, or one file with a `member` column);
//! * [`table`]: an ensemble as a table of initial states and parameters (CSV or Parquet);
//! * [`shard`]: shard `i` of `n` of such an ensemble, written atomically and skipped when already
//!   complete, failed members recorded with their typed error; [`shard::merge`] gives one table;
//! * [`progress`]: indicatif progress bars, drawn only when standard error is a terminal;
//! * [`integrity`]: the checksums every file written carries, checked by the [`read`]ers,
//!   [`shard::merge`] and the shards' skip-as-complete.
//!
//! # What survives a failure
//!
//! * **A killed process** (SIGKILL, a node lost, a time limit): every part published before it
//!   is complete and readable; the part being written is a hidden partial file
//!   (`.part-00007.parquet.partial`) that no reader sees. What is lost is at most that part's
//!   rows ([`Options::rows_per_file`], or about 64 MiB of values): the run waits at each part's
//!   end until it is published. [`ParquetObserver::resume`] continues the run from the last
//!   state published. A shard killed leaves no shard file.
//! * **A full disk** (any write error): `finish` returns the operating system's error
//!   ([`Error::Io`]), the hidden partial file is removed, and the parts published before stay.
//! * **An early return or a panic** (the observer dropped without `finish`): the rows held and
//!   the last state are written and the part published, with `dirac.outcome = aborted`.
//! * **Damage on disk** (a flipped bit, a truncation): the checksums disagree; the readers and
//!   [`shard::merge`] refuse the file naming it, and a rerun of its shard runs it again.
//!
//! # The trajectory schema
//!
//! One row per written state, in step order:
//!
//! | column | type | meaning |
//! | --- | --- | --- |
//! | `member` | u64 | the ensemble member (only in ensemble files written to one file) |
//! | `step` | u64 | `k`, from 0 (the initial state) |
//! | `t` | f64 | the time `t_k` of the state (`k · h` for a fixed step; a step-size schedule gives its own times) |
//! | `x_<name>`, `w_<name>`, `mu_<name>`, `g_<name>` | f64 | a [`ReducedState`](dirac::ReducedState): shape `x`, momenta `w`, `μ`, group `g`, one column per coordinate named in the annotation |
//! | `q_<name>`, `p_<name>` | f64 | a [`UnreducedState`](dirac::UnreducedState) instead |
//! | `q_<entry>`, `p_<component>` (then `mu_x`, `mu_y`, `mu_z` reduced) | f64 | a state on rotation groups ([`lie_names`]) instead |
//! | `q_<i>`, `p_<i>` | f64 | an element-wise state sized at run time, `i` the coordinate index, instead |
//! | `iterations` | u32, null at step 0 | Newton corrections of the step that produced the state |
//! | `residual` | f64, null at step 0 | its accepted `‖R‖∞` |
//! | `rcond` | f64, nullable | its reciprocal condition estimate (null when no Jacobian was factored) |
//! | extra names | f64 | [`Options::extra`]: energies or other functions of the state |
//!
//! The file's key-value metadata describes the run ([`RunInfo::key_values`]): `dirac.h`,
//! `dirac.parameters` (names, comma-separated) and `dirac.parameter.<name>` (value),
//! `dirac.shape`, `dirac.group`, `dirac.integrator`, `dirac.newton.{abs_tol, rel_tol,
//! max_iterations, min_rcond}`, `dirac.every`, and after [`ParquetObserver::finish_with`]
//! `dirac.outcome` (`completed`, `stopped`, `failed`, or `aborted` for an observer dropped
//! without `finish`), `dirac.steps` and for a failed run `dirac.error.{kind, step, residual,
//! message}`, and the checksums `dirac.checksum*` ([`integrity`]). A system with adaptive steps
//! (`time(t), adapt = ..`) adds `dirac.physical_time`, the name of the coordinate column that holds
//! the physical time `t_k` (`g_t` or `q_t`); the run's clock, the `t` column, is that time too.
//! A run on rotation groups records `dirac.coordinates` (`r:rotation`, each coordinate and its
//! kind), an element-wise one `dirac.coordinates` (its coordinate arrays) and `dirac.sizes`
//! (`n=200`). Floats are written in Rust's shortest round-trip form. Values are written with plain encoding and no compression by
//! default ([`Options::snappy`]), so a reader gets the run's bits exactly.
//!
//! ```
//! use dirac::paper::DoubleSphericalPendulum;
//! use dirac::prelude::*;
//! use dirac_io::{Describe, Options, ParquetObserver};
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let sys = DoubleSphericalPendulum::paper();
//! let integ = ReducedIntegrator::plus(sys, NewtonOptions::default());
//! // A directory of parts `part-00000.parquet`, …: pyarrow, Polars and DuckDB read it as one table.
//! let path = std::env::temp_dir().join(format!("dsp-lib-doc-{}", std::process::id()));
//! // Every state, and the energy at each state beside it.
//! let options = Options::new().extra(&["x_sum"], |_, s: &ReducedState<3, 1>, out| {
//!     out[0] = s.x.sum();
//! });
//! let mut out = ParquetObserver::create(&path, integ.describe(), options)?;
//! let result = integ.run(DoubleSphericalPendulum::paper_initial_state()).steps(1000).observe(out.observer()).stream();
//! // The outcome first (a failed run's typed error goes into the metadata), then `?`.
//! out.finish_with(&result)?;
//! result?;
//! assert_eq!(dirac_io::read::row_count(&path)?, 1001);
//! # std::fs::remove_dir_all(path)?;
//! # Ok(())
//! # }
//! ```
#![warn(missing_docs)]

pub mod columns;
pub mod ensemble;
pub mod error;
mod files;
pub mod output;
pub mod parquet;
pub mod progress;
pub mod shard;
pub mod table;

pub use self::parquet::{integrity, read, Parquet, ParquetObserver};
pub use columns::{lie_names, Describe, RunInfo, StateColumns};
pub use ensemble::{write_ensemble, EnsembleOutput};
pub use error::{Error, Result};
pub use output::{Layout, Options, Output, Resumed, Rows, Sink};
