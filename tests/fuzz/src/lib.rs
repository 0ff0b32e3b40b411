//! What the fuzz targets share: a scratch folder in memory, the session
//! file's header built around fuzzed bytes, the folder container the
//! `folder_import` target unpacks, the invariants checked on what a reader
//! accepts, and the tiny session and avatar the seeds are made of.
//!
//! Every target asserts only that a reader does not panic, hang or take
//! unbounded memory (libFuzzer's limits), plus the cheap invariants here:
//! what is read can be written and read back, and an error's message is
//! short.

pub mod capture_driver;
pub mod folder;
pub mod tiny;

use likeness::Session;
use likeness::session::file::{self, FORMAT_VERSION, MAGIC};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// The longest error message a reader may give: a path, a line, a field
/// and an excerpt of at most 40 characters of the bad cell. A message
/// past this echoes the input.
pub const MAX_MESSAGE_BYTES: usize = 1024;

/// A folder of this process's own (`/dev/shm` when there is one, so files
/// stay in memory), emptied by the scripts after a run.
pub fn scratch() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let shm = Path::new("/dev/shm");
        let base = if shm.is_dir() {
            shm.to_path_buf()
        } else {
            std::env::temp_dir()
        };
        let dir = base.join(format!("likeness-fuzz-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("scratch folder");
        dir
    })
}

/// Writes `bytes` to `name` in the scratch folder and returns its path.
pub fn scratch_file(name: &str, bytes: &[u8]) -> PathBuf {
    let path = scratch().join(name);
    if std::fs::write(&path, bytes).is_err() {
        // The folder was removed under us: make it again.
        std::fs::create_dir_all(scratch()).expect("scratch folder");
        std::fs::write(&path, bytes).expect("scratch file");
    }
    path
}

/// Checks that an error's message is short, and returns it.
pub fn check_message(error: &dyn std::error::Error) -> String {
    let message = error.to_string();
    assert!(
        message.len() <= MAX_MESSAGE_BYTES + scratch().as_os_str().len(),
        "an error message of {} bytes: {}…",
        message.len(),
        message.chars().take(200).collect::<String>()
    );
    message
}

/// The bytes of a session file holding `compressed` as its payload, which
/// declares `payload_len` bytes once inflated; the lengths and the CRC-32
/// are correct (the layout of `rust-core/src/session/file/mod.rs`).
pub fn seal_compressed(compressed: &[u8], payload_len: u64) -> Vec<u8> {
    let mut out = Vec::with_capacity(file::HEADER_LEN + compressed.len());
    out.extend_from_slice(&MAGIC);
    out.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    out.extend_from_slice(&(compressed.len() as u64).to_le_bytes());
    out.extend_from_slice(&payload_len.to_le_bytes());
    let mut crc = crc32fast::Hasher::new();
    crc.update(&out);
    crc.update(compressed);
    out.extend_from_slice(&crc.finalize().to_le_bytes());
    out.extend_from_slice(compressed);
    out
}

/// The bytes of a session file whose uncompressed payload is `payload`,
/// compressed as raw DEFLATE the way the writer does.
pub fn seal_payload(payload: &[u8]) -> Vec<u8> {
    let compressed = miniz_oxide::deflate::compress_to_vec(payload, 1);
    seal_compressed(&compressed, payload.len() as u64)
}

/// The uncompressed payload of a session file's bytes (for seeds).
pub fn payload_of(bytes: &[u8]) -> Vec<u8> {
    miniz_oxide::inflate::decompress_to_vec(&bytes[file::HEADER_LEN..]).expect("a valid file")
}

/// Decodes a session file's bytes; what decodes must encode and decode to
/// the same session again.
pub fn check_session_bytes(bytes: &[u8]) {
    match file::decode(bytes) {
        Ok(session) => check_round_trip(&session),
        Err(e) => {
            check_message(&e);
        }
    }
}

/// A decoded session encodes, and decodes to itself (positions and weights
/// are already quantized, so nothing is lost).
pub fn check_round_trip(session: &Session) {
    let bytes = file::encode(session).expect("a session that was read can be written");
    let again = file::decode(&bytes).expect("a session that was written can be read");
    assert!(
        &again == session,
        "a decoded session encodes to a different one"
    );
}

/// A session made by a reader other than the file's (a folder import)
/// can be written and read back.
pub fn check_writable(session: &Session) {
    let bytes = file::encode(session).expect("an imported session can be written");
    file::decode(&bytes).expect("a session that was written can be read");
}

/// `frames.csv` from `bytes`: what `read_frames` accepts is a stream a
/// session takes (finite times never going back, at most ten minutes,
/// finite weights).
pub fn check_frames_csv(bytes: &[u8]) {
    use likeness::session::file::MAX_DURATION_SECONDS;
    use likeness::session::interchange::read_frames;
    let path = scratch_file("frames.csv", bytes);
    let frames = match read_frames(&path) {
        Ok(frames) => frames,
        Err(e) => {
            check_message(&e);
            return;
        }
    };
    let first = frames.first().map_or(0.0, |f| f.timestamp);
    let mut previous = first;
    for (k, frame) in frames.iter().enumerate() {
        let t = frame.timestamp;
        assert!(t.is_finite() && t >= previous, "frame {k}: time {t}");
        assert!(t - first <= MAX_DURATION_SECONDS, "frame {k}: time {t}");
        assert!(frame.weights.0.iter().all(|w| w.is_finite()), "frame {k}");
        previous = t;
    }
}
