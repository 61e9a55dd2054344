//! The Parquet observer: a run's states streamed into a file in memory independent of the run's
//! length (see the [crate documentation](crate) for the schema).

use std::fs::File;
use std::io::BufWriter;
use std::marker::PhantomData;
use std::path::{Path, PathBuf};
use std::sync::mpsc::{sync_channel, SyncSender};
use std::sync::Arc;
use std::thread::JoinHandle;

use arrow_array::{ArrayRef, Float64Array, RecordBatch, UInt32Array, UInt64Array};
use arrow_schema::{DataType, Field, Schema, SchemaRef};
use dirac::prelude::*;
use dirac::runtime::driver::RunResult;
use parquet::arrow::ArrowWriter;
use parquet::basic::Compression;
use parquet::file::metadata::KeyValue;
use parquet::file::properties::{EnabledStatistics, WriterProperties};

use crate::columns::{float_text, RunInfo, StateColumns};
use crate::error::{Error, Result};

/// Row groups are cut at about this many bytes of values, so that what a writer holds before
/// it writes is bounded whatever the run's length and the state's size: 8 MiB is 2,600 rows of
/// the 200-particle lattice (406 columns) or 80,000 rows of a 4-coordinate system. Measured on
/// the lattice: 2 MiB groups cost more per row (per-column-chunk allocations and metadata) and
/// grew the footer 4× faster; the writer holds at most three groups (one filling, one queued,
/// one being written), 24 MiB.
pub const ROW_GROUP_BYTES: usize = 8 << 20;

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
    rows_per_file: Option<u64>,
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
            rows_per_file: None,
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

    /// Splits the output into files of at most about `rows` rows (whole row groups): the path
    /// given to [`ParquetObserver::create`] is then a directory of `part-00000.parquet`,
    /// `part-00001.parquet`, …, one dataset for pyarrow (`pq.read_table(dir)`), Polars
    /// (`pl.read_parquet(f"{dir}/*.parquet")`) and DuckDB (`'dir/*.parquet'`). A Parquet
    /// file's footer (held by the writer until the file is closed) grows by one entry per
    /// column and row group, about 120 bytes of memory per row of the 200-particle lattice; with
    /// parts, memory no longer grows with the run's length at all. Each part carries the run's
    /// metadata; the last one also its outcome.
    #[must_use]
    pub fn rows_per_file(mut self, rows: u64) -> Self {
        self.rows_per_file = Some(rows.max(1));
        self
    }

    /// Row groups of about `bytes` bytes of values (default [`ROW_GROUP_BYTES`]).
    #[must_use]
    pub fn row_group_bytes(mut self, bytes: usize) -> Self {
        self.row_group_bytes = bytes.max(1);
        self
    }
}

/// The columns of one row group, before they are written.
struct Buffer {
    step: Vec<u64>,
    t: Vec<f64>,
    /// Column-major: `state[c]` is column `c`.
    state: Vec<Vec<f64>>,
    iterations: Vec<Option<u32>>,
    residual: Vec<Option<f64>>,
    rcond: Vec<Option<f64>>,
    extra: Vec<Vec<f64>>,
}

impl Buffer {
    fn new(width: usize, extra: usize, rows: usize) -> Self {
        Buffer {
            step: Vec::with_capacity(rows),
            t: Vec::with_capacity(rows),
            state: (0..width).map(|_| Vec::with_capacity(rows)).collect(),
            iterations: Vec::with_capacity(rows),
            residual: Vec::with_capacity(rows),
            rcond: Vec::with_capacity(rows),
            extra: (0..extra).map(|_| Vec::with_capacity(rows)).collect(),
        }
    }

    fn len(&self) -> usize {
        self.step.len()
    }
}

