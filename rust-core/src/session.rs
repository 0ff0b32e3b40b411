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

use crate::arkit_names::{BLENDSHAPE_COUNT, Blendshape, Weights};
use crate::topology::{GeometryError, Topology};
use glam::Vec3;

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
    /// order; always [`BLENDSHAPE_COUNT`] meshes.
    pub shapes: Vec<Vec<Vec3>>,
}

impl Template {
    /// Delta blendshape of `shape`: `shapes[j] − neutral`, or `None` if the
    /// template lacks that shape (an unvalidated template).
    pub fn delta(&self, shape: Blendshape) -> Option<Vec<Vec3>> {
        let mesh = self.shapes.get(shape.index())?;
        Some(
            mesh.iter()
                .zip(&self.neutral)
                .map(|(s, n)| *s - *n)
                .collect(),
        )
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
    /// Index of the frame in [`Session::frames`] it was taken from, if the
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
    /// Index of the frame in [`Session::frames`], if the stream was kept.
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
    pub peak_frames: Vec<(Blendshape, u32)>,
    /// The subject's noise-free neutral face.
    pub neutral: Vec<Vec3>,
    /// The subject's own linear blendshapes (absolute, weight one each),
    /// in Apple's order: what personalization tries to recover.
    pub blendshapes: Vec<Vec<Vec3>>,
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
            .find(|(shape, _)| *shape == prompt)
            .map(|(_, frame)| *frame)
    }
}

/// Everything recorded in one capture session.
#[derive(Clone, Debug, PartialEq)]
pub struct Session {
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

/// A session whose parts contradict each other; the message names the part.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SessionError {
    /// A mesh does not fit the topology.
    #[error(transparent)]
    Geometry(#[from] GeometryError),
    /// The template does not have one mesh per ARKit blendshape.
    #[error("template has {0} blendshapes, expected {BLENDSHAPE_COUNT}")]
    TemplateShapeCount(usize),
    /// A weight is NaN or infinite.
    #[error("{what}: weight {shape} is {value}")]
    BadWeight {
        /// Which frame or expression.
        what: String,
        /// Which weight.
        shape: Blendshape,
        /// Its value.
        value: f32,
    },
    /// Timestamps are not finite, or go backwards.
    #[error("frame {frame}: timestamp {timestamp} is not finite or earlier than the frame before")]
    Timestamp {
        /// Index of the offending frame.
        frame: usize,
        /// Its timestamp.
        timestamp: f64,
    },
    /// An expression refers to a frame that is not in the stream.
    #[error("{what}: refers to frame {frame}, but the stream has {frames} frames")]
    FrameIndex {
        /// Which expression.
        what: String,
        /// The frame it names.
        frame: u32,
        /// Number of frames.
        frames: usize,
    },
    /// The same prompt was captured twice.
    #[error("prompt {0} is captured more than once")]
    DuplicateCapture(Blendshape),
    /// The frame rate is not a positive finite number.
    #[error("frame rate {0} is not a positive number")]
    FrameRate(f32),
    /// Ground truth has the wrong number of entries for something.
    #[error("ground truth: {0}")]
    Truth(String),
}

impl Session {
    /// Checks every invariant a reader may rely on: every mesh fits the
    /// topology and is finite, weights are finite, time runs forward, frame
    /// references exist, and each prompt is captured at most once.
    pub fn validate(&self) -> Result<(), SessionError> {
        self.validate_expressions()?;
        let mut previous = f64::NEG_INFINITY;
        for (i, frame) in self.frames.iter().enumerate() {
            if !frame.timestamp.is_finite() || frame.timestamp < previous {
                return Err(SessionError::Timestamp {
                    frame: i,
                    timestamp: frame.timestamp,
                });
            }
            previous = frame.timestamp;
            self.validate_frame(i)?;
        }
        Ok(())
    }

