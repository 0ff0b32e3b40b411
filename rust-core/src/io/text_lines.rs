//! A text file line by line, holding one line at a time: the file size and
//! the line length capped, each line checked to be UTF-8, every error naming
//! the file and the line.
//!
//! Lines end at `\n`; a `\r` before it is dropped, and so is a UTF-8
//! byte-order mark at the start of the first line.

use super::bounded_read::open_bounded;
use super::file_error::FileError;
use std::fs::File;
use std::io::{BufRead, BufReader, Read, Take};
use std::path::{Path, PathBuf};

/// How much text a reader accepts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TextLimits {
    /// Largest file, in bytes.
    pub max_bytes: u64,
    /// Longest line, in bytes, without its line end.
    pub max_line: usize,
    /// What kind of file, for messages (`an OBJ file`).
    pub what: &'static str,
}

/// The lines of one text, read on demand with [`TextLines::next_line`].
#[derive(Debug)]
pub struct TextLines<R> {
    reader: R,
    path: PathBuf,
    limits: TextLimits,
    line: usize,
    consumed: u64,
    buf: Vec<u8>,
}

/// Opens the regular file at `path` (see [`open_bounded`]) to read it line
/// by line within `limits`.
pub fn open_text(
    path: &Path,
    limits: TextLimits,
) -> Result<TextLines<BufReader<Take<File>>>, FileError> {
    let file = open_bounded(path, limits.max_bytes, limits.what)?;
    Ok(TextLines::new(BufReader::new(file.reader), path, limits))
}

impl<R: BufRead> TextLines<R> {
    /// Lines of `reader`; `path` names the text in errors.
    pub fn new(reader: R, path: &Path, limits: TextLimits) -> Self {
        TextLines {
            reader,
            path: path.to_path_buf(),
            limits,
            line: 0,
            consumed: 0,
            buf: Vec::new(),
        }
    }

    /// The file these lines come from.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The next line, with its 1-based number and without its line end;
    /// `None` at the end of the text.
    pub fn next_line(&mut self) -> Result<Option<(usize, &str)>, FileError> {
        self.buf.clear();
        // A line of `max_line` bytes and its `\r\n` fit in `max_line + 2`.
        let cap = self.limits.max_line as u64 + 2;
        let n = (&mut self.reader)
            .take(cap)
            .read_until(b'\n', &mut self.buf)
            .map_err(|e| FileError::io(&self.path, e))?;
        if n == 0 {
            return Ok(None);
        }
        self.line += 1;
        self.consumed += n as u64;
        if self.consumed > self.limits.max_bytes {
            return Err(FileError::TooLarge {
                path: self.path.clone(),
                size: self.consumed,
                limit: self.limits.max_bytes,
                what: self.limits.what,
            });
        }
        let mut content = self.buf.as_slice();
        content = content.strip_suffix(b"\n").unwrap_or(content);
        content = content.strip_suffix(b"\r").unwrap_or(content);
        if self.line == 1 {
            content = content.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(content);
        }
        if content.len() > self.limits.max_line {
            return Err(FileError::LineTooLong {
                path: self.path.clone(),
                line: self.line,
                limit: self.limits.max_line,
            });
        }
        match std::str::from_utf8(content) {
            Ok(text) => Ok(Some((self.line, text))),
            Err(_) => Err(FileError::NotText {
                path: self.path.clone(),
                line: self.line,
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const LIMITS: TextLimits = TextLimits {
        max_bytes: 64,
        max_line: 8,
        what: "a test file",
    };

    fn lines(text: &[u8], limits: TextLimits) -> Result<Vec<(usize, String)>, FileError> {
        let mut reader = TextLines::new(text, Path::new("t.txt"), limits);
        let mut out = Vec::new();
        while let Some((n, line)) = reader.next_line()? {
            out.push((n, line.to_string()));
        }
        Ok(out)
    }

    #[test]
    fn splits_lines_dropping_crlf_and_the_byte_order_mark() {
        let got = lines(b"\xEF\xBB\xBFab\r\n\r\n12345678\nlast", LIMITS).unwrap();
        let want = [(1, "ab"), (2, ""), (3, "12345678"), (4, "last")];
        assert_eq!(got, want.map(|(n, s)| (n, s.to_string())));
    }

    #[test]
    fn long_lines_big_texts_and_bad_bytes_are_named_by_line() {
        let err = lines(b"ok\n123456789\n", LIMITS).unwrap_err();
        assert!(
            matches!(
                err,
                FileError::LineTooLong {
                    line: 2,
                    limit: 8,
                    ..
                }
            ),
            "{err}"
        );
        assert_eq!(
            err.to_string(),
            "t.txt:2: line longer than the limit of 8 bytes"
        );
        let err = lines(&[b'\0'; 10_000], LIMITS).unwrap_err();
        assert!(
            matches!(err, FileError::LineTooLong { line: 1, .. }),
            "{err}"
        );
        let err = lines(&b"1234567\n".repeat(9), LIMITS).unwrap_err();
        assert!(matches!(err, FileError::TooLarge { size: 72, .. }), "{err}");
        let err = lines(b"ok\n\xFF\xFE\n", LIMITS).unwrap_err();
        assert!(matches!(err, FileError::NotText { line: 2, .. }), "{err}");
    }
}
