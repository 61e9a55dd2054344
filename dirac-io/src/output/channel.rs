//! Where an [`Output`](super::Output)'s full blocks go: into its sink on the run's thread, or on
//! a thread of its own.

use std::path::PathBuf;
use std::sync::mpsc::{sync_channel, Receiver, SyncSender};
use std::thread::JoinHandle;

use super::sink::{Rows, Sink};
use crate::error::{Error, Result};

/// Where full buffers go: written on the run's thread, or sent to a writer thread through a
/// channel of capacity 1 (so the run waits rather than queue more than one row group ahead).
/// Either way a buffer that ends a part returns only once the part is published: the thread
/// says so on `published`.
pub(super) enum Channel<S> {
    Inline {
        sink: Box<S>,
        error: Option<Error>,
    },
    Thread {
        sender: Option<SyncSender<Rows>>,
        published: Receiver<()>,
        worker: JoinHandle<Result<S>>,
        path: PathBuf,
    },
}

impl<S: Sink> Channel<S> {
    pub(super) fn start(sink: S, background: bool) -> Self {
        if !background {
            return Channel::Inline {
                sink: Box::new(sink),
                error: None,
            };
        }
        let path = sink.path().to_owned();
        let (sender, receiver) = sync_channel::<Rows>(1);
        // The run waits for each part it ends, so at most one is ever announced and unread.
        let (announce, published) = sync_channel::<()>(1);
        let worker = std::thread::spawn(move || {
            let mut sink = sink;
            for rows in receiver {
                let ends_part = rows.ends_part;
                // On an error the thread ends, the channels close, and the run stops sending.
                sink.write(rows)?;
                if ends_part {
                    let _ = announce.send(());
                }
            }
            Ok(sink)
        });
        Channel::Thread {
            sender: Some(sender),
            published,
            worker,
            path,
        }
    }

    pub(super) fn write(&mut self, buffer: Rows) {
        match self {
            Channel::Inline { sink, error } => {
                if error.is_none() {
                    if let Err(e) = sink.write(buffer) {
                        *error = Some(e);
                    }
                }
            }
            Channel::Thread {
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

    /// Waits for every block to be written; returns the sink, or the first error.
    pub(super) fn finish(self) -> Result<S> {
        match self {
            Channel::Inline { sink, error } => error.map_or(Ok(*sink), Err),
            Channel::Thread {
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
