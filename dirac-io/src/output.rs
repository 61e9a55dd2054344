//! A run's states as rows of named `f64` columns, streamed into any [`Sink`] in memory
//! independent of the run's length: the observer half of the output, written once for every
//! format. It turns each observed state into a row (`step`, `t`, the state's columns named by
//! the system's description ([`RunInfo`]), the step's Newton statistics, the extra columns of
//! [`Options::extra`]), cuts the rows into blocks and parts, hands the blocks to the sink (on a
//! thread of its own by default), and records the run's outcome when it ends. The sink only
//! stores blocks: Parquet is one ([`crate::parquet::Parquet`], behind [`ParquetObserver`]).
//!
//! [`ParquetObserver`]: crate::ParquetObserver

use std::path::{Path, PathBuf};

use dirac::prelude::*;
use dirac::runtime::driver::RunResult;

use crate::columns::{float_text, RunInfo, StateColumns};
use crate::error::{Error, Result};

mod channel;
mod sink;
use channel::Channel;
pub use sink::{Layout, Rows, Sink};

/// Blocks of rows (Parquet's row groups) are cut at about this many bytes of values, so that
/// what a writer holds before it writes is bounded whatever the run's length and the state's
/// size: 8 MiB is 2,600 rows of the 200-particle lattice (406 columns) or 80,000 rows of a
/// 4-coordinate system. Measured on the lattice with Parquet: 2 MiB groups cost more per row
/// (per-column-chunk allocations and metadata) and grew the footer 4× faster; the writer holds
/// at most three groups (one filling, one queued, one being written), 24 MiB.
pub const ROW_GROUP_BYTES: usize = 8 << 20;

/// The default size of a part ([`Options::rows_per_file`]): about 64 MiB of values, eight row
/// groups. What a killed run loses is at most the part being written (the run waits at each
/// part's end until the part is published), so this bounds the loss (a few seconds of writing);
/// it also bounds the footer the writer holds (about 2.5 MiB for the 200-particle lattice), and
/// a run of 10^6 steps of that lattice is 50 files.
pub const PART_BYTES: u64 = 64 << 20;

/// How the output is laid out on disk.
#[derive(Clone, Copy, Debug)]
enum Split {
    /// A directory of parts of about this many rows (`None`: [`PART_BYTES`] of values).
    Parts(Option<u64>),
    /// One file, published when the run ends.
    File,
}

/// The energies (or any other derived quantities) written beside each state: the column names,
/// and a function of the step index and the state that fills one value per name.
type Extra<St> = (Vec<String>, Box<dyn FnMut(usize, &St, &mut [f64]) + Send>);

/// How an [`Output`] writes: which states, which extra columns, how the rows are cut into
/// blocks and parts, whether they are compressed.
pub struct Options<St> {
    every: usize,
    member: Option<u64>,
    extra: Option<Extra<St>>,
    compress: bool,
    row_group_bytes: usize,
    background: bool,
    split: Split,
    sync: bool,
}

impl<St> Default for Options<St> {
    fn default() -> Self {
        Options {
            every: 1,
            member: None,
            extra: None,
            compress: false,
            row_group_bytes: ROW_GROUP_BYTES,
            background: true,
            split: Split::Parts(None),
            sync: false,
        }
    }
}

impl<St: StateColumns> Options<St> {
    /// Every state (the default).
    pub fn new() -> Self {
        Self::default()
    }

    /// Only every `k`-th state (`step % k == 0`); the last state of a run is written too, when
    /// it is not a multiple of `k`, by [`Output::finish_with`].
    #[must_use]
    pub fn every(mut self, k: usize) -> Self {
        self.every = k.max(1);
        self
    }

    /// A `member` column with this value on every row (for ensembles written to one file).
    #[must_use]
    pub fn member(mut self, member: u64) -> Self {
        self.member = Some(member);
        self
    }

    /// Columns `names` computed from each written state by `f(step, state, out)`, which fills
    /// `out[i]` for `names[i]`: energies, momenta, invariants.
    #[must_use]
    pub fn extra(
        mut self,
        names: &[&str],
        f: impl FnMut(usize, &St, &mut [f64]) + Send + 'static,
    ) -> Self {
        self.extra = Some((names.iter().map(|n| (*n).to_owned()).collect(), Box::new(f)));
        self
    }

    /// Compressed values (default: none), where the format compresses: Parquet's Snappy
    /// pages. States of a smooth trajectory compress little, and compression costs time on
    /// every row group.
    #[must_use]
    pub fn snappy(mut self) -> Self {
        self.compress = true;
        self
    }

