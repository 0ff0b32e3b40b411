//! The guided capture the app drives one ARKit frame at a time: the core's
//! [`Recorder`] behind a mutex (UniFFI shares objects between threads).

use crate::error::LikenessError;
use crate::session::SessionHandle;
use crate::types::{
    CaptureInfo, CaptureProgress, FaceTemplate, Prompt, count, packed_points, points,
};
use glam::Vec3;
use likeness::capture::guided_capture::{self, Step};
use likeness::capture::recorder::{Recorder, RecorderConfig, RecorderEvent};
use likeness::session::{DeviceInfo, Frame};
use std::sync::{Arc, Mutex, MutexGuard};

/// What the app hears back after each call on a [`CaptureSession`].
#[derive(Clone, Debug, PartialEq, uniffi::Enum)]
pub enum CaptureEvent {
    /// A step begins: show its instruction (and its preview).
    PromptStarted {
        /// The step.
        prompt: Prompt,
    },
    /// The step was captured.
    Captured {
        /// The step.
        prompt: Prompt,
        /// Its quality flags in words (offer a retake when not empty).
        warnings: Vec<String>,
    },
    /// The step was skipped.
    Skipped {
        /// The step.
        prompt: Prompt,
        /// Why, in words.
        reason: String,
    },
    /// This frame is the first without a tracked face.
    TrackingLost,
    /// This frame is the first with a tracked face again.
    TrackingResumed,
    /// The capture reached the longest a session holds (10 minutes or
    /// 36,000 frames): it ended with what it had, the steps left skipped;
    /// `Finished` follows. Say so, and save it.
    LimitReached {
        /// Seconds from the first frame to the one refused.
        seconds: f64,
        /// What happened, in words for the person.
        message: String,
    },
    /// No step is left; show the review (`captures()`), then `finish` when
    /// the person confirms (a retake may come first).
    Finished {
        /// Steps captured (the neutral scan included).
        captured: u32,
        /// Steps without a capture.
        skipped: u32,
    },
}

/// Where a capture is.
enum State {
    /// Frames are taken.
    Recording(Box<Recorder>),
    /// [`CaptureSession::finish`] made a session of it; its last progress.
    Done(CaptureProgress),
}

/// One person's guided capture: frames in, events out, a session at the end.
#[derive(uniffi::Object)]
pub struct CaptureSession {
    state: Mutex<State>,
}

impl CaptureSession {
    /// The state, or an internal error if an earlier call panicked while
    /// holding it.
    fn lock(&self) -> Result<MutexGuard<'_, State>, LikenessError> {
        self.state.lock().map_err(|_| LikenessError::Internal {
            message: "an earlier call on this capture panicked; start a new capture".into(),
        })
    }

    /// Records one frame (both `push_frame`s).
    fn push(
        &self,
        timestamp: f64,
        weights: &[f32],
        vertices: Option<Vec<Vec3>>,
        tracked: bool,
    ) -> Result<Vec<CaptureEvent>, LikenessError> {
        let frame = Frame {
            timestamp,
            weights: crate::types::weights("weights", weights)?,
            tracked,
            vertices,
        };
        self.recording(|r| {
            let e = r.push(frame)?;
            Ok(events(r, e))
        })
    }

    /// Runs `f` on the recorder while the capture is recording.
    fn recording<T>(
        &self,
        f: impl FnOnce(&mut Recorder) -> Result<T, LikenessError>,
    ) -> Result<T, LikenessError> {
        match &mut *self.lock()? {
            State::Recording(recorder) => f(recorder),
            State::Done(_) => Err(LikenessError::wrong_order(
                "this capture was already finished into a session: start a new CaptureSession",
            )),
        }
    }
}

/// The recorder's events as the app's.
fn events(recorder: &Recorder, events: Vec<RecorderEvent>) -> Vec<CaptureEvent> {
    let prompt = |step: Step| Prompt::from(&recorder.step_info(step));
    events
        .into_iter()
        .map(|e| match e {
            RecorderEvent::TrackingLost => CaptureEvent::TrackingLost,
            RecorderEvent::TrackingResumed => CaptureEvent::TrackingResumed,
            RecorderEvent::LimitReached { seconds, .. } => CaptureEvent::LimitReached {
                seconds,
                message: format!(
                    "The capture reached its limit after {:.0} minutes; what was captured is kept \
                     and the rest was skipped.",
                    seconds / 60.0
                ),
            },
            RecorderEvent::Capture(e) => match e {
                guided_capture::CaptureEvent::Started(step) => CaptureEvent::PromptStarted {
                    prompt: prompt(step),
                },
                guided_capture::CaptureEvent::Captured { step, quality, .. } => {
                    CaptureEvent::Captured {
                        prompt: prompt(step),
                        warnings: quality.warnings(),
                    }
                }
                guided_capture::CaptureEvent::Skipped { step, reason } => CaptureEvent::Skipped {
                    prompt: prompt(step),
                    reason: reason.description().to_string(),
                },
                guided_capture::CaptureEvent::Finished { captured, skipped } => {
                    CaptureEvent::Finished {
                        captured: count(captured),
                        skipped: count(skipped),
                    }
                }
            },
        })
        .collect()
}

#[uniffi::export]
impl CaptureSession {
    /// A capture against `template` (what `ARFaceGeometry` gives on this
    /// device); `device` (e.g. `iPhone13,3`) is stored with the session.
    #[uniffi::constructor]
    pub fn new(template: FaceTemplate, device: String) -> Result<Arc<Self>, LikenessError> {
        let (topology, template) = template.to_core()?;
        let device = DeviceInfo {
            model: device,
            app_version: format!("likeness-ffi {}", likeness::VERSION),
            ..DeviceInfo::default()
        };
        let recorder = Recorder::new(topology, template, device, RecorderConfig::default())?;
        Ok(Arc::new(CaptureSession {
            state: Mutex::new(State::Recording(Box::new(recorder))),
        }))
    }

