//! Truncated, damaged, hostile and random files: always an error naming
//! what is wrong, never a panic, never an allocation of a declared size.

use super::super::wire::{FRAME_HAS_VERTICES, FRAME_TRACKED, WireSession, bincode_config};
use super::super::*;
use super::small_session;
use crate::arkit::{Blendshape, Weights};
use crate::geometry::topology::Topology;
use crate::session::{
    CapturedExpression, DeviceInfo, Frame, SessionError, SessionParts, Template, TestExpression,
};
use glam::Vec3;
use rand::{Rng, RngCore, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

/// Records the largest single allocation made by the current thread, so a
/// test can check that a hostile file did not make the decoder allocate what
/// it declares.
struct PeakAllocator;

thread_local! {
    static LARGEST: Cell<usize> = const { Cell::new(0) };
}

unsafe impl GlobalAlloc for PeakAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let _ = LARGEST.try_with(|l| l.set(l.get().max(layout.size())));
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let _ = LARGEST.try_with(|l| l.set(l.get().max(new_size)));
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static ALLOCATOR: PeakAllocator = PeakAllocator;

/// The largest single allocation `f` made on this thread.
fn largest_allocation<T>(f: impl FnOnce() -> T) -> (T, usize) {
    LARGEST.with(|l| l.set(0));
    let out = f();
    (out, LARGEST.with(Cell::get))
}

#[test]
fn every_prefix_is_an_error() {
    let bytes = encode(&small_session()).unwrap();
    for len in 0..bytes.len() {
        assert!(
            decode(&bytes[..len]).is_err(),
            "prefix of {len} bytes decoded"
        );
    }
    assert!(matches!(
        decode(&bytes[..20]),
        Err(SessionFileError::Truncated { .. })
    ));
    assert!(matches!(
        decode(&bytes[..bytes.len() - 1]),
        Err(SessionFileError::Truncated {
            what: "payload",
            ..
        })
    ));
}

#[test]
fn every_single_bit_flip_is_an_error() {
    let bytes = encode(&small_session()).unwrap();
    let mut damaged = bytes.clone();
    for i in 0..bytes.len() {
        for bit in 0..8 {
            damaged[i] ^= 1 << bit;
            assert!(
                decode(&damaged).is_err(),
                "flip of bit {bit} of byte {i} decoded"
            );
            damaged[i] ^= 1 << bit;
        }
    }
    damaged[HEADER_LEN + 10] ^= 4;
    assert!(matches!(
        decode(&damaged),
        Err(SessionFileError::Checksum { .. })
    ));
}

fn payload_of(session: &Session) -> Vec<u8> {
    encode::encode_payload(session).unwrap()
}

/// `payload` decoded into its wire form, changed by `edit`, and sealed into
/// a file with a valid checksum.
fn edited<'a>(payload: &'a [u8], edit: impl FnOnce(&mut WireSession<'a>)) -> Vec<u8> {
    let (mut wire, _): (WireSession<'a>, usize) =
        bincode::serde::borrow_decode_from_slice(payload, bincode_config()).unwrap();
    edit(&mut wire);
    seal(&bincode::serde::encode_to_vec(&wire, bincode_config()).unwrap()).unwrap()
}

fn corrupt_field(bytes: &[u8]) -> String {
    match decode(bytes) {
        Err(SessionFileError::Corrupt { field, .. }) => field,
        other => panic!("expected a corrupt-field error, got {other:?}"),
    }
}

#[test]
fn errors_name_the_field_and_frame() {
    let s = small_session();
    let p = payload_of(&s);
    // Frames 0, 2, 3, 5, 6, 8, 9 have geometry; the stream's last byte is
    // the last value of frame 9.
    let bytes = edited(&p, |w| {
        w.frames.vertices = &w.frames.vertices[..w.frames.vertices.len() - 1]
    });
    assert_eq!(corrupt_field(&bytes), "frames[9].vertices");
    // Far too short for a block of 7 frames: named by the block's first frame.
    let bytes = edited(&p, |w| w.frames.vertices = &w.frames.vertices[..100]);
    assert_eq!(corrupt_field(&bytes), "frames[0].vertices");
    let bytes = edited(&p, |w| w.frames.flags = &[3, 3, 3]);
    assert_eq!(corrupt_field(&bytes), "frames.flags");
    let (wire, _): (WireSession<'_>, usize) =
        bincode::serde::borrow_decode_from_slice(&p, bincode_config()).unwrap();
    let long: Vec<u8> = [wire.frames.weights, &[0]].concat();
    let bytes = edited(&p, |w| w.frames.weights = &long);
    assert_eq!(corrupt_field(&bytes), "frames[9].weights");
    let bytes = edited(&p, |w| w.captures[1].prompt = 52);
    assert_eq!(corrupt_field(&bytes), "captures[1].prompt");
    let bytes = edited(&p, |w| w.tests[1].vertices = &[0; 90][..89]);
    assert_eq!(corrupt_field(&bytes), "tests[1].vertices");
    let bytes = edited(&p, |w| w.frames.count = 11);
    assert_eq!(corrupt_field(&bytes), "frames.flags");
    let bytes = edited(&p, |w| w.truth.as_mut().unwrap().peak_frames[0].1 = 10);
    assert!(matches!(
        decode(&bytes),
        Err(SessionFileError::Invalid(SessionError::FrameIndex { .. }))
    ));
    let bytes = edited(&p, |w| w.triangles[3][1] = 30);
    assert!(matches!(decode(&bytes), Err(SessionFileError::Topology(_))));
}

#[test]
fn a_value_leaving_the_storable_range_names_its_frame() {
    let p = payload_of(&small_session());
    // A huge residual at the very first varint of the stream: vertex 0's x
    // in the first geometry frame.
    let (wire, _): (WireSession<'_>, usize) =
        bincode::serde::borrow_decode_from_slice(&p, bincode_config()).unwrap();
    let mut stream = wire.frames.vertices.to_vec();
    let mut big = Vec::new();
    geometry_codec::put_varint(&mut big, 1 << 40);
    stream.splice(1..2, big);
    let bytes = edited(&p, |w| w.frames.vertices = &stream);
    let err = decode(&bytes).unwrap_err();
    assert!(err.to_string().contains("frames[0].vertices"), "{err}");
    assert!(
        err.to_string().contains("outside the storable range"),
        "{err}"
    );
}

#[test]
fn hostile_counts_are_rejected_without_allocating_them() {
    let s = small_session();
    let p = payload_of(&s);
    let cases: Vec<(&str, Vec<u8>)> = vec![
        ("frame count", edited(&p, |w| w.frames.count = u32::MAX)),
        ("frames in range", edited(&p, |w| w.frames.count = 900_000)),
        ("vertex count", edited(&p, |w| w.vertex_count = u32::MAX)),
        (
            "vertex count at the cap",
            edited(&p, |w| {
                w.vertex_count = crate::geometry::topology::MAX_VERTICES as u32;
                w.triangles = vec![[0, 1, 2]];
            }),
        ),
        (
            "template shapes",
            edited(&p, |w| {
                let one = w.template_shapes[0];
                w.template_shapes = vec![one; 1_000];
            }),
        ),
    ];
    for (what, bytes) in cases {
        let (result, largest) = largest_allocation(|| decode(&bytes));
        assert!(result.is_err(), "{what}: decoded");
        assert!(largest < 1 << 20, "{what}: allocated {largest} bytes");
    }
    // A declared length in the bincode payload: a string of 2^40 bytes.
    let mut payload = encode::encode_payload(&s).unwrap();
    let model_len_at = 0; // `device.model` is the first field: its length comes first.
    assert_eq!(payload[model_len_at] as usize, s.device.model.len());
    payload.splice(
        model_len_at..model_len_at + 1,
        [253, 0, 0, 0, 0, 0, 1, 0, 0],
    );
    let bytes = seal(&payload).unwrap();
    let (result, largest) = largest_allocation(|| decode(&bytes));
    assert!(
        matches!(result, Err(SessionFileError::Corrupt { .. })),
        "{result:?}"
    );
    assert!(
        largest < 1 << 20,
        "string length: allocated {largest} bytes"
    );
    // A header declaring a huge payload.
    let mut bytes = encode(&s).unwrap();
    bytes[20..28].copy_from_slice(&(1u64 << 40).to_le_bytes());
    let crc = {
        let mut h = crc32fast::Hasher::new();
        h.update(&bytes[..28]);
        h.update(&bytes[HEADER_LEN..]);
        h.finalize()
    };
    bytes[28..32].copy_from_slice(&crc.to_le_bytes());
    let (result, largest) = largest_allocation(|| decode(&bytes));
    assert!(
        matches!(result, Err(SessionFileError::TooLarge { .. })),
        "{result:?}"
    );
    assert!(largest < 1 << 20);
}

#[test]
fn random_bytes_never_panic() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let valid = encode(&small_session()).unwrap();
    for k in 0..5_000 {
        let len = rng.random_range(0..300);
        let mut bytes = vec![0u8; len];
        rng.fill_bytes(&mut bytes);
        // Give a third of them a real header start so they get further.
        if k % 3 == 0 {
            let keep = rng.random_range(0..=HEADER_LEN.min(len));
            bytes[..keep].copy_from_slice(&valid[..keep]);
        }
        assert!(decode(&bytes).is_err());
    }
}

/// Mutates the *uncompressed* payload (flips, overwrites, insertions,
/// deletions) and reseals it with a valid checksum, so the decoder's own
/// checks are exercised past the CRC and the inflater.
#[test]
fn mutated_payloads_with_valid_checksums_never_panic() {
    let payload = encode::encode_payload(&small_session()).unwrap();
    let accepted = decode_mutations(&payload, 11, 3_000);
    // Most mutations must be caught; a few (inside a weight) are harmless.
    assert!(accepted < 1_500, "{accepted} of 3000 mutations accepted");
}

/// Decodes `count` random mutations of `payload` (flips, overwrites,
/// insertions, deletions), each resealed with a valid checksum; returns how
/// many were accepted. Whatever is accepted must be a valid session that
/// round-trips.
fn decode_mutations(payload: &[u8], seed: u64, count: usize) -> usize {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut accepted = 0;
    for _ in 0..count {
        let mut p = payload.to_vec();
        for _ in 0..rng.random_range(1..4) {
            let at = rng.random_range(0..p.len());
            match rng.random_range(0..5) {
                0 => p[at] ^= 1 << rng.random_range(0..8),
                1 => p[at] = rng.random(),
                2 => p.insert(at, rng.random()),
                3 => {
                    p.remove(at);
                }
                _ => p.truncate(at),
            }
            if p.is_empty() {
                break;
            }
        }
        if let Ok(decoded) = decode(&seal(&p).unwrap()) {
            let parts = decoded.clone().into_parts();
            assert_eq!(Session::new(parts).as_ref(), Ok(&decoded));
            assert_eq!(decode(&encode(&decoded).unwrap()).unwrap(), decoded);
            accepted += 1;
        }
    }
    accepted
}

/// A session over a single triangle, the smallest topology there is, with
/// a frame stream, a capture and a test expression.
fn one_triangle_session() -> Session {
    let neutral = vec![
        Vec3::ZERO,
        Vec3::new(0.01, 0.0, 0.0),
        Vec3::new(0.0, 0.01, 0.0),
    ];
    let moved = |dz: f32| -> Vec<Vec3> { neutral.iter().map(|p| *p + Vec3::Z * dz).collect() };
    let mut weights = Weights::ZERO;
    weights.set(Blendshape::JawOpen, 0.8);
    let frames = (0..3)
        .map(|k| Frame {
            timestamp: k as f64 / 60.0,
            weights,
            tracked: true,
            vertices: (k != 1).then(|| moved(0.001 * k as f32)),
        })
        .collect();
    Session::new(SessionParts {
        device: DeviceInfo::default(),
        frame_rate: 60.0,
        topology: Topology::new(3, vec![[0, 1, 2]]).unwrap(),
        template: Template {
            neutral: neutral.clone(),
            shapes: std::array::from_fn(|j| moved(0.0001 * j as f32)),
        },
        neutral: neutral.clone(),
        frames,
        captures: vec![CapturedExpression {
            prompt: Blendshape::JawOpen,
            frame: Some(2),
            weights,
            vertices: moved(0.002),
        }],
        tests: vec![TestExpression {
            id: "t".into(),
            frame: None,
            weights,
            vertices: moved(0.003),
        }],
        truth: None,
    })
    .unwrap()
}

#[test]
fn tiny_and_mismatched_topologies_are_decoded_or_rejected_without_panicking() {
    // The smallest topology round-trips, and its mutations never panic.
    let tiny = one_triangle_session();
    let decoded = decode(&encode(&tiny).unwrap()).unwrap();
    assert_eq!(decode(&encode(&decoded).unwrap()).unwrap(), decoded);
    let payload = payload_of(&tiny);
    decode_mutations(&payload, 17, 2_000);

    // A topology that does not fit the meshes coded with another one.
    let p = payload_of(&small_session());
    let shrunk = edited(&p, |w| {
        w.vertex_count = 3;
        w.triangles = vec![[0, 1, 2]];
    });
    assert!(matches!(
        decode(&shrunk),
        Err(SessionFileError::Corrupt { .. })
    ));
    let bytes = edited(&payload, |w| {
        w.vertex_count = 4;
        w.triangles = vec![[0, 1, 2], [1, 3, 2]];
    });
    assert!(decode(&bytes).is_err());
    // Same vertex count, other connectivity: the spatial predictions change,
    // so the values decode differently or not at all, but never panic.
    for triangles in [vec![[0, 1, 2]], vec![[29, 0, 1], [0, 29, 2], [5, 6, 7]]] {
        let bytes = edited(&p, |w| w.triangles = triangles);
        let _ = decode(&bytes);
    }
    // Triangles that are no triangles, and no vertices at all.
    let bytes = edited(&payload, |w| w.triangles = vec![[0, 0, 1]]);
    assert!(matches!(decode(&bytes), Err(SessionFileError::Topology(_))));
    let bytes = edited(&payload, |w| w.triangles = Vec::new());
    assert!(matches!(decode(&bytes), Err(SessionFileError::Topology(_))));
    let bytes = edited(&payload, |w| w.vertex_count = 0);
    assert!(decode(&bytes).is_err());
}

#[test]
fn mutated_compressed_streams_with_valid_checksums_never_panic() {
    let mut rng = ChaCha8Rng::seed_from_u64(13);
    let valid = encode(&small_session()).unwrap();
    for _ in 0..2_000 {
        let mut bytes = valid.clone();
        let at = rng.random_range(HEADER_LEN..bytes.len());
        bytes[at] ^= 1 << rng.random_range(0..8);
        let mut h = crc32fast::Hasher::new();
        h.update(&bytes[..28]);
        h.update(&bytes[HEADER_LEN..]);
        let crc = h.finalize();
        bytes[28..32].copy_from_slice(&crc.to_le_bytes());
        let _ = decode(&bytes);
    }
}

#[test]
fn payloads_past_the_limits_are_refused_naming_the_limit() {
    let p = payload_of(&small_session());
    let flags = vec![FRAME_TRACKED | FRAME_HAS_VERTICES; 3_000];
    let cases = [
        (
            "frames.count",
            Limit::Frames,
            edited(&p, |w| w.frames.count = MAX_FRAMES as u32 + 1),
        ),
        (
            "topology.vertex_count",
            Limit::Vertices,
            edited(&p, |w| w.vertex_count = MAX_VERTICES as u32 + 1),
        ),
        (
            // 3,000 meshes of 16,384 vertices: 49 M vertices, 590 MB decoded.
            "meshes",
            Limit::DecodedVertices,
            edited(&p, |w| {
                w.vertex_count = MAX_VERTICES as u32;
                w.frames.count = 3_000;
                w.frames.flags = &flags;
            }),
        ),
    ];
    for (field, limit, bytes) in cases {
        let (result, largest) = largest_allocation(|| decode(&bytes));
        match result {
            Err(SessionFileError::TooLarge {
                field: f, limit: l, ..
            }) => assert_eq!((f.as_str(), l), (field, limit)),
            other => panic!("{field}: {other:?}"),
        }
        assert!(largest < 1 << 20, "{field}: allocated {largest} bytes");
    }
}

#[test]
fn sessions_past_the_limits_are_neither_written_nor_read() {
    let mut parts = small_session().into_parts();
    let last = parts.frames.len() - 1;
    parts.frames[last].timestamp = 700.0;
    let long = Session::new(parts).unwrap();
    let err = encode(&long).unwrap_err();
    assert!(
        matches!(
            err,
            SessionFileError::TooLarge {
                limit: Limit::Duration,
                ..
            }
        ),
        "{err}"
    );
    // Written past the check, it is refused on reading, naming the field.
    let err = decode(&seal(&payload_of(&long)).unwrap()).unwrap_err();
    assert_eq!(
        err.to_string(),
        "frames.timestamps is 700 s, over the limit MAX_DURATION_SECONDS = 600 s (ten minutes)"
    );
}

#[test]
fn a_payload_that_ends_early_is_blamed_on_its_field_in_our_words() {
    let p = payload_of(&small_session());
    let (wire, _): (WireSession<'_>, usize) =
        bincode::serde::borrow_decode_from_slice(&p, bincode_config()).unwrap();
    // Cut inside the frame stream's weights.
    let offset = wire.frames.weights.as_ptr() as usize - p.as_ptr() as usize;
    let err = decode(&seal(&p[..offset + 10]).unwrap()).unwrap_err();
    assert_eq!(
        err.to_string(),
        "corrupt session file: frames.weights: the payload ends inside this field"
    );
    // A DEFLATE stream cut short, resealed with a valid checksum.
    let bytes = encode(&small_session()).unwrap();
    let mut cut = bytes[..bytes.len() - 20].to_vec();
    let compressed_len = (cut.len() - HEADER_LEN) as u64;
    cut[12..20].copy_from_slice(&compressed_len.to_le_bytes());
    let mut h = crc32fast::Hasher::new();
    h.update(&cut[..28]);
    h.update(&cut[HEADER_LEN..]);
    let crc = h.finalize();
    cut[28..32].copy_from_slice(&crc.to_le_bytes());
    let message = decode(&cut).unwrap_err().to_string();
    assert!(
        message.contains("payload: the compressed payload"),
        "{message}"
    );
    assert!(!message.contains("Failed"), "{message}");
}
