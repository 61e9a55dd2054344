//! Apache Parquet, one format of the output ([`Parquet`], a [`Sink`]): a run's rows as row
//! groups of a directory of parts or of one file, each part published complete, with the
//! checksums of [`integrity`]; and what reads them back ([`read`]). See the
//! [crate documentation](crate) for the trajectory schema.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use arrow_array::{ArrayRef, Float64Array, RecordBatch, UInt32Array, UInt64Array};
use arrow_schema::{DataType, Field, Schema, SchemaRef};
use parquet::basic::Compression;

use crate::columns::{RunInfo, StateColumns};
use crate::error::{Error, Result};
use crate::files::{part_file, partial_file, publish_file, published_parts};
use crate::output::{Layout, Options, Output, Resumed, Rows, Sink};

pub mod integrity;
pub mod read;
pub(crate) mod shard_file;
mod table;

use integrity::FileWriter;

/// An [`Output`] into Apache Parquet: the observer a run streams its states into (see
/// [`Output`] for how, and the [crate documentation](crate) for the schema).
pub type ParquetObserver<St> = Output<St, Parquet>;

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

/// Where a [`Parquet`] sink writes.
enum Target {
    /// One file, published at the end.
    File { path: PathBuf },
    /// A directory of parts, each published when full; `index` is the part being written.
    Parts { dir: PathBuf, index: usize },
}

/// The Parquet [`Sink`]: each block of rows one row group of the part (or file) being written,
/// under its hidden name until it is published.
pub struct Parquet {
    /// The file being written (under its hidden name); `None` once closed.
    writer: Option<FileWriter>,
    schema: SchemaRef,
    member: Option<u64>,
    compression: Compression,
    kv: Vec<(String, String)>,
    target: Target,
    /// Whether a file is synced before it is published ([`Options::sync`]).
    sync: bool,
    /// The most rows of a row group, the writer's limit too.
    rows_per_group: usize,
    /// The file or directory written.
    path: PathBuf,
}

impl Parquet {
    /// The sink writing rows laid out as `layout` at `path`: a directory of parts, the first
    /// one numbered `first_part`, or one file ([`Layout::rows_per_part`] `None`). The directory
    /// must exist.
    pub fn open(path: &Path, layout: &Layout, first_part: usize) -> Result<Self> {
        let schema = Arc::new(trajectory_schema(
            &layout.state,
            layout.member.is_some(),
            &layout.extra,
        ));
        let compression = if layout.compress {
            Compression::SNAPPY
        } else {
            Compression::UNCOMPRESSED
        };
        let target = match layout.rows_per_part {
            None => Target::File {
                path: path.to_owned(),
            },
            Some(_) => Target::Parts {
                dir: path.to_owned(),
                index: first_part,
            },
        };
        let first = match &target {
            Target::File { path } => partial_file(path),
            Target::Parts { dir, index } => partial_file(&part_file(dir, *index)),
        };
        let writer = FileWriter::create_with_groups(
            &first,
            schema.clone(),
            compression,
            layout.metadata.clone(),
            layout.rows_per_group,
        )?;
        Ok(Parquet {
            writer: Some(writer),
            schema,
            member: layout.member,
            compression,
            kv: layout.metadata.clone(),
            target,
            sync: layout.sync,
            rows_per_group: layout.rows_per_group,
            path: path.to_owned(),
        })
    }

    fn writer(&mut self) -> Result<&mut FileWriter> {
        self.writer
            .as_mut()
            .ok_or_else(|| Error::Usage("the output was closed already".into()))
    }

    /// Closes the file being written (appending `kv` to its metadata) and publishes it. On an
    /// error (a full disk) its hidden partial file is removed: nothing is left that no reader
    /// reads and no run resumes from; the parts published before stay.
    fn publish(&mut self, kv: Vec<(String, String)>) -> Result<()> {
        let Some(mut writer) = self.writer.take() else {
            return Ok(());
        };
        for (k, v) in kv {
            writer.append(k, v);
        }
        let partial = writer.path().to_owned();
        let path = match &self.target {
            Target::File { path } => path.clone(),
            Target::Parts { dir, index } => part_file(dir, *index),
        };
        let published = writer
            .close(self.sync)
            .and_then(|()| publish_file(&partial, &path, self.sync));
        if published.is_err() {
            remove_partial(&partial);
        }
        published
    }

