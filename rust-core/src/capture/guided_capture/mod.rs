//! §3.1, the guided capture: the state machine the app drives one frame at a
//! time. Neutral scan → the 52 prompts in [`PROMPT_ORDER`] → optional test
//! expressions (§4.1) → finished. The app shows [`Step::instruction`] and the
//! [`progress`](GuidedCapture::progress), and reacts to the
//! [`CaptureEvent`]s; every rule lives here. The same frames in give the
//! same captures out: nothing depends on wall-clock time, only on the
//! frames' timestamps.
//!
//! Each expression prompt runs a [`PeakDetector`] on the requested weight;
//! a test expression runs one on the expression's intensity
//! ([`test_intensity`]) above each weight's minimum since the step began. Untracked frames are not fed to the detectors
//! (ARKit repeats its last estimate while it has lost the face) but are
//! remembered for the [`CaptureQuality::tracking_lost`] flag.
//!
//! | paper | what | file |
//! |---|---|---|
//! | §3.1 "scans their own face in a neutral expression" | every weight low and the face still for a second | [`neutral_detector`] |
//! | §3.1 "captures the facial expression when the requested expression is performed to a sufficient extent" | weak, dominated, tracking lost | [`capture_quality`] |
//! | §3.1, beyond the paper: a weight clamped at 1 over the peak | the peak from the companion weights or the mesh | [`saturated_peak`] |
//! | §3.1 | steps, events, skip, retake, timeouts (the types here) | `mod.rs`, `state_machine.rs` |

pub mod capture_quality;
pub mod neutral_detector;
pub mod saturated_peak;

pub use capture_quality::{CaptureQuality, QualityConfig};
pub use neutral_detector::{NeutralConfig, NeutralDetector, NeutralScan};

use crate::arkit::{Blendshape, Weights};
use crate::capture::peak_detector::{Peak, PeakDetector, PeakDetectorConfig};
use crate::capture::prompt_order::{PROMPT_ORDER, instruction};
use crate::capture::rest_levels::RestLevels;
use crate::session::Frame;
use glam::Vec3;
use saturated_peak::StretchFrame;
use std::collections::VecDeque;

/// One step of the guided capture.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Step {
    /// The neutral scan.
    Neutral,
    /// One of the 52 expression prompts.
    Expression(Blendshape),
    /// The test expression at this index of [`GuidedCaptureConfig::tests`].
    Test(usize),
}

/// A held-out test expression the app asks for after the 52 prompts.
#[derive(Clone, Debug, PartialEq)]
pub struct TestPrompt {
    /// Its name, e.g. `smile-squint` (kept in the session file).
    pub id: String,
    /// What the app shows, e.g. "Smile and squint".
    pub instruction: String,
}

/// Why a step was skipped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SkipReason {
    /// No capture within [`GuidedCaptureConfig::step_timeout`].
    TimedOut,
    /// The person asked to skip ([`GuidedCapture::skip`]).
    Requested,
    /// The capture reached the longest a session holds and ended
    /// ([`GuidedCapture::end`]).
    CaptureEnded,
}

impl SkipReason {
    /// The reason in words, for the person.
    pub const fn description(self) -> &'static str {
        match self {
            SkipReason::TimedOut => "timed out: the expression was not seen in time",
            SkipReason::Requested => "skipped on request",
            SkipReason::CaptureEnded => "not reached: the capture ended at its length limit",
        }
    }
}

/// What the app hears back after each call.
#[derive(Clone, Debug, PartialEq)]
pub enum CaptureEvent {
    /// A step begins: show its instruction.
    Started(Step),
    /// The step was captured at stream frame `frame`.
    Captured {
        /// The step.
        step: Step,
        /// Index of the captured frame in the stream fed so far.
        frame: u64,
        /// Flags for the app to offer a retake.
        quality: CaptureQuality,
    },
    /// The step was skipped.
    Skipped {
        /// The step.
        step: Step,
        /// Why.
        reason: SkipReason,
    },
    /// No step is left.
    Finished {
        /// Steps with a capture (neutral included).
        captured: usize,
        /// Steps without one.
        skipped: usize,
    },
}

/// Everything the guided capture can be told; [`Default`] gives the
/// documented values and no test expressions.
#[derive(Clone, Debug, PartialEq)]
pub struct GuidedCaptureConfig {
    /// The peak detector of each expression prompt.
    pub peak: PeakDetectorConfig,
    /// The peak detector of each test expression, on [`test_intensity`]
    /// (default threshold 0.3 and re-arm level 0.15: the mildest recipe, two
    /// or three shapes at 0.2–0.4, sums to about 0.4 past the dead zone).
    pub test_peak: PeakDetectorConfig,
    /// When the face counts as neutral.
    pub neutral: NeutralConfig,
    /// The quality flags.
    pub quality: QualityConfig,
    /// Rest levels of the neutral scan at or below this are ARKit's usual
    /// small offsets and count as 0 (default 0.1); above it, an expression
    /// weight is measured from its rest level ([`crate::capture::rest_levels`]).
    pub rest_floor: f32,
    /// Seconds a prompt or test waits for its expression before it is
    /// skipped (default 10: reaction 0.5 s, a failed try and a second one
    /// take 3–4 s; a person who has not managed in 10 s needs a skip).
    pub step_timeout: f64,
    /// Test expressions asked for after the prompts, in order.
    pub tests: Vec<TestPrompt>,
}