/// Streams the states of a run into an Apache Parquet file, in memory independent of the run's
/// length: rows are buffered column by column and written as one row group every
/// [`ROW_GROUP_BYTES`] (see the [crate documentation](crate) for the schema and metadata).
///
/// Pass [`Self::observer`] to [`Drive::run`], then call [`Self::finish`] (or
/// [`Self::finish_with`] with the run's result), which writes the footer and returns the path.
/// A write error inside the observer (a full disk) is kept and returned by `finish`: an
/// observer cannot fail, and the run goes on.
///
/// ```
/// use dirac::paper::DoubleSphericalPendulum;
/// use dirac::prelude::*;
/// use dirac_io::{Describe, Options, ParquetObserver};
///
/// # fn main() -> Result<(), Box<dyn std::error::Error>> {
/// let integ = ReducedIntegrator::plus(DoubleSphericalPendulum::paper(), NewtonOptions::default());
/// let path = std::env::temp_dir().join(format!("dsp-doc-{}.parquet", std::process::id()));
/// let mut out = ParquetObserver::create(&path, integ.describe(), Options::new().every(10))?;
/// let summary = integ.run(DoubleSphericalPendulum::paper_initial_state(), 100, out.observer());
/// let written = out.finish_with(&summary)?;
/// assert_eq!(written, path);
/// # std::fs::remove_file(path)?;
/// # Ok(())
/// # }
/// ```
pub struct ParquetObserver<St: StateColumns> {
    path: PathBuf,
    sink: Option<Sink>,
    h: f64,
    options: Options<St>,
    rows_per_group: usize,
    buffer: Buffer,
    scratch: Vec<f64>,
    extra_scratch: Vec<f64>,
    /// The last state observed and its record, kept so that `finish_with` can write the last
    /// state of a run that `every` skipped.
    last: Option<(usize, St, Option<StepStats>)>,
    last_written: Option<usize>,
    rows: u64,
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

/// Writer properties for `f64` columns: plain encoding (a dictionary of distinct floats is as
/// large as the data and costs a hash per value), no statistics and no offset index: the
/// footer, which the writer holds until the file is closed, then grows by one column chunk's
/// metadata per column and row group and nothing else.
pub(crate) fn writer_properties(
    compression: Compression,
    kv: Vec<(String, String)>,
) -> WriterProperties {
    WriterProperties::builder()
        .set_compression(compression)
        .set_dictionary_enabled(false)
        .set_statistics_enabled(EnabledStatistics::None)
        // A column chunk of a row group is one or a few pages: an index of their offsets
        // would only grow the footer.
        .set_offset_index_disabled(true)
        .set_max_row_group_row_count(None)
        .set_max_row_group_bytes(Some(ROW_GROUP_BYTES))
        .set_key_value_metadata(Some(
            kv.into_iter().map(|(k, v)| KeyValue::new(k, v)).collect(),
        ))
        .build()
}

pub(crate) fn create_writer(
    path: &Path,
    schema: SchemaRef,
    properties: WriterProperties,
) -> Result<ArrowWriter<BufWriter<File>>> {
    let file = File::create(path).map_err(Error::io(path))?;
    ArrowWriter::try_new(
        BufWriter::with_capacity(1 << 20, file),
        schema,
        Some(properties),
    )
    .map_err(Error::parquet(path))
}

/// Writes the footer and flushes the buffer; with `sync`, also syncs the file to disk (so that a
/// rename after it publishes a complete file).
pub(crate) fn close_writer(
    writer: ArrowWriter<BufWriter<File>>,
    path: &Path,
    sync: bool,
) -> Result<()> {
    // `into_inner` writes the footer.
    let file = writer
        .into_inner()
        .map_err(Error::parquet(path))?
        .into_inner()
        .map_err(|e| Error::io(path)(e.into_error()))?;
    if sync {
        file.sync_all().map_err(Error::io(path))?;
    }
    Ok(())
}

impl<St: StateColumns> ParquetObserver<St> {
    /// Creates (or truncates) the file at `path` for a run described by `info`; an
    /// [`Error::Content`] if `info` does not name one column per component of the state `St`.
    pub fn create(path: impl AsRef<Path>, info: RunInfo, options: Options<St>) -> Result<Self> {
        let path = path.as_ref().to_owned();
        if info.columns.len() != St::WIDTH {
            return Err(Error::content(
                &path,
                format!(
                    "the description names {} columns ({}), a state of this type has {}: a \
                     description of another system or state type",
                    info.columns.len(),
                    info.columns.join(", "),
                    St::WIDTH
                ),
            ));
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
        let properties = writer_properties(options.compression, kv);
        let (first, parts) = match options.rows_per_file {
            None => (path.clone(), None),
            Some(rows_per_file) => {
                std::fs::create_dir_all(&path).map_err(Error::io(&path))?;
                let parts = Parts {
                    dir: path.clone(),
                    rows_per_file,
                    index: 0,
                    rows: 0,
                };
                (parts.file(0), Some(parts))
            }
        };
        let writer = create_writer(&first, schema.clone(), properties.clone())?;
        let row_bytes = 8 * schema.fields().len();
        let rows_per_group = (options.row_group_bytes / row_bytes).max(1);
        let extra = extra_names.len();
        Ok(ParquetObserver {
            path: path.clone(),
            sink: Some(Sink::start(
                Encoder {
                    writer,
                    schema,
                    member: options.member,
                    path: first,
                    properties,
                    parts,
                },
                options.background,
            )),
            h: info.h,
            buffer: Buffer::new(St::WIDTH, extra, rows_per_group),
            options,
            rows_per_group,
            scratch: vec![0.0; St::WIDTH],
            extra_scratch: vec![0.0; extra],
            last: None,
            last_written: None,
            rows: 0,
            _state: PhantomData,
        })
    }

    /// The path written to.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Rows written or buffered so far.
    pub fn rows(&self) -> u64 {
        self.rows
    }

    /// The observer to pass to [`Drive::run`] (or any loop): it sees `(step, state, record)`.
    pub fn observer<R: AsRef<StepStats>>(
        &mut self,
    ) -> impl FnMut(usize, &St, Option<&R>) + Send + '_ {
        move |k, state, record| self.observe(k, state, record.map(AsRef::as_ref))
    }

