//! Hostile files are refused with bounded memory: a decompression bomb, huge
//! sparse files, headers that lie about their lengths, a FIFO, `/dev/zero`
//! and a directory, for the session file, the OBJ + CSV folder and GLB
//! import. Peak memory is measured with a counting allocator wrapping the
//! system's; the tests of this binary run one at a time so that the peak
//! belongs to one of them.

use likeness::avatar::glb::read_avatar;
use likeness::io::FileError;
use likeness::session::file::{self as session_file, HEADER_LEN, Limit, MAGIC, SessionFileError};
use likeness::session::interchange::{InterchangeError, export_folder, import_folder};
use std::alloc::{GlobalAlloc, Layout, System};
use std::fs::{self, File};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

/// The system allocator, counting the bytes currently allocated and the
/// peak since the last [`measure`].
struct Counting;

static CURRENT: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

fn grew(by: usize) {
    let now = CURRENT.fetch_add(by, Ordering::SeqCst) + by;
    PEAK.fetch_max(now, Ordering::SeqCst);
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            grew(layout.size());
        }
        p
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc_zeroed(layout) };
        if !p.is_null() {
            grew(layout.size());
        }
        p
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) };
        CURRENT.fetch_sub(layout.size(), Ordering::SeqCst);
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if !p.is_null() {
            CURRENT.fetch_sub(layout.size(), Ordering::SeqCst);
            grew(new_size);
        }
        p
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// One test at a time, so that a peak is one test's.
static SERIAL: Mutex<()> = Mutex::new(());

/// `f`'s result and the most memory it held at once beyond what was
/// allocated when it started, in bytes.
fn measure<T>(what: &str, f: impl FnOnce() -> T) -> (T, usize) {
    let base = CURRENT.load(Ordering::SeqCst);
    PEAK.store(base, Ordering::SeqCst);
    let out = f();
    let peak = PEAK.load(Ordering::SeqCst).saturating_sub(base);
    eprintln!("{what}: peak {peak} bytes");
    (out, peak)
}

const KIB: usize = 1 << 10;
const MIB: usize = 1 << 20;
/// The size of the huge sparse files.
const GIB2: u64 = 2 << 30;

/// A fresh, empty scratch folder for one test.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("likeness-hostile-{}-{name}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).unwrap();
    dir
}

/// A file of `len` bytes beginning with `head`, the rest a hole of zeros
/// that costs no disk.
fn sparse(path: &Path, head: &[u8], len: u64) {
    fs::write(path, head).unwrap();
    File::options()
        .write(true)
        .open(path)
        .unwrap()
        .set_len(len)
        .unwrap();
}

/// A FIFO at `path` (`mkfifo`), on which an unbounded reader would block.
fn fifo(path: &Path) {
    let status = std::process::Command::new("mkfifo")
        .arg(path)
        .status()
        .unwrap();
    assert!(status.success(), "mkfifo {}", path.display());
}

/// CRC-32 (IEEE), bit by bit.
fn crc32(parts: &[&[u8]]) -> u32 {
    let mut crc = !0u32;
    for byte in parts.iter().flat_map(|p| p.iter()) {
        crc ^= u32::from(*byte);
        for _ in 0..8 {
            crc = (crc >> 1) ^ (0xEDB8_8320 & (crc & 1).wrapping_neg());
        }
    }
    !crc
}

/// A session file header and its checksum over `compressed`.
fn session_header(compressed: &[u8], compressed_len: u64, payload_len: u64) -> Vec<u8> {
    let mut head = MAGIC.to_vec();
    head.extend_from_slice(&session_file::FORMAT_VERSION.to_le_bytes());
    head.extend_from_slice(&compressed_len.to_le_bytes());
    head.extend_from_slice(&payload_len.to_le_bytes());
    let crc = crc32(&[&head, compressed]);
    head.extend_from_slice(&crc.to_le_bytes());
    head
}

/// Raw DEFLATE of `len` zero bytes (`len` > 258): one fixed-Huffman block,
/// a literal zero, then matches of 258 bytes at distance 1, 13 bits each.
fn deflate_zeros(len: u64) -> Vec<u8> {
    let mut out = Vec::new();
    let (mut acc, mut bits) = (0u64, 0);
    // Huffman codes go most significant bit first, everything else LSB first.
    let mut put = |code: u64, n: u32, reversed: bool| {
        for i in 0..n {
            let bit = if reversed {
                (code >> (n - 1 - i)) & 1
            } else {
                (code >> i) & 1
            };
            acc |= bit << bits;
            bits += 1;
            if bits == 8 {
                out.push(acc as u8);
                (acc, bits) = (0, 0);
            }
        }
    };
    put(1, 1, false); // BFINAL
    put(1, 2, false); // BTYPE = 01, fixed Huffman
    put(0b0011_0000, 8, true); // literal 0
    let mut left = len - 1;
    while left >= 258 {
        put(0b1100_0101, 8, true); // length 258 (symbol 285)
        put(0, 5, true); // distance 1
        left -= 258;
    }
    for _ in 0..left {
        put(0b0011_0000, 8, true);
    }
    put(0, 7, true); // end of block
    put(0, 7, false); // flush the last byte
    out
}

