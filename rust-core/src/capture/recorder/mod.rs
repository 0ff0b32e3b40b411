//! The guided capture as the app records it (§3.1): frames in, events out,
//! and at the end the [`Session`] the rest of the pipeline takes.
//!
//! [`GuidedCapture`] decides when each step is captured; the recorder
//! around it checks every frame against the template's topology, reports
//! the face being lost and found, keeps the stream a session file stores,
//! and assembles the session once no step is left. An interruption (a
//! call, the app in the background) restarts the step under way
//! ([`Recorder::interrupt`]); the frame that would take the capture past
//! what a session file holds ends it with what it has
//! ([`RecorderEvent::LimitReached`]), so nothing recorded is lost.
//!
//! The stream keeps every frame's weights, but a mesh only near a capture
//! (within [`RecorderConfig::geometry_window`] of the neutral scan, an
//! expression or a test), as the committed sample sessions do: `multi`
//! fits the frames next to each peak, and two minutes of every mesh would
//! hold 100 MB on the phone. Which frames are near a capture is known only
//! once the capture is confirmed, a few frames after its peak, so the
//! meshes of the last [`RecorderConfig::recent_meshes`] seconds are kept
//! until then.

use super::guided_capture::{
    Capture, CaptureEvent, GuidedCapture, GuidedCaptureConfig, GuidedCaptureError, Progress, Step,
};
use super::prompt_order::PROMPT_ORDER;
use crate::geometry::topology::Topology;
use crate::session::file::{MAX_DURATION_SECONDS, MAX_FRAMES};
use crate::session::{
    CapturedExpression, DeviceInfo, Frame, Session, SessionError, SessionParts, Template,
    TestExpression,
};
use glam::Vec3;
use std::collections::VecDeque;

/// How the recorder runs the capture and what it keeps; [`Default`] gives
/// the documented values.
#[derive(Clone, Debug, PartialEq)]
pub struct RecorderConfig {
    /// The guided capture's rules.
    pub guided: GuidedCaptureConfig,
    /// Seconds of meshes kept on either side of each capture (default 0.4,
    /// the committed samples' window: twice the reach of the frames `multi`
    /// fits around a peak).
    pub geometry_window: f64,
    /// Seconds of the newest meshes kept until it is known whether a
    /// capture needs them (default 3: a peak is confirmed once the weight
    /// has fallen for two frames; a peak held longer than 2.6 s keeps fewer
    /// meshes before it).
    pub recent_meshes: f64,
}

impl Default for RecorderConfig {
    fn default() -> Self {
        RecorderConfig {
            guided: GuidedCaptureConfig::default(),
            geometry_window: 0.4,
            recent_meshes: 3.0,
        }
    }
}

/// What the app hears back after each call.
#[derive(Clone, Debug, PartialEq)]
pub enum RecorderEvent {
    /// An event of the guided capture.
    Capture(CaptureEvent),
    /// This frame is the first without a tracked face.
    TrackingLost,
    /// This frame is the first with a tracked face again.
    TrackingResumed,
    /// This frame would have taken the capture past what a session holds
    /// ([`MAX_FRAMES`] frames or [`MAX_DURATION_SECONDS`]): it was not
    /// recorded, the capture ended with what it had (the steps left are
    /// skipped), and later frames are ignored.
    LimitReached {
        /// The frame's index in the stream.
        frame: usize,
        /// Its time after the first frame (s).
        seconds: f64,
    },
}

