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
//! [`SessionFileError::UnsupportedVersion`]), the lengths against the file's
//! size and the [limits], all from the first 32 bytes and the file's
//! size before reading further; then the checksum, and only then inflates
//! and decodes, field by field, checking every count against the limits
//! before allocating for it; the decoded parts become a session only
//! through [`Session::new`]'s checks.
//!
//! # Limits
//!
//! A file may hold at most ten minutes of capture ([`MAX_DURATION_SECONDS`],
//! [`MAX_FRAMES`] = 36,000 frames at 60 fps), meshes of at most
//! [`MAX_VERTICES`] = 16,384 vertices and [`MAX_DECODED_VERTICES`] (ten
//! minutes of 1,220-vertex frames and a thousand meshes more, 542 MB
//! decoded) in all, and a payload of at most [`MAX_PAYLOAD_BYTES`] = 256 MiB
//! ([`MAX_COMPRESSED_BYTES`] compressed). A two-minute capture is about
//! 7,200 frames, a 33 MB payload: the limits leave five times that. A
//! file beyond a limit is refused with [`SessionFileError::TooLarge`] naming
//! the field and the limit, before anything is allocated for it; reading a
//! file within them needs at most the compressed payload, the payload and
//! the decoded session at once. [`read`] opens regular files only (not a
//! directory, a FIFO or `/dev/zero`).

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
//! | reading and writing files, compression | `mod.rs` |
//! | the header, checked before the payload is read | `header.rs` |
//! | the limits and their reasons | [`limits`] |
//! | the bincode structure of the payload, decoded field by field | `wire.rs` |
//! | session → payload; payload → session, trusting nothing | `encode.rs`, `decode.rs` |
//! | meshes and weights as quantized, predicted varint blobs | `geometry_codec.rs`, `series.rs` |
//! | the vertex order in which neighbours predict each other | `traversal.rs` |
//! | what can go wrong, naming the field | `error.rs` |

mod decode;
mod encode;
mod error;
mod geometry_codec;
mod header;
pub mod limits;
mod series;
mod traversal;
mod wire;

pub use error::SessionFileError;
pub use geometry_codec::{MAX_Q, QUANTUM, dequantize, quantize};
pub use limits::{
    Limit, MAX_COMPRESSED_BYTES, MAX_DECODED_VERTICES, MAX_DURATION_SECONDS, MAX_FRAMES,
    MAX_PAYLOAD_BYTES, MAX_VERTICES,
};

use crate::geometry::topology::Topology;
use crate::io::atomic_write::write_atomically;
use crate::io::{FileError, open_bounded};
use crate::session::{Session, Template};
use header::Header;
use std::io::Read;
use std::path::Path;

/// The first eight bytes of every session file.
pub const MAGIC: [u8; 8] = *b"LIKENESS";

/// The format version this build writes and reads.
pub const FORMAT_VERSION: u32 = 1;

/// Bytes before the payload.
pub const HEADER_LEN: usize = 32;

/// Largest session file: the header and [`MAX_COMPRESSED_BYTES`].
pub const MAX_FILE_BYTES: u64 = (HEADER_LEN + MAX_COMPRESSED_BYTES) as u64;

/// DEFLATE level (irrelevant to Huffman-only coding but part of the flags).
const COMPRESSION_LEVEL: u8 = 6;

/// DEFLATE strategy: 2 = Huffman only, no match search (see the table above).
const COMPRESSION_STRATEGY: i32 = 2;

