//! Sharded, restartable ensembles: shard `i` of `n` of an ensemble [`Table`] runs anywhere — a
//! Slurm array task, another machine, a later sitting — on all local cores, and writes one
//! Parquet file; [`merge`] concatenates the shards into the table a single process would have
//! written, bit for bit.
//!
//! * **Deterministic assignment.** Shard `i` of `n` takes the contiguous rows
//!   `⌊i·N/n⌋ .. ⌊(i+1)·N/n⌋` of a table of `N` rows ([`Shard::members`]): the same members
//!   whatever the machine, the thread count or the order the shards run in, so that the shards
//!   in order are the members in order.
//! * **Atomic output.** A shard is written to a hidden partial file in the output directory and
//!   renamed to `shard-<i>-of-<n>.parquet` when complete and synced, so a file with that name is
//!   always a whole shard. A shard killed before that leaves at most a partial file, which the
//!   next attempt removes.
//! * **Restart.** A shard whose file exists, records the same table (its
//!   [fingerprint](Table::fingerprint)), step count and shard, and whose checksums hold
//!   ([`crate::integrity`]), is skipped: resubmit the whole array after a failure or a
//!   pre-emption and only the missing shards run. A file of another ensemble in its place is an
//!   error, never silently kept; a damaged one (a changed byte, a truncation) is run again
//!   ([`ShardReport::corrupt`] says why).
//! * **Integrity.** [`merge`] checks every shard's checksums and refuses a damaged shard, naming
//!   it: it is never merged.
//! * **Failed members are rows.** A member whose integration fails is written with
//!   `status = "failed"`, the state and statistics up to the failed step, and its typed error
//!   ([`StepError`]): `error_kind`, `error_step`, `error_residual`, `error_message`. A member
//!   whose closure returns an error (`row.require("m2")?`, a value out of range) or panics is
//!   a failed row too: `error_kind` `member` or `member panicked`, `error_message` the error's
//!   text or the panic's message, no step or residual, no state (`steps` and `t` 0, the state
//!   columns `NaN`); the other members run.
//! * **Validated tables.** Before any member runs, the table's columns are checked against the
//!   names the run accepts ([`Table::validate_for`]): an unknown, misspelled or repeated name
//!   is an [`Error::Columns`] naming it and listing the accepted names.
//!
//! # The shard schema
//!
//! One row per member: `member` (u64), `status` (`completed` or `failed`), `steps` (completed),
//! `t` (time reached), the last state's columns (as in the [trajectory schema](crate)),
//! `iterations`, `max_iterations`, `factorizations` (u64), `max_residual` (f64), `worst_rcond`
//! (f64) and `worst_rcond_step` (u64, both null when no Jacobian was factored), and
//! `error_kind` (utf8), `error_step` (u64), `error_residual` (f64), `error_message` (utf8), null
//! for a completed member. Key-value metadata: the integrator's description, `dirac.steps`,
//! `dirac.table.fingerprint`, `dirac.table.rows`, `dirac.shard.index` and `dirac.shard.count`
//! (after [`merge`]: `dirac.shard.count` only).
//!
//! ```
//! use dirac::paper::DoubleSphericalPendulum;
//! use dirac::prelude::*;
//! use dirac_io::shard::{self, Shard};
//! use dirac_io::table::Table;
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! // Four members that differ in their first shape momentum.
//! let mut table = Table::new(["w_phi1"]);
//! for i in 0..4 {
//!     table.push(&[0.1 * i as f64])?;
//! }
//! let member = |row: shard::Row<'_>| -> shard::Member<_> {
//!     let integ = ReducedIntegrator::plus(DoubleSphericalPendulum::paper(), NewtonOptions::default());
//!     let default = DoubleSphericalPendulum::paper_initial_state();
//!     let names = dirac_io::Describe::describe(&integ).columns;
//!     let initial = row.state_or(&names, default);
//!     Ok((integ, initial))
//! };
//! let dir = std::env::temp_dir().join(format!("shard-doc-{}", std::process::id()));
//! for i in 0..2 {
//!     shard::run_shard(&table, Shard::new(i, 2)?, &dir, 10, member)?;
//! }
//! let merged = shard::merge(&dir, 2, &dir.join("merged.parquet"))?;
//! assert_eq!(merged.rows, 4);
//! # std::fs::remove_dir_all(dir)?;
//! # Ok(())
//! # }
//! ```