/// A call the recorder cannot take; the message names the field or step.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RecorderError {
    /// The template does not fit its topology.
    #[error("template: {0}")]
    Template(SessionError),
    /// A frame's weights or mesh are unusable (nothing was recorded).
    #[error(transparent)]
    Frame(SessionError),
    /// The guided capture refused the call (time going back, skipping the
    /// neutral scan).
    #[error(transparent)]
    Capture(#[from] GuidedCaptureError),
    /// A retake after the capture ended at its length limit
    /// ([`RecorderEvent::LimitReached`]).
    #[error(
        "the capture ended at its length limit ({MAX_FRAMES} frames or {MAX_DURATION_SECONDS} s): save it, or start a new one"
    )]
    Ended,
    /// The capture ended before the neutral scan, so there is no face.
    #[error("the capture ended before the neutral scan: there is no face to personalize")]
    NoNeutralScan,
    /// A step index past the last step.
    #[error("there is no step {index}: the capture has {total} (0 is the neutral scan)")]
    NoSuchStep {
        /// The index asked for.
        index: usize,
        /// Steps in all.
        total: usize,
    },
    /// A test expression has no single template shape to show.
    #[error("step {0} is a free test expression: the template has no shape for it")]
    NoPreview(String),
    /// Skip or retake before the capture started.
    #[error("the capture has not started: call start or push a frame first")]
    NotStarted,
    /// Skip with no step under way.
    #[error("the capture has finished: there is no step to skip")]
    NothingToSkip,
    /// A session asked for while steps are left.
    #[error("the capture has not finished: {done} of {total} steps are done")]
    NotFinished {
        /// Steps captured or skipped.
        done: usize,
        /// Steps in all.
        total: usize,
    },
    /// The neutral scan's frame had no mesh (only a replayed stream stored
    /// without every mesh can lack one).
    #[error("the neutral scan (frame {0}) carries no mesh, so the session has no neutral face")]
    NeutralWithoutMesh(u64),
    /// The assembled parts are not a valid session.
    #[error("the recorded session: {0}")]
    Session(SessionError),
}

/// One step as the app shows it.
#[derive(Clone, Debug, PartialEq)]
pub struct StepInfo {
    /// The step.
    pub step: Step,
    /// Its position among all steps (0 is the neutral scan).
    pub index: usize,
    /// Steps in all.
    pub total: usize,
    /// `neutral`, the ARKit name, or the test's id.
    pub name: String,
    /// What to tell the person.
    pub instruction: String,
}

/// The guided capture of one person, recording what the session keeps.
#[derive(Debug)]
pub struct Recorder {
    config: RecorderConfig,
    topology: Topology,
    template: Template,
    device: DeviceInfo,
    capture: GuidedCapture,
    steps: Vec<Step>,
    started: bool,
    tracked: bool,
    /// Every frame pushed, meshes dropped as described in the module docs.
    stream: Vec<Frame>,
    /// Stream indices of the newest frames that still hold a mesh.
    recent: VecDeque<usize>,
    /// Timestamps of every capture confirmed so far.
    centres: Vec<f64>,
    /// Whether the capture ended at its length limit.
    ended: bool,
}

impl Recorder {
    /// A capture against `template` (the topology's vertex count in every
    /// mesh, all finite); `device` is stored with the session.
    pub fn new(
        topology: Topology,
        template: Template,
        device: DeviceInfo,
        config: RecorderConfig,
    ) -> Result<Recorder, RecorderError> {
        let template_error = |e| RecorderError::Template(SessionError::Geometry(e));
        topology
            .check_positions("neutral", &template.neutral)
            .map_err(template_error)?;
        for (shape, mesh) in crate::arkit::Blendshape::ALL.iter().zip(&template.shapes) {
            topology
                .check_positions(shape.name(), mesh)
                .map_err(template_error)?;
        }
        Ok(Recorder {
            capture: GuidedCapture::new(config.guided.clone()),
            steps: config.guided.steps().collect(),
            config,
            topology,
            template,
            device,
            started: false,
            tracked: true,
            stream: Vec::new(),
            recent: VecDeque::new(),
            centres: Vec::new(),
            ended: false,
        })
    }

    /// Begins the neutral scan (a no-op once started).
    pub fn start(&mut self) -> Vec<RecorderEvent> {
        self.started = true;
        wrap(self.capture.start())
    }

