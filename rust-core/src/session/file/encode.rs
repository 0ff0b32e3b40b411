//! [`Session`] → uncompressed payload.

use super::error::SessionFileError;
use super::geometry_codec::{encode_mesh, encode_values, quantize_mesh, quantize_weights};
use super::limits::Extent;
use super::series::SeriesEncoder;
use super::traversal::Traversal;
use super::wire::{
    FRAME_HAS_VERTICES, FRAME_TRACKED, WireCapture, WireDevice, WireFrames, WireSession, WireTest,
    WireTruth, bincode_config,
};
use crate::arkit::{BLENDSHAPE_COUNT, Blendshape, Weights};
use crate::session::{GroundTruth, Session};
use glam::Vec3;

/// The frame stream's columns.
struct FrameBlobs {
    timestamps: Vec<u8>,
    flags: Vec<u8>,
    weights: Vec<u8>,
    vertices: Vec<u8>,
}

/// An expression's weights and mesh.
struct ExpressionBlobs {
    weights: Vec<u8>,
    vertices: Vec<u8>,
}

/// Ground truth's meshes and weights.
struct TruthBlobs {
    neutral: Vec<u8>,
    blendshapes: Vec<Vec<u8>>,
    captures: Vec<Vec<u8>>,
    tests: Vec<Vec<u8>>,
    test_activations: Vec<Vec<u8>>,
}

/// The template's neutral and its 52 shapes, each coded against it.
struct TemplateBlobs {
    neutral: Vec<u8>,
    shapes: Vec<Vec<u8>>,
}

/// Everything the payload holds, coded; the wire structure borrows it.
struct PayloadBlobs {
    template: TemplateBlobs,
    neutral: Vec<u8>,
    frames: FrameBlobs,
    captures: Vec<ExpressionBlobs>,
    tests: Vec<ExpressionBlobs>,
    truth: Option<TruthBlobs>,
}

/// The sizes of `session` that the [limits](super::limits) bound.
pub(super) fn extent(session: &Session) -> Extent {
    let stream_meshes = session
        .frames
        .iter()
        .filter(|f| f.vertices.is_some())
        .count();
    let truth_meshes = session.truth.as_ref().map_or(0, |t| {
        1 + t.blendshapes.len() + t.captures.len() + t.tests.len()
    });
    Extent {
        vertices: session.topology.vertex_count(),
        frames: session.frames.len(),
        meshes: 2
            + session.template.shapes.len()
            + session.captures.len()
            + session.tests.len()
            + truth_meshes
            + stream_meshes,
    }
}

/// Serializes `session` (valid by construction) to the uncompressed
/// payload: each part is quantized and coded ([`encode_parts`]), then
/// laid out in the wire structure ([`wire_session`]) and serialized.
pub(super) fn encode_payload(session: &Session) -> Result<Vec<u8>, SessionFileError> {
    let blobs = encode_parts(session)?;
    let wire = wire_session(session, &blobs)?;
    bincode::serde::encode_to_vec(&wire, bincode_config())
        .map_err(|e| SessionFileError::Encode(e.to_string()))
}

/// Quantizes and codes every part: the template, the neutral scan, the
/// stream, the expressions (meshes against the neutral) and the ground
/// truth.
fn encode_parts(session: &Session) -> Result<PayloadBlobs, SessionFileError> {
    let traversal = Traversal::for_mesh(&session.topology);
    let template = encode_template(session, &traversal)?;
    let neutral_q = quantize_mesh("neutral", &session.neutral)?;
    let neutral = encode_mesh(&neutral_q, None, &traversal);
    let frames = encode_frames(session, &neutral_q, &traversal)?;
    let expression = |field: String, weights, vertices| {
        encode_expression(&field, weights, vertices, &neutral_q, &traversal)
    };
    let captures = session
        .captures
        .iter()
        .enumerate()
        .map(|(k, c)| expression(format!("captures[{k}]"), &c.weights, &c.vertices))
        .collect::<Result<Vec<_>, _>>()?;
    let tests = session
        .tests
        .iter()
        .enumerate()
        .map(|(k, t)| expression(format!("tests[{k}]"), &t.weights, &t.vertices))
        .collect::<Result<Vec<_>, _>>()?;
    let truth = session
        .truth
        .as_ref()
        .map(|t| encode_truth(t, &neutral_q, &traversal))
        .transpose()?;
    Ok(PayloadBlobs {
        template,
        neutral,
        frames,
        captures,
        tests,
        truth,
    })
}

/// The template's neutral, then each shape against it.
fn encode_template(
    session: &Session,
    traversal: &Traversal,
) -> Result<TemplateBlobs, SessionFileError> {
    let neutral_q = quantize_mesh("template.neutral", &session.template.neutral)?;
    let shapes = session
        .template
        .shapes
        .iter()
        .zip(Blendshape::ALL)
        .map(|(shape_mesh, shape)| {
            let q = quantize_mesh(&format!("template.shapes[{shape}]"), shape_mesh)?;
            Ok(encode_mesh(&q, Some(&neutral_q), traversal))
        })
        .collect::<Result<Vec<_>, SessionFileError>>()?;
    Ok(TemplateBlobs {
        neutral: encode_mesh(&neutral_q, None, traversal),
        shapes,
    })
}

