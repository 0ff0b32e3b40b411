//! Uncompressed payload → [`Session`], trusting nothing.
//!
//! Every count is checked against a hard cap and against the bytes present
//! before anything sized by it is allocated; every error names the field.

use super::error::SessionFileError;
use super::geometry_codec::{decode_mesh, decode_values, dequantize_mesh, dequantize_weights};
use super::limits::{Extent, Limit, MAX_PAYLOAD_BYTES, check_duration, check_extent};
use super::series::{BLOCK, SeriesDecoder};
use super::traversal::Traversal;
use super::wire::{
    FRAME_HAS_VERTICES, FRAME_TRACKED, WireFrames, WireSession, WireTruth, decode_wire,
};
use crate::Weights;
use crate::arkit::{BLENDSHAPE_COUNT, Blendshape};
use crate::geometry::topology::Topology;
use crate::session::{
    CapturedExpression, DeviceInfo, Frame, GroundTruth, Session, SessionError, SessionParts,
    Template, TestExpression, TruePeak,
};
use glam::Vec3;

/// Decodes and validates a payload: the wire structure, the topology, the
/// template, the neutral scan, the stream, the expressions and the ground
/// truth, in that order, then the session's own checks. `early` is called
/// with the topology and the template as soon as both are decoded (before
/// the session's own checks, which may still refuse the file).
pub(super) fn decode_payload(
    payload: &[u8],
    early: impl FnOnce(&Topology, &Template),
) -> Result<Session, SessionFileError> {
    if payload.len() > MAX_PAYLOAD_BYTES {
        let limit = (Limit::PayloadBytes, payload.len() as u64);
        return Err(SessionFileError::too_large("payload", limit));
    }
    let mut wire = decode_wire(payload)?;
    check_wire_extent(&wire)?;
    let topology = decode_topology(&mut wire)?;
    let traversal = Traversal::for_mesh(&topology);
    let template_neutral_q =
        decode_mesh("template.neutral", wire.template_neutral, None, &traversal)?;
    let template = decode_template(&wire, &template_neutral_q, &traversal)?;
    early(&topology, &template);
    let neutral_q = decode_mesh("neutral", wire.neutral, None, &traversal)?;
    let frames = decode_frames(&wire.frames, &neutral_q, &traversal)?;
    let captures = decode_captures(&wire, &neutral_q, &traversal)?;
    let tests = decode_tests(&wire, &neutral_q, &traversal)?;
    let truth = wire
        .truth
        .as_ref()
        .map(|t| decode_truth(t, &neutral_q, &traversal))
        .transpose()?;
    let device = DeviceInfo {
        model: wire.device.model.to_string(),
        system_version: wire.device.system_version.to_string(),
        app_version: wire.device.app_version.to_string(),
        recorded_at: wire.device.recorded_at.to_string(),
    };
    Ok(Session::new(SessionParts {
        device,
        frame_rate: wire.frame_rate,
        topology,
        template,
        neutral: dequantize_mesh(&neutral_q),
        frames,
        captures,
        tests,
        truth,
    })?)
}

/// Checks the session's extent against the [limits](super::limits) before
/// anything is sized by it: the vertex count, the frame count, and the
/// vertices of every mesh together.
fn check_wire_extent(wire: &WireSession<'_>) -> Result<(), SessionFileError> {
    let stream_meshes = wire
        .frames
        .flags
        .iter()
        .filter(|&&f| f & FRAME_HAS_VERTICES != 0)
        .count();
    let truth_meshes = wire.truth.as_ref().map_or(0, |t| {
        1 + t.blendshapes.len() + t.captures.len() + t.tests.len()
    });
    let extent = Extent {
        vertices: wire.vertex_count as usize,
        frames: wire.frames.count as usize,
        meshes: 2
            + wire.template_shapes.len()
            + wire.captures.len()
            + wire.tests.len()
            + truth_meshes
            + stream_meshes,
    };
    check_extent(extent).map_err(|limit| {
        let field = match limit.0 {
            Limit::Vertices => "topology.vertex_count",
            Limit::Frames => "frames.count",
            _ => "meshes",
        };
        SessionFileError::too_large(field, limit)
    })
}

/// The triangle list (taken out of `wire`), once the vertex count is known
/// to be plausible.
fn decode_topology(wire: &mut WireSession<'_>) -> Result<Topology, SessionFileError> {
    // The vertex count is within MAX_VERTICES (`check_wire_extent`).
    let v = wire.vertex_count as usize;
    // Every mesh needs at least a byte per value: check against the first one
    // before sizing anything by the vertex count.
    if wire.template_neutral.len() <= 3 * v {
        let reason = format!(
            "{} bytes cannot hold {v} vertices",
            wire.template_neutral.len()
        );
        return Err(SessionFileError::corrupt("template.neutral", reason));
    }
    Ok(Topology::new(v, std::mem::take(&mut wire.triangles))?)
}

