//! Quality flags on a capture, for the app to offer a retake: the requested
//! weight stayed low, another shape dominated, or tracking was lost around
//! the captured moment.

use crate::arkit::{BLENDSHAPE_COUNT, Blendshape, Weights};

/// What may be wrong with one capture. All `false`/`None` is a clean capture.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CaptureQuality {
    /// The requested weight at the captured frame is below
    /// [`QualityConfig::weak_weight`]: the expression was performed only
    /// partly.
    pub weak: bool,
    /// Another shape's weight is larger than the requested one (shapes the
    /// requested one cannot be made without are not counted, see
    /// [`companions`]).
    pub dominated_by: Option<Blendshape>,
    /// The face was not tracked for some frame within
    /// [`QualityConfig::tracking_margin`] frames of the captured one (among
    /// the frames seen until the capture was confirmed).
    pub tracking_lost: bool,
    /// Neutral scan only: the person's face rests with this shape (the
    /// highest) above `NeutralConfig::max_weight`. Expressions are then
    /// measured from the rest levels ([`crate::capture::rest_levels`]); the
    /// app may ask the person to relax and retake the neutral scan.
    pub high_rest: Option<Blendshape>,
}

impl CaptureQuality {
    /// No flag raised.
    pub fn is_clean(&self) -> bool {
        !self.weak && self.dominated_by.is_none() && !self.tracking_lost && self.high_rest.is_none()
    }

    /// Each raised flag as a sentence for the person who made the capture
    /// (empty when [clean](Self::is_clean)), in the order of the fields.
    pub fn warnings(&self) -> Vec<String> {
        let mut out = Vec::new();
        if self.weak {
            out.push("weak: the expression was performed only partly".to_string());
        }
        if let Some(other) = self.dominated_by {
            out.push(format!("{other} was stronger than the requested shape"));
        }
        if self.tracking_lost {
            out.push("the face was lost around the captured moment".to_string());
        }
        if let Some(shape) = self.high_rest {
            out.push(format!(
                "the relaxed face rests high on {shape}: expressions are measured from it (retake the neutral scan if the face was not relaxed)"
            ));
        }
        out
    }
}

/// Thresholds of the quality flags; [`Default`] gives the documented values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QualityConfig {
    /// Requested weight below which a capture is weak (default 0.6: the
    /// detector fires from 0.5, and a capture between the two is a half
    /// expression the person can usually do better).
    pub weak_weight: f32,
    /// Frames either side of the capture in which a tracking loss counts
    /// (default 15 = 0.25 s at 60 fps, the span ARKit's temporal filter and
    /// the peak fit draw on).
    pub tracking_margin: u64,
}

impl Default for QualityConfig {
    fn default() -> Self {
        QualityConfig {
            weak_weight: 0.6,
            tracking_margin: 15,
        }
    }
}

/// Shapes that physiology moves together with `shape`, so their weight
/// rising with it is no fault: the eyes turn together (asked to look up
/// with the left eye, both look up; the left eye turning in is the right
/// eye turning out), and ARKit's mouthClose is performed with the jaw open.
pub fn companions(shape: Blendshape) -> &'static [Blendshape] {
    use Blendshape::*;
    match shape {
        EyeLookUpLeft => &[EyeLookUpRight],
        EyeLookUpRight => &[EyeLookUpLeft],
        EyeLookDownLeft => &[EyeLookDownRight],
        EyeLookDownRight => &[EyeLookDownLeft],
        EyeLookInLeft => &[EyeLookOutRight],
        EyeLookInRight => &[EyeLookOutLeft],
        EyeLookOutLeft => &[EyeLookInRight],
        EyeLookOutRight => &[EyeLookInLeft],
        MouthClose => &[JawOpen],
        _ => &[],
    }
}

/// The weight and dominance flags of a capture of `shape` with `weights`
/// (the tracking flag is the state machine's to set).
pub fn assess(shape: Blendshape, weights: &Weights, config: &QualityConfig) -> CaptureQuality {
    let requested = weights.get(shape);
    let dominated_by = (0..BLENDSHAPE_COUNT)
        .filter_map(Blendshape::from_index)
        .filter(|other| *other != shape && !companions(shape).contains(other))
        .filter(|other| weights.get(*other) > requested)
        .max_by(|a, b| weights.get(*a).total_cmp(&weights.get(*b)));
    CaptureQuality {
        weak: requested.is_nan() || requested < config.weak_weight,
        dominated_by,
        tracking_lost: false,
        high_rest: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_strong_lone_expression_is_clean() {
        let mut w = Weights::default();
        w.set(Blendshape::EyeBlinkLeft, 0.9);
        w.set(Blendshape::EyeBlinkRight, 0.3);
        assert!(assess(Blendshape::EyeBlinkLeft, &w, &QualityConfig::default()).is_clean());
    }

    #[test]
    fn a_half_expression_is_weak() {
        let mut w = Weights::default();
        w.set(Blendshape::JawOpen, 0.55);
        assert!(assess(Blendshape::JawOpen, &w, &QualityConfig::default()).weak);
    }

    #[test]
    fn the_strongest_other_shape_is_named() {
        let mut w = Weights::default();
        w.set(Blendshape::EyeBlinkLeft, 0.7);
        w.set(Blendshape::EyeBlinkRight, 0.8);
        w.set(Blendshape::EyeSquintLeft, 0.75);
        let q = assess(Blendshape::EyeBlinkLeft, &w, &QualityConfig::default());
        assert_eq!(q.dominated_by, Some(Blendshape::EyeBlinkRight));
    }

    #[test]
    fn each_flag_is_one_sentence_naming_the_shape() {
        assert!(CaptureQuality::default().warnings().is_empty());
        let q = CaptureQuality {
            weak: true,
            dominated_by: Some(Blendshape::JawOpen),
            tracking_lost: true,
            high_rest: Some(Blendshape::BrowDownLeft),
        };
        let w = q.warnings();
        assert_eq!(w.len(), 4);
        assert!(w[0].starts_with("weak"));
        assert!(w[1].starts_with("jawOpen"));
        assert!(w[2].contains("lost"));
        assert!(w[3].contains("browDownLeft"));
    }

    #[test]
    fn conjugate_gaze_is_not_a_fault() {
        let mut w = Weights::default();
        w.set(Blendshape::EyeLookInLeft, 0.7);
        w.set(Blendshape::EyeLookOutRight, 0.8);
        assert!(assess(Blendshape::EyeLookInLeft, &w, &QualityConfig::default()).is_clean());
    }
}