/// The wire structure: the session's scalars and strings, and the coded
/// blobs in the order [`decode_payload`](super::decode) reads them.
fn wire_session<'a>(
    session: &'a Session,
    blobs: &'a PayloadBlobs,
) -> Result<WireSession<'a>, SessionFileError> {
    let d = &session.device;
    let frames = &blobs.frames;
    Ok(WireSession {
        device: WireDevice {
            model: &d.model,
            system_version: &d.system_version,
            app_version: &d.app_version,
            recorded_at: &d.recorded_at,
        },
        frame_rate: session.frame_rate,
        vertex_count: count_u32("topology.vertex_count", session.topology.vertex_count())?,
        triangles: session.topology.triangles().to_vec(),
        template_neutral: &blobs.template.neutral,
        template_shapes: blobs.template.shapes.iter().map(Vec::as_slice).collect(),
        neutral: &blobs.neutral,
        frames: WireFrames {
            count: count_u32("frames", session.frames.len())?,
            timestamps: &frames.timestamps,
            flags: &frames.flags,
            weights: &frames.weights,
            vertices: &frames.vertices,
        },
        captures: session
            .captures
            .iter()
            .zip(&blobs.captures)
            .map(|(c, blobs)| WireCapture {
                prompt: c.prompt.index() as u8,
                frame: c.frame,
                weights: &blobs.weights,
                vertices: &blobs.vertices,
            })
            .collect(),
        tests: session
            .tests
            .iter()
            .zip(&blobs.tests)
            .map(|(t, blobs)| WireTest {
                id: &t.id,
                frame: t.frame,
                weights: &blobs.weights,
                vertices: &blobs.vertices,
            })
            .collect(),
        truth: session
            .truth
            .as_ref()
            .zip(blobs.truth.as_ref())
            .map(|(t, blobs)| WireTruth {
                seed: t.seed,
                peak_frames: t
                    .peak_frames
                    .iter()
                    .map(|peak| (peak.prompt.index() as u8, peak.frame))
                    .collect(),
                neutral: &blobs.neutral,
                blendshapes: blobs.blendshapes.iter().map(Vec::as_slice).collect(),
                captures: blobs.captures.iter().map(Vec::as_slice).collect(),
                tests: blobs.tests.iter().map(Vec::as_slice).collect(),
                test_activations: blobs.test_activations.iter().map(Vec::as_slice).collect(),
            }),
    })
}

fn count_u32(what: &str, n: usize) -> Result<u32, SessionFileError> {
    u32::try_from(n).map_err(|_| SessionFileError::Encode(format!("{what}: {n} is over 32 bits")))
}

fn encode_frames(
    session: &Session,
    neutral_q: &[i32],
    traversal: &Traversal,
) -> Result<FrameBlobs, SessionFileError> {
    let count = session.frames.len();
    let mut timestamps = Vec::with_capacity(8 * count);
    let mut flags = Vec::with_capacity(count);
    let weight_order = Traversal::identity(BLENDSHAPE_COUNT);
    let mut weights = SeriesEncoder::new(vec![0; BLENDSHAPE_COUNT], &weight_order);
    let mut vertices = SeriesEncoder::new(neutral_q.to_vec(), traversal);
    let mut previous_bits = 0u64;
    for (k, frame) in session.frames.iter().enumerate() {
        let bits = frame.timestamp.to_bits();
        timestamps.extend_from_slice(&(bits ^ previous_bits).to_le_bytes());
        previous_bits = bits;
        let mut flag = 0;
        if frame.tracked {
            flag |= FRAME_TRACKED;
        }
        weights.push(&quantize_weights(
            &format!("frames[{k}].weights"),
            &frame.weights,
        )?);
        if let Some(mesh) = &frame.vertices {
            flag |= FRAME_HAS_VERTICES;
            vertices.push(&quantize_mesh(&format!("frames[{k}].vertices"), mesh)?);
        }
        flags.push(flag);
    }
    Ok(FrameBlobs {
        timestamps,
        flags,
        weights: weights.finish(),
        vertices: vertices.finish(),
    })
}

fn encode_expression(
    field: &str,
    weights: &Weights,
    mesh: &[Vec3],
    neutral_q: &[i32],
    traversal: &Traversal,
) -> Result<ExpressionBlobs, SessionFileError> {
    let w = quantize_weights(&format!("{field}.weights"), weights)?;
    let q = quantize_mesh(&format!("{field}.vertices"), mesh)?;
    Ok(ExpressionBlobs {
        weights: encode_values(&w),
        vertices: encode_mesh(&q, Some(neutral_q), traversal),
    })
}

fn encode_truth(
    truth: &GroundTruth,
    neutral_q: &[i32],
    traversal: &Traversal,
) -> Result<TruthBlobs, SessionFileError> {
    let true_neutral = quantize_mesh("truth.neutral", &truth.neutral)?;
    let meshes = |what: &str, list: &[Vec<Vec3>]| {
        list.iter()
            .enumerate()
            .map(|(k, mesh)| {
                let q = quantize_mesh(&format!("truth.{what}[{k}]"), mesh)?;
                Ok(encode_mesh(&q, Some(&true_neutral), traversal))
            })
            .collect::<Result<Vec<_>, SessionFileError>>()
    };
    Ok(TruthBlobs {
        neutral: encode_mesh(&true_neutral, Some(neutral_q), traversal),
        blendshapes: meshes("blendshapes", &truth.blendshapes)?,
        captures: meshes("captures", &truth.captures)?,
        tests: meshes("tests", &truth.tests)?,
        test_activations: truth
            .test_activations
            .iter()
            .enumerate()
            .map(|(k, w)| {
                let q = quantize_weights(&format!("truth.test_activations[{k}]"), w)?;
                Ok(encode_values(&q))
            })
            .collect::<Result<Vec<_>, SessionFileError>>()?,
    })
}