    /// Checks and feeds the next frame (starting the capture if needed).
    /// On error nothing is recorded. The frame that would take the capture
    /// past what a session file holds ([`MAX_FRAMES`],
    /// [`MAX_DURATION_SECONDS`]) ends it instead
    /// ([`RecorderEvent::LimitReached`]), so what was recorded can be saved;
    /// frames after that are ignored.
    pub fn push(&mut self, frame: Frame) -> Result<Vec<RecorderEvent>, RecorderError> {
        if self.ended {
            return Ok(Vec::new());
        }
        let index = self.stream.len();
        let seconds = self
            .stream
            .first()
            .map_or(0.0, |first| frame.timestamp - first.timestamp);
        if index >= MAX_FRAMES || seconds > MAX_DURATION_SECONDS {
            self.ended = true;
            self.started = true;
            let mut events = vec![RecorderEvent::LimitReached {
                frame: index,
                seconds,
            }];
            events.extend(wrap(self.capture.end()));
            return Ok(events);
        }
        let what = format!("frame {index}");
        if let Some((shape, value)) = frame.weights.iter().find(|(_, w)| !w.is_finite()) {
            return Err(RecorderError::Frame(SessionError::BadWeight {
                what,
                shape,
                value,
            }));
        }
        if let Some(mesh) = &frame.vertices {
            self.topology
                .check_positions(&what, mesh)
                .map_err(|e| RecorderError::Frame(SessionError::Geometry(e)))?;
        }
        let captured = self.capture.push(frame.clone())?;
        self.started = true;
        let mut events = Vec::new();
        if frame.tracked != self.tracked {
            self.tracked = frame.tracked;
            events.push(if frame.tracked {
                RecorderEvent::TrackingResumed
            } else {
                RecorderEvent::TrackingLost
            });
        }
        let now = frame.timestamp;
        if frame.vertices.is_some() {
            self.recent.push_back(index);
        }
        self.stream.push(frame);
        for event in &captured {
            if let CaptureEvent::Captured { frame, .. } = event
                && let Some(f) = self.stream.get(*frame as usize)
            {
                self.centres.push(f.timestamp);
            }
        }
        self.forget_old_meshes(now);
        events.extend(wrap(captured));
        Ok(events)
    }

    /// Skips the step under way (not the neutral scan).
    pub fn skip(&mut self) -> Result<Vec<RecorderEvent>, RecorderError> {
        if !self.started {
            return Err(RecorderError::NotStarted);
        }
        if self.progress().current.is_none() {
            return Err(RecorderError::NothingToSkip);
        }
        Ok(wrap(self.capture.skip()?))
    }

    /// Asks for the step at `index` of [`Recorder::steps`] again now (also
    /// after the end, but not after the length limit ended it).
    pub fn retake(&mut self, index: usize) -> Result<Vec<RecorderEvent>, RecorderError> {
        let step = self.step_at(index)?;
        if !self.started {
            return Err(RecorderError::NotStarted);
        }
        if self.ended {
            return Err(RecorderError::Ended);
        }
        Ok(wrap(self.capture.retake(step)?))
    }

    /// The capture was interrupted (a call, the app in the background,
    /// the phone locked): the step under way starts again with the next
    /// frame ([`GuidedCapture::interrupt`]). Frames may resume at any later
    /// time; the time away still counts towards [`MAX_DURATION_SECONDS`].
    pub fn interrupt(&mut self) -> Vec<RecorderEvent> {
        if self.ended {
            return Vec::new();
        }
        wrap(self.capture.interrupt())
    }

    /// Whether the capture ended at its length limit.
    pub fn ended_at_limit(&self) -> bool {
        self.ended
    }

    /// How far along the capture is.
    pub fn progress(&self) -> Progress {
        self.capture.progress()
    }

    /// Whether the capture started and no step is left.
    pub fn is_finished(&self) -> bool {
        self.started && self.progress().current.is_none()
    }

    /// Every step in the order they are asked for.
    pub fn steps(&self) -> &[Step] {
        &self.steps
    }

