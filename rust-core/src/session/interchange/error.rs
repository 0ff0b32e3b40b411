//! Errors of the interchange folder: every one names the file, and the
//! line and column where there is one.

use super::*;
use crate::io::obj_reader::ObjError;
use crate::io::{Excerpt, FileError};

/// What can go wrong reading or writing an interchange folder. Every error
/// names the file, and the 1-based line and column where there is one.
#[derive(Debug, thiserror::Error)]
pub enum InterchangeError {
    /// A required file is missing, or reading or writing failed.
    #[error(transparent)]
    File(#[from] FileError),
    /// A line of an OBJ file could not be understood.
    #[error("{}:{line}: {message}", path.display())]
    Obj {
        /// The OBJ file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// `template/neutral.obj` does not describe a valid triangle mesh.
    #[error("{}: {message}", path.display())]
    Topology {
        /// The template file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// An OBJ's vertex count differs from `template/neutral.obj`'s.
    #[error("{}: {found} vertices, but template/neutral.obj has {expected}", path.display())]
    VertexCount {
        /// The OBJ file.
        path: PathBuf,
        /// Vertex count of the template.
        expected: usize,
        /// Vertex count of this file.
        found: usize,
    },
    /// An OBJ's face list differs from `template/neutral.obj`'s.
    #[error("{}{}: {message}", path.display(), line.map(|l| format!(":{l}")).unwrap_or_default())]
    Faces {
        /// The OBJ file.
        path: PathBuf,
        /// 1-based line of the first differing face, if it has one.
        line: Option<usize>,
        /// How it differs.
        message: String,
    },
    /// A CSV row has a different number of fields than the header.
    #[error("{}:{line}: {found} fields, but the header has {expected}", path.display())]
    FieldCount {
        /// The CSV file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// Number of header fields.
        expected: usize,
        /// Number of fields on this line.
        found: usize,
    },
    /// A cell that must be a finite number is not (includes NaN and ±inf).
    #[error("{}:{line}: column {column} ({name}): {value} is not a finite number", path.display())]
    NotANumber {
        /// The CSV file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// The column's header.
        name: String,
        /// The cell, quoted.
        value: Excerpt,
    },
    /// A weight lies outside `[0, 1]` by more than [`WEIGHT_TOLERANCE`].
    #[error(
        "{}:{line}: column {column} ({name}): weight {value} is outside [0, 1] (tolerance {WEIGHT_TOLERANCE})",
        path.display()
    )]
    WeightRange {
        /// The CSV file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// The column's header.
        name: String,
        /// The weight.
        value: f32,
    },
    /// A header names the same column twice.
    #[error("{}:{line}: column {column}: duplicate column {name} (first at column {first})", path.display())]
    DuplicateColumn {
        /// The CSV file.
        path: PathBuf,
        /// 1-based line of the header.
        line: usize,
        /// 1-based column of the repeat.
        column: usize,
        /// The header cell, quoted.
        name: Excerpt,
        /// 1-based column of the first occurrence.
        first: usize,
    },
    /// A header cell is neither the key column nor an ARKit name.
    #[error("{}:{line}: column {column}: unknown column {name}", path.display())]
    UnknownColumn {
        /// The CSV file.
        path: PathBuf,
        /// 1-based line of the header.
        line: usize,
        /// 1-based column.
        column: usize,
        /// The header cell, quoted.
        name: Excerpt,
    },
    /// A required column is absent (or the file has no header at all).
    #[error("{}: missing column {name}", path.display())]
    MissingColumn {
        /// The CSV file.
        path: PathBuf,
        /// The missing column.
        name: String,
    },
    /// A key cell is wrong: an unknown prompt, a repeated key, a timestamp
    /// that is not a number or goes backwards, a bad timecode.
    #[error("{}:{line}: column {column}: {message}", path.display())]
    Key {
        /// The CSV file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What is wrong.
        message: String,
    },
    /// A table has more than [`MAX_ROWS`](super::weights_csv::MAX_ROWS)
    /// data rows.
    #[error("{}:{line}: more than the limit of {limit} rows (ten minutes at 60 fps)", path.display())]
    TooManyRows {
        /// The CSV file.
        path: PathBuf,
        /// 1-based line of the first row past the limit.
        line: usize,
        /// The most rows accepted.
        limit: usize,
    },
    /// A row names an expression whose OBJ file does not exist.
    #[error("{}:{line}: {key} has no mesh: {} is missing", path.display(), mesh.display())]
    NoMesh {
        /// The CSV file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// The prompt or id, quoted.
        key: Excerpt,
        /// The expected OBJ file.
        mesh: PathBuf,
    },
    /// A test id cannot be written as a file name or CSV cell.
    #[error(
        "test expression id {0} cannot be a file name (empty, `.`, `..`, or contains `/`, `\\`, `,` or a line break)"
    )]
    BadId(Excerpt),
    /// The imported session, or the one to export, is not valid.
    #[error("{}: {source}", path.display())]
    Session {
        /// The folder.
        path: PathBuf,
        /// What is inconsistent.
        source: SessionError,
    },
}

impl From<ObjError> for InterchangeError {
    fn from(error: ObjError) -> Self {
        match error {
            ObjError::File(file) => InterchangeError::File(file),
            ObjError::Syntax {
                path,
                line,
                message,
            } => InterchangeError::Obj {
                path,
                line,
                message,
            },
        }
    }
}