    /// Observes state `k` and the statistics of the step that produced it (`None` for the
    /// initial state).
    pub fn observe(&mut self, k: usize, state: &St, stats: Option<&StepStats>) {
        if k.is_multiple_of(self.options.every) {
            self.push(k, state, stats);
        }
        self.last = Some((k, *state, stats.copied()));
    }

    fn push(&mut self, k: usize, state: &St, stats: Option<&StepStats>) {
        let b = &mut self.buffer;
        b.step.push(k as u64);
        b.t.push(k as f64 * self.h);
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
        if b.len() >= self.rows_per_group {
            self.write_group();
        }
    }

    /// Hands the buffered rows to the sink as one row group.
    fn write_group(&mut self) {
        let fresh = Buffer::new(St::WIDTH, self.extra_scratch.len(), self.rows_per_group);
        let full = std::mem::replace(&mut self.buffer, fresh);
        if full.len() > 0 {
            self.sink.as_mut().expect("open until finished").write(full);
        }
    }

    /// Writes the remaining rows and the footer; returns the path.
    pub fn finish(mut self) -> Result<PathBuf> {
        self.close_with(Vec::new())
    }

    /// [`Self::finish`] for a run that returned `result`: also writes its last state when
    /// `every` skipped it, and records its outcome as metadata: `dirac.outcome` (`completed`,
    /// `stopped` or `failed`), `dirac.steps` (steps completed) and, for a failure,
    /// `dirac.error.kind`, `.step`, `.residual` and `.message` (the typed [`StepError`]).
    pub fn finish_with(mut self, result: &RunResult<St>) -> Result<PathBuf> {
        if let Some((k, state, stats)) = self.last {
            if self.last_written != Some(k) {
                self.push(k, &state, stats.as_ref());
            }
        }
        let mut kv = Vec::new();
        match result {
            Ok(summary) => {
                let outcome = if summary.stopped {
                    "stopped"
                } else {
                    "completed"
                };
                kv.push(("dirac.outcome", outcome.to_owned()));
                kv.push(("dirac.steps", summary.steps.to_string()));
            }
            Err(e) => {
                kv.push(("dirac.outcome", "failed".to_owned()));
                kv.push(("dirac.steps", e.trajectory.steps.to_string()));
                kv.push(("dirac.error.kind", e.source.kind().to_owned()));
                kv.push(("dirac.error.step", e.source.step().to_string()));
                kv.push(("dirac.error.residual", float_text(e.source.residual())));
                kv.push(("dirac.error.message", e.source.to_string()));
            }
        }
        let kv = kv.into_iter().map(|(k, v)| (k.to_owned(), v)).collect();
        self.close_with(kv)
    }

