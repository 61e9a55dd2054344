//! The observer's writing machinery: the buffer of a row group, the encoder that writes row
//! groups into the file or the parts and publishes each part when full, and the sink that runs
//! it on the run's thread or a thread of its own.

use std::path::{Path, PathBuf};
use std::sync::mpsc::{sync_channel, Receiver, SyncSender};
use std::sync::Arc;
use std::thread::JoinHandle;

use arrow_array::{ArrayRef, Float64Array, RecordBatch, UInt32Array, UInt64Array};
use arrow_schema::SchemaRef;
use parquet::basic::Compression;

use crate::error::{Error, Result};
use crate::files::{part_file, partial_file, publish_file};
use crate::integrity::FileWriter;

/// The columns of one row group, before they are written.
pub(super) struct Buffer {
    pub(super) step: Vec<u64>,
    pub(super) t: Vec<f64>,
    /// Column-major: `state[c]` is column `c`.
    pub(super) state: Vec<Vec<f64>>,
    pub(super) iterations: Vec<Option<u32>>,
    pub(super) residual: Vec<Option<f64>>,
    pub(super) rcond: Vec<Option<f64>>,
    pub(super) extra: Vec<Vec<f64>>,
    /// Whether its last row is the last of a part: the part is published once it is written.
    pub(super) ends_part: bool,
}

impl Buffer {
    pub(super) fn new(width: usize, extra: usize, rows: usize) -> Self {
        Buffer {
            step: Vec::with_capacity(rows),
            t: Vec::with_capacity(rows),
            state: (0..width).map(|_| Vec::with_capacity(rows)).collect(),
            iterations: Vec::with_capacity(rows),
            residual: Vec::with_capacity(rows),
            rcond: Vec::with_capacity(rows),
            extra: (0..extra).map(|_| Vec::with_capacity(rows)).collect(),
            ends_part: false,
        }
    }

    pub(super) fn len(&self) -> usize {
        self.step.len()
    }
}

/// Where an [`Encoder`] writes.
pub(super) enum Target {
    /// One file, published at the end.
    File { path: PathBuf },
    /// A directory of parts, each published when full (the observer marks the row group that
    /// fills one: [`Buffer::ends_part`]); `index` is the part being written.
    Parts { dir: PathBuf, index: usize },
}

/// Writes buffers as row groups of the file's schema, into the current file or part.
pub(super) struct Encoder {
    /// The file being written (under its hidden name); `None` once closed.
    pub(super) writer: Option<FileWriter>,
    pub(super) schema: SchemaRef,
    pub(super) member: Option<u64>,
    pub(super) compression: Compression,
    pub(super) kv: Vec<(String, String)>,
    pub(super) target: Target,
    /// Whether a file is synced before it is published
    /// ([`Options::sync`](super::Options::sync)).
    pub(super) sync: bool,
    /// The most rows of a row group, the writer's limit too.
    pub(super) rows_per_group: usize,
}

impl Encoder {
    fn writer(&mut self) -> Result<&mut FileWriter> {
        self.writer
            .as_mut()
            .ok_or_else(|| Error::Usage("the output was closed already".into()))
    }

    /// Closes the file being written (appending `kv` to its metadata) and publishes it. On an
    /// error (a full disk) its hidden partial file is removed: nothing is left that no reader
    /// reads and no run resumes from; the parts published before stay.
    pub(super) fn close(&mut self, kv: Vec<(String, String)>) -> Result<()> {
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

    /// Writes `b` as one row group, and publishes the part it ends ([`Buffer::ends_part`]). On
    /// an error (a full disk) the hidden partial file is removed and nothing more is written.
    fn write(&mut self, b: Buffer) -> Result<()> {
        let written = self.write_group(b);
        if written.is_err() {
            if let Some(writer) = self.writer.take() {
                let partial = writer.path().to_owned();
                drop(writer);
                remove_partial(&partial);
            }
        }
        written
    }

    fn write_group(&mut self, b: Buffer) -> Result<()> {
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
            self.close(Vec::new())?;
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

/// Removes the hidden partial file of a write that failed (a file already gone is fine: a
/// publishing rename may have moved it before the error).
fn remove_partial(partial: &Path) {
    let _ = std::fs::remove_file(partial);
}

/// Where full buffers go: written on the run's thread, or sent to a writer thread through a
/// channel of capacity 1 (so the run waits rather than queue more than one row group ahead).
/// Either way a buffer that ends a part returns only once the part is published: the thread
/// says so on `published`.
pub(super) enum Sink {
    Inline {
        encoder: Box<Encoder>,
        error: Option<Error>,
    },
    Thread {
        sender: Option<SyncSender<Buffer>>,
        published: Receiver<()>,
        worker: JoinHandle<Result<Encoder>>,
        path: PathBuf,
    },
}

impl Sink {
    pub(super) fn start(encoder: Encoder, background: bool) -> Self {
        if !background {
            return Sink::Inline {
                encoder: Box::new(encoder),
                error: None,
            };
        }
        let path = encoder
            .writer
            .as_ref()
            .map_or_else(PathBuf::new, |w| w.path().to_owned());
        let (sender, receiver) = sync_channel::<Buffer>(1);
        // The run waits for each part it ends, so at most one is ever announced and unread.
        let (announce, published) = sync_channel::<()>(1);
        let worker = std::thread::spawn(move || {
            let mut encoder = encoder;
            for buffer in receiver {
                let ends_part = buffer.ends_part;
                // On an error the thread ends, the channels close, and the run stops sending.
                encoder.write(buffer)?;
                if ends_part {
                    let _ = announce.send(());
                }
            }
            Ok(encoder)
        });
        Sink::Thread {
            sender: Some(sender),
            published,
            worker,
            path,
        }
    }

    pub(super) fn write(&mut self, buffer: Buffer) {
        match self {
            Sink::Inline { encoder, error } => {
                if error.is_none() {
                    if let Err(e) = encoder.write(buffer) {
                        *error = Some(e);
                    }
                }
            }
            Sink::Thread {
                sender, published, ..
            } => {
                if let Some(s) = sender {
                    let ends_part = buffer.ends_part;
                    // An error sending or waiting: the writer failed, and its error is returned
                    // by `finish`.
                    if s.send(buffer).is_err() || (ends_part && published.recv().is_err()) {
                        *sender = None;
                    }
                }
            }
        }
    }

    /// Waits for every row group to be written; returns the encoder, or the first error.
    pub(super) fn finish(self) -> Result<Encoder> {
        match self {
            Sink::Inline { encoder, error } => error.map_or(Ok(*encoder), Err),
            Sink::Thread {
                sender,
                worker,
                path,
                ..
            } => {
                drop(sender);
                worker.join().unwrap_or_else(|_| {
                    Err(Error::content(
                        path,
                        "the writer thread panicked: the rows it held are lost",
                    ))
                })
            }
        }
    }
}
