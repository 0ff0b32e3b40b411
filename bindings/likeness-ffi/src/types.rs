//! The records that cross the boundary, and the conversions between flat
//! arrays (as ARKit and Swift hold them) and the core's meshes and
//! weights. Every conversion names the field it refuses.

use crate::error::LikenessError;
use glam::{DVec3, Vec3};
use likeness::arkit::{BLENDSHAPE_COUNT, Blendshape, Weights};
use likeness::capture::guided_capture::Progress;
use likeness::capture::recorder::StepInfo;
use likeness::capture::session_summary;
use likeness::geometry::Topology;
use likeness::session::{Frame, Session, Template};

/// ARKit's generic face: `ARFaceGeometry(blendShapes:)` with no weight
/// set (`neutral`) and with each single weight at one (`shapes`, in
/// `arkitNames()` order); positions are xyz flattened, in metres.
#[derive(Clone, Debug, PartialEq, uniffi::Record)]
pub struct FaceTemplate {
    /// `ARFaceGeometry.triangleIndices`, three per triangle.
    pub triangles: Vec<u32>,
    /// The neutral face's vertices, xyz flattened.
    pub neutral: Vec<f32>,
    /// 52 faces, each the full vertex positions with one weight at one.
    pub shapes: Vec<Vec<f32>>,
}

/// One step of the guided capture as the app shows it.
#[derive(Clone, Debug, PartialEq, uniffi::Record)]
pub struct Prompt {
    /// Its position among all steps (0 is the neutral scan).
    pub index: u32,
    /// Steps in all.
    pub total: u32,
    /// `neutral` or the ARKit name.
    pub name: String,
    /// What to tell the person.
    pub instruction: String,
    /// Whether this is the neutral scan.
    pub is_neutral: bool,
}

/// How far along the capture is.
#[derive(Clone, Debug, PartialEq, uniffi::Record)]
pub struct CaptureProgress {
    /// Steps captured (the neutral scan included).
    pub captured: u32,
    /// Steps skipped without a capture.
    pub skipped: u32,
    /// Steps in all.
    pub total: u32,
    /// Share of the steps done, in `[0, 1]`.
    pub fraction: f64,
    /// Whether the capture ended at its length limit (10 minutes or 36,000
    /// frames): the steps left were skipped, what was captured is kept, no
    /// retake is possible.
    pub ended_at_limit: bool,
}

/// A personalization method.
#[derive(Clone, Debug, PartialEq, uniffi::Record)]
pub struct MethodInfo {
    /// Its name, as `personalize(method:)` takes it.
    pub name: String,
    /// What it does, in one sentence.
    pub description: String,
}

/// A session's captures in words.
#[derive(Clone, Debug, PartialEq, uniffi::Record)]
pub struct QualitySummary {
    /// One line for the top of the review screen.
    pub headline: String,
    /// Prompts captured, of 52.
    pub captured: u32,
    /// ARKit names of the prompts not captured.
    pub skipped: Vec<String>,
    /// One sentence per quality flag, each starting with the prompt's name.
    pub warnings: Vec<String>,
}

/// The person's avatar.
#[derive(Clone, Debug, PartialEq, uniffi::Record)]
pub struct AvatarResult {
    /// The GLB file's bytes.
    pub glb: Vec<u8>,
    /// The 52 × k map from ARKit's weights to the avatar's own targets
    /// (format in the project's docs/avatar.md, "The retarget map").
    pub retarget_map_json: String,
    /// A few sentences on what was made.
    pub summary: String,
    /// What the avatar lacked (the avatar is made anyway).
    pub warnings: Vec<String>,
    /// Whose face the avatar has at rest.
    pub rest_face: crate::personalized::RestFaceChoice,
}

/// One frame of a recorded stream, as `CaptureSession.push_frame` takes it
///.
#[derive(Clone, Debug, PartialEq, uniffi::Record)]
pub struct RecordedFrame {
    /// Seconds since the start of recording.
    pub timestamp: f64,
    /// The 52 weights in `arkitNames()` order.
    pub weights: Vec<f32>,
    /// The face mesh, xyz flattened; empty when the session did not keep
    /// this frame's mesh.
    pub vertices: Vec<f32>,
    /// Whether the face was tracked.
    pub tracked: bool,
}

