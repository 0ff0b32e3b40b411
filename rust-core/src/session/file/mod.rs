//! The session file: one capture [`Session`] on disk.
//!
//! # Layout
//!
//! | offset | size | content |
//! |-------:|-----:|---------|
//! | 0      | 8    | [`MAGIC`], `b"LIKENESS"` |
//! | 8      | 4    | format version, u32 little-endian ([`FORMAT_VERSION`]) |
//! | 12     | 8    | compressed payload length, u64 LE |
//! | 20     | 8    | uncompressed payload length, u64 LE |
//! | 28     | 4    | CRC-32 (IEEE) of bytes 0..28 followed by the compressed payload |
//! | 32     | ...  | the payload, raw DEFLATE (RFC 1951) |
//!
//! The uncompressed payload is `WireSession` (`session_file/wire.rs`)
//! serialized with bincode 2 (standard configuration): every field of
//! [`Session`], with meshes and weights as varint blobs written by
//! `session/file/geometry_codec.rs`. A reader checks the
//! magic, then the version (a file of another version is
//! [`SessionFileError::UnsupportedVersion`]), the lengths, the checksum, and
//! only then inflates and decodes; the decoded parts become a session only
//! through [`Session::new`]'s checks.
//!
//! # Precision
//!
//! Positions are stored in units of 10 µm and weights in units of 1e-5
//! ([`QUANTUM`], [`quantize`], [`dequantize`]): a decoded value is within **±5 µm** (±5e-6 for a
//! weight) of the value written, plus the f32 rounding of the decoded value
//! (under 0.06 µm for |x| < 1 m). The decoded f32 is exactly
//! `(q as f64 * 1e-5) as f32`, so a decoded session encodes to the same
//! bytes again. Positions beyond ±100 m and weights beyond ±100 cannot be
//! stored ([`SessionFileError::OutOfRange`]). Timestamps, the frame rate,
//! strings and indices are stored exactly.
//!
//! # Size and compressor
//!
//! Measured on two 1,220-vertex sessions with a mesh in every frame, on the
//! 2-core development machine, pure-Rust compressors only (this crate ships
//! on iOS): the synthetic session of `benches/session_file.rs` (2 minutes at
//! 60 fps, 7,200 frames; smooth motion, noise smooth in time but independent
//! per vertex; 27.6 MB uncompressed payload) and the simulator's session for
//! seed 1 (`likeness-sim`, 8,461 frames; tracking noise smooth over the face
//! but a random walk in time; 32.8 MB payload). Times are for the simulator
//! session.
//!
//! | compressor | synthetic | simulator | compress | decompress |
//! |------------|----------:|----------:|---------:|-----------:|
//! | `miniz_oxide` DEFLATE, Huffman only (**chosen**) | 6.65 MB | **7.79 MB** | 0.34 s | 0.13 s |
//! | `miniz_oxide` DEFLATE level 1 | 8.81 MB | 11.05 MB | 0.38 s | 0.31 s |
//! | `miniz_oxide` DEFLATE level 6 | 6.19 MB | 9.03 MB | 5.2 s | 0.13 s |
//! | `miniz_oxide` DEFLATE level 9 | 5.83 MB | 8.72 MB | 16.8 s | 0.07 s |
//! | `miniz_oxide` DEFLATE, run-length only | 6.98 MB | 8.33 MB | 0.43 s | 0.13 s |
//! | `ruzstd` 0.9 (only its "fastest" level exists) | 12.09 MB | 14.96 MB | 0.40 s | 0.17 s |
//! | `lz4_flex` 0.11 | 13.91 MB | 17.50 MB | 0.08 s | 0.04 s |
//! | `brotli` 8, quality 5 | 6.15 MB | 8.94 MB | 2.0 s | 0.14 s |
//! | `brotli` 8, quality 9 | 5.81 MB | 8.75 MB | 16.7 s | 0.11 s |
//! | `brotli` 8, quality 11 | 4.90 MB | — | 100 s (synthetic) | 0.09 s |
//!
//! After prediction the residuals are nearly memoryless noise over a few
//! symbols, so what matters is the entropy coder, not match finding: on noisy
//! data LZ matches cost more than the literals they replace, and Huffman-only
//! DEFLATE comes within 5% of the residuals' zeroth-order entropy, an order
//! of magnitude faster than any setting that searches for matches. Matches
//! help only where long runs of zeros occur (the synthetic session, 7%);
//! brotli's context modelling beats DEFLATE clearly only at quality 11, far
//! too slow to run on a phone after every session. Before spatial prediction
//! (`series.rs`) the simulator session took 17.6 MB.
//!
//! # Files
//!
//! | what | file |
//! |---|---|
//! | header, checksum, compression, the limits | `mod.rs` |
//! | the bincode structure of the payload | `wire.rs` |
//! | session → payload; payload → session, trusting nothing | `encode.rs`, `decode.rs` |
//! | meshes and weights as quantized, predicted varint blobs | `geometry_codec.rs`, `series.rs` |
//! | the vertex order in which neighbours predict each other | `traversal.rs` |
//! | what can go wrong, naming the field | `error.rs` |