#[test]
fn a_decompression_bomb_is_refused_from_its_header() {
    let _serial = SERIAL.lock().unwrap();
    let dir = scratch("bomb");
    // The issue's bomb: 535 MB of payload behind a valid header and checksum.
    let payload_len = 535_000_000;
    let compressed = deflate_zeros(payload_len);
    let path = dir.join("bomb.likeness");
    let mut file = session_header(&compressed, compressed.len() as u64, payload_len);
    file.extend_from_slice(&compressed);
    fs::write(&path, &file).unwrap();
    drop((file, compressed));
    let (result, peak) = measure("decompression bomb", || session_file::read(&path));
    match result {
        Err(SessionFileError::TooLarge {
            field,
            value,
            limit,
        }) => {
            assert_eq!(
                (field.as_str(), value, limit),
                ("header.payload_len", payload_len, Limit::PayloadBytes)
            );
        }
        other => panic!("{other:?}"),
    }
    assert!(peak < 64 * KIB, "peak {peak}");
    let message = session_file::read(&path).unwrap_err().to_string();
    assert!(message.contains("MAX_PAYLOAD_BYTES"), "{message}");
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn huge_sparse_and_lying_session_files_are_refused_before_reading_them() {
    let _serial = SERIAL.lock().unwrap();
    let dir = scratch("session-sparse");
    // 2 GiB of zeros: not a session, seen from its first 8 bytes.
    let zeros = dir.join("zeros.likeness");
    sparse(&zeros, &[], GIB2);
    let (result, peak) = measure("2 GiB of zeros", || session_file::read(&zeros));
    assert!(
        matches!(result, Err(SessionFileError::NotASessionFile)),
        "{result:?}"
    );
    assert!(peak < 64 * KIB, "peak {peak}");
    // A valid header whose payload is the whole 2 GiB: over the limit.
    let big = dir.join("big.likeness");
    sparse(
        &big,
        &session_header(&[], GIB2 - HEADER_LEN as u64, 1 << 20),
        GIB2,
    );
    let (result, peak) = measure("2 GiB sparse session", || session_file::read(&big));
    assert!(
        matches!(
            result,
            Err(SessionFileError::TooLarge {
                limit: Limit::CompressedBytes,
                ..
            })
        ),
        "{result:?}"
    );
    assert!(peak < 64 * KIB, "peak {peak}");
    // Headers that lie: a terabyte in a small file, a small payload in a
    // 2 GiB file.
    let liar = dir.join("liar.likeness");
    let mut bytes = session_header(&[0; 100], 1 << 40, 1000);
    bytes.extend_from_slice(&[0; 100]);
    fs::write(&liar, &bytes).unwrap();
    let (result, peak) = measure("header lies: 1 TB payload", || session_file::read(&liar));
    assert!(
        matches!(
            result,
            Err(SessionFileError::Truncated {
                what: "payload",
                expected: 1_099_511_627_776,
                found: 100
            })
        ),
        "{result:?}"
    );
    assert!(peak < 64 * KIB, "peak {peak}");
    sparse(&liar, &session_header(&[0; 100], 100, 1000), GIB2);
    let (result, peak) = measure("header lies: short payload in 2 GiB", || {
        session_file::read(&liar)
    });
    let message = result.unwrap_err().to_string();
    assert!(
        message.contains("bytes after the end of the payload"),
        "{message}"
    );
    assert!(peak < 64 * KIB, "peak {peak}");
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn what_is_not_a_regular_file_is_refused_without_reading() {
    let _serial = SERIAL.lock().unwrap();
    let dir = scratch("irregular");
    let pipe = dir.join("pipe.likeness");
    fifo(&pipe);
    let cases = [
        (Path::new("/dev/zero"), "a device"),
        (pipe.as_path(), "a FIFO"),
        (dir.as_path(), "a directory"),
    ];
    for (path, kind) in cases {
        let (result, peak) = measure(kind, || session_file::read(path));
        assert!(
            matches!(result, Err(SessionFileError::File(FileError::NotAFile { kind: k, .. })) if k == kind),
            "{kind}: {result:?}"
        );
        assert!(peak < 16 * KIB, "{kind}: peak {peak}");
        let (result, _) = measure(kind, || read_avatar(path));
        assert!(
            result
                .unwrap_err()
                .to_string()
                .contains("not a regular file")
        );
    }
    fs::remove_dir_all(&dir).unwrap();
}

/// A committed session exported as an interchange folder.
fn exported(name: &str) -> PathBuf {
    let root =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../sim-data/sessions/subject-1.likeness");
    let session = session_file::read(root).unwrap();
    let dir = scratch(name).join("folder");
    export_folder(&session, &dir).unwrap();
    dir
}

/// Imports `dir`, expecting an error, and returns it with the peak memory.
fn import_refused(what: &str, dir: &Path) -> (InterchangeError, usize) {
    let (result, peak) = measure(what, || import_folder(dir));
    (result.map(|_| ()).unwrap_err(), peak)
}

#[test]
fn hostile_folders_are_refused_with_bounded_memory() {
    let _serial = SERIAL.lock().unwrap();
    let dir = exported("folder");
    // A valid OBJ followed by 2 GiB of NUL bytes.
    let neutral = dir.join("neutral.obj");
    let obj = fs::read(&neutral).unwrap();
    sparse(&neutral, &obj, GIB2);
    let (err, peak) = import_refused("2 GiB sparse OBJ", &dir);
    assert!(
        matches!(err, InterchangeError::File(FileError::TooLarge { size, .. }) if size == GIB2),
        "{err}"
    );
    assert!(peak < 4 * MIB, "peak {peak}");
    // Past the vertex limit: refused at the first vertex too many.
    let many = "v 0 0 0\n".repeat(session_file::MAX_VERTICES + 1);
    fs::write(&neutral, many).unwrap();
    let (err, peak) = import_refused("OBJ past the vertex limit", &dir);
    let message = err.to_string();
    assert!(
        message.ends_with(&format!(
            "neutral.obj:{}: more than the limit of {} vertices",
            session_file::MAX_VERTICES + 1,
            session_file::MAX_VERTICES
        )),
        "{message}"
    );
    assert!(peak < 4 * MIB, "peak {peak}");
    fs::write(&neutral, &obj).unwrap();
    // frames.csv: 2 GiB sparse, a FIFO, /dev/zero.
    let frames = dir.join("frames.csv");
    let csv = fs::read(&frames).unwrap();
    sparse(&frames, &csv, GIB2);
    let (err, peak) = import_refused("2 GiB sparse frames.csv", &dir);
    assert!(
        matches!(err, InterchangeError::File(FileError::TooLarge { .. })),
        "{err}"
    );
    assert!(peak < 4 * MIB, "peak {peak}");
    fs::remove_file(&frames).unwrap();
    fifo(&frames);
    let (err, peak) = import_refused("FIFO as frames.csv", &dir);
    assert!(
        matches!(
            err,
            InterchangeError::File(FileError::NotAFile { kind: "a FIFO", .. })
        ),
        "{err}"
    );
    assert!(peak < 4 * MIB, "peak {peak}");
    fs::remove_file(&frames).unwrap();
    std::os::unix::fs::symlink("/dev/zero", &frames).unwrap();
    let (err, _) = import_refused("/dev/zero as frames.csv", &dir);
    assert!(
        matches!(
            err,
            InterchangeError::File(FileError::NotAFile {
                kind: "a device",
                ..
            })
        ),
        "{err}"
    );
    // A take of the real size: its rows are weights, not strings, as soon
    // as they are read.
    fs::remove_file(&frames).unwrap();
    fs::write(&frames, &csv).unwrap();
    let (result, peak) = measure("whole folder import", || import_folder(&dir));
    let frames_read = result.unwrap().0.frames.len();
    eprintln!("frames.csv of {} bytes, {frames_read} rows", csv.len());
    assert!(peak < 64 * MIB, "peak {peak}");
    fs::remove_dir_all(dir.parent().unwrap()).unwrap();
}

#[test]
fn hostile_glb_files_are_refused_with_bounded_memory() {
    let _serial = SERIAL.lock().unwrap();
    let dir = scratch("glb");
    let big = dir.join("big.glb");
    let mut head = b"glTF".to_vec();
    head.extend_from_slice(&2u32.to_le_bytes());
    head.extend_from_slice(&(GIB2 as u32 - 1).to_le_bytes());
    sparse(&big, &head, GIB2);
    let (result, peak) = measure("2 GiB sparse GLB", || read_avatar(&big));
    let message = result.map(|_| ()).unwrap_err().to_string();
    assert!(
        message.contains("over the limit of 536870912 bytes"),
        "{message}"
    );
    assert!(peak < 64 * KIB, "peak {peak}");
    // A chunk that claims 4 GiB in a file of 60 bytes.
    let liar = dir.join("liar.glb");
    let json = br#"{"asset":{"version":"2.0"}}    "#;
    let mut bytes = b"glTF".to_vec();
    bytes.extend_from_slice(&2u32.to_le_bytes());
    bytes.extend_from_slice(&((20 + json.len()) as u32).to_le_bytes());
    bytes.extend_from_slice(&u32::MAX.to_le_bytes());
    bytes.extend_from_slice(b"JSON");
    bytes.extend_from_slice(json);
    fs::write(&liar, &bytes).unwrap();
    let (result, peak) = measure("GLB chunk length lies", || read_avatar(&liar));
    let message = result.map(|_| ()).unwrap_err().to_string();
    assert!(
        message.contains("truncated GLB: chunk at byte 12"),
        "{message}"
    );
    assert!(peak < 64 * KIB, "peak {peak}");
    fs::remove_dir_all(&dir).unwrap();
}
