//! Held-out test expressions (§4.1): natural combinations of shapes, unlike
//! the single-shape prompts, performed after the 52 prompts.
//!
//! The recipes are everyday expressions described in FACS terms (Ekman &
//! Friesen): happiness = smile + cheek raise + squint; surprise = brows up +
//! eyes wide + jaw drop; and so on. Each session performs 20–30 of them, at
//! 60–100% of the recipe's intensity.

use crate::envelope::{Envelope, Score};
use crate::timeline::{TestTrack, frame_at};
use likeness::Blendshape;
use rand::Rng;
use rand::seq::SliceRandom;
use rand_chacha::ChaCha8Rng;

/// Range of the number of test expressions per session.
pub const TEST_COUNT: (usize, usize) = (20, 30);

/// A named test expression and its shapes with base intensities.
pub type Recipe = (&'static str, &'static [(Blendshape, f64)]);

/// The recipe book.
pub const RECIPES: [Recipe; 32] = {
    use Blendshape::*;
    [
        (
            "smile",
            &[
                (MouthSmileLeft, 0.8),
                (MouthSmileRight, 0.8),
                (CheekSquintLeft, 0.4),
                (CheekSquintRight, 0.4),
            ],
        ),
        (
            "smile-squint",
            &[
                (MouthSmileLeft, 0.8),
                (MouthSmileRight, 0.8),
                (EyeSquintLeft, 0.6),
                (EyeSquintRight, 0.6),
            ],
        ),
        (
            "laugh",
            &[
                (JawOpen, 0.45),
                (MouthSmileLeft, 0.9),
                (MouthSmileRight, 0.9),
                (CheekSquintLeft, 0.6),
                (CheekSquintRight, 0.6),
                (EyeSquintLeft, 0.5),
                (EyeSquintRight, 0.5),
            ],
        ),
        (
            "surprise",
            &[
                (BrowInnerUp, 0.8),
                (BrowOuterUpLeft, 0.7),
                (BrowOuterUpRight, 0.7),
                (EyeWideLeft, 0.7),
                (EyeWideRight, 0.7),
                (JawOpen, 0.4),
            ],
        ),
        (
            "anger",
            &[
                (BrowDownLeft, 0.8),
                (BrowDownRight, 0.8),
                (NoseSneerLeft, 0.3),
                (NoseSneerRight, 0.3),
                (MouthPressLeft, 0.6),
                (MouthPressRight, 0.6),
            ],
        ),
        (
            "sadness",
            &[
                (BrowInnerUp, 0.7),
                (MouthFrownLeft, 0.6),
                (MouthFrownRight, 0.6),
                (MouthShrugLower, 0.5),
            ],
        ),
        (
            "disgust",
            &[
                (NoseSneerLeft, 0.8),
                (NoseSneerRight, 0.8),
                (MouthUpperUpLeft, 0.6),
                (MouthUpperUpRight, 0.6),
                (BrowDownLeft, 0.3),
                (BrowDownRight, 0.3),
            ],
        ),
        (
            "fear",
            &[
                (BrowInnerUp, 0.8),
                (EyeWideLeft, 0.8),
                (EyeWideRight, 0.8),
                (MouthStretchLeft, 0.5),
                (MouthStretchRight, 0.5),
                (JawOpen, 0.2),
            ],
        ),
        (
            "contempt-left",
            &[(MouthSmileLeft, 0.5), (MouthDimpleLeft, 0.6)],
        ),
        (
            "smirk-right",
            &[
                (MouthSmileRight, 0.7),
                (MouthRight, 0.3),
                (CheekSquintRight, 0.3),
                (EyeSquintRight, 0.2),
            ],
        ),
        (
            "wink-left-smile",
            &[
                (EyeBlinkLeft, 1.0),
                (MouthSmileLeft, 0.7),
                (MouthSmileRight, 0.4),
                (CheekSquintLeft, 0.5),
            ],
        ),
        (
            "wink-right",
            &[
                (EyeBlinkRight, 1.0),
                (CheekSquintRight, 0.4),
                (MouthSmileRight, 0.3),
            ],
        ),
        (
            "kiss",
            &[
                (MouthPucker, 0.9),
                (EyeBlinkLeft, 0.8),
                (EyeBlinkRight, 0.8),
            ],
        ),
        ("oh", &[(JawOpen, 0.4), (MouthFunnel, 0.7)]),
        (
            "ee",
            &[
                (MouthStretchLeft, 0.6),
                (MouthStretchRight, 0.6),
                (MouthSmileLeft, 0.3),
                (MouthSmileRight, 0.3),
                (JawOpen, 0.1),
            ],
        ),
        (
            "shout",
            &[
                (JawOpen, 0.6),
                (MouthStretchLeft, 0.5),
                (MouthStretchRight, 0.5),
                (BrowDownLeft, 0.5),
                (BrowDownRight, 0.5),
                (NoseSneerLeft, 0.3),
                (NoseSneerRight, 0.3),
            ],
        ),
        (
            "yawn",
            &[
                (JawOpen, 0.9),
                (EyeSquintLeft, 0.5),
                (EyeSquintRight, 0.5),
                (BrowInnerUp, 0.3),
                (MouthFunnel, 0.2),
            ],
        ),
        (
            "grimace",
            &[
                (MouthStretchLeft, 0.8),
                (MouthStretchRight, 0.8),
                (MouthPressLeft, 0.4),
                (MouthPressRight, 0.4),
                (EyeSquintLeft, 0.4),
                (EyeSquintRight, 0.4),
            ],
        ),
        (
            "pout",
            &[
                (MouthShrugLower, 0.7),
                (MouthShrugUpper, 0.4),
                (MouthFrownLeft, 0.3),
                (MouthFrownRight, 0.3),
            ],
        ),
        (
            "lips-in",
            &[
                (MouthRollLower, 0.7),
                (MouthRollUpper, 0.7),
                (MouthPressLeft, 0.3),
                (MouthPressRight, 0.3),
            ],
        ),
        (
            "puff-squint",
            &[
                (CheekPuff, 0.8),
                (EyeSquintLeft, 0.3),
                (EyeSquintRight, 0.3),
            ],
        ),
        (
            "skeptical-left",
            &[
                (BrowOuterUpLeft, 0.8),
                (BrowDownRight, 0.6),
                (MouthLeft, 0.3),
            ],
        ),
        (
            "thinking",
            &[
                (MouthRight, 0.5),
                (MouthPressLeft, 0.3),
                (MouthPressRight, 0.3),
                (BrowDownLeft, 0.3),
                (EyeLookUpLeft, 0.5),
                (EyeLookUpRight, 0.5),
            ],
        ),
        (
            "look-down-sad",
            &[
                (EyeLookDownLeft, 0.7),
                (EyeLookDownRight, 0.7),
                (BrowInnerUp, 0.5),
                (MouthFrownLeft, 0.3),
                (MouthFrownRight, 0.3),
            ],
        ),
        (
            "side-eye",
            &[
                (EyeLookOutLeft, 0.8),
                (EyeLookInRight, 0.8),
                (BrowDownLeft, 0.4),
                (BrowDownRight, 0.4),
                (MouthPressLeft, 0.3),
                (MouthPressRight, 0.3),
            ],
        ),
        (
            "sneer-left",
            &[
                (NoseSneerLeft, 0.8),
                (MouthUpperUpLeft, 0.7),
                (EyeSquintLeft, 0.3),
            ],
        ),
        (
            "chew",
            &[(JawOpen, 0.25), (JawLeft, 0.5), (MouthClose, 0.3)],
        ),
        (
            "jaw-thrust",
            &[
                (JawForward, 0.8),
                (MouthShrugLower, 0.3),
                (BrowDownLeft, 0.2),
                (BrowDownRight, 0.2),
            ],
        ),
        (
            "tongue",
            &[
                (TongueOut, 0.9),
                (JawOpen, 0.4),
                (EyeSquintLeft, 0.3),
                (EyeSquintRight, 0.3),
            ],
        ),
        (
            "sleepy",
            &[
                (EyeBlinkLeft, 0.6),
                (EyeBlinkRight, 0.6),
                (BrowInnerUp, 0.2),
                (JawOpen, 0.15),
            ],
        ),
        (
            "teeth-bared",
            &[
                (MouthUpperUpLeft, 0.7),
                (MouthUpperUpRight, 0.7),
                (MouthLowerDownLeft, 0.6),
                (MouthLowerDownRight, 0.6),
                (MouthStretchLeft, 0.4),
                (MouthStretchRight, 0.4),
            ],
        ),
        (
            "closed-mouth-chew",
            &[(JawOpen, 0.35), (MouthClose, 0.35), (MouthPucker, 0.2)],
        ),
    ]
};

/// Performs 20–30 recipes, in random order, from time `t` (advanced past
/// them), writing them into `score`; returns where each one peaks.
pub(crate) fn perform_tests(
    rng: &mut ChaCha8Rng,
    t: &mut f64,
    frame_rate: f64,
    score: &mut Score,
) -> Vec<TestTrack> {
    let count = rng.random_range(TEST_COUNT.0..=TEST_COUNT.1);
    let mut book: Vec<&Recipe> = RECIPES.iter().collect();
    book.shuffle(rng);
    let mut tests = Vec::new();
    for (id, recipe) in book.into_iter().take(count) {
        let start = *t + rng.random_range(0.5..0.9);
        let intensity = rng.random_range(0.6..1.0);
        let env = Envelope::draw(rng, start, 1.0);
        let shapes: Vec<(usize, f64)> = recipe
            .iter()
            .filter(|(_, amount)| *amount > 0.0)
            .map(|(shape, amount)| (shape.index(), amount * intensity))
            .collect();
        score.perform(&shapes, env);
        tests.push(TestTrack {
            id: id.to_string(),
            frame: frame_at(env.peak_time(), frame_rate),
        });
        *t = env.end() + 0.1;
    }
    tests
}