    /// Whether row groups are written on a thread of their own (the default), so that the run's
    /// thread only copies its states into the buffer and goes on stepping while the previous
    /// row group is written; at most two row groups are then held at once. Off, the run's thread
    /// writes them itself (what an ensemble, whose members already occupy every core, wants:
    /// [`crate::write_ensemble`] turns it off).
    #[must_use]
    pub fn background(mut self, background: bool) -> Self {
        self.background = background;
        self
    }

    /// Parts of `rows` rows each (the last one fewer) instead of the default [`PART_BYTES`] of
    /// values each. The path given to [`ParquetObserver::create`] is a directory of
    /// `part-00000.parquet`, `part-00001.parquet`, …, one dataset for pyarrow
    /// (`pq.read_table(dir)`), Polars (`pl.read_parquet(f"{dir}/*.parquet")`), DuckDB
    /// (`'dir/*.parquet'`) and this crate's readers ([`crate::read`]). A part is written under a
    /// hidden name (`.part-00003.parquet.partial`, which none of them reads) and published by a
    /// rename as soon as its `rows`-th row is written (synced first with [`Options::sync`]);
    /// the run waits for that at each part's end. So a killed run loses at most `rows` rows —
    /// those written since the last part was published, never more than one part — and every
    /// part published is complete.
    ///
    /// Row groups are no larger than a part: a row group ends at a part's end or at
    /// [`Options::row_group_bytes`] of values, whichever comes first, so parts smaller than a
    /// row group (1000 rows of a 4-coordinate system is 104 KB, a group 8 MiB) are one row
    /// group each, and the run then waits for each part, not only for the last group of a larger
    /// one. Each part carries the run's metadata; the last one also its outcome (a run whose last
    /// part is full ends with a part of no rows that carries its outcome). Smaller parts lose
    /// less to a kill (a slow run may want parts of a minute's steps) and cost a file, a footer
    /// and a wait each; the footer a writer holds grows with a part (about 120 bytes per row of
    /// the 200-particle lattice), not with the run.
    ///
    /// [`ParquetObserver::create`]: crate::ParquetObserver::create
    #[must_use]
    pub fn rows_per_file(mut self, rows: u64) -> Self {
        self.split = Split::Parts(Some(rows.max(1)));
        self
    }

    /// One file at the path instead of a directory of parts: written under a hidden name beside
    /// it (`.<name>.partial`) and published by a rename when the run ends
    /// ([`Output::finish_with`], or the observer dropped). Readers never see it unfinished, but a
    /// killed run leaves nothing readable (only the hidden partial file), and the footer held in
    /// memory grows with the run: for runs short enough to rerun.
    #[must_use]
    pub fn single_file(mut self) -> Self {
        self.split = Split::File;
        self
    }

    /// Whether each part (or the file) is synced to disk before it is published (default: no).
    /// Publishing by rename alone survives any death of the process (a kill, a panic, a time
    /// limit): the operating system holds what was written. A crash of the machine itself (power,
    /// kernel) may then lose the last parts written or leave them damaged, which their
    /// checksums detect ([`crate::integrity`]); syncing rules that out too, at the cost of
    /// waiting for the disk at every part (on the `lattice_parquet` benchmark, 15.5 MiB written,
    /// syncing added 0.05–0.1 s to runs of 0.1–0.2 s).
    #[must_use]
    pub fn sync(mut self, sync: bool) -> Self {
        self.sync = sync;
        self
    }

    /// [`Self::single_file`] for the members of an ensemble, which are concatenated (and the
    /// result synced) or many small files.
    #[must_use]
    pub(crate) fn member_file(mut self) -> Self {
        self.split = Split::File;
        self.sync = false;
        self
    }

    /// Row groups of about `bytes` bytes of values (default [`ROW_GROUP_BYTES`]).
    #[must_use]
    pub fn row_group_bytes(mut self, bytes: usize) -> Self {
        self.row_group_bytes = bytes.max(1);
        self
    }

    /// Whether the output is one file ([`Self::single_file`]) rather than a directory of parts.
    pub fn is_single_file(&self) -> bool {
        matches!(self.split, Split::File)
    }