    /// Checks frame `i`'s weights and mesh (not its timestamp): what a method
    /// that uses a few stream frames needs.
    pub fn validate_frame(&self, i: usize) -> Result<(), SessionError> {
        let Some(frame) = self.frames.get(i) else {
            return Err(SessionError::FrameIndex {
                what: "stream".to_string(),
                frame: i as u32,
                frames: self.frames.len(),
            });
        };
        check_weights(&format!("frame {i}"), &frame.weights)?;
        if let Some(v) = &frame.vertices {
            self.topology.check_positions(&format!("frame {i}"), v)?;
        }
        Ok(())
    }

    /// Checks everything but the stream: frame rate, template, neutral scan,
    /// captures, test expressions and ground truth. Personalization calls
    /// this (and [`Session::validate_frame`] for the frames it uses) instead
    /// of [`Session::validate`], which also walks every streamed mesh.
    pub fn validate_expressions(&self) -> Result<(), SessionError> {
        let topo = &self.topology;
        if !(self.frame_rate.is_finite() && self.frame_rate > 0.0) {
            return Err(SessionError::FrameRate(self.frame_rate));
        }
        topo.check_positions("template neutral", &self.template.neutral)?;
        if self.template.shapes.len() != BLENDSHAPE_COUNT {
            return Err(SessionError::TemplateShapeCount(self.template.shapes.len()));
        }
        for (shape, mesh) in Blendshape::ALL.iter().zip(&self.template.shapes) {
            topo.check_positions(&format!("template {shape}"), mesh)?;
        }
        topo.check_positions("neutral", &self.neutral)?;
        let mut seen = [false; BLENDSHAPE_COUNT];
        for capture in &self.captures {
            let what = format!("capture {}", capture.prompt);
            if std::mem::replace(&mut seen[capture.prompt.index()], true) {
                return Err(SessionError::DuplicateCapture(capture.prompt));
            }
            self.check_frame_ref(&what, capture.frame)?;
            check_weights(&what, &capture.weights)?;
            topo.check_positions(&what, &capture.vertices)?;
        }
        for test in &self.tests {
            let what = format!("test expression {:?}", test.id);
            self.check_frame_ref(&what, test.frame)?;
            check_weights(&what, &test.weights)?;
            topo.check_positions(&what, &test.vertices)?;
        }
        if let Some(truth) = &self.truth {
            self.validate_truth(truth)?;
        }
        Ok(())
    }

    fn validate_truth(&self, truth: &GroundTruth) -> Result<(), SessionError> {
        let topo = &self.topology;
        let counts = [
            ("blendshapes", truth.blendshapes.len(), BLENDSHAPE_COUNT),
            ("captures", truth.captures.len(), self.captures.len()),
            ("tests", truth.tests.len(), self.tests.len()),
            (
                "test activations",
                truth.test_activations.len(),
                self.tests.len(),
            ),
        ];
        for (what, found, expected) in counts {
            if found != expected {
                return Err(SessionError::Truth(format!(
                    "{found} {what}, expected {expected}"
                )));
            }
        }
        topo.check_positions("true neutral", &truth.neutral)?;
        let meshes = truth
            .blendshapes
            .iter()
            .chain(&truth.captures)
            .chain(&truth.tests);
        for (k, mesh) in meshes.enumerate() {
            topo.check_positions(&format!("ground-truth mesh {k}"), mesh)?;
        }
        for (shape, frame) in &truth.peak_frames {
            self.check_frame_ref(&format!("true peak of {shape}"), Some(*frame))?;
        }
        for (k, w) in truth.test_activations.iter().enumerate() {
            check_weights(&format!("true activation of test {k}"), w)?;
        }
        Ok(())
    }

    fn check_frame_ref(&self, what: &str, frame: Option<u32>) -> Result<(), SessionError> {
        match frame {
            Some(f) if f as usize >= self.frames.len() => Err(SessionError::FrameIndex {
                what: what.to_string(),
                frame: f,
                frames: self.frames.len(),
            }),
            _ => Ok(()),
        }
    }

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

fn check_weights(what: &str, weights: &Weights) -> Result<(), SessionError> {
    match weights.iter().find(|(_, w)| !w.is_finite()) {
        Some((shape, value)) => Err(SessionError::BadWeight {
            what: what.to_string(),
            shape,
            value,
        }),
        None => Ok(()),
    }
}
