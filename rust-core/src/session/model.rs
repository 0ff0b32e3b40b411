//! A capture session: everything the app records in one sitting (§3.1).
//!
//! The app shows the person ARKit's 52 expressions one after another and
//! records the tracked stream; when the tracked weight of the requested shape
//! peaks it keeps that frame as a *captured expression* (weights
//! `w_{i,1..52}` and face mesh `S_i`). Test expressions, recorded the same way,
//! are held out for evaluation (§4.1). A simulated session also carries the
//! simulator's ground truth.
//!
//! Positions are in metres in ARKit's face-anchor space: +x towards the
//! person's left, +y up, +z out of the face towards the camera.

use super::error::SessionError;
use crate::arkit::{BLENDSHAPE_COUNT, Blendshape, Blendshapes, BlendshapesError, Weights};
use crate::geometry::topology::Topology;
use glam::{DVec3, Vec3};

/// Where a session was recorded.
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub struct DeviceInfo {
    /// Device model, e.g. `iPhone13,3`, or `likeness-sim` for a simulated one.
    pub model: String,
    /// Operating system version, e.g. `iOS 17.4`.
    pub system_version: String,
    /// Version of the recording app or simulator.
    pub app_version: String,
    /// When recording started, RFC 3339 (empty if unknown).
    pub recorded_at: String,
}

/// The generic ARKit template: `ARFaceGeometry(blendShapes:)` evaluated with
/// all weights zero (`neutral`) and with each single weight one (`shapes`).
#[derive(Clone, Debug, PartialEq)]
pub struct Template {
    /// Template face with all weights zero.
    pub neutral: Vec<Vec3>,
    /// Absolute positions of the template with weight `j` = 1, in Apple's
    /// order: one mesh per ARKit blendshape.
    pub shapes: [Vec<Vec3>; BLENDSHAPE_COUNT],
}

impl Template {
    /// The template's meshes as `(neutral, shapes)`, `shapes` in Apple's
    /// order; `shapes` must hold one mesh per ARKit blendshape (else
    /// [`SessionError::TemplateShapeCount`]).
    pub fn new(neutral: Vec<Vec3>, shapes: Vec<Vec<Vec3>>) -> Result<Template, SessionError> {
        let shapes = <[Vec<Vec3>; BLENDSHAPE_COUNT]>::try_from(shapes)
            .map_err(|shapes| SessionError::TemplateShapeCount(shapes.len()))?;
        Ok(Template { neutral, shapes })
    }

    /// Delta blendshape of `shape`: `shapes[j] − neutral`.
    pub fn delta(&self, shape: Blendshape) -> Vec<Vec3> {
        // Indexing: `shapes` has one mesh per blendshape index.
        self.shapes[shape.index()]
            .iter()
            .zip(&self.neutral)
            .map(|(s, n)| *s - *n)
            .collect()
    }

    /// The template as blendshapes (neutral and deltas, double precision):
    /// the generic rig whose face is found on an avatar (§3.3). An error if
    /// a shape's vertex count differs from the neutral's or a position is
    /// not finite.
    pub fn blendshapes(&self) -> Result<Blendshapes, BlendshapesError> {
        let neutral: Vec<DVec3> = self.neutral.iter().map(|p| p.as_dvec3()).collect();
        let deltas = self
            .shapes
            .iter()
            .map(|s| {
                s.iter()
                    .zip(&neutral)
                    .map(|(p, n)| p.as_dvec3() - *n)
                    .collect()
            })
            .collect();
        Blendshapes::new(neutral, deltas)
    }
}

/// One tracked frame of the stream.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    /// Seconds since the start of recording.
    pub timestamp: f64,
    /// The 52 tracked weights.
    pub weights: Weights,
    /// Whether ARKit reported the face as tracked in this frame.
    pub tracked: bool,
    /// The tracked face mesh, when the app stored geometry for this frame.
    pub vertices: Option<Vec<Vec3>>,
}

