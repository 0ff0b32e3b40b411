//! The 32-byte header, checked from the first bytes of a file and its size
//! alone, before the payload is read: magic, version, the two lengths
//! against the file size and the [limits](super::limits).

use super::error::SessionFileError;
use super::limits::Limit;
use super::{FORMAT_VERSION, HEADER_LEN, MAGIC};

/// DEFLATE can expand at most 1032:1 (a 258-byte match in two bits).
const MAX_INFLATE_RATIO: u64 = 1032;

/// What a header declares, once checked.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Header {
    /// Bytes 0..28, covered by the checksum together with the payload.
    pub checked: [u8; 28],
    /// Length of the compressed payload (the rest of the file).
    pub compressed_len: usize,
    /// Length of the payload once inflated.
    pub payload_len: usize,
    /// The CRC-32 stored in bytes 28..32.
    pub crc: u32,
}

/// Checks the header of a file of `file_len` bytes whose first
/// `min(HEADER_LEN, file_len)` bytes are `prefix`.
pub(super) fn parse(prefix: &[u8], file_len: u64) -> Result<Header, SessionFileError> {
    // Indexing: every slice of `prefix` is taken only after the length
    // check before it (8, 12, then HEADER_LEN bytes).
    let truncated = || SessionFileError::Truncated {
        what: "header",
        expected: HEADER_LEN as u64,
        found: file_len,
    };
    if prefix.len() < MAGIC.len() {
        return Err(if MAGIC.starts_with(prefix) && !prefix.is_empty() {
            truncated()
        } else {
            SessionFileError::NotASessionFile
        });
    }
    if prefix[..MAGIC.len()] != MAGIC {
        return Err(SessionFileError::NotASessionFile);
    }
    if prefix.len() < 12 {
        return Err(truncated());
    }
    let version = u32::from_le_bytes(array(&prefix[8..12]));
    if version != FORMAT_VERSION {
        return Err(SessionFileError::UnsupportedVersion(version));
    }
    if prefix.len() < HEADER_LEN {
        return Err(truncated());
    }
    let compressed_len = u64::from_le_bytes(array(&prefix[12..20]));
    let payload_len = u64::from_le_bytes(array(&prefix[20..28]));
    let present = file_len.saturating_sub(HEADER_LEN as u64);
    if compressed_len > present {
        return Err(SessionFileError::Truncated {
            what: "payload",
            expected: compressed_len,
            found: present,
        });
    }
    if compressed_len < present {
        let reason = format!(
            "{} bytes after the end of the payload",
            present - compressed_len
        );
        return Err(SessionFileError::corrupt("file", reason));
    }
    if compressed_len > Limit::CompressedBytes.max() {
        let limit = (Limit::CompressedBytes, compressed_len);
        return Err(SessionFileError::too_large("header.compressed_len", limit));
    }
    if payload_len > Limit::PayloadBytes.max() {
        let limit = (Limit::PayloadBytes, payload_len);
        return Err(SessionFileError::too_large("header.payload_len", limit));
    }
    if payload_len > compressed_len.saturating_mul(MAX_INFLATE_RATIO) {
        let reason = format!("{compressed_len} compressed bytes cannot inflate to {payload_len}");
        return Err(SessionFileError::corrupt("header", reason));
    }
    // Both lengths are now within limits far below `usize::MAX`.
    Ok(Header {
        checked: array(&prefix[..28]),
        compressed_len: compressed_len as usize,
        payload_len: payload_len as usize,
        crc: u32::from_le_bytes(array(&prefix[28..32])),
    })
}

impl Header {
    /// Checks `compressed` against the stored CRC-32.
    pub(super) fn check_crc(&self, compressed: &[u8]) -> Result<(), SessionFileError> {
        let mut crc = crc32fast::Hasher::new();
        crc.update(&self.checked);
        crc.update(compressed);
        let found = crc.finalize();
        if found != self.crc {
            return Err(SessionFileError::Checksum {
                expected: self.crc,
                found,
            });
        }
        Ok(())
    }
}

/// Copies a slice whose length the caller has checked into an array.
fn array<const N: usize>(slice: &[u8]) -> [u8; N] {
    let mut a = [0u8; N];
    a.copy_from_slice(slice);
    a
}
