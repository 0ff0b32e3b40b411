//! Round trips, damaged files, hostile files and fuzzing of the session file.

use super::*;
use crate::arkit::{Blendshape, Weights};
use crate::geometry::topology::Topology;
use crate::session::{
    CapturedExpression, DeviceInfo, Frame, GroundTruth, SessionError, SessionParts, Template,
    TestExpression, TruePeak,
};
use glam::Vec3;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

mod damage;

const W: usize = 6;
const H: usize = 5;

fn jitter(rng: &mut ChaCha8Rng, mesh: &[Vec3], amp: f32) -> Vec<Vec3> {
    mesh.iter()
        .map(|p| {
            *p + Vec3::new(
                rng.random_range(-amp..amp),
                rng.random_range(-amp..amp),
                rng.random_range(-amp..amp),
            )
        })
        .collect()
}

fn random_weights(rng: &mut ChaCha8Rng) -> Weights {
    let mut w = Weights::ZERO;
    for shape in Blendshape::ALL {
        w.set(shape, rng.random_range(0.0..1.0));
    }
    w
}

/// A small session with every field filled: 30 vertices, 10 frames (some
/// without geometry), captures, tests and ground truth.
pub(super) fn small_session() -> Session {
    let mut rng = ChaCha8Rng::seed_from_u64(42);
    let mut triangles = Vec::new();
    for r in 0..H - 1 {
        for c in 0..W - 1 {
            let a = (r * W + c) as u32;
            let w = W as u32;
            triangles.push([a, a + 1, a + w]);
            triangles.push([a + 1, a + w + 1, a + w]);
        }
    }
    let topology = Topology::new(W * H, triangles).unwrap();
    let base: Vec<Vec3> = (0..W * H)
        .map(|i| {
            let (r, c) = ((i / W) as f32, (i % W) as f32);
            Vec3::new(
                c * 0.02 - 0.05,
                r * 0.02 - 0.04,
                0.03 + rng.random_range(0.0..0.01),
            )
        })
        .collect();
    let shapes = std::array::from_fn(|_| jitter(&mut rng, &base, 0.005));
    let neutral = jitter(&mut rng, &base, 0.002);
    let frames: Vec<Frame> = (0..10usize)
        .map(|k| Frame {
            // Frames 5 and 6 share a timestamp: allowed, time only may not go back.
            timestamp: 0.25 + (k.min(5) + k.saturating_sub(6)) as f64 / 60.0,
            weights: random_weights(&mut rng),
            tracked: k % 4 != 3,
            vertices: (k % 3 != 1).then(|| jitter(&mut rng, &neutral, 0.003)),
        })
        .collect();
    let captures: Vec<CapturedExpression> = [
        (Blendshape::JawOpen, Some(2)),
        (Blendshape::EyeBlinkLeft, None),
        (Blendshape::MouthSmileRight, Some(9)),
    ]
    .into_iter()
    .map(|(prompt, frame)| CapturedExpression {
        prompt,
        frame,
        weights: random_weights(&mut rng),
        vertices: jitter(&mut rng, &neutral, 0.004),
    })
    .collect();
    let tests: Vec<TestExpression> = [("smile-squint", Some(4)), ("bärtig ✓", None)]
        .into_iter()
        .map(|(id, frame)| TestExpression {
            id: id.to_string(),
            frame,
            weights: random_weights(&mut rng),
            vertices: jitter(&mut rng, &neutral, 0.004),
        })
        .collect();
    let true_neutral = jitter(&mut rng, &neutral, 0.0002);
    let truth = GroundTruth {
        seed: 0xdead_beef_1234,
        peak_frames: vec![
            TruePeak {
                prompt: Blendshape::JawOpen,
                frame: 2,
            },
            TruePeak {
                prompt: Blendshape::MouthSmileRight,
                frame: 8,
            },
        ],
        blendshapes: std::array::from_fn(|_| jitter(&mut rng, &true_neutral, 0.005)),
        captures: (0..3)
            .map(|_| jitter(&mut rng, &true_neutral, 0.004))
            .collect(),
        tests: (0..2)
            .map(|_| jitter(&mut rng, &true_neutral, 0.004))
            .collect(),
        test_activations: (0..2).map(|_| random_weights(&mut rng)).collect(),
        neutral: true_neutral,
    };
    Session::new(SessionParts {
        device: DeviceInfo {
            model: "likeness-sim".into(),
            system_version: "iOS 17.4".into(),
            app_version: "0.1.0".into(),
            recorded_at: "2025-01-02T03:04:05Z".into(),
        },
        frame_rate: 60.0,
        topology,
        template: Template {
            neutral: base,
            shapes,
        },
        neutral,
        frames,
        captures,
        tests,
        truth: Some(truth),
    })
    .unwrap()
}

fn q(x: f32) -> f32 {
    dequantize(quantize(x).unwrap())
}

fn q_mesh(mesh: &mut [Vec3]) {
    for p in mesh {
        *p = Vec3::new(q(p.x), q(p.y), q(p.z));
    }
}

fn q_weights(w: &mut Weights) {
    for x in &mut w.0 {
        *x = q(*x);
    }
}