/// One step of a capture under way, for a review screen.
#[derive(Clone, Debug, PartialEq, uniffi::Record)]
pub struct CaptureInfo {
    /// The step.
    pub prompt: Prompt,
    /// Index of the captured frame among the frames pushed, `None` if not
    /// captured (yet).
    pub frame: Option<u64>,
    /// The capture's quality flags in words.
    pub warnings: Vec<String>,
    /// For an expression captured, the prompted weight at the captured
    /// frame (0–1, for a weight bar); `None` otherwise.
    pub weight: Option<f32>,
    /// Whether the step was skipped without a capture.
    pub skipped: bool,
}

/// `n` as the boundary's `u32` (every count here is far below its limit).
pub(crate) fn count(n: usize) -> u32 {
    u32::try_from(n).unwrap_or(u32::MAX)
}

/// Flat xyz values as points; `field` names them in the error.
pub(crate) fn points(field: &str, flat: &[f32]) -> Result<Vec<Vec3>, LikenessError> {
    if !flat.len().is_multiple_of(3) {
        return Err(LikenessError::invalid(format!(
            "{field}: {} values are not a whole number of xyz points",
            flat.len()
        )));
    }
    Ok(flat
        .chunks_exact(3)
        .map(|p| Vec3::new(p[0], p[1], p[2]))
        .collect())
}

/// `points` as little-endian `f32` x, y, z after x, y, z.
pub(crate) fn packed(points: &[Vec3]) -> Vec<u8> {
    points
        .iter()
        .flat_map(|p| p.to_array())
        .flat_map(f32::to_le_bytes)
        .collect()
}

/// Points from little-endian 32-bit floats, xyz after xyz; `field` names
/// them in the error.
pub(crate) fn packed_points(field: &str, bytes: &[u8]) -> Result<Vec<Vec3>, LikenessError> {
    const POINT: usize = 3 * size_of::<f32>();
    if !bytes.len().is_multiple_of(POINT) {
        return Err(LikenessError::invalid(format!(
            "{field}: {} bytes are not a whole number of xyz points of three little-endian 32-bit floats",
            bytes.len()
        )));
    }
    let float = |b: &[u8]| f32::from_le_bytes([b[0], b[1], b[2], b[3]]);
    Ok(bytes
        .chunks_exact(POINT)
        .map(|p| Vec3::new(float(&p[0..4]), float(&p[4..8]), float(&p[8..12])))
        .collect())
}

/// Points as flat xyz values.
pub(crate) fn flat(points: &[Vec3]) -> Vec<f32> {
    points.iter().flat_map(|p| p.to_array()).collect()
}

/// Double-precision points as flat single-precision xyz values.
pub(crate) fn flat_f64(points: &[DVec3]) -> Vec<f32> {
    points.iter().flat_map(|p| p.as_vec3().to_array()).collect()
}

/// 52 finite weights in ARKit's order; `field` names them in the error.
pub(crate) fn weights(field: &str, values: &[f32]) -> Result<Weights, LikenessError> {
    let array: [f32; BLENDSHAPE_COUNT] = values.try_into().map_err(|_| {
        LikenessError::invalid(format!(
            "{field}: {} values, expected {BLENDSHAPE_COUNT} in arkitNames() order",
            values.len()
        ))
    })?;
    let weights = Weights(array);
    if let Some((shape, value)) = weights.iter().find(|(_, w)| !w.is_finite()) {
        return Err(LikenessError::invalid(format!(
            "{field}: {shape} is {value}, not a finite number"
        )));
    }
    Ok(weights)
}

