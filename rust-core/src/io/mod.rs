//! Files: atomic writes, and Wavefront OBJ reading and writing side by side.
//! The session's own formats live with the session model
//! ([`crate::session::file`], [`crate::session::interchange`]).
//!
//! | what | file |
//! |---|---|
//! | write to a temporary file, then rename into place | [`atomic_write`] |
//! | read a text file, with the path in every error | [`text_file`] |
//! | OBJ in: `v` and `f` lines, errors naming file and line | [`obj_reader`] |
//! | OBJ out: one mesh per file | [`obj_writer`] |

pub mod atomic_write;
pub mod obj_reader;
pub mod obj_writer;
pub mod text_file;

pub use atomic_write::write_atomically;