mod decode;
mod encode;
mod error;
mod geometry_codec;
mod series;
mod traversal;
mod wire;

pub use error::SessionFileError;
pub use geometry_codec::{MAX_Q, QUANTUM, dequantize, quantize};

use crate::io::atomic_write::write_atomically;
use crate::session::Session;
use std::path::Path;

/// The first eight bytes of every session file.
pub const MAGIC: [u8; 8] = *b"LIKENESS";

/// The format version this build writes and reads.
pub const FORMAT_VERSION: u32 = 1;

/// Bytes before the payload.
pub const HEADER_LEN: usize = 32;

/// Largest number of frames a file may hold (4.6 hours at 60 fps).
pub const MAX_FRAMES: usize = 1_000_000;

/// Largest uncompressed payload a file may declare (512 MiB, about half an
/// hour of 60 fps geometry). Decoding never allocates more than a small
/// multiple of this.
pub const MAX_PAYLOAD_BYTES: usize = 1 << 29;

/// DEFLATE level (irrelevant to Huffman-only coding but part of the flags).
const COMPRESSION_LEVEL: u8 = 6;

/// DEFLATE strategy: 2 = Huffman only, no match search (see the table above).
const COMPRESSION_STRATEGY: i32 = 2;

/// DEFLATE can expand at most 1032:1 (a 258-byte match in two bits).
const MAX_INFLATE_RATIO: u64 = 1032;

/// Serializes `session` to the bytes of a session file. A [`Session`] is
/// valid by construction, so every file written can be read back.
pub fn encode(session: &Session) -> Result<Vec<u8>, SessionFileError> {
    let payload = encode::encode_payload(session)?;
    if payload.len() > MAX_PAYLOAD_BYTES {
        return Err(SessionFileError::TooLarge {
            what: "uncompressed payload".to_string(),
            value: payload.len() as u64,
            limit: MAX_PAYLOAD_BYTES as u64,
        });
    }
    seal(&payload)
}

/// Compresses a payload and puts the header in front of it.
fn seal(payload: &[u8]) -> Result<Vec<u8>, SessionFileError> {
    let compressed = deflate(payload)?;
    let mut out = Vec::with_capacity(HEADER_LEN + compressed.len());
    out.extend_from_slice(&MAGIC);
    out.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    out.extend_from_slice(&(compressed.len() as u64).to_le_bytes());
    out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    let mut crc = crc32fast::Hasher::new();
    crc.update(&out);
    crc.update(&compressed);
    out.extend_from_slice(&crc.finalize().to_le_bytes());
    out.extend_from_slice(&compressed);
    Ok(out)
}

