//! The Parquet observer: a run's states streamed into a file in memory independent of the run's
//! length (see the [crate documentation](crate) for the schema).

use std::marker::PhantomData;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use arrow_schema::{DataType, Field, Schema};
use dirac::prelude::*;
use dirac::runtime::driver::RunResult;
use parquet::basic::Compression;

use crate::columns::{float_text, RunInfo, StateColumns};
use crate::error::{Error, Result};
use crate::files::{part_file, partial_file, published_parts};
use crate::integrity::FileWriter;
pub use crate::integrity::ROW_GROUP_BYTES;

mod sink;
use sink::{Buffer, Encoder, Sink, Target};

/// The default size of a part ([`Options::rows_per_file`]): about 64 MiB of values, eight row
/// groups. What a killed run loses is at most the part being written (the run waits at each
/// part's end until the part is published), so this bounds the loss (a few seconds of writing);
/// it also bounds the footer the writer holds (about 2.5 MiB for the 200-particle lattice), and
/// a run of 10^6 steps of that lattice is 50 files.
pub const PART_BYTES: u64 = 64 << 20;

/// How the output is laid out on disk.
#[derive(Clone, Copy, Debug)]
enum Layout {
    /// A directory of parts of about this many rows (`None`: [`PART_BYTES`] of values).
    Parts(Option<u64>),
    /// One file, published when the run ends.
    File,
}

/// The energies (or any other derived quantities) written beside each state: the column names,
/// and a function of the step index and the state that fills one value per name.
type Extra<St> = (Vec<String>, Box<dyn FnMut(usize, &St, &mut [f64]) + Send>);

/// How a [`ParquetObserver`] writes: which states, which extra columns, which compression.
pub struct Options<St> {
    every: usize,
    member: Option<u64>,
    extra: Option<Extra<St>>,
    compression: Compression,
    row_group_bytes: usize,
    background: bool,
    layout: Layout,
    sync: bool,
}

