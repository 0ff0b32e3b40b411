//! The committed sample sessions (`sim-data/sessions/`), simulated subjects
//! 1–4 (see `sim-data/README.md`).

use likeness::Session;
use likeness::session::file::{self as session_file, SessionFileError};
use std::path::PathBuf;

/// Seeds of the committed sessions.
pub const SEEDS: [u64; 4] = [1, 2, 3, 4];

/// Path of the committed session of simulated subject `seed`.
pub fn path(seed: u64) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join(format!("../sim-data/sessions/subject-{seed}.likeness"))
}

/// Reads the committed session of simulated subject `seed`.
pub fn read(seed: u64) -> Result<Session, SessionFileError> {
    session_file::read(path(seed))
}
