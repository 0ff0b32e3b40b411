//! Opening a file to read at most a known number of bytes: regular files
//! only, the size checked before the first byte is read, and reads capped
//! even when the size the system reports is wrong.
//!
//! A directory, a FIFO (which would block until someone writes to it), a
//! device such as `/dev/zero` (endless) or a socket is refused from its
//! metadata before it is opened, and once more from the opened file's own
//! metadata (the path may have been replaced in between). On Unix the file
//! is opened with `O_NONBLOCK`, so that even a FIFO swapped in between the
//! two checks cannot block the open; the flag changes nothing for a
//! regular file, whose reads never block (POSIX `open(2)`). Every reader
//! returned is a [`Read::take`] of one byte over the limit, so a file that
//! grows, or lies about its size, still cannot be read past the limit.

use super::file_error::FileError;
use std::fs::{File, Metadata};
use std::io::{Read, Take};
use std::path::Path;

/// An opened regular file, read through a cap.
#[derive(Debug)]
pub struct BoundedFile {
    /// The file, capped at `limit + 1` bytes.
    pub reader: Take<File>,
    /// Its size when opened.
    pub size: u64,
}

/// What `metadata` describes, if it is not a regular file.
fn irregular_kind(metadata: &Metadata) -> Option<&'static str> {
    let kind = metadata.file_type();
    if kind.is_file() {
        return None;
    }
    if kind.is_dir() {
        return Some("a directory");
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if kind.is_fifo() {
            return Some("a FIFO");
        }
        if kind.is_char_device() || kind.is_block_device() {
            return Some("a device");
        }
        if kind.is_socket() {
            return Some("a socket");
        }
    }
    Some("something else")
}

fn check_regular(path: &Path, metadata: &Metadata) -> Result<(), FileError> {
    match irregular_kind(metadata) {
        Some(kind) => Err(FileError::NotAFile {
            path: path.to_path_buf(),
            kind,
        }),
        None => Ok(()),
    }
}

/// Opens `path` for reading without blocking (`O_NONBLOCK` on Unix), and
/// refuses it unless the opened file is a regular one; returns the file
/// and its metadata.
fn open_regular(path: &Path) -> Result<(File, Metadata), FileError> {
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        options.custom_flags(libc::O_NONBLOCK);
    }
    let file = options.open(path).map_err(|e| FileError::io(path, e))?;
    let metadata = file.metadata().map_err(|e| FileError::io(path, e))?;
    check_regular(path, &metadata)?;
    Ok((file, metadata))
}

/// Opens the regular file at `path` if it holds at most `limit` bytes
/// (`what` names the kind of file in the error).
pub fn open_bounded(path: &Path, limit: u64, what: &'static str) -> Result<BoundedFile, FileError> {
    let too_large = |size: u64| FileError::TooLarge {
        path: path.to_path_buf(),
        size,
        limit,
        what,
    };
    let metadata = std::fs::metadata(path).map_err(|e| FileError::io(path, e))?;
    check_regular(path, &metadata)?;
    if metadata.len() > limit {
        return Err(too_large(metadata.len()));
    }
    let (file, metadata) = open_regular(path)?;
    if metadata.len() > limit {
        return Err(too_large(metadata.len()));
    }
    Ok(BoundedFile {
        reader: file.take(limit.saturating_add(1)),
        size: metadata.len(),
    })
}

/// The bytes of the regular file at `path`, if it holds at most `limit`.
pub fn read_bounded(path: &Path, limit: u64, what: &'static str) -> Result<Vec<u8>, FileError> {
    let mut file = open_bounded(path, limit, what)?;
    // The size was checked against the limit: the capacity is bounded.
    let mut bytes = Vec::with_capacity(file.size as usize);
    file.reader
        .read_to_end(&mut bytes)
        .map_err(|e| FileError::io(path, e))?;
    if bytes.len() as u64 > limit {
        return Err(FileError::TooLarge {
            path: path.to_path_buf(),
            size: bytes.len() as u64,
            limit,
            what,
        });
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("likeness-bounded-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    #[test]
    fn reads_a_file_within_the_limit_and_refuses_one_past_it() {
        let path = scratch("ten.txt");
        std::fs::write(&path, b"0123456789").unwrap();
        assert_eq!(read_bounded(&path, 10, "a test file").unwrap().len(), 10);
        let err = read_bounded(&path, 9, "a test file").unwrap_err();
        assert!(
            matches!(
                err,
                FileError::TooLarge {
                    size: 10,
                    limit: 9,
                    ..
                }
            ),
            "{err}"
        );
        assert!(err.to_string().ends_with("for a test file"), "{err}");
    }

    #[test]
    fn refuses_what_is_not_a_regular_file() {
        let dir = scratch("a-folder");
        std::fs::create_dir_all(&dir).unwrap();
        let err = read_bounded(&dir, 10, "a test file").unwrap_err();
        assert!(
            matches!(
                err,
                FileError::NotAFile {
                    kind: "a directory",
                    ..
                }
            ),
            "{err}"
        );
        let missing = scratch("missing.txt");
        assert!(matches!(
            read_bounded(&missing, 10, "a test file"),
            Err(FileError::Missing { .. })
        ));
        #[cfg(unix)]
        {
            // A FIFO that passed the check on the path (it was swapped in
            // after it) is refused by the open itself, without blocking
            // for a writer that never comes.
            let fifo = scratch("swapped-fifo");
            let _ = std::fs::remove_file(&fifo);
            let made = std::process::Command::new("mkfifo").arg(&fifo).status();
            assert!(made.is_ok_and(|s| s.success()), "mkfifo");
            let (sender, receiver) = std::sync::mpsc::channel();
            let path = fifo.clone();
            std::thread::spawn(move || sender.send(open_regular(&path).map(|_| ())));
            let err = receiver
                .recv_timeout(std::time::Duration::from_secs(10))
                .expect("opening a FIFO blocked")
                .unwrap_err();
            assert!(
                matches!(err, FileError::NotAFile { kind: "a FIFO", .. }),
                "{err}"
            );
            let _ = std::fs::remove_file(&fifo);
            let err = read_bounded(Path::new("/dev/zero"), 10, "a test file").unwrap_err();
            assert!(
                matches!(
                    err,
                    FileError::NotAFile {
                        kind: "a device",
                        ..
                    }
                ),
                "{err}"
            );
        }
    }
}
