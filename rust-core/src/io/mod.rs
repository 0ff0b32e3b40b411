//! Files: reading within limits, atomic writes, and Wavefront OBJ reading
//! and writing side by side. The session's own formats live with the
//! session model ([`crate::session::file`], [`crate::session::interchange`]).
//!
//! | what | file |
//! |---|---|
//! | write to a temporary file, then rename into place | [`atomic_write`] |
//! | what can go wrong reading a file, naming the path and line | [`file_error`] |
//! | open regular files only, size checked first, reads capped | [`bounded_read`] |
//! | a text file line by line, file size and line length capped | [`text_lines`] |
//! | quoting a bad cell in a message: short and escaped | [`excerpt`] |
//! | OBJ in: `v` and `f` lines, errors naming file and line | [`obj_reader`] |
//! | OBJ out: one mesh per file | [`obj_writer`] |

pub mod atomic_write;
pub mod bounded_read;
pub mod excerpt;
pub mod file_error;
pub mod obj_reader;
pub mod obj_writer;
pub mod text_lines;

pub use atomic_write::write_atomically;
pub use bounded_read::{BoundedFile, open_bounded, read_bounded};
pub use excerpt::Excerpt;
pub use file_error::FileError;
pub use text_lines::{TextLimits, TextLines, open_text};
