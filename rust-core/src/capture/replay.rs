//! Replay: a recorded frame stream fed through the [`GuidedCapture`] state
//! machine exactly as the app feeds live frames, so every capture rule is
//! tested on desktop. Where the session carries the simulator's ground
//! truth, each capture is compared with the frame at which the expression
//! truly peaked.

use crate::capture::guided_capture::{
    CaptureQuality, GuidedCapture, GuidedCaptureConfig, GuidedCaptureError, Step, TestPrompt,
};
use crate::session::{Frame, Session, SessionParts};

/// What happened to one step in the replay.
#[derive(Clone, Debug, PartialEq)]
pub struct ReplayedStep {
    /// The step.
    pub step: Step,
    /// Its name: `neutral`, the ARKit name, or the test's id.
    pub name: String,
    /// The captured frame, `None` if skipped.
    pub frame: Option<u64>,
    /// The frame at which the expression truly peaked, if known.
    pub true_frame: Option<u64>,
    /// Quality flags of the capture.
    pub quality: CaptureQuality,
    /// Whether the captured frame carried a mesh.
    pub has_mesh: bool,
}

impl ReplayedStep {
    /// Captured frame − true frame, when both are known.
    pub fn frame_error(&self) -> Option<i64> {
        Some(self.frame? as i64 - self.true_frame? as i64)
    }
}

/// The outcome of a replay.
#[derive(Clone, Debug, PartialEq)]
pub struct ReplayReport {
    /// Frames fed.
    pub frames: u64,
    /// Neutral scan, the 52 prompts in app order, then the tests.
    pub steps: Vec<ReplayedStep>,
    /// Whether the state machine reached [`crate::capture::guided_capture::CaptureEvent::Finished`].
    pub finished: bool,
}

impl ReplayReport {
    /// Steps with a capture.
    pub fn captured(&self) -> usize {
        self.steps.iter().filter(|s| s.frame.is_some()).count()
    }

    /// Steps without one.
    pub fn skipped(&self) -> usize {
        self.steps.len() - self.captured()
    }

    /// Largest |capture − true peak| over the 52 prompts (where known).
    pub fn max_frame_error(&self) -> Option<u64> {
        self.prompt_errors().map(|e| e.unsigned_abs()).max()
    }

    /// Largest |capture − true peak| over the test expressions.
    pub fn max_test_frame_error(&self) -> Option<u64> {
        self.steps
            .iter()
            .filter(|s| matches!(s.step, Step::Test(_)))
            .filter_map(|s| s.frame_error())
            .map(i64::unsigned_abs)
            .max()
    }

    /// capture − true peak of each prompt where both are known.
    pub fn prompt_errors(&self) -> impl Iterator<Item = i64> + '_ {
        self.steps
            .iter()
            .filter(|s| matches!(s.step, Step::Expression(_)))
            .filter_map(|s| s.frame_error())
    }
}

/// Replays `frames` with `config`; `true_frame(step)` gives the true peak
/// where known.
pub fn replay_frames(
    frames: impl IntoIterator<Item = Frame>,
    config: GuidedCaptureConfig,
    true_frame: impl Fn(Step) -> Option<u64>,
) -> Result<ReplayReport, GuidedCaptureError> {
    let mut capture = GuidedCapture::new(config);
    let mut finished = false;
    for frame in frames {
        let events = capture.push(frame)?;
        finished |= events.iter().any(|e| {
            matches!(
                e,
                crate::capture::guided_capture::CaptureEvent::Finished { .. }
            )
        });
    }
    let config = capture.config();
    let steps = config
        .steps()
        .map(|step| {
            let c = capture.capture_of(step);
            ReplayedStep {
                step,
                name: step.name(config),
                frame: c.map(|c| c.frame),
                true_frame: true_frame(step),
                quality: c.map(|c| c.quality).unwrap_or_default(),
                has_mesh: c.is_some_and(|c| c.vertices.is_some()),
            }
        })
        .collect();
    Ok(ReplayReport {
        frames: capture.frames_seen(),
        steps,
        finished,
    })
}

/// Replays a session's recorded stream, asking for its test expressions
/// after the prompts (by id, as the app that recorded it did) and comparing
/// with the simulator's true peaks when the session has them. Consumes the
/// session so the frames are moved, not copied.
pub fn replay_session(
    session: Session,
    config: GuidedCaptureConfig,
) -> Result<ReplayReport, GuidedCaptureError> {
    let SessionParts {
        frames,
        tests,
        truth,
        ..
    } = session.into_parts();
    let config = GuidedCaptureConfig {
        tests: tests
            .iter()
            .map(|t| TestPrompt {
                id: t.id.clone(),
                instruction: t.id.clone(),
            })
            .collect(),
        ..config
    };
    let true_frame = |step: Step| {
        let truth = truth.as_ref()?;
        match step {
            Step::Expression(shape) => truth.peak_frame(shape),
            Step::Test(i) => tests.get(i)?.frame,
            Step::Neutral => None,
        }
        .map(u64::from)
    };
    replay_frames(frames, config, true_frame)
}
