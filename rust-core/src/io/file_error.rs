//! What can go wrong opening and reading a file, with the path (and the
//! line, for text) in every message.

use std::io;
use std::path::PathBuf;

/// A file that could not be read.
#[derive(Debug, thiserror::Error)]
pub enum FileError {
    /// The file does not exist.
    #[error("{}: missing", path.display())]
    Missing {
        /// The missing file.
        path: PathBuf,
    },
    /// The path names something other than a regular file (a directory, a
    /// FIFO, a device such as `/dev/zero`, a socket); it is not read.
    #[error("{}: {kind}, not a regular file", path.display())]
    NotAFile {
        /// The path.
        path: PathBuf,
        /// What it is instead, e.g. `a directory`.
        kind: &'static str,
    },
    /// The file is larger than the reader accepts; nothing past the limit
    /// was read.
    #[error("{}: {size} bytes, over the limit of {limit} bytes for {what}", path.display())]
    TooLarge {
        /// The file.
        path: PathBuf,
        /// Its size (at least `limit + 1` if the system reported less).
        size: u64,
        /// The largest size accepted.
        limit: u64,
        /// What kind of file, e.g. `an OBJ file`.
        what: &'static str,
    },
    /// A line of a text file is longer than the reader accepts.
    #[error("{}:{line}: line longer than the limit of {limit} bytes", path.display())]
    LineTooLong {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// The longest line accepted, in bytes.
        limit: usize,
    },
    /// A line of a text file is not UTF-8.
    #[error("{}:{line}: not UTF-8 text", path.display())]
    NotText {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
    },
    /// Reading failed.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What the system reported.
        source: io::Error,
    },
}

impl FileError {
    /// An I/O error on `path`; a missing file is [`FileError::Missing`].
    pub fn io(path: impl Into<PathBuf>, source: io::Error) -> Self {
        let path = path.into();
        if source.kind() == io::ErrorKind::NotFound {
            FileError::Missing { path }
        } else {
            FileError::Io { path, source }
        }
    }
}
