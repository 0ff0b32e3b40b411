//! The order in which the app asks for ARKit's 52 expressions.
//!
//! Grouped by face region (brows, eyes, cheeks and nose, jaw, mouth, tongue)
//! so the person's attention stays in one place, with each left/right pair
//! adjacent (left first), and easy expressions before hard ones within a
//! region. The simulator performs prompts in this order, as a person
//! following the app would.

#[cfg(test)]
use crate::arkit::Side;
use crate::arkit::{BLENDSHAPE_COUNT, Blendshape};

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

/// A short instruction a person understands, shown with the prompt. "Left"
/// and "right" are the person's own sides (the screen mirrors them).
pub fn instruction(shape: Blendshape) -> &'static str {
    use Blendshape::*;
    match shape {
        BrowInnerUp => "Raise the inner ends of both eyebrows, as if worried",
        BrowOuterUpLeft => "Raise the outer end of your left eyebrow only",
        BrowOuterUpRight => "Raise the outer end of your right eyebrow only",
        BrowDownLeft => "Frown with your left eyebrow, pulling it down",
        BrowDownRight => "Frown with your right eyebrow, pulling it down",
        EyeBlinkLeft => "Close your left eye only",
        EyeBlinkRight => "Close your right eye only",
        EyeSquintLeft => "Squint your left eye, lifting the lower lid",
        EyeSquintRight => "Squint your right eye, lifting the lower lid",
        EyeWideLeft => "Open your left eye as wide as you can",
        EyeWideRight => "Open your right eye as wide as you can",
        EyeLookUpLeft => "Look up, keeping your head still",
        EyeLookUpRight => "Look up again, keeping your head still",
        EyeLookDownLeft => "Look down, keeping your head still",
        EyeLookDownRight => "Look down again, keeping your head still",
        EyeLookInLeft => "Look to your right, head still (left eye turns in)",
        EyeLookInRight => "Look to your left, head still (right eye turns in)",
        EyeLookOutLeft => "Look to your left again (left eye turns out)",
        EyeLookOutRight => "Look to your right again (right eye turns out)",
        CheekSquintLeft => "Raise your left cheek towards your eye",
        CheekSquintRight => "Raise your right cheek towards your eye",
        NoseSneerLeft => "Wrinkle your nose on the left side, as if smelling something bad",
        NoseSneerRight => "Wrinkle your nose on the right side, as if smelling something bad",
        CheekPuff => "Puff out both cheeks with air, lips closed",
        JawOpen => "Open your mouth wide, dropping your jaw",
        MouthClose => "Drop your jaw but keep your lips closed",
        JawForward => "Push your lower jaw forward",
        JawLeft => "Shift your lower jaw to your left",
        JawRight => "Shift your lower jaw to your right",
        MouthSmileLeft => "Smile with the left corner of your mouth only",
        MouthSmileRight => "Smile with the right corner of your mouth only",
        MouthFrownLeft => "Pull the left corner of your mouth down",
        MouthFrownRight => "Pull the right corner of your mouth down",
        MouthDimpleLeft => "Press the left corner of your mouth back into a dimple",
        MouthDimpleRight => "Press the right corner of your mouth back into a dimple",
        MouthStretchLeft => "Stretch the left corner of your mouth out and down",
        MouthStretchRight => "Stretch the right corner of your mouth out and down",
        MouthLeft => "Move your closed mouth to your left",
        MouthRight => "Move your closed mouth to your right",
        MouthPucker => "Pucker your lips as if for a kiss",
        MouthFunnel => "Shape your lips into an 'O', as if saying 'oo'",
        MouthRollUpper => "Roll your upper lip in over your teeth",
        MouthRollLower => "Roll your lower lip in over your teeth",
        MouthShrugUpper => "Push your upper lip up, lips closed",
        MouthShrugLower => "Push your lower lip and chin up, as if pouting",
        MouthPressLeft => "Press your lips together on the left side",
        MouthPressRight => "Press your lips together on the right side",
        MouthUpperUpLeft => "Raise your upper lip on the left, showing your teeth",
        MouthUpperUpRight => "Raise your upper lip on the right, showing your teeth",
        MouthLowerDownLeft => "Pull your lower lip down on the left, showing your teeth",
        MouthLowerDownRight => "Pull your lower lip down on the right, showing your teeth",
        TongueOut => "Stick your tongue out",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_sided_prompt_names_its_side_and_instructions_are_distinct() {
        let mut seen = std::collections::HashSet::new();
        for shape in PROMPT_ORDER {
            let text = instruction(shape);
            assert!(text.len() > 10 && text.len() < 80, "{shape}: {text:?}");
            assert!(seen.insert(text), "{shape}: instruction repeated");
            let lower = text.to_lowercase();
            match shape.side() {
                Side::Left if !shape.name().starts_with("eyeLook") => {
                    assert!(lower.contains("left"), "{shape}: {text}")
                }
                Side::Right if !shape.name().starts_with("eyeLook") => {
                    assert!(lower.contains("right"), "{shape}: {text}")
                }
                _ => {}
            }
        }
    }

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