impl<St> Default for Options<St> {
    fn default() -> Self {
        Options {
            every: 1,
            member: None,
            extra: None,
            compression: Compression::UNCOMPRESSED,
            row_group_bytes: ROW_GROUP_BYTES,
            background: true,
            layout: Layout::Parts(None),
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
    /// it is not a multiple of `k`, by [`ParquetObserver::finish_with`].
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

    /// Snappy compression of the pages (default: none). States of a smooth trajectory compress
    /// little, and compression costs time on every row group.
    #[must_use]
    pub fn snappy(mut self) -> Self {
        self.compression = Compression::SNAPPY;
        self
    }

    /// Whether row groups are encoded and written on a thread of their own (the default), so that
    /// the run's thread only copies its states into the buffer and goes on stepping while the
    /// previous row group is written; at most two row groups are then held at once. Off, the
    /// run's thread writes them itself (what an ensemble, whose members already occupy every
    /// core, wants: [`crate::write_ensemble`] turns it off).
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
    #[must_use]
    pub fn rows_per_file(mut self, rows: u64) -> Self {
        self.layout = Layout::Parts(Some(rows.max(1)));
        self
    }

    /// One Parquet file at the path instead of a directory of parts: written under a hidden
    /// name beside it (`.<name>.partial`) and published by a rename when the run ends
    /// ([`ParquetObserver::finish_with`], or the observer dropped). Readers never see it
    /// unfinished, but a killed run leaves nothing readable (only the hidden partial file), and
    /// the footer held in memory grows with the run: for runs short enough to rerun.
    #[must_use]
    pub fn single_file(mut self) -> Self {
        self.layout = Layout::File;
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
        self.layout = Layout::File;
        self.sync = false;
        self
    }

    /// Row groups of about `bytes` bytes of values (default [`ROW_GROUP_BYTES`]).
    #[must_use]
    pub fn row_group_bytes(mut self, bytes: usize) -> Self {
        self.row_group_bytes = bytes.max(1);
        self
    }
}

/// Where a resumed run continues ([`ParquetObserver::resume`]): the last state published, its
/// step `k` and its time `t_k`. Continue with `integ.run(state).start_time(t).steps(n − step)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Resumed<St> {
    /// The step index `k` of the state.
    pub step: usize,
    /// Its time `t_k`.
    pub t: f64,
    /// The state.
    pub state: St,
}

/// Streams the states of a run into Apache Parquet, in memory independent of the run's length:
/// rows are buffered column by column and written as one row group every [`ROW_GROUP_BYTES`]
/// (or at a part's end), into a directory of parts, each published complete when full (see
/// [`Options::rows_per_file`];
/// [`Options::single_file`] for one file). See the [crate documentation](crate) for the schema and
/// metadata.
///
/// Pass [`Self::observer`] to [`Drive::run`], then call [`Self::finish_with`] with the run's
/// result (or [`Self::finish`]), which writes the last part's footer and the run's outcome and
/// returns the path. A write error inside the observer (a full disk) is kept and returned by
/// `finish` ([`Error::Io`] with the operating system's error): an observer cannot fail, and the
/// run goes on, writing nothing more. The hidden partial file of the part (or file) being
/// written is then removed; the parts published before stay, complete.
///
/// Dropped without `finish` (an early return through `?`, a panic unwinding), it writes what it
/// holds, the last state observed and the footer, with `dirac.outcome = aborted` and
/// `dirac.steps` the last step observed, and publishes the part: nothing observed is lost. Call
/// `finish_with(&result)` before `?` to record the run's own outcome (`failed`, with its typed
/// error) instead.
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
pub struct ParquetObserver<St: StateColumns> {
    path: PathBuf,
    sink: Option<Sink>,
    options: Options<St>,
    rows_per_group: usize,
    buffer: Buffer,
    scratch: Vec<f64>,
    extra_scratch: Vec<f64>,
    /// The last state observed and its record, kept so that `finish_with` can write the last
    /// state of a run that `every` skipped.
    last: Option<(usize, f64, St, Option<StepStats>)>,
    last_written: Option<usize>,
    rows: u64,
    /// The rows of a part ([`Options::rows_per_file`]; `None` for one file), and those pushed
    /// into the part being written so far.
    rows_per_file: Option<u64>,
    part_rows: u64,
    /// The step of a resumed run's first state ([`Self::resume`]): observed step `k` is written
    /// as step `offset + k`, and its state `0`, written already, is skipped.
    offset: usize,
    _state: PhantomData<St>,
}

/// The schema of a trajectory file: `[member], step, t, <state columns>, iterations, residual,
/// rcond, <extra columns>`.
pub fn trajectory_schema(columns: &[String], member: bool, extra: &[String]) -> Schema {
    let mut fields = Vec::with_capacity(columns.len() + extra.len() + 6);
    if member {
        fields.push(Field::new("member", DataType::UInt64, false));
    }
    fields.push(Field::new("step", DataType::UInt64, false));
    fields.push(Field::new("t", DataType::Float64, false));
    for name in columns {
        fields.push(Field::new(name, DataType::Float64, false));
    }
    fields.push(Field::new("iterations", DataType::UInt32, true));
    fields.push(Field::new("residual", DataType::Float64, true));
    fields.push(Field::new("rcond", DataType::Float64, true));
    for name in extra {
        fields.push(Field::new(name, DataType::Float64, false));
    }
    Schema::new(fields)
}

impl<St: StateColumns> ParquetObserver<St> {
    /// Creates the output at `path` for a run described by `info`: a directory of parts (by
    /// default; its previous parts, if any, are removed) or one file ([`Options::single_file`]).
    /// An error if `info` does not describe states of type `St`.
    pub fn create(path: impl AsRef<Path>, info: RunInfo, options: Options<St>) -> Result<Self> {
        let path = path.as_ref().to_owned();
        if let Layout::Parts(_) = options.layout {
            std::fs::create_dir_all(&path).map_err(Error::io(&path))?;
            let (parts, partials) = published_parts(&path).unwrap_or_default();
            for old in parts.iter().chain(&partials) {
                std::fs::remove_file(old).map_err(Error::io(old))?;
            }
        }
        Self::open(path, info, options, 0, 0)
    }

