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
    /// A command-line argument or environment variable is malformed.
    #[error("{0}")]
    Usage(String),
}

impl Error {
    pub(crate) fn io(path: impl Into<PathBuf>) -> impl FnOnce(std::io::Error) -> Self {
        let path = path.into();
        move |source| Error::Io { path, source }
    }

    pub(crate) fn parquet(
        path: impl Into<PathBuf>,
    ) -> impl FnOnce(parquet::errors::ParquetError) -> Self {
        let path = path.into();
        move |source| Error::Parquet { path, source }
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