/// The expression kept for one prompt: the frame where the requested weight
/// peaked (`w_{i,·}` and `S_i` of Eq. 1).
#[derive(Clone, Debug, PartialEq)]
pub struct CapturedExpression {
    /// The blendshape the person was asked to perform.
    pub prompt: Blendshape,
    /// Index of the frame in [`SessionParts::frames`] it was taken from, if the
    /// stream was kept.
    pub frame: Option<u32>,
    /// Tracked weights at capture.
    pub weights: Weights,
    /// Tracked face mesh at capture.
    pub vertices: Vec<Vec3>,
}

/// A held-out expression for evaluation (§4.1), e.g. a smile with a squint.
#[derive(Clone, Debug, PartialEq)]
pub struct TestExpression {
    /// A short identifier, e.g. `smile-squint`.
    pub id: String,
    /// Index of the frame in [`SessionParts::frames`], if the stream was kept.
    pub frame: Option<u32>,
    /// Tracked weights.
    pub weights: Weights,
    /// Tracked face mesh (`T_i` of Eq. 5).
    pub vertices: Vec<Vec3>,
}

/// What the simulator knows and a phone never does.
#[derive(Clone, Debug, PartialEq)]
pub struct GroundTruth {
    /// Seed the subject and session were drawn from.
    pub seed: u64,
    /// For each prompt, the frame where the true activation of the requested
    /// shape peaked during the attempt that counts.
    pub peak_frames: Vec<TruePeak>,
    /// The subject's noise-free neutral face.
    pub neutral: Vec<Vec3>,
    /// The subject's own linear blendshapes (absolute, weight one each),
    /// in Apple's order: what personalization tries to recover.
    pub blendshapes: [Vec<Vec3>; BLENDSHAPE_COUNT],
    /// Noise-free face at each captured expression, in capture order.
    pub captures: Vec<Vec<Vec3>>,
    /// Noise-free face at each test expression, in test order.
    pub tests: Vec<Vec<Vec3>>,
    /// True muscle activations at each test expression.
    pub test_activations: Vec<Weights>,
}

impl GroundTruth {
    /// The frame where `prompt`'s true activation peaked, if it was prompted.
    pub fn peak_frame(&self, prompt: Blendshape) -> Option<u32> {
        self.peak_frames
            .iter()
            .find(|peak| peak.prompt == prompt)
            .map(|peak| peak.frame)
    }
}

/// Where one prompt's expression truly peaked.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TruePeak {
    /// The prompt.
    pub prompt: Blendshape,
    /// The frame of [`SessionParts::frames`] where its true activation
    /// peaked.
    pub frame: u32,
}

/// Everything recorded in one capture session, as parts that may still
/// contradict each other. [`Session::new`](super::Session::new) checks them
/// and is the only way to a [`Session`](super::Session).
#[derive(Clone, Debug, PartialEq)]
pub struct SessionParts {
    /// Recording device and software.
    pub device: DeviceInfo,
    /// Nominal frame rate of the stream in Hz (ARKit face tracking: 60).
    pub frame_rate: f32,
    /// Connectivity shared by every mesh below.
    pub topology: Topology,
    /// The generic ARKit template.
    pub template: Template,
    /// The person's neutral face scan (`B_0`).
    pub neutral: Vec<Vec3>,
    /// The tracked stream, in time order.
    pub frames: Vec<Frame>,
    /// The captured training expressions, at most one per prompt.
    pub captures: Vec<CapturedExpression>,
    /// Held-out test expressions.
    pub tests: Vec<TestExpression>,
    /// Simulator ground truth, if simulated.
    pub truth: Option<GroundTruth>,
}

impl SessionParts {
    /// Length of the stream in seconds (last minus first timestamp).
    pub fn duration(&self) -> f64 {
        match (self.frames.first(), self.frames.last()) {
            (Some(a), Some(b)) => b.timestamp - a.timestamp,
            _ => 0.0,
        }
    }

    /// The captured expression for `prompt`, if it was captured.
    pub fn capture(&self, prompt: Blendshape) -> Option<&CapturedExpression> {
        self.captures.iter().find(|c| c.prompt == prompt)
    }
}