    /// Continues the run whose parts a killed (or failed) process left in the directory `path`:
    /// returns the observer, which writes the next parts, and the last state published with its
    /// step `k` (`None` if no part was published: then this is [`Self::create`]). Run the rest
    /// from that state, `steps − k` steps: the observer numbers them from `k` (`step`, `t`,
    /// `every`) and skips their first state, written already, so that the directory holds every
    /// step once, in order. The continuation agrees with the uninterrupted run to the Newton
    /// tolerance, not bit for bit: Newton's first guess extrapolates the previous steps, which
    /// the file does not hold (rerun from the start for the uninterrupted run's bits). The
    /// hidden partial part of the killed process is removed; its rows are integrated again.
    ///
    /// `info` and `options` must be those of the run continued. An error if the directory's
    /// last part records an outcome (the run ended: nothing to continue), or `options` writes
    /// one file.
    ///
    /// ```
    /// use dirac::paper::DoubleSphericalPendulum;
    /// use dirac::prelude::*;
    /// use dirac_io::{Describe, Options, ParquetObserver};
    ///
    /// # fn main() -> Result<(), Box<dyn std::error::Error>> {
    /// let integ = ReducedIntegrator::plus(DoubleSphericalPendulum::paper(), NewtonOptions::default());
    /// let dir = std::env::temp_dir().join(format!("dsp-resume-doc-{}", std::process::id()));
    /// # let _ = std::fs::remove_dir_all(&dir);
    /// let (steps, options) = (1000, || Options::new().rows_per_file(300));
    /// let (mut out, last) = ParquetObserver::resume(&dir, integ.describe(), options())?;
    /// let (done, t, start) = match last {
    ///     Some(r) => (r.step, r.t, r.state),
    ///     None => (0, 0.0, DoubleSphericalPendulum::paper_initial_state()),
    /// };
    /// let result = integ
    ///     .run(start)
    ///     .start_time(t)
    ///     .steps(steps - done)
    ///     .observe(out.observer())
    ///     .stream();
    /// out.finish_with(&result)?;
    /// result?;
    /// assert_eq!(dirac_io::read::row_count(&dir)?, 1001);
    /// # std::fs::remove_dir_all(dir)?;
    /// # Ok(())
    /// # }
    /// ```
    pub fn resume(
        path: impl AsRef<Path>,
        info: RunInfo,
        options: Options<St>,
    ) -> Result<(Self, Option<Resumed<St>>)> {
        let path = path.as_ref().to_owned();
        if let Layout::File = options.layout {
            return Err(Error::Usage(
                "a run written to one file cannot be resumed: write it in parts (the default)"
                    .into(),
            ));
        }
        if !path.exists() {
            return Ok((Self::create(path, info, options)?, None));
        }
        let (parts, partials) = published_parts(&path)?;
        for old in &partials {
            std::fs::remove_file(old).map_err(Error::io(old))?;
        }
        let Some(last_part) = parts.last() else {
            return Ok((Self::create(path, info, options)?, None));
        };
        let kv = crate::read::key_values(last_part)?;
        if let Some(outcome) = kv.get("dirac.outcome") {
            return Err(Error::content(
                last_part,
                format!("the run ended ({outcome}): nothing to resume"),
            ));
        }
        let (step, t, state) = crate::read::last_state::<St>(last_part, &info.columns)?;
        let observer = Self::open(path, info, options, parts.len(), step)?;
        Ok((observer, Some(Resumed { step, t, state })))
    }