    /// The step at `index` of [`Recorder::steps`].
    pub fn step_at(&self, index: usize) -> Result<Step, RecorderError> {
        self.steps
            .get(index)
            .copied()
            .ok_or(RecorderError::NoSuchStep {
                index,
                total: self.steps.len(),
            })
    }

    /// `step` as the app shows it.
    pub fn step_info(&self, step: Step) -> StepInfo {
        let config = self.capture.config();
        StepInfo {
            step,
            index: self.steps.iter().position(|s| *s == step).unwrap_or(0),
            total: self.steps.len(),
            name: step.name(config),
            instruction: step.instruction(config).to_string(),
        }
    }

    /// The steps skipped without a capture.
    pub fn skipped(&self) -> &[Step] {
        self.capture.skipped()
    }

    /// The capture of `step`, if any.
    pub fn capture_of(&self, step: Step) -> Option<&Capture> {
        self.capture.capture_of(step)
    }

    /// The template's face at the step at `index`: its neutral for the
    /// neutral scan, the prompted shape at weight one for an expression.
    pub fn preview(&self, index: usize) -> Result<&[Vec3], RecorderError> {
        match self.step_at(index)? {
            Step::Neutral => Ok(&self.template.neutral),
            // Indexing: the template holds one mesh per blendshape index.
            Step::Expression(shape) => Ok(&self.template.shapes[shape.index()]),
            step @ Step::Test(_) => Err(RecorderError::NoPreview(step.name(self.capture.config()))),
        }
    }

    /// The session recorded (the recorder is left as it is): the neutral
    /// scan's mesh as the person's neutral, every captured expression and
    /// test with a mesh, the stream with timestamps from its first frame
    /// and meshes only within the window of a capture, and the frame rate
    /// measured on the stream. A capture whose frame had no mesh cannot be
    /// fitted and is left out (only replays of streams stored without every
    /// mesh have such frames).
    pub fn session(&self) -> Result<Session, RecorderError> {
        let progress = self.progress();
        let neutral = match self.capture_of(Step::Neutral) {
            Some(n) if self.is_finished() => n,
            None if self.ended => return Err(RecorderError::NoNeutralScan),
            _ => {
                return Err(RecorderError::NotFinished {
                    done: progress.captured + progress.skipped,
                    total: progress.total,
                });
            }
        };
        let neutral_mesh = match &neutral.vertices {
            Some(mesh) => mesh.clone(),
            None => self
                .still_mesh_near(neutral)
                .ok_or(RecorderError::NeutralWithoutMesh(neutral.frame))?,
        };
        let with_mesh = |step| {
            let c = self.capture_of(step)?;
            Some((c, c.vertices.clone()?))
        };
        let captures: Vec<CapturedExpression> = PROMPT_ORDER
            .iter()
            .filter_map(|&prompt| {
                let (c, vertices) = with_mesh(Step::Expression(prompt))?;
                Some(CapturedExpression {
                    prompt,
                    frame: u32::try_from(c.frame).ok(),
                    weights: c.weights,
                    vertices,
                })
            })
            .collect();
        let tests: Vec<TestExpression> = (self.config.guided.tests.iter().enumerate())
            .filter_map(|(i, test)| {
                let (c, vertices) = with_mesh(Step::Test(i))?;
                Some(TestExpression {
                    id: test.id.clone(),
                    frame: u32::try_from(c.frame).ok(),
                    weights: c.weights,
                    vertices,
                })
            })
            .collect();
        let centres: Vec<f64> = std::iter::once(neutral.frame)
            .chain(captures.iter().filter_map(|c| c.frame.map(u64::from)))
            .chain(tests.iter().filter_map(|t| t.frame.map(u64::from)))
            .filter_map(|f| Some(self.stream.get(f as usize)?.timestamp))
            .collect();
        let start = self.stream.first().map_or(0.0, |f| f.timestamp);
        let frames = self
            .stream
            .iter()
            .map(|f| Frame {
                timestamp: f.timestamp - start,
                weights: f.weights,
                tracked: f.tracked,
                vertices: f
                    .vertices
                    .as_ref()
                    .filter(|_| self.near(&centres, f.timestamp))
                    .cloned(),
            })
            .collect();
        Session::new(SessionParts {
            device: self.device.clone(),
            frame_rate: frame_rate(&self.stream),
            topology: self.topology.clone(),
            template: self.template.clone(),
            neutral: neutral_mesh,
            frames,
            captures,
            tests,
            truth: None,
        })
        .map_err(RecorderError::Session)
    }

