//! The `folder_import` target's input: an interchange folder packed as
//! text, so that seeds are written from real folders and the fuzzer mutates
//! file names and contents alike.
//!
//! ```text
//! @@ template/neutral.obj
//! v 0 0 0
//! …
//! @@ expressions/weights.csv
//! prompt,eyeBlinkLeft,…
//! @@/ test/weights.csv
//! @@> frames.csv
//! neutral.obj
//! ```
//!
//! Each entry starts at a line `@@ NAME` (a file; its content runs up to
//! the next entry), `@@/ NAME` (a directory in place of a file) or
//! `@@> NAME` (a symbolic link to the path on the next line, another entry
//! of the folder). A name is one to three `/`-separated parts of at most
//! 64 bytes, none empty, `.` or `..`; an entry with another name is
//! dropped, so nothing is written outside the folder. At most
//! [`MAX_ENTRIES`] entries are unpacked.

use std::path::{Path, PathBuf};

/// Most entries unpacked from one input.
pub const MAX_ENTRIES: usize = 128;

/// What an entry puts in the folder.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A regular file with these bytes.
    File(Vec<u8>),
    /// A directory.
    Dir,
    /// A symbolic link to this relative path.
    Link(PathBuf),
}

/// One entry: its path inside the folder and what it is.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Entry {
    /// Relative path, checked by [`safe_name`].
    pub name: PathBuf,
    /// File, directory or link.
    pub kind: Kind,
}

/// The entries of a packed folder, in order (a later entry of the same name
/// replaces an earlier one when written).
pub fn unpack(bytes: &[u8]) -> Vec<Entry> {
    let mut entries = Vec::new();
    let mut starts = Vec::new();
    if bytes.starts_with(b"@@") {
        starts.push(0);
    }
    starts.extend(
        bytes
            .windows(3)
            .enumerate()
            .filter(|(_, w)| *w == b"\n@@")
            .map(|(i, _)| i + 1),
    );
    for (k, &start) in starts.iter().enumerate() {
        let end = starts.get(k + 1).copied().unwrap_or(bytes.len());
        if let Some(entry) = entry(&bytes[start..end]) {
            entries.push(entry);
        }
        if entries.len() == MAX_ENTRIES {
            break;
        }
    }
    entries
}

/// One entry from its text, `@@…` up to the next entry.
fn entry(text: &[u8]) -> Option<Entry> {
    let line_end = text.iter().position(|&b| b == b'\n').unwrap_or(text.len());
    let (head, body) = (&text[..line_end], &text[(line_end + 1).min(text.len())..]);
    let (marker, name) = match head.get(2) {
        Some(b' ') => (b' ', &head[3..]),
        Some(&m @ (b'/' | b'>')) if head.get(3) == Some(&b' ') => (m, &head[4..]),
        _ => return None,
    };
    let name = safe_name(name)?;
    let kind = match marker {
        b'/' => Kind::Dir,
        b'>' => {
            let target_end = body.iter().position(|&b| b == b'\n').unwrap_or(body.len());
            Kind::Link(safe_name(&body[..target_end])?)
        }
        _ => Kind::File(body.to_vec()),
    };
    Some(Entry { name, kind })
}

/// `name` as a relative path of one to three plain parts, or `None`.
pub fn safe_name(name: &[u8]) -> Option<PathBuf> {
    let name = std::str::from_utf8(name).ok()?;
    let parts: Vec<&str> = name.split('/').collect();
    let plain = |p: &&str| !p.is_empty() && p.len() <= 64 && *p != "." && *p != "..";
    if parts.len() > 3 || !parts.iter().all(plain) || name.contains('\0') {
        return None;
    }
    Some(PathBuf::from(name))
}

/// Writes `entries` into `dir`, which is emptied first. An entry that
/// cannot be written (its parent is a file, say) is left out: the folder is
/// then what it is, and the reader must cope with it.
pub fn write(dir: &Path, entries: &[Entry]) {
    let _ = std::fs::remove_dir_all(dir);
    std::fs::create_dir_all(dir).expect("folder to unpack into");
    for entry in entries {
        let path = dir.join(&entry.name);
        if let Some(parent) = path.parent() {
            let _ = std::fs::create_dir_all(parent);
        }
        let _ = match &entry.kind {
            Kind::File(bytes) => std::fs::write(&path, bytes),
            Kind::Dir => std::fs::create_dir_all(&path),
            Kind::Link(target) => std::os::unix::fs::symlink(dir.join(target), &path),
        };
    }
}

/// Packs the regular files under `dir` (seeds from a real folder).
pub fn pack(dir: &Path) -> Vec<u8> {
    let mut files = Vec::new();
    collect(dir, dir, &mut files);
    files.sort();
    let mut out = Vec::new();
    for (name, path) in files {
        out.extend_from_slice(format!("@@ {name}\n").as_bytes());
        out.extend_from_slice(&std::fs::read(path).expect("a file to pack"));
        if out.last() != Some(&b'\n') {
            out.push(b'\n');
        }
    }
    out
}

/// The files under `dir`, as (name relative to `root`, path).
fn collect(root: &Path, dir: &Path, files: &mut Vec<(String, PathBuf)>) {
    for entry in std::fs::read_dir(dir).expect("a folder to pack").flatten() {
        let path = entry.path();
        if path.is_dir() {
            collect(root, &path, files);
        } else {
            let name = path.strip_prefix(root).expect("under root");
            files.push((name.to_string_lossy().into_owned(), path));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn entries_are_unpacked_and_unsafe_names_dropped() {
        let text = b"@@ a/b.obj\nv 0 0 0\n@@ ../x\nno\n@@/ c\n@@> d\na/b.obj\n@@ /abs\n";
        let entries = unpack(text);
        assert_eq!(
            entries,
            vec![
                Entry {
                    name: "a/b.obj".into(),
                    kind: Kind::File(b"v 0 0 0\n".to_vec())
                },
                Entry {
                    name: "c".into(),
                    kind: Kind::Dir
                },
                Entry {
                    name: "d".into(),
                    kind: Kind::Link("a/b.obj".into())
                },
            ]
        );
    }
}