    /// The observer writing to `path`, its first part numbered `first_part`, its first state
    /// step `offset` (written already when `offset > 0`).
    fn open(
        path: PathBuf,
        info: RunInfo,
        options: Options<St>,
        first_part: usize,
        offset: usize,
    ) -> Result<Self> {
        if info.columns.len() != St::WIDTH {
            return Err(Error::Usage(format!(
                "the run's description names {} state columns ({}) where its states have {}: a description of another system",
                info.columns.len(),
                info.columns.join(", "),
                St::WIDTH
            )));
        }
        let extra_names: &[String] = options.extra.as_ref().map_or(&[], |(n, _)| n);
        let schema = Arc::new(trajectory_schema(
            &info.columns,
            options.member.is_some(),
            extra_names,
        ));
        let mut kv = info.key_values();
        kv.push(("dirac.every".into(), options.every.to_string()));
        if let Some(m) = options.member {
            kv.push(("dirac.member".into(), m.to_string()));
        }
        let row_bytes = 8 * schema.fields().len();
        let (target, rows_per_file) = match options.layout {
            Layout::File => (Target::File { path: path.clone() }, None),
            Layout::Parts(rows) => (
                Target::Parts {
                    dir: path.clone(),
                    index: first_part,
                },
                Some(rows.unwrap_or((PART_BYTES / row_bytes as u64).max(1))),
            ),
        };
        // A row group never spans two parts: no larger than a part, cut at each part's end.
        let by_bytes = (options.row_group_bytes / row_bytes).max(1);
        let rows_per_group = rows_per_file.map_or(by_bytes, |r| {
            by_bytes.min(usize::try_from(r).unwrap_or(usize::MAX))
        });
        let first = match &target {
            Target::File { path, .. } => partial_file(path),
            Target::Parts { dir, index } => partial_file(&part_file(dir, *index)),
        };
        let writer = FileWriter::create_with_groups(
            &first,
            schema.clone(),
            options.compression,
            kv.clone(),
            rows_per_group,
        )?;
        let extra = extra_names.len();
        Ok(ParquetObserver {
            path,
            sink: Some(Sink::start(
                Encoder {
                    writer: Some(writer),
                    schema,
                    member: options.member,
                    compression: options.compression,
                    kv,
                    target,
                    sync: options.sync,
                    rows_per_group,
                },
                options.background,
            )),
            buffer: Buffer::new(St::WIDTH, extra, rows_per_group),
            options,
            rows_per_group,
            scratch: vec![0.0; St::WIDTH],
            extra_scratch: vec![0.0; extra],
            last: None,
            last_written: None,
            rows: 0,
            rows_per_file,
            part_rows: 0,
            offset,
            _state: PhantomData,
        })
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
    ) -> impl FnMut(usize, f64, &St, Option<&R>) + Send + '_ {
        move |k, t, state, record| self.observe(k, t, state, record.map(AsRef::as_ref))
    }

    /// Observes state `k` at time `t` and the statistics of the step that produced it (`None`
    /// for the initial state).
    pub fn observe(&mut self, k: usize, t: f64, state: &St, stats: Option<&StepStats>) {
        let k = k + self.offset;
        if self.offset > 0 && k == self.offset {
            // A resumed run's first state: published already.
            self.last_written = Some(k);
        } else if k.is_multiple_of(self.options.every) {
            self.push(k, t, state, stats);
        }
        self.last = Some((k, t, *state, stats.copied()));
    }

    fn push(&mut self, k: usize, t: f64, state: &St, stats: Option<&StepStats>) {
        let b = &mut self.buffer;
        b.step.push(k as u64);
        b.t.push(t);
        state.write_to(&mut self.scratch);
        for (column, v) in b.state.iter_mut().zip(&self.scratch) {
            column.push(*v);
        }
        b.iterations.push(stats.map(|s| s.iterations as u32));
        b.residual.push(stats.map(|s| s.residual));
        b.rcond.push(stats.and_then(|s| s.rcond));
        if let Some((_, f)) = &mut self.options.extra {
            f(k, state, &mut self.extra_scratch);
            for (column, v) in b.extra.iter_mut().zip(&self.extra_scratch) {
                column.push(*v);
            }
        }
        self.rows += 1;
        self.last_written = Some(k);
        self.part_rows += 1;
        let ends_part = Some(self.part_rows) == self.rows_per_file;
        if ends_part || b.len() >= self.rows_per_group {
            self.write_group(ends_part);
        }
        if ends_part {
            self.part_rows = 0;
        }
    }