    /// For a neutral scan whose own frame has no mesh (only a replay of a
    /// stream stored without every mesh has such a frame): the mesh of the
    /// nearest frame that still shows the same face, by the neutral
    /// detector's own rules ([`NeutralConfig`](super::guided_capture::NeutralConfig)):
    /// within its `duration` of the scan, and every frame from the scan to
    /// it tracked with each weight within `max_weight_change` of the
    /// scan's. `None` if there is none.
    fn still_mesh_near(&self, scan: &Capture) -> Option<Vec<Vec3>> {
        let rules = &self.config.guided.neutral;
        let at = usize::try_from(scan.frame).ok()?;
        let same_face = |f: &Frame| {
            f.tracked
                && (f.timestamp - scan.timestamp).abs() <= rules.duration
                && f.weights
                    .0
                    .iter()
                    .zip(&scan.weights.0)
                    .all(|(w, s)| (w - s).abs() <= rules.max_weight_change)
        };
        // Walk outwards both ways while the face stays the same; the first
        // mesh met on either side (the nearer one first) is taken.
        let before = self.stream[..at].iter().rev().take_while(|f| same_face(f));
        let after = self
            .stream
            .get(at + 1..)?
            .iter()
            .take_while(|f| same_face(f));
        let (mut before, mut after) = (before.peekable(), after.peekable());
        loop {
            let next = match (before.peek(), after.peek()) {
                (None, None) => return None,
                (Some(b), Some(a))
                    if scan.timestamp - b.timestamp <= a.timestamp - scan.timestamp =>
                {
                    before.next()
                }
                (Some(_), None) => before.next(),
                _ => after.next(),
            };
            if let Some(mesh) = next.and_then(|f| f.vertices.clone()) {
                return Some(mesh);
            }
        }
    }

    /// Whether time `t` is within the geometry window of one of `centres`.
    fn near(&self, centres: &[f64], t: f64) -> bool {
        // A microsecond of slack for timestamps on the window's edge.
        let window = self.config.geometry_window + 1e-6;
        centres.iter().any(|c| (t - c).abs() <= window)
    }

    /// Drops the meshes that left the recent span and are near no capture.
    fn forget_old_meshes(&mut self, now: f64) {
        // Indexing: `recent` holds indices of frames already in `stream`.
        while let Some(&i) = self.recent.front() {
            let t = self.stream[i].timestamp;
            if t >= now - self.config.recent_meshes {
                break;
            }
            self.recent.pop_front();
            if !self.near(&self.centres, t) {
                self.stream[i].vertices = None;
            }
        }
    }
}

fn wrap(events: Vec<CaptureEvent>) -> Vec<RecorderEvent> {
    events.into_iter().map(RecorderEvent::Capture).collect()
}

/// ARKit face tracking's nominal rate (Hz), for a stream too short to
/// measure.
const NOMINAL_FRAME_RATE: f32 = 60.0;

/// The stream's frame rate: one over the median interval between frames.
fn frame_rate(frames: &[Frame]) -> f32 {
    let mut intervals: Vec<f64> = frames
        .windows(2)
        .map(|w| w[1].timestamp - w[0].timestamp)
        .filter(|d| *d > 0.0)
        .collect();
    if intervals.is_empty() {
        return NOMINAL_FRAME_RATE;
    }
    let middle = intervals.len() / 2;
    let (_, median, _) = intervals.select_nth_unstable_by(middle, f64::total_cmp);
    (1.0 / *median) as f32
}

#[cfg(test)]
mod tests;