    fn write_group(&mut self, b: Rows) -> Result<()> {
        let rows = b.len();
        let ends_part = b.ends_part;
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
        let schema = self.schema.clone();
        let writer = self.writer()?;
        let batch = RecordBatch::try_new(schema, columns).map_err(Error::arrow(writer.path()))?;
        writer.write(&batch)?;
        // One batch is one row group: what is held in memory is bounded by it.
        writer.flush()?;
        if let (true, Target::Parts { dir, index }) = (ends_part, &self.target) {
            // The part is full: published now, and the next one opened (for more rows, or for
            // the run's outcome alone when the run ends here).
            let next = partial_file(&part_file(dir, index + 1));
            self.publish(Vec::new())?;
            if let Target::Parts { index, .. } = &mut self.target {
                *index += 1;
            }
            self.writer = Some(FileWriter::create_with_groups(
                &next,
                self.schema.clone(),
                self.compression,
                self.kv.clone(),
                self.rows_per_group,
            )?);
        }
        Ok(())
    }
}

impl Sink for Parquet {
    /// Writes `rows` as one row group, and publishes the part it ends. On an error (a full
    /// disk) the hidden partial file is removed and nothing more is written.
    fn write(&mut self, rows: Rows) -> Result<()> {
        let written = self.write_group(rows);
        if written.is_err() {
            if let Some(writer) = self.writer.take() {
                let partial = writer.path().to_owned();
                drop(writer);
                remove_partial(&partial);
            }
        }
        written
    }

    fn close(&mut self, outcome: Vec<(String, String)>) -> Result<()> {
        self.publish(outcome)
    }

    fn path(&self) -> &Path {
        &self.path
    }
}

/// Removes the hidden partial file of a write that failed (a file already gone is fine: a
/// publishing rename may have moved it before the error).
fn remove_partial(partial: &Path) {
    let _ = std::fs::remove_file(partial);
}

impl<St: StateColumns> Output<St, Parquet> {
    /// Creates the output at `path` for a run described by `info`: a directory of parts (by
    /// default; its previous parts, if any, are removed) or one file ([`Options::single_file`]).
    /// An error if `info` does not describe states of type `St`.
    pub fn create(path: impl AsRef<Path>, info: RunInfo, options: Options<St>) -> Result<Self> {
        let path = path.as_ref();
        let layout = options.layout(&info)?;
        if !options.is_single_file() {
            std::fs::create_dir_all(path).map_err(Error::io(path))?;
            let (parts, partials) = published_parts(path).unwrap_or_default();
            for old in parts.iter().chain(&partials) {
                std::fs::remove_file(old).map_err(Error::io(old))?;
            }
        }
        let sink = Parquet::open(path, &layout, 0)?;
        Ok(Output::new(sink, &layout, options))
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
        let path = path.as_ref();
        if options.is_single_file() {
            return Err(Error::Usage(
                "a run written to one file cannot be resumed: write it in parts (the default)"
                    .into(),
            ));
        }
        if !path.exists() {
            return Ok((Self::create(path, info, options)?, None));
        }
        let (parts, partials) = published_parts(path)?;
        for old in &partials {
            std::fs::remove_file(old).map_err(Error::io(old))?;
        }
        let Some(last_part) = parts.last() else {
            return Ok((Self::create(path, info, options)?, None));
        };
        let kv = read::key_values(last_part)?;
        if let Some(outcome) = kv.get("dirac.outcome") {
            return Err(Error::content(
                last_part,
                format!("the run ended ({outcome}): nothing to resume"),
            ));
        }
        let layout = options.layout(&info)?;
        let (step, t, state) = read::last_state::<St>(last_part, &info.columns)?;
        let sink = Parquet::open(path, &layout, parts.len())?;
        let observer = Output::starting_at(sink, &layout, options, step);
        Ok((observer, Some(Resumed { step, t, state })))
    }
}
