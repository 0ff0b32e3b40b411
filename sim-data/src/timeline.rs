//! What a person performed in a session, frame by frame: the true
//! activations, and where each prompt and test expression happened.
//!
//! The performance draws a [`Timeline`]; the capture session tracks it frame
//! by frame.

use likeness::{BLENDSHAPE_COUNT, Blendshape};
use std::ops::Range;

/// One prompt as performed.
#[derive(Clone, Debug)]
pub struct PromptTrack {
    /// The requested shape.
    pub shape: Blendshape,
    /// Frame at which the app showed the prompt.
    pub shown: usize,
    /// Frames of the attempt that counts.
    pub attempt: Range<usize>,
    /// Frame of the true peak of the requested activation.
    pub true_peak: usize,
    /// Frames of a failed first attempt, if any.
    pub failed_attempt: Option<Range<usize>>,
    /// A one-frame tracker spike: frame and reported value.
    pub spike: Option<(usize, f32)>,
}

/// A held-out test expression as performed.
#[derive(Clone, Debug)]
pub struct TestTrack {
    /// Its name, e.g. `smile-squint`.
    pub id: String,
    /// Frame of its true peak.
    pub frame: usize,
}

/// A whole session's true activations, frame by frame.
#[derive(Clone, Debug)]
pub struct Timeline {
    /// Frame rate (Hz).
    pub frame_rate: f64,
    /// True activations per frame.
    pub activations: Vec<[f64; BLENDSHAPE_COUNT]>,
    /// Frame of the neutral scan.
    pub neutral_frame: usize,
    /// The 52 prompts in order.
    pub prompts: Vec<PromptTrack>,
    /// The test expressions in order.
    pub tests: Vec<TestTrack>,
    /// Frames during which tracking is lost.
    pub tracking_lost: Vec<Range<usize>>,
}

/// The frame nearest to time `t` (s) at `frame_rate` Hz.
pub fn frame_at(t: f64, frame_rate: f64) -> usize {
    (t * frame_rate).round() as usize
}
