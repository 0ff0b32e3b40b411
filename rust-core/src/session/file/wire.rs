//! The payload as it sits on disk, kept apart from the in-memory types so
//! that either can change without silently changing the other.
//!
//! The payload is this struct in bincode 2's standard configuration
//! (little-endian, variable-length integers). Strings and byte blobs are
//! borrowed from the payload, so decoding them allocates nothing and a
//! declared length is checked against the bytes actually present. Blobs are
//! varint streams written by [`geometry_codec`](super::geometry_codec)
//! (single meshes and weight vectors) and [`series`](super::series) (the
//! frame stream); meshes are `3 × vertex_count` values in planar order.
//!
//! bincode writes a struct as its fields one after the other, so
//! [`decode_wire`] reads the payload one field at a time: a payload that
//! ends early or holds a malformed value is blamed on the field, in our
//! words rather than bincode's.

use super::error::SessionFileError;
use bincode::config::{Configuration, Limit, LittleEndian, Varint};
use bincode::error::DecodeError;
use serde::{Deserialize, Serialize};

/// bincode's standard configuration, with reads capped at
/// [`MAX_PAYLOAD_BYTES`](super::MAX_PAYLOAD_BYTES).
pub fn bincode_config() -> Configuration<LittleEndian, Varint, Limit<{ super::MAX_PAYLOAD_BYTES }>>
{
    bincode::config::standard().with_limit()
}

/// The whole session.
#[derive(Debug, Serialize, Deserialize)]
pub struct WireSession<'a> {
    /// Recording device and software.
    #[serde(borrow)]
    pub device: WireDevice<'a>,
    /// Nominal frame rate in Hz.
    pub frame_rate: f32,
    /// Vertex count shared by every mesh.
    pub vertex_count: u32,
    /// Triangles, as vertex indices.
    pub triangles: Vec<[u32; 3]>,
    /// Template neutral, an absolute mesh (coded against zero, then
    /// spatially).
    pub template_neutral: &'a [u8],
    /// Template shapes in Apple's order, each coded against the template
    /// neutral.
    #[serde(borrow)]
    pub template_shapes: Vec<&'a [u8]>,
    /// Neutral scan, an absolute mesh.
    pub neutral: &'a [u8],
    /// The tracked stream.
    #[serde(borrow)]
    pub frames: WireFrames<'a>,
    /// Captured expressions.
    #[serde(borrow)]
    pub captures: Vec<WireCapture<'a>>,
    /// Test expressions.
    #[serde(borrow)]
    pub tests: Vec<WireTest<'a>>,
    /// Simulator ground truth.
    #[serde(borrow)]
    pub truth: Option<WireTruth<'a>>,
}

/// [`DeviceInfo`](crate::DeviceInfo) on disk.
#[derive(Debug, Serialize, Deserialize)]
pub struct WireDevice<'a> {
    /// Device model.
    pub model: &'a str,
    /// Operating system version.
    pub system_version: &'a str,
    /// App or simulator version.
    pub app_version: &'a str,
    /// Start of recording, RFC 3339.
    pub recorded_at: &'a str,
}

/// Bit 0 of a frame's flag byte: ARKit tracked the face.
pub const FRAME_TRACKED: u8 = 1;
/// Bit 1 of a frame's flag byte: the frame has a mesh in `vertices`.
pub const FRAME_HAS_VERTICES: u8 = 2;

/// The frame stream, column by column.
#[derive(Debug, Serialize, Deserialize)]
pub struct WireFrames<'a> {
    /// Number of frames.
    pub count: u32,
    /// 8 bytes per frame: the f64 timestamp's bits XOR the previous
    /// timestamp's bits (the first XOR 0), little-endian. Lossless.
    pub timestamps: &'a [u8],
    /// 1 byte per frame: [`FRAME_TRACKED`] | [`FRAME_HAS_VERTICES`].
    pub flags: &'a [u8],
    /// The weights of every frame, a time series of 52-value frames starting
    /// from zero.
    pub weights: &'a [u8],
    /// The meshes of the frames that have one, a time series starting from
    /// the neutral scan.
    pub vertices: &'a [u8],
}

