//! The one error type of this crate: what went wrong, and with which file.

use std::path::PathBuf;

/// Why writing, reading, sharding or merging failed. Every variant names the file involved.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// The operating system refused a read, write, rename or directory operation.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The Parquet encoder or decoder failed (or the file is not Parquet).
    #[error("{}: {source}", path.display())]
    Parquet {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: parquet::errors::ParquetError,
    },
    /// A table or a file does not have the content expected: a missing or non-numeric column, a
    /// malformed CSV line, a shard of another ensemble.
    #[error("{}: {message}", path.display())]
    Content {
        /// The file.
        path: PathBuf,
        /// What was found and what is accepted.
        message: String,
    },
    /// A call's arguments are malformed: a command-line argument or environment variable, a
    /// shard index not below the count, a table row of the wrong length.
    #[error("{0}")]
    Usage(String),
    /// An ensemble table's columns are not those its run accepts
    /// ([`Table::validate`](crate::table::Table::validate)): found before any member runs.
    #[error("{}", columns_message(.unknown, .duplicated, .accepted))]
    Columns {
        /// Columns the run does not accept, each with the closest accepted name when it looks
        /// like a misspelling of one.
        unknown: Vec<(String, Option<String>)>,
        /// Names given to more than one column.
        duplicated: Vec<String>,
        /// The names the run accepts.
        accepted: Vec<String>,
    },
    /// No member of an ensemble could be built, so not even the run's columns are known: the
    /// first member's error (see [`run_shard`](crate::shard::run_shard)).
    #[error("member {member} could not be built: {message}")]
    Member {
        /// The member (row of the table).
        member: usize,
        /// Its closure's error, or its panic's message.
        message: String,
    },
}

/// The message of [`Error::Columns`].
fn columns_message(
    unknown: &[(String, Option<String>)],
    duplicated: &[String],
    accepted: &[String],
) -> String {
    let mut parts = Vec::new();
    if !unknown.is_empty() {
        let names: Vec<String> = unknown
            .iter()
            .map(|(name, close)| match close {
                Some(c) => format!("`{name}` (did you mean `{c}`?)"),
                None => format!("`{name}`"),
            })
            .collect();
        parts.push(format!("unknown column(s) {}", names.join(", ")));
    }
    if !duplicated.is_empty() {
        let names: Vec<String> = duplicated.iter().map(|n| format!("`{n}`")).collect();
        parts.push(format!(
            "column(s) {} given more than once",
            names.join(", ")
        ));
    }
    format!(
        "the ensemble table has {}; the accepted columns are: {}",
        parts.join(" and "),
        accepted.join(", ")
    )
}

impl Error {
    pub(crate) fn io(path: impl Into<PathBuf>) -> impl FnOnce(std::io::Error) -> Self {
        let path = path.into();
        move |source| Error::Io { path, source }
    }

    /// The Parquet encoder's or decoder's error; one the operating system caused (a full disk,
    /// a file size limit, a read error), which the encoder passes on as `External`, is
    /// [`Error::Io`], with its [`std::io::ErrorKind`] (`StorageFull`, `FileTooLarge`, …).
    pub(crate) fn parquet(
        path: impl Into<PathBuf>,
    ) -> impl FnOnce(parquet::errors::ParquetError) -> Self {
        let path = path.into();
        move |source| match source {
            parquet::errors::ParquetError::External(e) => match e.downcast::<std::io::Error>() {
                Ok(io) => Error::Io { path, source: *io },
                Err(e) => Error::Parquet {
                    path,
                    source: parquet::errors::ParquetError::External(e),
                },
            },
            source => Error::Parquet { path, source },
        }
    }

    pub(crate) fn arrow(path: impl Into<PathBuf>) -> impl FnOnce(arrow_schema::ArrowError) -> Self {
        let path = path.into();
        move |source| Error::Parquet {
            path,
            source: parquet::errors::ParquetError::ArrowError(source.to_string()),
        }
    }

    pub(crate) fn content(path: impl Into<PathBuf>, message: impl Into<String>) -> Self {
        Error::Content {
            path: path.into(),
            message: message.into(),
        }
    }
}

/// What this crate's functions return.
pub type Result<T, E = Error> = std::result::Result<T, E>;