    /// Hands the buffered rows to the sink as one row group; `ends_part`: the last of its part,
    /// which is then published before this returns (so that no more than one part's rows are
    /// ever unpublished).
    fn write_group(&mut self, ends_part: bool) {
        let fresh = Buffer::new(St::WIDTH, self.extra_scratch.len(), self.rows_per_group);
        let mut full = std::mem::replace(&mut self.buffer, fresh);
        full.ends_part = ends_part;
        if full.len() > 0 {
            if let Some(sink) = &mut self.sink {
                sink.write(full);
            }
        }
    }

    /// Writes the last state observed when `every` skipped it.
    fn write_last(&mut self) {
        if let Some((k, t, state, stats)) = self.last {
            if self.last_written != Some(k) {
                self.push(k, t, &state, stats.as_ref());
            }
        }
    }

    /// Writes the remaining rows and the footer, publishes the last part (or the file); returns
    /// the path. Records no outcome: [`Self::finish_with`] does.
    pub fn finish(mut self) -> Result<PathBuf> {
        self.close_with(Vec::new())
    }

    /// [`Self::finish`] for a run that returned `result`: also writes its last state when
    /// `every` skipped it, and records its outcome as metadata: `dirac.outcome` (`completed`,
    /// `stopped` or `failed`), `dirac.steps` (steps completed) and, for a failure,
    /// `dirac.error.kind`, `.step`, `.residual` and `.message` (the typed [`StepError`]).
    pub fn finish_with(mut self, result: &RunResult<St>) -> Result<PathBuf> {
        self.write_last();
        let offset = self.offset;
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
        let kv = kv.into_iter().map(|(k, v)| (k.to_owned(), v)).collect();
        self.close_with(kv)
    }

    fn close_with(&mut self, kv: Vec<(String, String)>) -> Result<PathBuf> {
        self.write_group(false);
        let Some(sink) = self.sink.take() else {
            return Err(Error::Usage("the observer was closed already".into()));
        };
        let mut encoder = sink.finish()?;
        encoder.close(kv)?;
        Ok(self.path.clone())
    }
}

/// An observer dropped before [`ParquetObserver::finish`] (an early return through `?`, a panic
/// unwinding) keeps what it observed: the rows held, the last state, the footer, published with
/// `dirac.outcome = aborted` and `dirac.steps` the last step observed. An error writing them is
/// lost (a drop cannot return it): call `finish_with` to see it.
impl<St: StateColumns> Drop for ParquetObserver<St> {
    fn drop(&mut self) {
        if self.sink.is_none() {
            return;
        }
        self.write_last();
        let steps = self.last.map_or(self.offset, |(k, _, _, _)| k);
        let _ = self.close_with(vec![
            ("dirac.outcome".to_owned(), "aborted".to_owned()),
            ("dirac.steps".to_owned(), steps.to_string()),
        ]);
    }
}

/// One run of `integ` from `start` for `steps` steps, every state written to `path` (a directory
/// of parts) with the run's description and the Newton options `newton` the integrator was
/// built with: the whole of a run to Parquet in one call, what the command line `dirac` and
/// the Python package do. Returns the run's result — a failed step is the `Err` inside, with
/// the states before it on disk — and the path written; the outer error is the writer's.
pub fn run_to_parquet<I>(
    integ: &I,
    start: I::State,
    steps: usize,
    path: &Path,
    newton: &NewtonOptions,
) -> Result<(RunResult<I::State>, PathBuf)>
where
    I: crate::Describe + Drive,
    I::State: StateColumns,
    I::Record: AsRef<StepStats>,
{
    let info = integ.describe().with_newton(newton);
    let mut writer = ParquetObserver::create(path, info, Options::new())?;
    let result = integ
        .run(start)
        .steps(steps)
        .observe(writer.observer())
        .stream();
    let written = writer.finish_with(&result)?;
    Ok((result, written))
}