/// A captured expression.
#[derive(Debug, Serialize, Deserialize)]
pub struct WireCapture<'a> {
    /// The prompt's blendshape index in Apple's order.
    pub prompt: u8,
    /// Index of the frame it was taken from.
    pub frame: Option<u32>,
    /// The 52 weights, as plain values.
    pub weights: &'a [u8],
    /// The mesh, coded against the neutral scan.
    pub vertices: &'a [u8],
}

/// A test expression.
#[derive(Debug, Serialize, Deserialize)]
pub struct WireTest<'a> {
    /// Its identifier.
    pub id: &'a str,
    /// Index of the frame it was taken from.
    pub frame: Option<u32>,
    /// The 52 weights, as plain values.
    pub weights: &'a [u8],
    /// The mesh, coded against the neutral scan.
    pub vertices: &'a [u8],
}

/// [`GroundTruth`](crate::GroundTruth) on disk.
#[derive(Debug, Serialize, Deserialize)]
pub struct WireTruth<'a> {
    /// Seed of the simulated subject and session.
    pub seed: u64,
    /// `(blendshape index, frame)` of each true peak.
    pub peak_frames: Vec<(u8, u32)>,
    /// True neutral, coded against the neutral scan.
    pub neutral: &'a [u8],
    /// True blendshapes, each coded against the true neutral.
    #[serde(borrow)]
    pub blendshapes: Vec<&'a [u8]>,
    /// Noise-free captured faces, each coded against the true neutral.
    #[serde(borrow)]
    pub captures: Vec<&'a [u8]>,
    /// Noise-free test faces, each coded against the true neutral.
    #[serde(borrow)]
    pub tests: Vec<&'a [u8]>,
    /// True activations at each test, as plain values.
    #[serde(borrow)]
    pub test_activations: Vec<&'a [u8]>,
}

/// The rest of a payload, read one field at a time.
struct Fields<'a> {
    rest: &'a [u8],
}

impl<'a> Fields<'a> {
    /// Decodes the next field, named `field` in errors.
    fn next<T: Deserialize<'a>>(&mut self, field: &str) -> Result<T, SessionFileError> {
        let (value, used): (T, usize) =
            bincode::serde::borrow_decode_from_slice(self.rest, bincode_config())
                .map_err(|e| SessionFileError::corrupt(field, describe(&e)))?;
        // Indexing: bincode never reports more bytes used than it was given.
        self.rest = &self.rest[used.min(self.rest.len())..];
        Ok(value)
    }
}

/// What a bincode error means for the payload, in our words.
fn describe(error: &DecodeError) -> String {
    match error {
        DecodeError::UnexpectedEnd { .. } => "the payload ends inside this field".into(),
        DecodeError::LimitExceeded => "declares more bytes than a payload may hold".into(),
        DecodeError::Utf8 { .. } | DecodeError::InvalidCharEncoding(_) => {
            "text that is not UTF-8".into()
        }
        DecodeError::UnexpectedVariant { .. } | DecodeError::InvalidBooleanValue(_) => {
            "an invalid tag".into()
        }
        DecodeError::OutsideUsizeRange(_) | DecodeError::InvalidIntegerType { .. } => {
            "a number out of range".into()
        }
        _ => "malformed".into(),
    }
}

/// The payload's structure, which must use every byte; strings and blobs
/// are borrowed from `payload`.
pub fn decode_wire(payload: &[u8]) -> Result<WireSession<'_>, SessionFileError> {
    let mut f = Fields { rest: payload };
    // Fields are evaluated in the order written, which is the order on disk.
    let wire = WireSession {
        device: f.next("device")?,
        frame_rate: f.next("frame_rate")?,
        vertex_count: f.next("topology.vertex_count")?,
        triangles: f.next("topology.triangles")?,
        template_neutral: f.next("template.neutral")?,
        template_shapes: f.next("template.shapes")?,
        neutral: f.next("neutral")?,
        frames: WireFrames {
            count: f.next("frames.count")?,
            timestamps: f.next("frames.timestamps")?,
            flags: f.next("frames.flags")?,
            weights: f.next("frames.weights")?,
            vertices: f.next("frames.vertices")?,
        },
        captures: f.next("captures")?,
        tests: f.next("tests")?,
        truth: f.next("truth")?,
    };
    if !f.rest.is_empty() {
        let reason = format!("{} unexpected bytes after the session", f.rest.len());
        return Err(SessionFileError::corrupt("payload", reason));
    }
    Ok(wire)
}