/// Reads a session from the bytes of a session file. Never panics and never
/// trusts a length it has not checked; the session returned is valid.
pub fn decode(bytes: &[u8]) -> Result<Session, SessionFileError> {
    // Indexing: every header slice is taken only after the length check
    // before it (8, 12, then HEADER_LEN bytes).
    let header = |expected: usize| SessionFileError::Truncated {
        what: "header",
        expected: expected as u64,
        found: bytes.len() as u64,
    };
    if bytes.len() < MAGIC.len() {
        return Err(if MAGIC.starts_with(bytes) && !bytes.is_empty() {
            header(HEADER_LEN)
        } else {
            SessionFileError::NotASessionFile
        });
    }
    if bytes[..MAGIC.len()] != MAGIC {
        return Err(SessionFileError::NotASessionFile);
    }
    if bytes.len() < 12 {
        return Err(header(HEADER_LEN));
    }
    let version = u32::from_le_bytes(array(&bytes[8..12]));
    if version != FORMAT_VERSION {
        return Err(SessionFileError::UnsupportedVersion(version));
    }
    if bytes.len() < HEADER_LEN {
        return Err(header(HEADER_LEN));
    }
    let compressed_len = u64::from_le_bytes(array(&bytes[12..20]));
    let payload_len = u64::from_le_bytes(array(&bytes[20..28]));
    let stored_crc = u32::from_le_bytes(array(&bytes[28..32]));
    let present = (bytes.len() - HEADER_LEN) as u64;
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
    let compressed = &bytes[HEADER_LEN..];
    let mut crc = crc32fast::Hasher::new();
    crc.update(&bytes[..28]);
    crc.update(compressed);
    let found = crc.finalize();
    if found != stored_crc {
        return Err(SessionFileError::Checksum {
            expected: stored_crc,
            found,
        });
    }
    if payload_len > MAX_PAYLOAD_BYTES as u64 {
        return Err(SessionFileError::TooLarge {
            what: "uncompressed payload".to_string(),
            value: payload_len,
            limit: MAX_PAYLOAD_BYTES as u64,
        });
    }
    if payload_len > compressed_len.saturating_mul(MAX_INFLATE_RATIO) {
        let reason = format!("{compressed_len} compressed bytes cannot inflate to {payload_len}");
        return Err(SessionFileError::corrupt("header", reason));
    }
    let payload = inflate(compressed, payload_len as usize)?;
    decode::decode_payload(&payload)
}

/// Encodes `session` and writes it to `path` atomically: a crash leaves
/// either the old file or the new one.
pub fn write(path: impl AsRef<Path>, session: &Session) -> Result<(), SessionFileError> {
    let path = path.as_ref();
    let bytes = encode(session)?;
    write_atomically(path, &bytes).map_err(|source| SessionFileError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// Reads and decodes the session file at `path`. I/O errors name the path;
/// errors in the contents are returned as [`decode()`] gives them.
pub fn read(path: impl AsRef<Path>) -> Result<Session, SessionFileError> {
    let path = path.as_ref();
    let bytes = std::fs::read(path).map_err(|source| SessionFileError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    decode(&bytes)
}

/// Copies a slice whose length the caller has checked into an array.
fn array<const N: usize>(slice: &[u8]) -> [u8; N] {
    let mut a = [0u8; N];
    a.copy_from_slice(slice);
    a
}

fn deflate(data: &[u8]) -> Result<Vec<u8>, SessionFileError> {
    use miniz_oxide::deflate::core::{
        CompressorOxide, TDEFLFlush, TDEFLStatus, compress, create_comp_flags_from_zip_params,
    };
    // Negative window bits: raw DEFLATE, no zlib wrapper (the header has a CRC).
    let flags =
        create_comp_flags_from_zip_params(COMPRESSION_LEVEL.into(), -15, COMPRESSION_STRATEGY);
    let mut compressor = CompressorOxide::new(flags);
    let mut out = vec![0u8; data.len() / 4 + 1024];
    // Slicing: `written` never passes `out.len()` (the compressor writes at
    // most the space it is given), and `consumed` is clamped to the input.
    let (mut input, mut written) = (data, 0);
    loop {
        let (status, consumed, produced) = compress(
            &mut compressor,
            input,
            &mut out[written..],
            TDEFLFlush::Finish,
        );
        written += produced;
        input = &input[consumed.min(input.len())..];
        match status {
            TDEFLStatus::Done => {
                out.truncate(written);
                return Ok(out);
            }
            TDEFLStatus::Okay => {
                if out.len() - written < 1024 {
                    out.resize(out.len() * 2, 0);
                }
            }
            other => {
                return Err(SessionFileError::Encode(format!(
                    "DEFLATE failed: {other:?}"
                )));
            }
        }
    }
}

fn inflate(compressed: &[u8], expected: usize) -> Result<Vec<u8>, SessionFileError> {
    let payload = miniz_oxide::inflate::decompress_to_vec_with_limit(compressed, expected)
        .map_err(|e| {
            let reason = match e.status {
                miniz_oxide::inflate::TINFLStatus::HasMoreOutput => {
                    format!("inflates to more than the declared {expected} bytes")
                }
                status => format!("invalid DEFLATE stream ({status:?})"),
            };
            SessionFileError::corrupt("payload", reason)
        })?;
    if payload.len() != expected {
        let reason = format!(
            "inflates to {} bytes, not the declared {expected}",
            payload.len()
        );
        return Err(SessionFileError::corrupt("payload", reason));
    }
    Ok(payload)
}

#[cfg(test)]
mod tests;