    /// The layout of the rows of a run described by `info`, written with these options: the
    /// columns (the state's from `info`, the extra ones), the metadata (`info`'s, the stride,
    /// the member), and the rows of a block and of a part. An error if `info` names another
    /// number of state columns than states of type `St` have.
    pub fn layout(&self, info: &RunInfo) -> Result<Layout> {
        if let Some(width) = St::WIDTH.filter(|w| *w != info.columns.len()) {
            return Err(Error::Usage(format!(
                "the run's description names {} state columns ({}) where its states have {width}: a description of another system",
                info.columns.len(),
                info.columns.join(", "),
            )));
        }
        let extra: Vec<String> = self.extra.as_ref().map_or(Vec::new(), |(n, _)| n.clone());
        let mut metadata = info.key_values();
        metadata.push(("dirac.every".into(), self.every.to_string()));
        if let Some(m) = self.member {
            metadata.push(("dirac.member".into(), m.to_string()));
        }
        // `member`, `step`, `t`, the state, `iterations`, `residual`, `rcond`, the extra: 8
        // bytes a value at most.
        let row_bytes =
            8 * (usize::from(self.member.is_some()) + 5 + info.columns.len() + extra.len());
        let rows_per_part = match self.split {
            Split::File => None,
            Split::Parts(rows) => Some(rows.unwrap_or((PART_BYTES / row_bytes as u64).max(1))),
        };
        // A row group never spans two parts: no larger than a part, cut at each part's end.
        let by_bytes = (self.row_group_bytes / row_bytes).max(1);
        let rows_per_group = rows_per_part.map_or(by_bytes, |r| {
            by_bytes.min(usize::try_from(r).unwrap_or(usize::MAX))
        });
        Ok(Layout {
            member: self.member,
            state: info.columns.clone(),
            extra,
            metadata,
            rows_per_group,
            rows_per_part,
            sync: self.sync,
            compress: self.compress,
        })
    }
}

/// Where a resumed run continues ([`ParquetObserver::resume`]): the last state published, its
/// step `k` and its time `t_k`. Continue with `integ.run(state).start_time(t).steps(n − step)`.
///
/// [`ParquetObserver::resume`]: crate::ParquetObserver::resume
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Resumed<St> {
    /// The step index `k` of the state.
    pub step: usize,
    /// Its time `t_k`.
    pub t: f64,
    /// The state.
    pub state: St,
}

/// Streams the states of a run into a [`Sink`], in memory independent of the run's length: rows
/// are buffered column by column and handed to the sink one block every [`ROW_GROUP_BYTES`]
/// (or at a part's end), each part published complete when full (see
/// [`Options::rows_per_file`]; [`Options::single_file`] for one file). With the Parquet sink
/// this is [`ParquetObserver`]; see the [crate documentation](crate) for its schema and
/// metadata.
///
/// Pass [`Self::observer`] to [`Drive::run`] (`run.observe(out.observer())`), then call
/// [`Self::finish_with`] with the run's result (or [`Self::finish`]), which writes the last
/// part and the run's outcome and returns the path. A write error inside the observer (a full
/// disk) is kept and returned by `finish` ([`Error::Io`] with the operating system's error): an
/// observer cannot fail, and the run goes on, writing nothing more. The sink's unpublished part
/// (or file) is then removed; the parts published before stay, complete.
///
/// Dropped without `finish` (an early return through `?`, a panic unwinding), it writes what it
/// holds and the last state observed, with `dirac.outcome = aborted` and `dirac.steps` the last
/// step observed, and publishes the part: nothing observed is lost. Call `finish_with(&result)`
/// before `?` to record the run's own outcome (`failed`, with its typed error) instead.
///
/// ```
/// use dirac::paper::DoubleSphericalPendulum;
/// use dirac::prelude::*;
/// use dirac_io::{Describe, Options, ParquetObserver};
///
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// let integ = ReducedIntegrator::plus(DoubleSphericalPendulum::paper(), NewtonOptions::default());
/// let path = std::env::temp_dir().join(format!("dsp-doc-{}", std::process::id()));
/// let mut out = ParquetObserver::create(&path, integ.describe(), Options::new().every(10))?;
/// let result = integ.run(DoubleSphericalPendulum::paper_initial_state()).steps(100).observe(out.observer()).stream();
/// let written = out.finish_with(&result)?; // the outcome recorded, then the run's error if any
/// result?;
/// assert_eq!(written, path);
/// assert_eq!(dirac_io::read::row_count(&path)?, 11);
/// # std::fs::remove_dir_all(path)?;
/// # Ok(())
/// # }
/// ```
///
/// [`ParquetObserver`]: crate::ParquetObserver
pub struct Output<St: StateColumns, S: Sink> {
    path: PathBuf,
    channel: Option<Channel<S>>,
    every: usize,
    extra: Option<Extra<St>>,
    rows_per_group: usize,
    buffer: Rows,
    /// The names of a state's columns (the layout's), which read a state back.
    columns: Vec<String>,
    /// The components of the last state observed (its width is the layout's).
    scratch: Vec<f64>,
    extra_scratch: Vec<f64>,
    /// The step, time and record of the last state observed (its components in `scratch`), kept
    /// so that `finish_with` can write the last state of a run that `every` skipped.
    last: Option<(usize, f64, Option<StepStats>)>,
    last_written: Option<usize>,
    rows: u64,
    /// The rows of a part ([`Options::rows_per_file`]; `None` for one file), and those pushed
    /// into the part being written so far.
    rows_per_part: Option<u64>,
    part_rows: u64,
    /// The step of a resumed run's first state: observed step `k` is written as step
    /// `offset + k`, and its state `0`, written already, is skipped.
    offset: usize,
    /// A state of another width than the layout's (a run-time-sized state of another system):
    /// nothing more is written, and `finish` returns it.
    mismatch: Option<Error>,
}

