//! A short account of a session's captures for the person who made them:
//! how many of the 52 prompts were captured, which were not, and what may
//! be wrong with the captured ones.
//!
//! It is computed from the [`Session`] alone, so a session reads the same
//! fresh from the capture and loaded from its file. The flags are those of
//! [`capture_quality`](super::guided_capture::capture_quality) with its
//! default thresholds, on the weights stored with each capture and on the
//! stream's tracking around it. The live capture measures a weight from
//! the person's rest level, which a session does not store, so for a face
//! that rests high the live events may flag a weak capture this summary
//! does not.

use super::guided_capture::capture_quality::{QualityConfig, assess};
use super::prompt_order::PROMPT_ORDER;
use crate::arkit::{BLENDSHAPE_COUNT, Blendshape};
use crate::session::{CapturedExpression, Session};

/// What [`quality_summary`] says about a session.
#[derive(Clone, Debug, PartialEq)]
pub struct QualitySummary {
    /// One line: how many were captured, how many are missing, how many
    /// warnings.
    pub headline: String,
    /// Prompts with a capture (of 52).
    pub captured: usize,
    /// Prompts without one, in the order they are asked for; their
    /// personalized shapes are the generic ones.
    pub skipped: Vec<Blendshape>,
    /// One sentence per flag raised, each starting with the prompt's name.
    pub warnings: Vec<String>,
}

/// Summarizes `session`'s captures (see the module docs).
pub fn quality_summary(session: &Session) -> QualitySummary {
    let config = QualityConfig::default();
    let skipped: Vec<Blendshape> = PROMPT_ORDER
        .iter()
        .copied()
        .filter(|shape| session.capture(*shape).is_none())
        .collect();
    let warnings: Vec<String> = PROMPT_ORDER
        .iter()
        .filter_map(|shape| session.capture(*shape))
        .flat_map(|capture| {
            let mut quality = assess(capture.prompt, &capture.weights, &config);
            quality.tracking_lost = tracking_lost_near(session, capture, config.tracking_margin);
            quality
                .warnings()
                .into_iter()
                .map(move |w| format!("{}: {w}", capture.prompt))
        })
        .collect();
    let captured = session.captures.len();
    let mut headline = if skipped.is_empty() {
        format!("All {BLENDSHAPE_COUNT} expressions captured")
    } else {
        format!(
            "{captured} of {BLENDSHAPE_COUNT} expressions captured, {} missing (their generic shapes are used)",
            skipped.len()
        )
    };
    headline.push_str(&match warnings.len() {
        0 => ", no warnings".to_string(),
        1 => "; 1 warning".to_string(),
        n => format!("; {n} warnings"),
    });
    QualitySummary {
        headline,
        captured,
        skipped,
        warnings,
    }
}

/// Whether a stream frame within `margin` frames of the capture's frame
/// was untracked (`false` when the capture names no frame).
fn tracking_lost_near(session: &Session, capture: &CapturedExpression, margin: u64) -> bool {
    let Some(frame) = capture.frame else {
        return false;
    };
    let frame = u64::from(frame);
    let from = frame.saturating_sub(margin) as usize;
    let to = (frame + margin) as usize;
    session
        .frames
        .iter()
        .take(to + 1)
        .skip(from)
        .any(|f| !f.tracked)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::arkit::Weights;
    use crate::session::Frame;
    use crate::test_support::{face_grid, stretch_session};

    #[test]
    fn one_clean_capture_of_52() {
        let (topology, neutral, _) = face_grid();
        let summary = quality_summary(&stretch_session(topology, neutral));
        assert_eq!(summary.captured, 1);
        assert_eq!(summary.skipped.len(), 51);
        assert!(!summary.skipped.contains(&Blendshape::JawOpen));
        assert_eq!(summary.skipped[0], PROMPT_ORDER[0]);
        assert!(summary.warnings.is_empty());
        assert_eq!(
            summary.headline,
            "1 of 52 expressions captured, 51 missing (their generic shapes are used), no warnings"
        );
    }

    #[test]
    fn weak_dominated_and_untracked_captures_are_named() {
        let (topology, neutral, _) = face_grid();
        let mut parts = stretch_session(topology, neutral).into_parts();
        let mut weights = Weights::ZERO;
        weights.set(Blendshape::JawOpen, 0.55);
        weights.set(Blendshape::MouthFunnel, 0.7);
        parts.frames = (0..40)
            .map(|i| Frame {
                timestamp: i as f64 / 60.0,
                weights: Weights::ZERO,
                tracked: i != 25,
                vertices: None,
            })
            .collect();
        parts.captures[0].weights = weights;
        parts.captures[0].frame = Some(12);
        let session = Session::new(parts).unwrap();
        let summary = quality_summary(&session);
        assert_eq!(summary.warnings.len(), 3, "{:?}", summary.warnings);
        assert!(summary.warnings[0].starts_with("jawOpen: weak"));
        assert!(summary.warnings[1].starts_with("jawOpen: mouthFunnel"));
        assert!(summary.warnings[2].contains("lost"));
        assert!(summary.headline.ends_with("; 3 warnings"));
        // Frame 25 is 13 frames from 12 (within 15), not from 5 (20 away).
        let mut parts = session.into_parts();
        parts.captures[0].frame = Some(5);
        let summary = quality_summary(&Session::new(parts).unwrap());
        assert_eq!(summary.warnings.len(), 2);
    }
}