    fn close_with(&mut self, kv: Vec<(String, String)>) -> Result<PathBuf> {
        self.write_group();
        let mut encoder = self.sink.take().expect("closed once").finish()?;
        for (k, v) in kv {
            encoder
                .writer
                .append_key_value_metadata(KeyValue::new(k, v));
        }
        close_writer(encoder.writer, &encoder.path, false)?;
        Ok(self.path.clone())
    }
}

type Writer = ArrowWriter<BufWriter<File>>;

/// Where [`Options::rows_per_file`] splits a run into parts.
struct Parts {
    dir: PathBuf,
    rows_per_file: u64,
    /// The part being written.
    index: usize,
    /// Rows written to it.
    rows: u64,
}

impl Parts {
    fn file(&self, index: usize) -> PathBuf {
        self.dir.join(format!("part-{index:05}.parquet"))
    }
}

/// Writes buffers as row groups of the file's schema, into the current file or part.
struct Encoder {
    writer: Writer,
    schema: SchemaRef,
    member: Option<u64>,
    /// The file being written.
    path: PathBuf,
    properties: WriterProperties,
    parts: Option<Parts>,
}

impl Encoder {
    fn write(&mut self, b: Buffer) -> Result<()> {
        let rows = b.len();
        if let Some(parts) = &mut self.parts {
            // A full part is closed when the next row group arrives, so the last part is never
            // empty and always open for the run's outcome.
            if parts.rows >= parts.rows_per_file {
                parts.index += 1;
                parts.rows = 0;
                let next = parts.file(parts.index);
                let writer = create_writer(&next, self.schema.clone(), self.properties.clone())?;
                let full = std::mem::replace(&mut self.writer, writer);
                close_writer(full, &self.path, false)?;
                self.path = next;
            }
            parts.rows += rows as u64;
        }
        let writer = &mut self.writer;
        let mut columns: Vec<ArrayRef> = Vec::with_capacity(self.schema.fields().len());
        if let Some(m) = self.member {
            columns.push(Arc::new(UInt64Array::from(vec![m; rows])));
        }
        columns.push(Arc::new(UInt64Array::from(b.step)));
        columns.push(Arc::new(Float64Array::from(b.t)));
        columns.extend(
            b.state
                .into_iter()
                .map(|c| Arc::new(Float64Array::from(c)) as ArrayRef),
        );
        columns.push(Arc::new(UInt32Array::from(b.iterations)));
        columns.push(Arc::new(Float64Array::from(b.residual)));
        columns.push(Arc::new(Float64Array::from(b.rcond)));
        columns.extend(
            b.extra
                .into_iter()
                .map(|c| Arc::new(Float64Array::from(c)) as ArrayRef),
        );
        let batch =
            RecordBatch::try_new(self.schema.clone(), columns).map_err(Error::arrow(&self.path))?;
        writer.write(&batch).map_err(Error::parquet(&self.path))?;
        // One batch is one row group: what is held in memory is bounded by it.
        writer.flush().map_err(Error::parquet(&self.path))
    }
}

/// Where full buffers go: written on the run's thread, or sent to a writer thread through a
/// channel of capacity 1 (so the run waits rather than queue more than one row group ahead).
enum Sink {
    Inline {
        encoder: Box<Encoder>,
        error: Option<Error>,
    },
    Thread {
        sender: Option<SyncSender<Buffer>>,
        worker: JoinHandle<Result<Encoder>>,
    },
}

impl Sink {
    fn start(encoder: Encoder, background: bool) -> Self {
        if !background {
            return Sink::Inline {
                encoder: Box::new(encoder),
                error: None,
            };
        }
        let (sender, receiver) = sync_channel::<Buffer>(1);
        let worker = std::thread::spawn(move || {
            let mut encoder = encoder;
            for buffer in receiver {
                // On an error the thread ends, the channel closes, and the run stops sending.
                encoder.write(buffer)?;
            }
            Ok(encoder)
        });
        Sink::Thread {
            sender: Some(sender),
            worker,
        }
    }

    fn write(&mut self, buffer: Buffer) {
        match self {
            Sink::Inline { encoder, error } => {
                if error.is_none() {
                    if let Err(e) = encoder.write(buffer) {
                        *error = Some(e);
                    }
                }
            }
            Sink::Thread { sender, .. } => {
                if let Some(s) = sender {
                    if s.send(buffer).is_err() {
                        // The writer failed; its error is returned by `finish`.
                        *sender = None;
                    }
                }
            }
        }
    }

    /// Waits for every row group to be written; returns the encoder, or the first error.
    fn finish(self) -> Result<Encoder> {
        match self {
            Sink::Inline { encoder, error } => error.map_or(Ok(*encoder), Err),
            Sink::Thread { sender, worker } => {
                drop(sender);
                worker.join().expect("the writer thread does not panic")
            }
        }
    }
}
