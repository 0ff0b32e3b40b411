//! The report's files, gathered in memory and written as one folder that
//! appears whole or not at all: the files go to a temporary folder next to
//! the destination, are flushed, and the folder is renamed into place (as
//! `likeness::io::atomic_write` does for one file). A previous report in
//! the destination is replaced; any other folder there is left alone.

use std::fs;
use std::io::{self, Write};
use std::path::{Path, PathBuf};

/// The name of the report's page, and what marks a folder as a report.
pub const INDEX: &str = "index.html";

/// What the page carries so that a later run knows it may replace it.
pub const GENERATOR: &str = r#"<meta name="generator" content="likeness report">"#;

/// The report's files: paths relative to the report's folder (forward
/// slashes, one level of subfolder at most) and their bytes.
#[derive(Debug, Default)]
pub struct Files {
    entries: Vec<(String, Vec<u8>)>,
}

impl Files {
    /// Adds a file at `name` (replacing one of the same name).
    pub fn add(&mut self, name: impl Into<String>, bytes: Vec<u8>) {
        let name = name.into();
        self.entries.retain(|(n, _)| *n != name);
        self.entries.push((name, bytes));
    }

    /// The files, in the order added.
    pub fn entries(&self) -> &[(String, Vec<u8>)] {
        &self.entries
    }

    /// Their total size in bytes.
    pub fn bytes(&self) -> usize {
        self.entries.iter().map(|(_, b)| b.len()).sum()
    }
}

/// Whether `dir` may be written: it does not exist, is empty, or holds a
/// report written earlier; otherwise the error says why not.
pub fn check_replaceable(dir: &Path) -> io::Result<()> {
    if !dir.exists() {
        return Ok(());
    }
    if !dir.is_dir() {
        return Err(io::Error::other(format!(
            "{} exists and is not a folder",
            dir.display()
        )));
    }
    let empty = fs::read_dir(dir)?.next().is_none();
    let earlier_report = fs::read_to_string(dir.join(INDEX)).is_ok_and(|t| t.contains(GENERATOR));
    if empty || earlier_report {
        Ok(())
    } else {
        Err(io::Error::other(format!(
            "{} exists and is not a Likeness report: not replacing it",
            dir.display()
        )))
    }
}

/// `.NAME.SUFFIX.PID` next to `dir`.
fn sibling(dir: &Path, suffix: &str) -> io::Result<PathBuf> {
    let name = dir
        .file_name()
        .ok_or_else(|| io::Error::other(format!("{} has no folder name", dir.display())))?;
    let mut hidden = std::ffi::OsString::from(".");
    hidden.push(name);
    hidden.push(format!(".{suffix}.{}", std::process::id()));
    Ok(match dir.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.join(hidden),
        _ => PathBuf::from(hidden),
    })
}

/// Writes `files` as the folder `dir` (module docs).
pub fn write_folder(dir: &Path, files: &Files) -> io::Result<()> {
    check_replaceable(dir)?;
    let tmp = sibling(dir, "tmp")?;
    let result = (|| {
        if tmp.exists() {
            fs::remove_dir_all(&tmp)?;
        }
        fs::create_dir_all(&tmp)?;
        for (name, bytes) in files.entries() {
            let path = tmp.join(name);
            if let Some(parent) = path.parent() {
                fs::create_dir_all(parent)?;
            }
            let mut file = fs::File::create(&path)?;
            file.write_all(bytes)?;
            file.sync_all()?;
        }
        replace(dir, &tmp)
    })();
    if result.is_err() {
        let _ = fs::remove_dir_all(&tmp);
    }
    result
}

/// Renames `tmp` to `dir`, moving an existing `dir` aside first and
/// removing it after (putting it back if the rename fails).
fn replace(dir: &Path, tmp: &Path) -> io::Result<()> {
    if !dir.exists() {
        return fs::rename(tmp, dir);
    }
    let old = sibling(dir, "old")?;
    if old.exists() {
        fs::remove_dir_all(&old)?;
    }
    fs::rename(dir, &old)?;
    if let Err(e) = fs::rename(tmp, dir) {
        let _ = fs::rename(&old, dir);
        return Err(e);
    }
    fs::remove_dir_all(&old)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("likeness-report-out-{}-{name}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn a_report_replaces_a_report_and_leaves_nothing_beside_it() {
        let root = scratch("replace");
        let dir = root.join("report");
        let mut files = Files::default();
        files.add(INDEX, format!("{GENERATOR}first").into_bytes());
        files.add("images/a.png", vec![1, 2, 3]);
        write_folder(&dir, &files).unwrap();
        files.add(INDEX, format!("{GENERATOR}second").into_bytes());
        write_folder(&dir, &files).unwrap();
        let index = fs::read_to_string(dir.join(INDEX)).unwrap();
        assert!(index.ends_with("second"));
        assert_eq!(fs::read(dir.join("images/a.png")).unwrap(), vec![1, 2, 3]);
        let beside: Vec<_> = fs::read_dir(&root).unwrap().collect();
        assert_eq!(beside.len(), 1, "only the report is left");
        fs::remove_dir_all(&root).unwrap();
    }

    #[test]
    fn another_folder_is_not_replaced() {
        let root = scratch("other");
        fs::write(root.join("notes.txt"), b"mine").unwrap();
        let mut files = Files::default();
        files.add(INDEX, GENERATOR.as_bytes().to_vec());
        let err = write_folder(&root, &files).unwrap_err();
        assert!(err.to_string().contains("not a Likeness report"), "{err}");
        assert_eq!(fs::read(root.join("notes.txt")).unwrap(), b"mine");
        fs::remove_dir_all(&root).unwrap();
    }
}