impl Default for GuidedCaptureConfig {
    fn default() -> Self {
        GuidedCaptureConfig {
            peak: PeakDetectorConfig::default(),
            test_peak: PeakDetectorConfig {
                threshold: 0.3,
                rearm_below: 0.15,
                ..PeakDetectorConfig::default()
            },
            neutral: NeutralConfig::default(),
            quality: QualityConfig::default(),
            rest_floor: 0.1,
            step_timeout: 10.0,
            tests: Vec::new(),
        }
    }
}

impl GuidedCaptureConfig {
    /// Every step in the order they are asked for: neutral, the 52 prompts,
    /// the tests.
    pub fn steps(&self) -> impl Iterator<Item = Step> + use<> {
        std::iter::once(Step::Neutral)
            .chain(PROMPT_ORDER.iter().map(|s| Step::Expression(*s)))
            .chain((0..self.tests.len()).map(Step::Test))
    }
}

/// A weight at most this far above its baseline does not count towards a
/// test expression's intensity: 0.05 is about four times the frame noise of
/// one ARKit weight, so 52 noisy weights add next to nothing.
pub const TEST_INTENSITY_DEAD_ZONE: f32 = 0.05;

/// Intensity of a free expression: Σⱼ max(wⱼ − bⱼ − δ, 0), with δ
/// [`TEST_INTENSITY_DEAD_ZONE`] and b the baseline. All the shapes of a
/// combined expression rise and fall together, so it peaks when the
/// expression does, whatever it is made of.
///
/// The state machine's baseline is each weight's minimum since the test
/// step began: the previous expression, still fading when the step starts,
/// then counts for nothing (it only falls), and a shape the new expression
/// shares with the previous one counts from the valley between them.
pub fn test_intensity(weights: &Weights, baseline: &Weights) -> f32 {
    weights
        .0
        .iter()
        .zip(&baseline.0)
        .map(|(w, b)| {
            let w = if w.is_finite() { *w } else { 0.0 };
            (w - b - TEST_INTENSITY_DEAD_ZONE).max(0.0)
        })
        .sum()
}

/// One captured step.
#[derive(Clone, Debug, PartialEq)]
pub struct Capture {
    /// Index of the captured frame in the stream.
    pub frame: u64,
    /// Its timestamp (s).
    pub timestamp: f64,
    /// All 52 weights there.
    pub weights: Weights,
    /// The mesh there, if the frame carried one.
    pub vertices: Option<Vec<Vec3>>,
    /// Quality flags (all clear for the neutral scan unless tracking).
    pub quality: CaptureQuality,
}

/// How far along the capture is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Progress {
    /// Steps in all: neutral + 52 + tests.
    pub total: usize,
    /// Steps with a capture.
    pub captured: usize,
    /// Steps skipped without a capture.
    pub skipped: usize,
    /// The step under way, `None` when finished.
    pub current: Option<Step>,
}

impl Progress {
    /// Share of the steps done, captured or skipped, in `[0, 1]` (a
    /// retake after the end counts nothing twice).
    pub fn fraction(&self) -> f64 {
        if self.total == 0 {
            return 1.0;
        }
        ((self.captured + self.skipped) as f64 / self.total as f64).min(1.0)
    }
}

/// A call the state machine cannot take.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum GuidedCaptureError {
    /// Frames must come in time order.
    #[error(
        "frame {frame}: timestamp {timestamp} s is earlier than the previous frame's {previous} s"
    )]
    TimeWentBack {
        /// Index the frame would have had.
        frame: u64,
        /// Its timestamp.
        timestamp: f64,
        /// The previous frame's.
        previous: f64,
    },
    /// A timestamp that is NaN or infinite.
    #[error("frame {frame}: timestamp {timestamp} is not a finite number")]
    BadTimestamp {
        /// Index the frame would have had.
        frame: u64,
        /// Its timestamp.
        timestamp: f64,
    },
    /// Every mesh of a capture must have the same vertex count.
    #[error("frame {frame}: mesh has {found} vertices, earlier frames had {expected}")]
    VertexCount {
        /// Index the frame would have had.
        frame: u64,
        /// Count of the first mesh.
        expected: usize,
        /// Count of this one.
        found: usize,
    },
    /// The neutral scan is needed by everything after it.
    #[error("the neutral scan cannot be skipped")]
    NeutralNotSkippable,
    /// A test index beyond the configured tests.
    #[error("there is no test expression {0} (only {1} are configured)")]
    NoSuchTest(usize, usize),
}

/// A frame kept for a possible capture, with its index in the stream and in
/// the detector's (tracked frames only) count.
#[derive(Debug)]
struct Retained {
    index: u64,
    detector_index: Option<usize>,
    frame: Frame,
}

/// The step under way.
#[derive(Debug)]
struct Active {
    step: Step,
    detector: PeakDetector,
    /// Tracked frames fed to the detector.
    fed: usize,
    /// Timestamp of the step's first frame.
    started_at: Option<f64>,
    /// Each weight's minimum since the step began (tracked frames).
    baseline: Option<Weights>,
}

/// The guided capture of one person.
#[derive(Debug)]
pub struct GuidedCapture {
    config: GuidedCaptureConfig,
    active: Option<Active>,
    queue: VecDeque<Step>,
    neutral_detector: NeutralDetector,
    /// The person's rest levels, from the neutral scan.
    rest: RestLevels,
    retained: VecDeque<Retained>,
    /// Stream indices of recent untracked frames.
    untracked: VecDeque<u64>,
    neutral: Option<Capture>,
    expressions: Vec<Option<Capture>>,
    tests: Vec<Option<Capture>>,
    skipped: Vec<Step>,
    frames_seen: u64,
    last_timestamp: Option<f64>,
    vertex_count: Option<usize>,
}

mod state_machine;

#[cfg(test)]
mod tests;