use std::collections::BTreeMap;
use std::ops::Range;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

use dirac::prelude::*;
use dirac::runtime::ensemble::map;

use crate::columns::{Describe, RunInfo, StateColumns};
use crate::error::{Error, Result};
pub use crate::files::publish;
use crate::files::{member_file, remove_partials};
use crate::integrity::verify_required;
use crate::output::Options;
use crate::parquet::shard_file::{write_rows, Failure, MemberRow};
use crate::parquet::ParquetObserver;
use crate::progress;
use crate::read::{concatenate, key_values, row_count};
pub use crate::table::{MissingColumn, Row, Table};

/// Why a member closure could not build its member: any error converts into it with `?`
/// ([`MissingColumn`] from [`Row::require`], a `String` with `.into()`); its text becomes the
/// member's `error_message`.
pub type MemberError = Box<dyn std::error::Error + Send + Sync>;

/// What a member closure returns: the member's integrator and initial state, or why it cannot
/// be built.
pub type Member<I> = std::result::Result<(I, <I as Stepper>::State), MemberError>;

/// Shard `index` of `count` (from 0).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// Which shard, `0 ≤ index < count`.
    pub index: usize,
    /// How many shards the ensemble is split into.
    pub count: usize,
}

impl Shard {
    /// Shard `index` of `count`; an error unless `index < count`.
    pub fn new(index: usize, count: usize) -> Result<Self> {
        if index >= count {
            return Err(Error::Usage(format!(
                "shard {index} of {count}: the index must be below the count (shards are numbered from 0)"
            )));
        }
        Ok(Shard { index, count })
    }

    /// `"i/n"`, e.g. `"2/4"`.
    pub fn parse(text: &str) -> Result<Self> {
        let parsed = text
            .split_once('/')
            .and_then(|(i, n)| Some((i.trim().parse().ok()?, n.trim().parse().ok()?)));
        let (i, n) = parsed.ok_or_else(|| {
            Error::Usage(format!(
                "`{text}` is not a shard: expected `i/n`, e.g. `2/4`"
            ))
        })?;
        Self::new(i, n)
    }

    /// The shard of a Slurm array task: the index is `SLURM_ARRAY_TASK_ID` (an array
    /// `--array=0-(n-1)`), the count `count` if given, else `SLURM_ARRAY_TASK_COUNT`.
    ///
    /// Give the count when resubmitting part of an array: `sbatch --array=2 ...` runs task 2 with
    /// `SLURM_ARRAY_TASK_COUNT=1`, which is then rejected here (index 2 of 1) rather than
    /// assigning the wrong members.
    pub fn from_slurm(count: Option<usize>) -> Result<Self> {
        let var = |name: &str| -> Result<usize> {
            let value = std::env::var(name).map_err(|_| {
                Error::Usage(format!(
                    "{name} is not set: give the shard as `--shard i/n`, or run as a Slurm array task"
                ))
            })?;
            value.trim().parse().map_err(|_| {
                Error::Usage(format!("{name}=`{value}` is not a non-negative integer"))
            })
        };
        let index = var("SLURM_ARRAY_TASK_ID")?;
        let count = match count {
            Some(n) => n,
            None => var("SLURM_ARRAY_TASK_COUNT")?,
        };
        Self::new(index, count).map_err(|e| {
            Error::Usage(format!(
                "{e}; when resubmitting part of an array, give the number of shards (`--shards n`)"
            ))
        })
    }