impl<St: StateColumns, S: Sink> Output<St, S> {
    /// The observer writing the rows laid out as `layout` (made by [`Options::layout`] from the
    /// same `options`) into `sink`.
    pub fn new(sink: S, layout: &Layout, options: Options<St>) -> Self {
        Self::starting_at(sink, layout, options, 0)
    }

    /// [`Self::new`] for a resumed run whose first state, step `offset`, is written already
    /// (`offset > 0`): observed step `k` is written as step `offset + k`.
    pub(crate) fn starting_at(
        sink: S,
        layout: &Layout,
        options: Options<St>,
        offset: usize,
    ) -> Self {
        let (width, extra) = (layout.state.len(), layout.extra.len());
        Output {
            path: sink.path().to_owned(),
            channel: Some(Channel::start(sink, options.background)),
            every: options.every,
            extra: options.extra,
            rows_per_group: layout.rows_per_group,
            buffer: Rows::new(width, extra, layout.rows_per_group),
            columns: layout.state.clone(),
            scratch: vec![0.0; width],
            extra_scratch: vec![0.0; extra],
            last: None,
            last_written: None,
            rows: 0,
            rows_per_part: layout.rows_per_part,
            part_rows: 0,
            offset,
            mismatch: None,
        }
    }

    /// The path written to.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Rows written or buffered so far (by this observer: a resumed run's earlier rows are not
    /// counted).
    pub fn rows(&self) -> u64 {
        self.rows
    }

    /// The observer to pass to [`Drive::run`] (or any loop): it sees `(step, state, record)`.
    pub fn observer<R: AsRef<StepStats>>(
        &mut self,
    ) -> impl FnMut(usize, f64, &St, Option<&R>) + Send + '_
    where
        S: Send,
    {
        move |k, t, state, record| self.observe(k, t, state, record.map(AsRef::as_ref))
    }

    /// Observes state `k` at time `t` and the statistics of the step that produced it (`None`
    /// for the initial state).
    pub fn observe(&mut self, k: usize, t: f64, state: &St, stats: Option<&StepStats>) {
        if self.mismatch.is_some() {
            return;
        }
        if state.width() != self.scratch.len() {
            self.mismatch = Some(Error::Usage(format!(
                "state {k} has {} components where the output has {} state columns: a state of another system",
                state.width(),
                self.scratch.len()
            )));
            return;
        }
        let k = k + self.offset;
        state.write_to(&mut self.scratch);
        if self.offset > 0 && k == self.offset {
            // A resumed run's first state: published already.
            self.last_written = Some(k);
        } else if k.is_multiple_of(self.every) {
            self.push(k, t, state, stats);
        }
        self.last = Some((k, t, stats.copied()));
    }

    /// Appends the row of state `k`, whose components are in `scratch`.
    fn push(&mut self, k: usize, t: f64, state: &St, stats: Option<&StepStats>) {
        let b = &mut self.buffer;
        b.step.push(k as u64);
        b.t.push(t);
        for (column, v) in b.state.iter_mut().zip(&self.scratch) {
            column.push(*v);
        }
        b.iterations.push(stats.map(|s| s.iterations as u32));
        b.residual.push(stats.map(|s| s.residual));
        b.rcond.push(stats.and_then(|s| s.rcond));
        if let Some((_, f)) = &mut self.extra {
            f(k, state, &mut self.extra_scratch);
            for (column, v) in b.extra.iter_mut().zip(&self.extra_scratch) {
                column.push(*v);
            }
        }
        self.rows += 1;
        self.last_written = Some(k);
        self.part_rows += 1;
        let ends_part = Some(self.part_rows) == self.rows_per_part;
        if ends_part || b.len() >= self.rows_per_group {
            self.write_block(ends_part);
        }
        if ends_part {
            self.part_rows = 0;
        }
    }

