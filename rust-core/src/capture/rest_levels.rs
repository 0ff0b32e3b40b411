//! A real person's resting face, as ARKit reports it: the weights of the
//! neutral scan. They are not zero, and they differ per person and per
//! shape (Live Link Face offers a neutral-pose calibration for exactly this
//! reason); someone whose brows rest low shows browDown at 0.3–0.5 with a
//! relaxed face. An expression detector that ignores this never re-arms for
//! that shape and takes the rest for half the expression.
//!
//! So the guided capture measures each prompted weight from the person's
//! rest level `r`. ARKit's weights for such a face behave like an offset on
//! the usual ones, clamped at 1: a half-hearted try rises from the rest by
//! as much as anyone's does, and a full expression runs into the clamp. So
//! the rise `w − r` is what counts, against the detector's usual threshold
//! `T` (0.5) — except where less than `T / κ` is left below 1: there the
//! rise is stretched so that reaching a share `κ` ([`RANGE_SHARE`], 0.8) of
//! what is left counts as `T`:
//!
//! ```text
//! u = (w − r) · s(r),   s(r) = max(1, T / (κ (1 − r)))
//! ```
//!
//! For r = 0.3 that is the plain rise; for r = 0.45 the rise is stretched
//! by 1.14, so a full expression (w = 1) reads 0.62 and a failed try
//! (a rise of at most 0.37) stays under 0.5. Rest levels at or below a
//! floor ([`super::guided_capture::GuidedCaptureConfig::rest_floor`],
//! default 0.1, ARKit's usual small offsets) are taken as 0, so for most
//! people and shapes the absolute rules apply unchanged; so they do before
//! the neutral scan has been taken.

use crate::arkit::{BLENDSHAPE_COUNT, Blendshape, Weights};

/// The highest rest level that is rescaled: above it the remaining range is
/// too small to measure an expression in (the neutral scan accepts rests up
/// to 0.6, see `NeutralConfig::max_rest_weight`).
pub const MAX_REST: f32 = 0.9;

/// κ: where less than `T / κ` is left between the rest level and 1, a
/// rise to this share of what is left counts as the detector's threshold
/// `T` (see the module docs).
pub const RANGE_SHARE: f32 = 0.8;

/// Per-shape rest levels the expression weights are measured from, and the
/// stretch `s(r)` of each.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RestLevels {
    levels: Weights,
    stretch: Weights,
}

impl RestLevels {
    /// No rest levels: every weight is measured from 0 (the absolute rules).
    pub const NONE: RestLevels = RestLevels {
        levels: Weights::ZERO,
        stretch: Weights([1.0; BLENDSHAPE_COUNT]),
    };

    /// The rest levels of a neutral scan's weights `rest`, for a detector
    /// whose threshold is `threshold`: each level above `floor` (capped at
    /// [`MAX_REST`]), the others 0.
    pub fn from_neutral(rest: &Weights, floor: f32, threshold: f32) -> RestLevels {
        let levels = Weights(rest.0.map(|r| {
            if r.is_finite() && r > floor {
                r.min(MAX_REST)
            } else {
                0.0
            }
        }));
        let stretch = Weights(
            levels
                .0
                .map(|r| (threshold / (RANGE_SHARE * (1.0 - r))).max(1.0)),
        );
        RestLevels { levels, stretch }
    }

    /// The level of `shape`.
    pub fn get(&self, shape: Blendshape) -> f32 {
        self.levels.get(shape)
    }

    /// `shape`'s weight `w` measured from its rest level:
    /// `(w − r) · s(r)` (`w` itself where the level is 0).
    pub fn relative(&self, shape: Blendshape, w: f32) -> f32 {
        let r = self.get(shape);
        if r > 0.0 {
            (w - r) * self.stretch.get(shape)
        } else {
            w
        }
    }

    /// Every weight measured from its rest level.
    pub fn relative_weights(&self, weights: &Weights) -> Weights {
        let mut out = *weights;
        for (shape, w) in weights.iter() {
            out.set(shape, self.relative(shape, w));
        }
        out
    }

    /// The shape resting highest, if its level is above `level`.
    pub fn highest_above(&self, level: f32) -> Option<Blendshape> {
        let shape = self.levels.dominant();
        (self.get(shape) > level).then_some(shape)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn low_rests_keep_the_absolute_rules_and_high_ones_count_the_rise() {
        let mut rest = Weights::ZERO;
        rest.set(Blendshape::BrowDownLeft, 0.45);
        rest.set(Blendshape::BrowInnerUp, 0.3);
        rest.set(Blendshape::EyeSquintLeft, 0.05);
        let levels = RestLevels::from_neutral(&rest, 0.1, 0.5);
        assert_eq!(levels.relative(Blendshape::EyeSquintLeft, 0.7), 0.7);
        // At 0.3 the plain rise counts.
        assert!((levels.relative(Blendshape::BrowInnerUp, 0.8) - 0.5).abs() < 1e-6);
        // At 0.45 only 0.55 is left: 80% of it counts as the threshold.
        assert_eq!(levels.relative(Blendshape::BrowDownLeft, 0.45), 0.0);
        let at = 0.45 + 0.8 * 0.55;
        assert!((levels.relative(Blendshape::BrowDownLeft, at) - 0.5).abs() < 1e-6);
        // A failed try (a rise of 0.35) stays under the threshold.
        assert!(levels.relative(Blendshape::BrowDownLeft, 0.8) < 0.45);
        assert_eq!(levels.highest_above(0.25), Some(Blendshape::BrowDownLeft));
        assert_eq!(levels.highest_above(0.5), None);
        assert_eq!(
            RestLevels::NONE.relative(Blendshape::BrowDownLeft, 0.3),
            0.3
        );
    }
}
