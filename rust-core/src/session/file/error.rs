//! What can go wrong reading or writing a session file.

use super::FORMAT_VERSION;
use super::limits::Limit;
use crate::geometry::topology::TopologyError;
use crate::io::FileError;
use crate::session::SessionError;
use std::path::PathBuf;

/// Why a session could not be written, or a file could not be read back as a
/// session. Every variant that comes from a file's contents names what is
/// wrong and, where it can, where (`frames[812].vertices`).
#[derive(Debug, thiserror::Error)]
pub enum SessionFileError {
    /// The file could not be opened or read: missing, not a regular file
    /// (a directory, a FIFO, a device), or unreadable.
    #[error(transparent)]
    File(#[from] FileError),
    /// The file could not be written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What the operating system said.
        source: std::io::Error,
    },
    /// The bytes do not start with [`MAGIC`](super::MAGIC): this is not a
    /// Likeness session file at all.
    #[error("not a Likeness session file (the first bytes are not \"LIKENESS\")")]
    NotASessionFile,
    /// A session file of a format version this build cannot read.
    #[error("unsupported session format version {0} (this build reads version {FORMAT_VERSION})")]
    UnsupportedVersion(u32),
    /// The file ends before the header says it should.
    #[error("truncated session file: {what} needs {expected} bytes, but only {found} are present")]
    Truncated {
        /// What was being read (`header`, `payload`).
        what: &'static str,
        /// Bytes needed.
        expected: u64,
        /// Bytes present.
        found: u64,
    },
    /// The payload's CRC-32 does not match the header: the file was damaged.
    #[error(
        "session file is damaged: checksum {found:#010x} does not match the stored {expected:#010x}"
    )]
    Checksum {
        /// The checksum stored in the header.
        expected: u32,
        /// The checksum of the bytes actually present.
        found: u32,
    },
    /// A size declared in the header or the payload is over one of the
    /// format's [limits](super::limits); nothing was allocated for it.
    #[error("{field} is {value} {}, over the limit {limit}", limit.unit())]
    TooLarge {
        /// Which size, e.g. `frames.count`.
        field: String,
        /// The declared size.
        value: u64,
        /// The limit it passes.
        limit: Limit,
    },
    /// The payload passed its checksum but does not decode: a bug in the
    /// writer, or a deliberately crafted file.
    #[error("corrupt session file: {field}: {reason}")]
    Corrupt {
        /// Where, e.g. `frames[812].vertices`.
        field: String,
        /// What is wrong.
        reason: String,
    },
    /// The decoded connectivity is not a valid triangle list.
    #[error("session file topology: {0}")]
    Topology(#[from] TopologyError),
    /// The decoded parts break one of the invariants that
    /// [`Session::new`](crate::Session::new) checks.
    #[error("invalid session: {0}")]
    Invalid(#[from] SessionError),
    /// A value is too large to store at the format's fixed precision
    /// (positions beyond ±100 m, weights beyond ±100).
    #[error("{field}: {value} is outside the storable range ±{limit}")]
    OutOfRange {
        /// Where, e.g. `frames[3].weights[jawOpen]`.
        field: String,
        /// The value.
        value: f64,
        /// The largest storable magnitude.
        limit: f64,
    },
    /// The compressor or serializer failed while writing (should not happen).
    #[error("could not encode session: {0}")]
    Encode(String),
}

impl SessionFileError {
    /// Shorthand for [`SessionFileError::Corrupt`].
    pub(super) fn corrupt(field: impl Into<String>, reason: impl Into<String>) -> Self {
        SessionFileError::Corrupt {
            field: field.into(),
            reason: reason.into(),
        }
    }

    /// Shorthand for [`SessionFileError::TooLarge`], from what
    /// [`check_extent`](super::limits::check_extent) and its kin return.
    pub(super) fn too_large(field: impl Into<String>, (limit, value): (Limit, u64)) -> Self {
        SessionFileError::TooLarge {
            field: field.into(),
            value,
            limit,
        }
    }
}