/// `session` with every position and weight rounded to the stored precision.
pub(super) fn quantized(session: &Session) -> Session {
    let mut s = session.clone().into_parts();
    q_mesh(&mut s.template.neutral);
    s.template.shapes.iter_mut().for_each(|m| q_mesh(m));
    q_mesh(&mut s.neutral);
    for f in &mut s.frames {
        q_weights(&mut f.weights);
        f.vertices.iter_mut().for_each(|m| q_mesh(m));
    }
    for c in &mut s.captures {
        q_weights(&mut c.weights);
        q_mesh(&mut c.vertices);
    }
    for t in &mut s.tests {
        q_weights(&mut t.weights);
        q_mesh(&mut t.vertices);
    }
    if let Some(t) = &mut s.truth {
        q_mesh(&mut t.neutral);
        let meshes = t
            .blendshapes
            .iter_mut()
            .chain(&mut t.captures)
            .chain(&mut t.tests);
        meshes.for_each(|m| q_mesh(m));
        t.test_activations.iter_mut().for_each(q_weights);
    }
    Session::new(s).unwrap()
}

#[test]
fn every_field_round_trips_and_re_encodes_to_the_same_bytes() {
    let session = small_session();
    let bytes = encode(&session).unwrap();
    let decoded = decode(&bytes).unwrap();
    assert_eq!(decoded, quantized(&session));
    assert_eq!(encode(&decoded).unwrap(), bytes);
    let mut without_truth = session.clone().into_parts();
    without_truth.truth = None;
    without_truth
        .frames
        .iter_mut()
        .for_each(|f| f.vertices = None);
    let without_truth = Session::new(without_truth).unwrap();
    let decoded = decode(&encode(&without_truth).unwrap()).unwrap();
    assert_eq!(decoded, quantized(&without_truth));
}

#[test]
fn decoded_positions_are_within_five_micrometres() {
    let session = small_session();
    let decoded = decode(&encode(&session).unwrap()).unwrap();
    let pairs = session.frames.iter().zip(&decoded.frames);
    for (a, b) in pairs.filter_map(|(a, b)| a.vertices.as_ref().zip(b.vertices.as_ref())) {
        for (p, r) in a.iter().zip(b) {
            assert!((*p - *r).abs().max_element() <= 5.0e-6 + 1e-8, "{p} vs {r}");
        }
    }
}

/// [`small_session`] written to `s.likeness` in a new folder of the
/// temporary directory named after `test`: the folder, the file, the
/// session.
fn written_small_session(test: &str) -> (std::path::PathBuf, std::path::PathBuf, Session) {
    let dir = std::env::temp_dir().join(format!("likeness-{test}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("s.likeness");
    let session = small_session();
    write(&path, &session).unwrap();
    (dir, path, session)
}

#[test]
fn files_are_written_atomically_and_read_back() {
    let (dir, path, session) = written_small_session("session-file");
    assert_eq!(read(&path).unwrap(), quantized(&session));
    std::fs::remove_dir_all(&dir).unwrap();
    let err = read(&path).unwrap_err();
    assert!(matches!(
        err,
        SessionFileError::File(FileError::Missing { .. })
    ));
    assert!(err.to_string().contains("s.likeness"), "{err}");
}

#[test]
fn the_template_comes_first_and_once_and_not_from_a_file_broken_before_it() {
    let (dir, path, _) = written_small_session("template-first");
    let mut early: Vec<(Topology, Template)> = Vec::new();
    let read_back = read_template_first(&path, |t, m| early.push((t.clone(), m.clone()))).unwrap();
    assert_eq!(early.len(), 1);
    assert_eq!(
        early[0],
        (read_back.topology.clone(), read_back.template.clone())
    );
    // A file whose payload is damaged fails its checksum before anything
    // is decoded: no template is announced.
    let mut bytes = std::fs::read(&path).unwrap();
    let last = bytes.len() - 1;
    bytes[last] ^= 0xff;
    std::fs::write(&path, &bytes).unwrap();
    let mut called = false;
    assert!(read_template_first(&path, |_, _| called = true).is_err());
    assert!(!called);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn an_invalid_session_cannot_be_made_and_an_unstorable_one_is_not_written() {
    let mut s = small_session().into_parts();
    s.frame_rate = 0.0;
    assert!(matches!(Session::new(s), Err(SessionError::FrameRate(_))));
    let mut s = small_session().into_parts();
    s.frames[1].weights.set(Blendshape::JawOpen, 250.0);
    let err = encode(&Session::new(s).unwrap()).unwrap_err();
    assert!(matches!(err, SessionFileError::OutOfRange { .. }));
    assert!(
        err.to_string().contains("frames[1].weights[jawOpen]"),
        "{err}"
    );
}

#[test]
fn another_version_or_magic_is_named_as_such() {
    let mut bytes = encode(&small_session()).unwrap();
    bytes[8..12].copy_from_slice(&2u32.to_le_bytes());
    let err = decode(&bytes).unwrap_err();
    assert!(matches!(err, SessionFileError::UnsupportedVersion(2)));
    assert!(
        err.to_string()
            .contains("unsupported session format version 2"),
        "{err}"
    );
    bytes[0] = b'l';
    assert!(matches!(
        decode(&bytes),
        Err(SessionFileError::NotASessionFile)
    ));
    assert!(matches!(
        decode(b"PK\x03\x04"),
        Err(SessionFileError::NotASessionFile)
    ));
    assert!(matches!(
        decode(b""),
        Err(SessionFileError::NotASessionFile)
    ));
}