    /// Hands the buffered rows to the sink as one block; `ends_part`: the last of its part,
    /// which is then published before this returns (so that no more than one part's rows are
    /// ever unpublished).
    fn write_block(&mut self, ends_part: bool) {
        let fresh = Rows::new(
            self.scratch.len(),
            self.extra_scratch.len(),
            self.rows_per_group,
        );
        let mut full = std::mem::replace(&mut self.buffer, fresh);
        full.ends_part = ends_part;
        if !full.is_empty() {
            if let Some(channel) = &mut self.channel {
                channel.write(full);
            }
        }
    }

    /// Writes the last state observed when `every` skipped it (its components are in
    /// `scratch`; the state itself is read back from them, bit for bit, for the extra columns).
    fn write_last(&mut self) {
        if let Some((k, t, stats)) = self.last {
            if self.last_written != Some(k) {
                let state = St::read_from(&self.columns, &self.scratch);
                self.push(k, t, &state, stats.as_ref());
            }
        }
    }

    /// Writes the remaining rows and publishes the last part (or the file); returns the path.
    /// Records no outcome: [`Self::finish_with`] does.
    pub fn finish(mut self) -> Result<PathBuf> {
        self.close_with(Vec::new())
    }

    /// [`Self::finish`] for a run that returned `result`: also writes its last state when
    /// `every` skipped it, and records its outcome as metadata: `dirac.outcome` (`completed`,
    /// `stopped` or `failed`), `dirac.steps` (steps completed) and, for a failure,
    /// `dirac.error.kind`, `.step`, `.residual` and `.message` (the typed [`StepError`]).
    pub fn finish_with(mut self, result: &RunResult<St>) -> Result<PathBuf> {
        self.write_last();
        self.close_with(outcome(result, self.offset))
    }

    fn close_with(&mut self, kv: Vec<(String, String)>) -> Result<PathBuf> {
        self.write_block(false);
        let Some(channel) = self.channel.take() else {
            return Err(Error::Usage("the observer was closed already".into()));
        };
        let mut sink = channel.finish()?;
        // The rows written before a state of another width stay, published with the outcome.
        sink.close(kv)?;
        match self.mismatch.take() {
            Some(e) => Err(e),
            None => Ok(self.path.clone()),
        }
    }
}

/// The metadata recording a run's outcome: `dirac.outcome`, `dirac.steps` (counted from
/// `offset`, a resumed run's first step) and for a failure `dirac.error.*`.
fn outcome<St: StateColumns>(result: &RunResult<St>, offset: usize) -> Vec<(String, String)> {
    let mut kv = Vec::new();
    match result {
        Ok(summary) => {
            let outcome = if summary.stopped {
                "stopped"
            } else {
                "completed"
            };
            kv.push(("dirac.outcome", outcome.to_owned()));
            kv.push(("dirac.steps", (offset + summary.step_count).to_string()));
        }
        Err(e) => {
            kv.push(("dirac.outcome", "failed".to_owned()));
            kv.push((
                "dirac.steps",
                (offset + e.trajectory.step_count).to_string(),
            ));
            kv.push(("dirac.error.kind", e.source.kind().to_owned()));
            kv.push(("dirac.error.step", (offset + e.source.step()).to_string()));
            kv.push(("dirac.error.residual", float_text(e.source.residual())));
            kv.push(("dirac.error.message", e.source.to_string()));
        }
    }
    kv.into_iter().map(|(k, v)| (k.to_owned(), v)).collect()
}

/// An observer dropped before [`Output::finish`] (an early return through `?`, a panic
/// unwinding) keeps what it observed: the rows held and the last state, published with
/// `dirac.outcome = aborted` and `dirac.steps` the last step observed. An error writing them is
/// lost (a drop cannot return it): call `finish_with` to see it.
impl<St: StateColumns, S: Sink> Drop for Output<St, S> {
    fn drop(&mut self) {
        if self.channel.is_none() {
            return;
        }
        self.write_last();
        let steps = self.last.map_or(self.offset, |(k, _, _)| k);
        let _ = self.close_with(vec![
            ("dirac.outcome".to_owned(), "aborted".to_owned()),
            ("dirac.steps".to_owned(), steps.to_string()),
        ]);
    }
}
