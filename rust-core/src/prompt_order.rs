//! The order in which the app asks for ARKit's 52 expressions.
//!
//! Grouped by face region (brows, eyes, cheeks and nose, jaw, mouth, tongue)
//! so the person's attention stays in one place, with each left/right pair
//! adjacent (left first), and easy expressions before hard ones within a
//! region. The simulator performs prompts in this order, as a person
//! following the app would.

use crate::arkit_names::{BLENDSHAPE_COUNT, Blendshape};

/// All 52 shapes in prompting order.
#[rustfmt::skip]
pub const PROMPT_ORDER: [Blendshape; BLENDSHAPE_COUNT] = {
    use Blendshape::*;
    [
        BrowInnerUp, BrowOuterUpLeft, BrowOuterUpRight, BrowDownLeft, BrowDownRight,
        EyeBlinkLeft, EyeBlinkRight, EyeSquintLeft, EyeSquintRight, EyeWideLeft, EyeWideRight,
        EyeLookUpLeft, EyeLookUpRight, EyeLookDownLeft, EyeLookDownRight, EyeLookInLeft,
        EyeLookInRight, EyeLookOutLeft, EyeLookOutRight,
        CheekSquintLeft, CheekSquintRight, NoseSneerLeft, NoseSneerRight, CheekPuff,
        JawOpen, MouthClose, JawForward, JawLeft, JawRight,
        MouthSmileLeft, MouthSmileRight, MouthFrownLeft, MouthFrownRight, MouthDimpleLeft,
        MouthDimpleRight, MouthStretchLeft, MouthStretchRight, MouthLeft, MouthRight,
        MouthPucker, MouthFunnel, MouthRollUpper, MouthRollLower, MouthShrugUpper,
        MouthShrugLower, MouthPressLeft, MouthPressRight, MouthUpperUpLeft, MouthUpperUpRight,
        MouthLowerDownLeft, MouthLowerDownRight, TongueOut,
    ]
};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_shape_once_and_pairs_adjacent() {
        let mut seen = [false; BLENDSHAPE_COUNT];
        for s in PROMPT_ORDER {
            assert!(!std::mem::replace(&mut seen[s.index()], true), "{s} twice");
        }
        for (i, s) in PROMPT_ORDER.iter().enumerate() {
            if s.mirror() != *s {
                let j = PROMPT_ORDER.iter().position(|t| *t == s.mirror()).unwrap();
                assert_eq!(i.abs_diff(j), 1, "{s} and its mirror are not adjacent");
            }
        }
    }
}