    /// The rows of a table of `total` rows that this shard integrates: `⌊i·N/n⌋ .. ⌊(i+1)·N/n⌋`.
    /// (Empty for a shard with `index >= count`, which [`Shard::new`] refuses.)
    pub fn members(&self, total: usize) -> Range<usize> {
        if self.index >= self.count {
            return total..total;
        }
        let bound = |i: usize| (i as u128 * total as u128 / self.count as u128) as usize;
        bound(self.index)..bound(self.index + 1)
    }

    /// The shard's file name, `shard-00002-of-00004.parquet` (zero-padded so that names sort
    /// in shard order).
    pub fn file_name(&self) -> String {
        format!("shard-{:05}-of-{:05}.parquet", self.index, self.count)
    }

    /// The file of the shard's trajectories ([`run_shard_with_states`]),
    /// `shard-00002-of-00004.states.parquet`.
    pub fn states_file_name(&self) -> String {
        format!(
            "shard-{:05}-of-{:05}.states.parquet",
            self.index, self.count
        )
    }
}

/// What [`run_shard`] did.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ShardReport {
    /// The shard's file.
    pub path: PathBuf,
    /// The file was already complete: nothing was integrated.
    pub skipped: bool,
    /// The members of the shard.
    pub members: Range<usize>,
    /// Members whose integration failed (recorded as rows).
    pub failed: usize,
    /// A shard file found in place but damaged (its checksums disagree, or it cannot be read),
    /// and why: it was run again and replaced.
    pub corrupt: Option<String>,
}

/// The text of a panic's payload (a `&str` or a `String`, as `panic!` makes them).
fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| (*s).to_owned())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "a panic without a message".to_owned())
}

