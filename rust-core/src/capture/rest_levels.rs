//! A real person's resting face, as ARKit reports it: the weights of the
//! neutral scan. They are not zero, and they differ per person and per
//! shape (Live Link Face offers a neutral-pose calibration for exactly this
//! reason); someone whose brows rest low shows browDown at 0.3–0.5 with a
//! relaxed face. An expression detector that ignores this never re-arms for
//! that shape and takes the rest for half the expression.
//!
//! So the guided capture measures each prompted weight from the person's
//! rest level `r`, rescaled so that the remaining range still ends at 1:
//!
//! ```text
//! u = (w − r) / (1 − r)
//! ```
//!
//! which leaves the detector's thresholds (0.5 to count, 0.4 to re-arm)
//! meaning the same share of what that person can still show. Rest levels
//! at or below a floor ([`super::guided_capture::GuidedCaptureConfig::rest_floor`],
//! default 0.1, ARKit's usual small offsets) are taken as 0, so for most
//! people and shapes the absolute rules apply unchanged; so they do before
//! the neutral scan has been taken.

use crate::arkit::{BLENDSHAPE_COUNT, Blendshape, Weights};

/// The highest rest level that is rescaled: above it the remaining range is
/// too small to measure an expression in (the neutral scan accepts rests up
/// to 0.6, see `NeutralConfig::max_rest_weight`).
pub const MAX_REST: f32 = 0.9;

/// Per-shape rest levels the expression weights are measured from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RestLevels(Weights);

impl RestLevels {
    /// No rest levels: every weight is measured from 0 (the absolute rules).
    pub const NONE: RestLevels = RestLevels(Weights::ZERO);

    /// The rest levels of a neutral scan's weights `rest`: each level above
    /// `floor` (capped at [`MAX_REST`]), the others 0.
    pub fn from_neutral(rest: &Weights, floor: f32) -> RestLevels {
        RestLevels(Weights(rest.0.map(|r| {
            if r.is_finite() && r > floor {
                r.min(MAX_REST)
            } else {
                0.0
            }
        })))
    }

    /// The level of `shape`.
    pub fn get(&self, shape: Blendshape) -> f32 {
        self.0.get(shape)
    }

    /// `shape`'s weight `w` measured from its rest level:
    /// `(w − r) / (1 − r)` (`w` itself where the level is 0).
    pub fn relative(&self, shape: Blendshape, w: f32) -> f32 {
        let r = self.get(shape);
        if r > 0.0 { (w - r) / (1.0 - r) } else { w }
    }

    /// Every weight measured from its rest level.
    pub fn relative_weights(&self, weights: &Weights) -> Weights {
        Weights(std::array::from_fn::<f32, BLENDSHAPE_COUNT, _>(|j| {
            Blendshape::ALL
                .get(j)
                .map_or(0.0, |s| self.relative(*s, weights.get(*s)))
        }))
    }

    /// The shape resting highest, if its level is above `level`.
    pub fn highest_above(&self, level: f32) -> Option<Blendshape> {
        let shape = self.0.dominant();
        (self.get(shape) > level).then_some(shape)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn low_rests_keep_the_absolute_rules_and_high_ones_rescale() {
        let mut rest = Weights::ZERO;
        rest.set(Blendshape::BrowDownLeft, 0.45);
        rest.set(Blendshape::EyeSquintLeft, 0.05);
        let levels = RestLevels::from_neutral(&rest, 0.1);
        assert_eq!(levels.relative(Blendshape::EyeSquintLeft, 0.7), 0.7);
        assert_eq!(levels.relative(Blendshape::BrowDownLeft, 0.45), 0.0);
        assert!((levels.relative(Blendshape::BrowDownLeft, 1.0) - 1.0).abs() < 1e-6);
        // Half of what is left above the rest counts as half an expression.
        assert!((levels.relative(Blendshape::BrowDownLeft, 0.725) - 0.5).abs() < 1e-6);
        assert_eq!(levels.highest_above(0.25), Some(Blendshape::BrowDownLeft));
        assert_eq!(levels.highest_above(0.5), None);
        assert_eq!(
            RestLevels::NONE.relative(Blendshape::BrowDownLeft, 0.3),
            0.3
        );
    }
}
