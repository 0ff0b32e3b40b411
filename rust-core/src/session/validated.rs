//! A session whose parts agree: the only kind the pipeline accepts.
//!
//! [`Session::new`] checks every invariant a reader relies on (every mesh fits
//! the topology and is finite, weights are finite, time runs forward, frame
//! references exist, each prompt is captured at most once, the ground truth
//! has one entry per expression) and is the only way to obtain a
//! [`Session`]; the parts are then read-only. To change a session, take it
//! apart with [`Session::into_parts`] and check the changed parts again.

use super::error::SessionError;
use super::model::{GroundTruth, SessionParts};
use crate::arkit::{BLENDSHAPE_COUNT, Blendshape, Weights};
use std::ops::Deref;

/// A capture session whose parts agree with each other (see the module
/// docs). Read its parts through [`Deref`] (`session.frames`, …); they
/// cannot be changed in place.
#[derive(Clone, Debug, PartialEq)]
pub struct Session(SessionParts);

impl Deref for Session {
    type Target = SessionParts;

    fn deref(&self) -> &SessionParts {
        &self.0
    }
}

impl Session {
    /// Checks `parts` and makes them a session. The checks run in this
    /// order, and the first that fails is the error: frame rate, template,
    /// neutral scan, captures, test expressions, ground truth, then the
    /// stream frame by frame (time runs forward; weights and meshes).
    pub fn new(parts: SessionParts) -> Result<Session, SessionError> {
        check_expressions(&parts)?;
        check_stream(&parts)?;
        Ok(Session(parts))
    }

    /// The parts, to change them (then check them again with
    /// [`Session::new`]).
    pub fn into_parts(self) -> SessionParts {
        self.0
    }

    /// The parts, read-only (the same as dereferencing).
    pub fn parts(&self) -> &SessionParts {
        &self.0
    }
}

/// Time runs forward through the stream, and every frame's weights and
/// mesh are finite and fit the topology.
fn check_stream(parts: &SessionParts) -> Result<(), SessionError> {
    let mut previous = f64::NEG_INFINITY;
    for (i, frame) in parts.frames.iter().enumerate() {
        if !frame.timestamp.is_finite() || frame.timestamp < previous {
            return Err(SessionError::Timestamp {
                frame: i,
                timestamp: frame.timestamp,
            });
        }
        previous = frame.timestamp;
        check_weights(&format!("frame {i}"), &frame.weights)?;
        if let Some(v) = &frame.vertices {
            parts.topology.check_positions(&format!("frame {i}"), v)?;
        }
    }
    Ok(())
}

/// Everything but the stream: frame rate, template, neutral scan, captures,
/// test expressions and ground truth.
fn check_expressions(parts: &SessionParts) -> Result<(), SessionError> {
    let topo = &parts.topology;
    if !(parts.frame_rate.is_finite() && parts.frame_rate > 0.0) {
        return Err(SessionError::FrameRate(parts.frame_rate));
    }
    topo.check_positions("template neutral", &parts.template.neutral)?;
    for (shape, mesh) in Blendshape::ALL.iter().zip(&parts.template.shapes) {
        topo.check_positions(&format!("template {shape}"), mesh)?;
    }
    topo.check_positions("neutral", &parts.neutral)?;
    // Indexed by `Blendshape::index()`, always below BLENDSHAPE_COUNT.
    let mut seen = [false; BLENDSHAPE_COUNT];
    for capture in &parts.captures {
        let what = format!("capture {}", capture.prompt);
        if std::mem::replace(&mut seen[capture.prompt.index()], true) {
            return Err(SessionError::DuplicateCapture(capture.prompt));
        }
        check_frame_ref(parts, &what, capture.frame)?;
        check_weights(&what, &capture.weights)?;
        topo.check_positions(&what, &capture.vertices)?;
    }
    for test in &parts.tests {
        let what = format!("test expression {:?}", test.id);
        check_frame_ref(parts, &what, test.frame)?;
        check_weights(&what, &test.weights)?;
        topo.check_positions(&what, &test.vertices)?;
    }
    if let Some(truth) = &parts.truth {
        check_truth(parts, truth)?;
    }
    Ok(())
}

/// The ground truth has one entry per expression, and its meshes fit.
fn check_truth(parts: &SessionParts, truth: &GroundTruth) -> Result<(), SessionError> {
    let topo = &parts.topology;
    let counts = [
        ("captures", truth.captures.len(), parts.captures.len()),
        ("tests", truth.tests.len(), parts.tests.len()),
        (
            "test activations",
            truth.test_activations.len(),
            parts.tests.len(),
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
    for peak in &truth.peak_frames {
        let what = format!("true peak of {}", peak.prompt);
        check_frame_ref(parts, &what, Some(peak.frame))?;
    }
    for (k, w) in truth.test_activations.iter().enumerate() {
        check_weights(&format!("true activation of test {k}"), w)?;
    }
    Ok(())
}

fn check_frame_ref(
    parts: &SessionParts,
    what: &str,
    frame: Option<u32>,
) -> Result<(), SessionError> {
    match frame {
        Some(f) if f as usize >= parts.frames.len() => Err(SessionError::FrameIndex {
            what: what.to_string(),
            frame: f,
            frames: parts.frames.len(),
        }),
        _ => Ok(()),
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