/// Member `i` built by its closure, or why not: the closure's error (kind `member`), or its
/// panic (kind `member panicked`), caught so that one member's failure does not end the others
/// (the closure is called again for the next members: one that keeps state across calls must
/// tolerate a panic mid-call).
fn build<I, F>(table: &Table, i: usize, member: &F) -> std::result::Result<(I, I::State), Failure>
where
    I: Describe,
    F: Fn(Row<'_>) -> Member<I>,
{
    let failure = |kind: &str, message: String| Failure {
        kind: kind.to_owned(),
        step: None,
        residual: None,
        message,
    };
    let row = table.row(i).ok_or_else(|| {
        failure(
            "member",
            format!("no row {i} in a table of {} rows", table.len()),
        )
    })?;
    match catch_unwind(AssertUnwindSafe(|| member(row))) {
        Ok(Ok(built)) => Ok(built),
        Ok(Err(e)) => Err(failure("member", e.to_string())),
        Err(payload) => Err(failure("member panicked", panic_message(payload.as_ref()))),
    }
}

/// The run's description: that of the first member of the table that can be built (the same
/// member whichever shard asks, so that the shards' files agree), checked to name one column
/// per state component. If none can be built, the first member's error.
fn description<I, F>(table: &Table, member: &F) -> Result<RunInfo>
where
    I: Describe,
    F: Fn(Row<'_>) -> Member<I>,
{
    let mut first = None;
    for i in 0..table.len() {
        match build(table, i, member) {
            Ok((integ, _)) => {
                let info = integ.describe();
                if let Some(width) = I::State::WIDTH.filter(|w| *w != info.columns.len()) {
                    return Err(Error::Usage(format!(
                        "the integrator's description names {} state columns ({}) where its \
                         state has {width}",
                        info.columns.len(),
                        info.columns.join(", "),
                    )));
                }
                return Ok(info);
            }
            Err(failure) => {
                first.get_or_insert((i, failure.message));
            }
        }
    }
    let (member, message) = first.unwrap_or((0, "the table has no rows".to_owned()));
    Err(Error::Member { member, message })
}

/// The identity a shard file records and a rerun checks.
fn identity(
    table: &Table,
    steps: usize,
    every: Option<usize>,
    shard: Option<Shard>,
) -> Vec<(String, String)> {
    let mut kv = vec![
        ("dirac.steps".to_owned(), steps.to_string()),
        (
            "dirac.states.every".to_owned(),
            every.map_or("none".to_owned(), |k| k.to_string()),
        ),
        (
            "dirac.table.fingerprint".to_owned(),
            format!("{:016x}", table.fingerprint()),
        ),
        ("dirac.table.rows".to_owned(), table.len().to_string()),
    ];
    if let Some(s) = shard {
        kv.push(("dirac.shard.index".to_owned(), s.index.to_string()));
        kv.push(("dirac.shard.count".to_owned(), s.count.to_string()));
    }
    kv
}

/// Whether the metadata `found` agrees with every pair of `expected`: `None`, or the first key
/// that differs.
fn disagreement(found: &BTreeMap<String, String>, expected: &[(String, String)]) -> Option<String> {
    expected.iter().find_map(|(k, v)| {
        let f = found.get(k);
        (f != Some(v)).then(|| {
            format!(
                "{k} = {} where {v} was expected",
                f.map_or("(missing)", String::as_str)
            )
        })
    })
}

/// Integrates shard `shard` of the ensemble `table`, `steps` steps per member, on all local
/// cores (rayon's pool), and writes its file into `dir` (created if missing); skips the shard
/// when its file is already complete (see the [module documentation](self)). `member(row)`
/// builds each member's integrator and initial state from its row, or returns why it cannot
/// (the member is then a failed row, as when it panics).
///
/// Before any member runs, the table's columns are checked against the run's description
/// ([`Table::validate_for`]; the description is that of the first member that can be built):
/// an unknown, misspelled or repeated column is an [`Error::Columns`], and a table none of
/// whose members can be built an [`Error::Member`]. A panic inside an integration (in a
/// Lagrangian's own code) is not caught.
///
/// A bar of members follows the shard on a terminal ([`progress`]).
pub fn run_shard<I, F>(
    table: &Table,
    shard: Shard,
    dir: &Path,
    steps: usize,
    member: F,
) -> Result<ShardReport>
where
    I: Describe,
    F: Fn(Row<'_>) -> Member<I> + Sync,
{
    run_shard_with_states(table, shard, dir, steps, None, member)
}

/// [`run_shard`] that also writes every member's trajectory, every `every`-th state (and the
/// last), to `shard-<i>-of-<n>.states.parquet` in the [trajectory schema](crate) with a `member`
/// column, members in order. Each member streams into its own part (a hidden directory beside
/// the shard), so memory stays bounded; the parts are concatenated and published before the
/// shard's own file, whose presence still means "complete". With `every = None`, only the
/// shard's table of members is written.
pub fn run_shard_with_states<I, F>(
    table: &Table,
    shard: Shard,
    dir: &Path,
    steps: usize,
    every: Option<usize>,
    member: F,
) -> Result<ShardReport>
where
    I: Describe,
    F: Fn(Row<'_>) -> Member<I> + Sync,
{
    if table.is_empty() {
        return Err(Error::Usage("the ensemble table has no rows".into()));
    }
    // The fields are public: a shard made without `Shard::new` is checked here.
    let shard = Shard::new(shard.index, shard.count)?;
    let info = description(table, &member)?;
    table.validate_for(&info)?;
    std::fs::create_dir_all(dir).map_err(Error::io(dir))?;
    let path = dir.join(shard.file_name());
    let members = shard.members(table.len());
    let expected = identity(table, steps, every, Some(shard));
    let mut corrupt = None;
    if path.exists() {
        // A footer that cannot be read is damage (the shard is rerun); a readable one of another
        // ensemble is an error: that file is someone else's.
        match key_values(&path) {
            Ok(found) => {
                if let Some(d) = disagreement(&found, &expected) {
                    return Err(Error::content(
                        &path,
                        format!("this file belongs to another ensemble or run ({d}); remove it to rerun the shard"),
                    ));
                }
                let states_file = dir.join(shard.states_file_name());
                let sound = verify_required(&path)
                    .and_then(|()| match every {
                        Some(_) => verify_required(&states_file),
                        None => Ok(()),
                    })
                    .and_then(|()| row_count(&path));
                match sound {
                    Ok(rows) if rows == members.len() as u64 => {
                        return Ok(ShardReport {
                            path,
                            skipped: true,
                            members,
                            failed: 0,
                            corrupt: None,
                        });
                    }
                    Ok(rows) => {
                        corrupt = Some(format!(
                            "{}: {rows} rows where the shard has {} members",
                            path.display(),
                            members.len()
                        ));
                    }
                    Err(e) => corrupt = Some(e.to_string()),
                }
            }
            Err(e) => corrupt = Some(e.to_string()),
        }
    }
    remove_partials(&path)?;
    let states = dir.join(shard.states_file_name());
    remove_partials(&states)?;
    let parts = dir.join(format!(".{}.parts", shard.states_file_name()));
    if parts.exists() {
        std::fs::remove_dir_all(&parts).map_err(Error::io(&parts))?;
    }
    if every.is_some() {
        std::fs::create_dir_all(&parts).map_err(Error::io(&parts))?;
    }

    let bar = progress::bar(
        members.len() as u64,
        &format!("shard {}/{}", shard.index, shard.count),
        "members",
    );
    let indices: Vec<usize> = members.clone().collect();
    let rows = map(&indices, |&i| -> Result<MemberRow> {
        let (integ, initial) = match build(table, i, &member) {
            Ok(built) => built,
            Err(failure) => {
                if let Some(k) = every {
                    // An empty part, so that the states file still has every member's.
                    let options = Options::<I::State>::new()
                        .every(k)
                        .member(i as u64)
                        .background(false);
                    ParquetObserver::create(member_file(&parts, i), info.clone(), options)?
                        .finish()?;
                }
                bar.inc(1);
                return Ok(MemberRow {
                    member: i as u64,
                    steps: 0,
                    t: 0.0,
                    last: vec![f64::NAN; info.columns.len()],
                    summary: [0; 3],
                    max_residual: 0.0,
                    worst_rcond: None,
                    error: Some(failure),
                });
            }
        };
        let result = match every {
            None => integ
                .run(initial)
                .steps(steps)
                .observe(|_, _, _, _| {})
                .stream(),
            Some(k) => {
                // The members occupy every core: each writes its own row groups.
                let options = Options::new()
                    .every(k)
                    .member(i as u64)
                    .background(false)
                    .member_file();
                let mut out =
                    ParquetObserver::create(member_file(&parts, i), info.clone(), options)?;
                let result = integ
                    .run(initial)
                    .steps(steps)
                    .observe(out.observer())
                    .stream();
                out.finish_with(&result)?;
                result
            }
        };
        let (summary, error) = match result {
            Ok(s) => (s, None),
            Err(e) => (e.trajectory, Some(Failure::from(e.source))),
        };
        let mut last = vec![0.0; summary.last.width()];
        summary.last.write_to(&mut last);
        bar.inc(1);
        Ok(MemberRow {
            member: i as u64,
            steps: summary.step_count as u64,
            t: summary.t,
            last,
            summary: [
                summary.iterations as u64,
                summary.max_iterations as u64,
                summary.factorizations as u64,
            ],
            max_residual: summary.max_residual,
            worst_rcond: summary.worst_rcond,
            error,
        })
    });
    bar.finish_and_clear();
    let rows = rows.into_iter().collect::<Result<Vec<_>>>()?;
    if every.is_some() {
        let files: Vec<PathBuf> = indices.iter().map(|&i| member_file(&parts, i)).collect();
        let mut kv = info.key_values();
        kv.extend(expected.iter().cloned());
        if files.is_empty() {
            return Err(Error::Usage(format!(
                "shard {}/{} has no members: use fewer shards than the table's {} rows",
                shard.index,
                shard.count,
                table.len()
            )));
        }
        publish(&states, |partial| {
            concatenate(&files, partial, kv).map(drop)
        })?;
        std::fs::remove_dir_all(&parts).map_err(Error::io(&parts))?;
    }
    let failed = rows.iter().filter(|r| r.error.is_some()).count();
    let mut kv = info.metadata.clone();
    kv.extend(expected);
    publish(&path, |partial| {
        write_rows(partial, &info.columns, &rows, kv)
    })?;
    Ok(ShardReport {
        path,
        skipped: false,
        members,
        failed,
        corrupt,
    })
}

fn first_states(kv: &BTreeMap<String, String>) -> bool {
    kv.get("dirac.states.every").is_some_and(|e| e != "none")
}

/// Where [`merge`] writes the merged trajectories of shards run with states: `out` with
/// `.parquet` replaced by `.states.parquet` (`merged.parquet` → `merged.states.parquet`).
pub fn states_path(out: &Path) -> PathBuf {
    out.with_extension("states.parquet")
}

/// What [`merge`] wrote.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MergeReport {
    /// The merged file.
    pub path: PathBuf,
    /// Its rows: every member of the table.
    pub rows: u64,
}

/// Concatenates the `count` shard files in `dir`, in shard order, into one table at `out`
/// (written atomically): the members in table order, bit for bit what one process running the
/// whole table as shard `0/1` writes. Shards run with states ([`run_shard_with_states`]) also
/// have their trajectories concatenated, into [`states_path`]`(out)`. Fails, naming them, if
/// shards are missing, incomplete, damaged (their checksums disagree: rerun them) or of
/// different ensembles.
pub fn merge(dir: &Path, count: usize, out: &Path) -> Result<MergeReport> {
    if count == 0 {
        return Err(Error::Usage(
            "merging 0 shards: give the number of shards run".into(),
        ));
    }
    let paths: Vec<PathBuf> = (0..count)
        .map(|i| dir.join(Shard { index: i, count }.file_name()))
        .collect();
    let missing: Vec<String> = (0..count)
        .filter(|&i| !paths[i].exists())
        .map(|i| i.to_string())
        .collect();
    if !missing.is_empty() {
        return Err(Error::content(
            dir,
            format!(
                "shards {} of {count} are missing: run (or resubmit) them first",
                missing.join(", ")
            ),
        ));
    }
    // A damaged shard is refused, naming it, before anything is written.
    for path in &paths {
        verify_required(path)?;
    }
    let first = key_values(&paths[0])?;
    let keys = [
        "dirac.steps",
        "dirac.states.every",
        "dirac.table.fingerprint",
        "dirac.table.rows",
    ];
    let common: Vec<(String, String)> = keys
        .iter()
        .filter_map(|k| Some(((*k).to_owned(), first.get(*k)?.clone())))
        .collect();
    let rows_total: u64 = first
        .get("dirac.table.rows")
        .and_then(|r| r.parse().ok())
        .ok_or_else(|| Error::content(&paths[0], "not a shard file (no dirac.table.rows)"))?;
    for (i, path) in paths.iter().enumerate() {
        let kv = key_values(path)?;
        let mut expected = common.clone();
        expected.push(("dirac.shard.index".into(), i.to_string()));
        expected.push(("dirac.shard.count".into(), count.to_string()));
        if let Some(d) = disagreement(&kv, &expected) {
            return Err(Error::content(
                path,
                format!("not shard {i} of this ensemble: {d}"),
            ));
        }
    }
    let with_states = first_states(&first);
    let mut kv: Vec<(String, String)> = first
        .into_iter()
        .filter(|(k, _)| k != "dirac.shard.index")
        .collect();
    kv.sort();
    if with_states {
        let states: Vec<PathBuf> = (0..count)
            .map(|i| dir.join(Shard { index: i, count }.states_file_name()))
            .collect();
        for path in &states {
            verify_required(path)?;
        }
        let states_out = states_path(out);
        publish(&states_out, |partial| {
            concatenate(&states, partial, kv.clone()).map(drop)
        })?;
    }
    let mut rows = 0;
    publish(out, |partial| {
        rows = concatenate(&paths, partial, kv)?;
        Ok(())
    })?;
    if rows != rows_total {
        return Err(Error::content(
            out,
            format!("{rows} rows merged where the table has {rows_total}"),
        ));
    }
    Ok(MergeReport {
        path: out.to_owned(),
        rows,
    })
}