    /// Begins the neutral scan (the first `push_frame` does too).
    pub fn start(&self) -> Result<Vec<CaptureEvent>, LikenessError> {
        self.recording(|r| {
            let e = r.start();
            Ok(events(r, e))
        })
    }

    /// Feeds one ARKit frame: `timestamp` is `ARFrame.timestamp` (s),
    /// `weights` the 52 blend shape values in `arkitNames()` order,
    /// `vertices` the face geometry's vertices xyz flattened (empty for a
    /// frame without a mesh, as stored sessions have), `tracked`
    /// `ARFaceAnchor.isTracked`. On error nothing is recorded.
    pub fn push_frame(
        &self,
        timestamp: f64,
        weights: Vec<f32>,
        vertices: Vec<f32>,
        tracked: bool,
    ) -> Result<Vec<CaptureEvent>, LikenessError> {
        let vertices = match vertices.is_empty() {
            true => None,
            false => Some(points("vertices", &vertices)?),
        };
        self.push(timestamp, &weights, vertices, tracked)
    }

    /// [`CaptureSession::push_frame`] with the vertices packed as
    /// little-endian 32-bit floats, xyz after xyz (12 bytes a vertex; empty
    /// for a frame without a mesh): the mesh crosses the boundary as one
    /// copy instead of one write per float, which is what makes the call
    /// cheap from Python and saves the phone 3,660 conversions a frame.
    pub fn push_frame_packed(
        &self,
        timestamp: f64,
        weights: Vec<f32>,
        vertices: Vec<u8>,
        tracked: bool,
    ) -> Result<Vec<CaptureEvent>, LikenessError> {
        let vertices = match vertices.is_empty() {
            true => None,
            false => Some(packed_points("vertices", &vertices)?),
        };
        self.push(timestamp, &weights, vertices, tracked)
    }

    /// Skips the step under way (not the neutral scan).
    pub fn skip(&self) -> Result<Vec<CaptureEvent>, LikenessError> {
        self.recording(|r| {
            let e = r.skip()?;
            Ok(events(r, e))
        })
    }

    /// Asks for the step at `index` (`Prompt.index`) again now; the step
    /// under way resumes afterwards. Works after `Finished` too.
    pub fn retake(&self, index: u32) -> Result<Vec<CaptureEvent>, LikenessError> {
        self.recording(|r| {
            let e = r.retake(index as usize)?;
            Ok(events(r, e))
        })
    }

    /// The capture was interrupted (a phone call, the app sent to the
    /// background, the phone locked): call it when the interruption begins.
    /// The step under way starts again with the next frame and is announced
    /// again (`PromptStarted`), so the time away neither times it out nor
    /// joins its peak to frames from before.
    pub fn interrupt(&self) -> Result<Vec<CaptureEvent>, LikenessError> {
        self.recording(|r| {
            let e = r.interrupt();
            Ok(events(r, e))
        })
    }

    /// How far along the capture is.
    pub fn progress(&self) -> Result<CaptureProgress, LikenessError> {
        Ok(match &*self.lock()? {
            State::Recording(r) => CaptureProgress::new(r.progress(), r.ended_at_limit()),
            State::Done(p) => p.clone(),
        })
    }

    /// The step under way, `None` once finished.
    pub fn current_prompt(&self) -> Result<Option<Prompt>, LikenessError> {
        Ok(match &*self.lock()? {
            State::Recording(r) => r
                .progress()
                .current
                .map(|step| Prompt::from(&r.step_info(step))),
            State::Done(_) => None,
        })
    }

    /// Whether no step is left (also after `finish`).
    pub fn is_finished(&self) -> Result<bool, LikenessError> {
        Ok(match &*self.lock()? {
            State::Recording(r) => r.is_finished(),
            State::Done(_) => true,
        })
    }

    /// The generic template's vertices (xyz flattened) at the step at
    /// `index`: the neutral face, or the prompted shape at weight one.
    pub fn prompt_preview(&self, index: u32) -> Result<Vec<f32>, LikenessError> {
        self.recording(|r| Ok(crate::types::flat(r.preview(index as usize)?)))
    }

    /// Every step with its capture so far, in the order they are asked for
    /// (for a review screen).
    pub fn captures(&self) -> Result<Vec<CaptureInfo>, LikenessError> {
        self.recording(|r| {
            Ok(r.steps()
                .iter()
                .map(|&step| {
                    let capture = r.capture_of(step);
                    let weight = match (step, capture) {
                        (Step::Expression(shape), Some(c)) => Some(c.weights.get(shape)),
                        _ => None,
                    };
                    CaptureInfo {
                        prompt: Prompt::from(&r.step_info(step)),
                        frame: capture.map(|c| c.frame),
                        warnings: capture.map(|c| c.quality.warnings()).unwrap_or_default(),
                        weight,
                        skipped: r.skipped().contains(&step),
                    }
                })
                .collect())
        })
    }

    /// The session recorded, once no step is left; the capture then takes
    /// no more calls.
    pub fn finish(&self) -> Result<Arc<SessionHandle>, LikenessError> {
        let mut state = self.lock()?;
        let State::Recording(recorder) = &*state else {
            return Err(LikenessError::wrong_order(
                "this capture was already finished into a session",
            ));
        };
        let session = recorder.session()?;
        let progress = CaptureProgress::new(recorder.progress(), recorder.ended_at_limit());
        *state = State::Done(progress);
        Ok(Arc::new(SessionHandle::new(session)))
    }
}
