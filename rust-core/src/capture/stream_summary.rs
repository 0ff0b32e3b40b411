//! What a weight stream holds when it is not a guided session: a free
//! performance (a Live Link Face take of someone acting, talking or
//! reading), which `likeness replay` is often given.
//!
//! A replay decides ([`is_guided`]) from what the state machine captured: a
//! guided session asks for the 52 expressions one after another, and a
//! person following it completes most of them; a performance runs into the
//! prompt timeout again and again. For a performance the useful facts are
//! per shape: how high it went, when, and for how long it was active.

use super::replay::ReplayReport;
use crate::arkit::Blendshape;
use crate::session::Frame;

/// A replay is a guided session when at least this share of the 52 prompts
/// was captured. A person following the prompts completes nearly all (the
/// simulated subjects: 52 of 52); a free performance completes few (the
/// real Live Link Face takes: 2 to 5), because each prompt waits for its
/// own shape and times out.
pub const GUIDED_MIN_SHARE: f64 = 0.5;

/// A shape counts as active while its weight is at least this.
pub const ACTIVE_LEVEL: f32 = 0.5;

/// Whether the replayed stream followed the guided capture (see
/// [`GUIDED_MIN_SHARE`]).
pub fn is_guided(report: &ReplayReport) -> bool {
    let prompts = report
        .steps
        .iter()
        .filter(|s| matches!(s.step, super::guided_capture::Step::Expression(_)));
    let (asked, captured) = prompts.fold((0usize, 0usize), |(a, c), s| {
        (a + 1, c + usize::from(s.frame.is_some()))
    });
    asked > 0 && captured as f64 >= GUIDED_MIN_SHARE * asked as f64
}

/// One shape over a stream.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShapeActivity {
    /// The shape.
    pub shape: Blendshape,
    /// Its largest weight.
    pub peak: f32,
    /// The first frame where it reached that weight.
    pub peak_frame: usize,
    /// That frame's timestamp (s).
    pub peak_time: f64,
    /// Frames at or above [`ACTIVE_LEVEL`].
    pub active_frames: usize,
}

/// Every shape's peak and activity over `frames`, in Apple's order.
pub fn shape_activity(frames: &[Frame]) -> Vec<ShapeActivity> {
    Blendshape::ALL
        .into_iter()
        .map(|shape| {
            let mut activity = ShapeActivity {
                shape,
                peak: f32::NEG_INFINITY,
                peak_frame: 0,
                peak_time: 0.0,
                active_frames: 0,
            };
            for (k, frame) in frames.iter().enumerate() {
                let w = frame.weights.get(shape);
                if w > activity.peak {
                    activity.peak = w;
                    activity.peak_frame = k;
                    activity.peak_time = frame.timestamp;
                }
                activity.active_frames += usize::from(w >= ACTIVE_LEVEL);
            }
            if frames.is_empty() {
                activity.peak = 0.0;
            }
            activity
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::arkit::Weights;

    #[test]
    fn peaks_and_activity_of_a_short_stream() {
        let frames: Vec<Frame> = [0.1f32, 0.6, 0.9, 0.7, 0.2]
            .iter()
            .enumerate()
            .map(|(k, w)| {
                let mut weights = Weights::ZERO;
                weights.set(Blendshape::JawOpen, *w);
                Frame {
                    timestamp: k as f64 / 60.0,
                    weights,
                    tracked: true,
                    vertices: None,
                }
            })
            .collect();
        let activity = shape_activity(&frames);
        let jaw = activity[Blendshape::JawOpen.index()];
        assert_eq!((jaw.peak, jaw.peak_frame, jaw.active_frames), (0.9, 2, 3));
        assert!((jaw.peak_time - 2.0 / 60.0).abs() < 1e-12);
        let blink = activity[Blendshape::EyeBlinkLeft.index()];
        assert_eq!((blink.peak, blink.active_frames), (0.0, 0));
        assert!(shape_activity(&[]).iter().all(|a| a.peak == 0.0));
    }
}
