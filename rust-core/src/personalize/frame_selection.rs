//! Which frames of the capture stream, besides the captured peaks, the fit
//! uses (`multi`), and (with the `study` feature) which held-out frames
//! score λ for the study's rule `LambdaRule::Holdout`.
//!
//! Around each captured peak the stream holds the ramp up, the peak and the
//! hold of the same expression: the same blendshape at other weights, and
//! other noise. Frames close to the peak (within [`FIT_REACH`]) are nearly
//! the captured expression itself and make good extra fitting data.
//!
//! The study's held-out frames lie farther away (`VALIDATION_GAP` to
//! `VALIDATION_REACH` frames): they carry intermediate weights that no
//! capture has, are never fitted, and are at least a quarter second away
//! from any fitted frame, so their tracker noise is only weakly correlated
//! with it (ARKit filters over ~0.3 s).

use crate::session::Session;

/// Frames on either side of a capture that `multi` may fit (0.2 s at 60 fps).
pub const FIT_REACH: usize = 12;
/// Closest a validation frame may be to a capture (0.25 s at 60 fps).
#[cfg(feature = "study")]
pub const VALIDATION_GAP: usize = 15;
/// Farthest a validation frame may be from a capture (0.67 s at 60 fps).
#[cfg(feature = "study")]
pub const VALIDATION_REACH: usize = 40;
/// A fitted extra frame shows at least this share of the capture's weight
/// of the prompted shape.
pub const FIT_MIN_SHARE: f32 = 0.5;
/// Every this many frames is kept for validation: neighbouring frames at
/// 60 fps are nearly the same sample, and a third of them scores λ as well
/// at a third of the cost.
#[cfg(feature = "study")]
pub const VALIDATION_STRIDE: usize = 3;
/// A validation frame shows at least this share of the capture's weight of
/// the prompted shape (it must show the expression, not the rest face).
#[cfg(feature = "study")]
pub const VALIDATION_MIN_SHARE: f32 = 0.2;

/// Frames usable at all: tracked, with a mesh.
fn usable(session: &Session, f: usize) -> bool {
    session
        .frames
        .get(f)
        .is_some_and(|fr| fr.tracked && fr.vertices.is_some())
}

/// A stream frame near a captured peak.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FrameNearCapture {
    /// Index into the session's captures.
    pub capture: usize,
    /// Index into the session's frames.
    pub frame: usize,
}

/// For each capture with a frame index, the stream frames within `reach`
/// frames of it (outside `gap`), showing at least `share` of its prompted
/// weight.
fn around_captures(
    session: &Session,
    gap: usize,
    reach: usize,
    share: f32,
) -> Vec<FrameNearCapture> {
    let mut out = Vec::new();
    for (c, capture) in session.captures.iter().enumerate() {
        let Some(peak) = capture.frame.map(|f| f as usize) else {
            continue;
        };
        let target = capture.weights.get(capture.prompt) * share;
        let from = peak.saturating_sub(reach);
        let to = (peak + reach).min(session.frames.len().saturating_sub(1));
        for f in from..=to {
            // Indexing: `usable` checks that frame `f` exists.
            if f.abs_diff(peak) < gap || !usable(session, f) {
                continue;
            }
            if session.frames[f].weights.get(capture.prompt) >= target {
                out.push(FrameNearCapture {
                    capture: c,
                    frame: f,
                });
            }
        }
    }
    out
}

/// Extra frames for the `multi` fit, within [`FIT_REACH`] of each capture
/// (the capture itself excluded).
pub fn fit_frames(session: &Session) -> Vec<FrameNearCapture> {
    around_captures(session, 1, FIT_REACH, FIT_MIN_SHARE)
}

#[cfg(feature = "study")]
/// Held-out frames for choosing λ, [`VALIDATION_GAP`]–[`VALIDATION_REACH`]
/// frames from each capture. Disjoint from [`fit_frames`] and from every
/// captured frame.
pub fn validation_frames(session: &Session) -> Vec<usize> {
    let captured: Vec<usize> = session
        .captures
        .iter()
        .filter_map(|c| c.frame.map(|f| f as usize))
        .collect();
    let mut frames: Vec<usize> = around_captures(
        session,
        VALIDATION_GAP,
        VALIDATION_REACH,
        VALIDATION_MIN_SHARE,
    )
    .into_iter()
    .map(|near| near.frame)
    .filter(|f| captured.iter().all(|c| c.abs_diff(*f) >= VALIDATION_GAP))
    .collect();
    frames.sort_unstable();
    frames.dedup();
    frames.into_iter().step_by(VALIDATION_STRIDE).collect()
}