/// Serializes `session` to the bytes of a session file. A [`Session`] is
/// valid by construction, and one within the [limits] can be read
/// back; one beyond them is refused here.
pub fn encode(session: &Session) -> Result<Vec<u8>, SessionFileError> {
    limits::check_extent(encode::extent(session))
        .map_err(|limit| SessionFileError::too_large("session", limit))?;
    if let (Some(first), Some(last)) = (session.frames.first(), session.frames.last()) {
        limits::check_duration(first.timestamp, last.timestamp)
            .map_err(|limit| SessionFileError::too_large("frames", limit))?;
    }
    let payload = encode::encode_payload(session)?;
    if payload.len() > MAX_PAYLOAD_BYTES {
        let limit = (Limit::PayloadBytes, payload.len() as u64);
        return Err(SessionFileError::too_large("payload", limit));
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
    let header = header::parse(&bytes[..bytes.len().min(HEADER_LEN)], bytes.len() as u64)?;
    // Indexing: the header checked that exactly `compressed_len` bytes follow it.
    open_payload(&header, &bytes[HEADER_LEN..], |_, _| ())
}

/// The session in a compressed payload that `header` describes: checksum,
/// inflate, decode.
fn open_payload(
    header: &Header,
    compressed: &[u8],
    early: impl FnOnce(&Topology, &Template),
) -> Result<Session, SessionFileError> {
    header.check_crc(compressed)?;
    let payload = inflate(compressed, header.payload_len)?;
    decode::decode_payload(&payload, early)
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

/// Reads and decodes the session file at `path`. Only a regular file is
/// opened; its header is read and checked against the file's size and the
/// [limits] before the payload is read, and never more than the
/// header declares is read. I/O errors name the path; errors in the
/// contents are returned as [`decode()`] gives them.
pub fn read(path: impl AsRef<Path>) -> Result<Session, SessionFileError> {
    read_template_first(path, |_, _| ())
}

/// [`read`], calling `early` with the mask's topology and the template as
/// soon as they are decoded, before the stream, the captures and the
/// session's own checks: the avatar stage finds the face on the avatar
/// (which needs only those) on another thread while the rest is decoded.
/// `early` is not called where the file fails before its template; it may
/// be called for a file the session's checks then refuse.
pub fn read_template_first(
    path: impl AsRef<Path>,
    early: impl FnOnce(&Topology, &Template),
) -> Result<Session, SessionFileError> {
    let path = path.as_ref();
    let io = |e| SessionFileError::File(FileError::io(path, e));
    // No size limit here: a file too large is refused from its header, whose
    // first bytes may already say it is no session at all.
    let mut file = open_bounded(path, u64::MAX - 1, "a session file")?;
    let mut prefix = Vec::with_capacity(HEADER_LEN);
    (&mut file.reader)
        .take(HEADER_LEN as u64)
        .read_to_end(&mut prefix)
        .map_err(io)?;
    let header = header::parse(&prefix, file.size)?;
    // The header matched the file's size, within MAX_COMPRESSED_BYTES.
    let mut compressed = Vec::with_capacity(header.compressed_len);
    (&mut file.reader)
        .take(header.compressed_len as u64 + 1)
        .read_to_end(&mut compressed)
        .map_err(io)?;
    if compressed.len() != header.compressed_len {
        let reason = format!(
            "the file changed while it was read: {} payload bytes, the header says {}",
            compressed.len(),
            header.compressed_len
        );
        return Err(SessionFileError::corrupt("file", reason));
    }
    open_payload(&header, &compressed, early)
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

/// Inflates `compressed`, which must give exactly `expected` bytes.
fn inflate(compressed: &[u8], expected: usize) -> Result<Vec<u8>, SessionFileError> {
    use miniz_oxide::inflate::TINFLStatus;
    let payload = miniz_oxide::inflate::decompress_to_vec_with_limit(compressed, expected)
        .map_err(|e| {
            let reason = match e.status {
                TINFLStatus::HasMoreOutput => {
                    format!("inflates to more than the declared {expected} bytes")
                }
                TINFLStatus::FailedCannotMakeProgress | TINFLStatus::NeedsMoreInput => {
                    "the compressed payload ends before its last block".to_string()
                }
                _ => "the compressed payload is damaged (not a valid DEFLATE stream)".to_string(),
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