/// The template's 52 shapes, each coded against its neutral.
fn decode_template(
    wire: &WireSession<'_>,
    neutral_q: &[i32],
    traversal: &Traversal,
) -> Result<Template, SessionFileError> {
    if wire.template_shapes.len() != BLENDSHAPE_COUNT {
        return Err(SessionError::TemplateShapeCount(wire.template_shapes.len()).into());
    }
    let mut shapes = Vec::with_capacity(BLENDSHAPE_COUNT);
    for (shape, blob) in Blendshape::ALL.iter().zip(&wire.template_shapes) {
        let field = format!("template.shapes[{shape}]");
        let q = decode_mesh(&field, blob, Some(neutral_q), traversal)?;
        shapes.push(dequantize_mesh(&q));
    }
    Ok(Template::new(dequantize_mesh(neutral_q), shapes)?)
}

/// The captured expressions, meshes coded against the neutral scan.
fn decode_captures(
    wire: &WireSession<'_>,
    neutral_q: &[i32],
    traversal: &Traversal,
) -> Result<Vec<CapturedExpression>, SessionFileError> {
    let mut captures = Vec::with_capacity(wire.captures.len());
    for (k, c) in wire.captures.iter().enumerate() {
        let prompt = blendshape(&format!("captures[{k}].prompt"), c.prompt)?;
        let field = format!("captures[{k}]");
        let (weights, vertices) =
            decode_expression(&field, c.weights, c.vertices, (neutral_q, traversal))?;
        captures.push(CapturedExpression {
            prompt,
            frame: c.frame,
            weights,
            vertices,
        });
    }
    Ok(captures)
}

/// The test expressions, meshes coded against the neutral scan.
fn decode_tests(
    wire: &WireSession<'_>,
    neutral_q: &[i32],
    traversal: &Traversal,
) -> Result<Vec<TestExpression>, SessionFileError> {
    let mut tests = Vec::with_capacity(wire.tests.len());
    for (k, t) in wire.tests.iter().enumerate() {
        let field = format!("tests[{k}]");
        let (weights, vertices) =
            decode_expression(&field, t.weights, t.vertices, (neutral_q, traversal))?;
        tests.push(TestExpression {
            id: t.id.to_string(),
            frame: t.frame,
            weights,
            vertices,
        });
    }
    Ok(tests)
}

fn blendshape(field: &str, index: u8) -> Result<Blendshape, SessionFileError> {
    Blendshape::from_index(index as usize).ok_or_else(|| {
        SessionFileError::corrupt(field, format!("{index} is not an ARKit blendshape index"))
    })
}

fn decode_weights(field: &str, blob: &[u8]) -> Result<Weights, SessionFileError> {
    let q = decode_values(field, blob, BLENDSHAPE_COUNT)?;
    Ok(dequantize_weights(&q))
}

/// Decodes an expression's weights, and its mesh coded against the neutral
/// scan.
fn decode_expression(
    field: &str,
    weights: &[u8],
    vertices: &[u8],
    (neutral_q, traversal): (&[i32], &Traversal),
) -> Result<(Weights, Vec<Vec3>), SessionFileError> {
    let w = decode_weights(&format!("{field}.weights"), weights)?;
    let q = decode_mesh(
        &format!("{field}.vertices"),
        vertices,
        Some(neutral_q),
        traversal,
    )?;
    Ok((w, dequantize_mesh(&q)))
}