impl FaceTemplate {
    /// The template as the core's topology and meshes (vertex counts and
    /// finiteness are the core's to check).
    pub(crate) fn to_core(&self) -> Result<(Topology, Template), LikenessError> {
        let neutral = points("template neutral", &self.neutral)?;
        if !self.triangles.len().is_multiple_of(3) {
            return Err(LikenessError::invalid(format!(
                "template triangles: {} indices are not a whole number of triangles",
                self.triangles.len()
            )));
        }
        let triangles = self
            .triangles
            .chunks_exact(3)
            .map(|t| [t[0], t[1], t[2]])
            .collect();
        let topology = Topology::new(neutral.len(), triangles)
            .map_err(|e| LikenessError::invalid(format!("template triangles: {e}")))?;
        let shapes = self
            .shapes
            .iter()
            .enumerate()
            .map(|(j, s)| {
                let name = Blendshape::from_index(j).map_or("extra", Blendshape::name);
                points(&format!("template shapes[{j}] ({name})"), s)
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok((topology, Template::new(neutral, shapes)?))
    }

    /// A session's template, flattened.
    pub(crate) fn of(session: &Session) -> FaceTemplate {
        FaceTemplate {
            triangles: session
                .topology
                .triangles()
                .iter()
                .flatten()
                .copied()
                .collect(),
            neutral: flat(&session.template.neutral),
            shapes: session.template.shapes.iter().map(|s| flat(s)).collect(),
        }
    }
}

impl From<&StepInfo> for Prompt {
    fn from(info: &StepInfo) -> Self {
        Prompt {
            index: count(info.index),
            total: count(info.total),
            name: info.name.clone(),
            instruction: info.instruction.clone(),
            is_neutral: info.step == likeness::capture::guided_capture::Step::Neutral,
        }
    }
}

impl CaptureProgress {
    /// `p`, and whether the capture ended at its length limit.
    pub(crate) fn new(p: Progress, ended_at_limit: bool) -> Self {
        CaptureProgress {
            captured: count(p.captured),
            skipped: count(p.skipped),
            total: count(p.total),
            fraction: p.fraction(),
            ended_at_limit,
        }
    }
}

impl From<session_summary::QualitySummary> for QualitySummary {
    fn from(s: session_summary::QualitySummary) -> Self {
        QualitySummary {
            headline: s.headline,
            captured: count(s.captured),
            skipped: s.skipped.iter().map(|b| b.name().to_string()).collect(),
            warnings: s.warnings,
        }
    }
}

impl From<&Frame> for RecordedFrame {
    fn from(f: &Frame) -> Self {
        RecordedFrame {
            timestamp: f.timestamp,
            weights: f.weights.0.to_vec(),
            vertices: f.vertices.as_deref().map(flat).unwrap_or_default(),
            tracked: f.tracked,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arrays_of_the_wrong_size_or_not_finite_are_refused_by_name() {
        let e = points("vertices", &[0.0; 7]).unwrap_err();
        assert!(e.to_string().contains("vertices: 7 values"), "{e}");
        assert_eq!(
            points("v", &[1.0, 2.0, 3.0]).unwrap(),
            [Vec3::new(1.0, 2.0, 3.0)]
        );
        let e = weights("weights", &[0.0; 51]).unwrap_err();
        assert!(e.to_string().contains("51 values, expected 52"), "{e}");
        let mut w = [0.0; 52];
        w[Blendshape::JawOpen.index()] = f32::INFINITY;
        let e = weights("weights", &w).unwrap_err();
        assert!(e.to_string().contains("jawOpen is inf"), "{e}");
        assert_eq!(
            flat(&points("v", &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0]).unwrap()).len(),
            6
        );
    }

    #[test]
    fn a_template_of_51_shapes_or_broken_triangles_is_refused() {
        let template = FaceTemplate {
            triangles: vec![0, 1, 2],
            neutral: vec![0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0],
            shapes: vec![vec![0.0; 9]; 51],
        };
        let e = template.to_core().unwrap_err();
        assert!(e.to_string().contains("51 blendshapes, expected 52"), "{e}");
        let broken = FaceTemplate {
            triangles: vec![0, 1, 3],
            ..template
        };
        let e = broken.to_core().unwrap_err();
        assert!(e.to_string().contains("template triangles"), "{e}");
    }
}
