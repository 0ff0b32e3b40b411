//! `likeness import` / `likeness export`: a session as a folder of OBJ and
//! CSV files (layout in `likeness::session::interchange`).

use crate::CliResult;
use likeness::session::{file as session_file, interchange};
use std::path::Path;

/// `likeness import DIR --out FILE`: reads an interchange folder and writes
/// it as a session file; warnings go to stderr.
pub fn import_command(dir: &Path, out: &Path) -> CliResult {
    let (session, warnings) = interchange::import_folder(dir)?;
    for warning in &warnings {
        eprintln!("warning: {warning}");
    }
    // Writing fails on the `--out` file (which the error names) or on the
    // imported session itself (a limit of the format): name the folder.
    session_file::write(out, &session).map_err(|e| match e {
        session_file::SessionFileError::Io { .. } => Box::<dyn std::error::Error>::from(e),
        other => format!(
            "{}: cannot be stored as a session file: {other}",
            dir.display()
        )
        .into(),
    })?;
    eprintln!(
        "imported {}: {} captures, {} test expressions, {} frames, {} warnings -> {}",
        dir.display(),
        session.captures.len(),
        session.tests.len(),
        session.frames.len(),
        warnings.len(),
        out.display()
    );
    Ok(())
}

/// `likeness export FILE --out DIR`: writes a session file as an
/// interchange folder.
pub fn export_command(file: &Path, out: &Path) -> CliResult {
    let session = crate::info::read_session(file)?;
    interchange::export_folder(&session, out)?;
    eprintln!(
        "exported {}: {} captures, {} test expressions, {} frames -> {}",
        file.display(),
        session.captures.len(),
        session.tests.len(),
        session.frames.len(),
        out.display()
    );
    Ok(())
}