fn decode_frames(
    wire: &WireFrames<'_>,
    neutral_q: &[i32],
    traversal: &Traversal,
) -> Result<Vec<Frame>, SessionFileError> {
    // The count is within MAX_FRAMES (`check_wire_extent`).
    let count = wire.count as usize;
    let corrupt = |field: String, reason: String| SessionFileError::corrupt(field, reason);
    if wire.flags.len() != count {
        let reason = format!("{} flag bytes for {count} frames", wire.flags.len());
        return Err(corrupt("frames.flags".into(), reason));
    }
    if wire.timestamps.len() != 8 * count {
        let reason = format!("{} bytes for {count} timestamps", wire.timestamps.len());
        return Err(corrupt("frames.timestamps".into(), reason));
    }
    // `count` is now known to be at most the number of flag bytes present.
    let mut frames = Vec::with_capacity(count);
    let mut bits = 0u64;
    for (k, (flag, stamp)) in wire
        .flags
        .iter()
        .zip(wire.timestamps.chunks_exact(8))
        .enumerate()
    {
        if flag & !(FRAME_TRACKED | FRAME_HAS_VERTICES) != 0 {
            return Err(corrupt(
                format!("frames[{k}].flags"),
                format!("unknown bits in {flag:#04x}"),
            ));
        }
        let mut le = [0u8; 8];
        le.copy_from_slice(stamp);
        bits ^= u64::from_le_bytes(le);
        frames.push(Frame {
            timestamp: f64::from_bits(bits),
            weights: Weights::ZERO,
            tracked: flag & FRAME_TRACKED != 0,
            vertices: None,
        });
    }
    if let (Some(first), Some(last)) = (frames.first(), frames.last()) {
        check_duration(first.timestamp, last.timestamp)
            .map_err(|limit| SessionFileError::too_large("frames.timestamps", limit))?;
    }

    let series_error = |frame: usize, what: &str, reason: String| {
        corrupt(format!("frames[{frame}].{what}"), reason)
    };
    // Indexing: `frames` and `wire.flags` have `count` entries (checked
    // above), blocks cover `start..start + len` within `0..count`, and
    // `with_geometry` holds frame indices below `count`.
    let weight_order = Traversal::identity(BLENDSHAPE_COUNT);
    let mut weights = SeriesDecoder::new(wire.weights, vec![0; BLENDSHAPE_COUNT], &weight_order);
    for start in (0..count).step_by(BLOCK) {
        let len = BLOCK.min(count - start);
        let block = weights
            .next_block(len)
            .map_err(|e| series_error(e.frame, "weights", e.reason))?;
        for (frame, q) in frames[start..start + len]
            .iter_mut()
            .zip(block.chunks_exact(BLENDSHAPE_COUNT))
        {
            frame.weights = dequantize_weights(q);
        }
    }
    weights
        .finish()
        .map_err(|e| series_error(e.frame, "weights", e.reason))?;

    let with_geometry: Vec<usize> = (0..count)
        .filter(|&k| wire.flags[k] & FRAME_HAS_VERTICES != 0)
        .collect();
    // The stream index of the `g`-th frame with geometry (`count` past them).
    let geometry_frame = |g: usize| with_geometry.get(g).copied().unwrap_or(count);
    let n = neutral_q.len();
    let mut vertices = SeriesDecoder::new(wire.vertices, neutral_q.to_vec(), traversal);
    for chunk in with_geometry.chunks(BLOCK) {
        let block = vertices
            .next_block(chunk.len())
            .map_err(|e| series_error(geometry_frame(e.frame), "vertices", e.reason))?;
        for (&k, q) in chunk.iter().zip(block.chunks_exact(n)) {
            frames[k].vertices = Some(dequantize_mesh(q));
        }
    }
    vertices
        .finish()
        .map_err(|e| series_error(geometry_frame(e.frame), "vertices", e.reason))?;
    Ok(frames)
}

fn decode_truth(
    wire: &WireTruth<'_>,
    neutral_q: &[i32],
    traversal: &Traversal,
) -> Result<GroundTruth, SessionFileError> {
    let true_neutral = decode_mesh("truth.neutral", wire.neutral, Some(neutral_q), traversal)?;
    let meshes = |what: &str, blobs: &[&[u8]]| {
        blobs
            .iter()
            .enumerate()
            .map(|(k, blob)| {
                let field = format!("truth.{what}[{k}]");
                let q = decode_mesh(&field, blob, Some(&true_neutral), traversal)?;
                Ok(dequantize_mesh(&q))
            })
            .collect::<Result<Vec<_>, SessionFileError>>()
    };
    let peak_frames = wire
        .peak_frames
        .iter()
        .enumerate()
        .map(|(k, &(shape, frame))| {
            let prompt = blendshape(&format!("truth.peak_frames[{k}]"), shape)?;
            Ok(TruePeak { prompt, frame })
        })
        .collect::<Result<Vec<_>, SessionFileError>>()?;
    let blendshapes =
        <[Vec<Vec3>; BLENDSHAPE_COUNT]>::try_from(meshes("blendshapes", &wire.blendshapes)?)
            .map_err(|found| {
                SessionError::Truth(format!(
                    "{} blendshapes, expected {BLENDSHAPE_COUNT}",
                    found.len()
                ))
            })?;
    Ok(GroundTruth {
        seed: wire.seed,
        peak_frames,
        neutral: dequantize_mesh(&true_neutral),
        blendshapes,
        captures: meshes("captures", &wire.captures)?,
        tests: meshes("tests", &wire.tests)?,
        test_activations: wire
            .test_activations
            .iter()
            .enumerate()
            .map(|(k, blob)| decode_weights(&format!("truth.test_activations[{k}]"), blob))
            .collect::<Result<Vec<_>, _>>()?,
    })
}
