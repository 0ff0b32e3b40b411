//! ARKit's vocabulary of 52 facial blendshapes.
//!
//! The names are ARKit's `ARFaceAnchor.BlendShapeLocation` case names, in the
//! order of Apple's documentation (left eye, right eye, mouth and jaw, brows,
//! cheeks and nose, tongue). "Left" and "right" are the *person's* own sides:
//! `eyeBlinkLeft` closes the left eye, which a viewer sees on the right and
//! which lies at positive x in ARKit's face coordinates.
//!
//! [`Blendshape::parse`] is the one place where the spellings found in the wild
//! become ARKit names: ARKit's own (`eyeBlinkLeft`), Live Link Face CSV headers
//! (`EyeBlinkLeft`), ARKit's raw values and ICT-FaceKit (`eyeBlink_L`), and
//! glTF morph-target names with a prefix (`blendShape1.eyeBlinkLeft`).

use std::fmt;
use std::str::FromStr;

/// Number of ARKit blendshapes.
pub const BLENDSHAPE_COUNT: usize = 52;

macro_rules! blendshapes {
    ($($variant:ident = $name:literal, $mirror:ident;)*) => {
        /// One of ARKit's 52 facial blendshapes; the discriminant is its index
        /// in Apple's documented order.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize, serde::Deserialize)]
        #[repr(u8)]
        pub enum Blendshape {
            $(#[doc = concat!("`", $name, "`")] $variant,)*
        }

        impl Blendshape {
            /// All 52 blendshapes in Apple's documented order.
            pub const ALL: [Blendshape; BLENDSHAPE_COUNT] = [$(Blendshape::$variant,)*];

            /// ARKit's spelling, e.g. `"eyeBlinkLeft"`.
            pub const fn name(self) -> &'static str {
                match self { $(Blendshape::$variant => $name,)* }
            }

            /// The same motion on the other side of the face (`eyeBlinkLeft` ↔
            /// `eyeBlinkRight`); a shape without a side is its own mirror.
            pub const fn mirror(self) -> Blendshape {
                match self { $(Blendshape::$variant => Blendshape::$mirror,)* }
            }
        }
    };
}

blendshapes! {
    EyeBlinkLeft = "eyeBlinkLeft", EyeBlinkRight;
    EyeLookDownLeft = "eyeLookDownLeft", EyeLookDownRight;
    EyeLookInLeft = "eyeLookInLeft", EyeLookInRight;
    EyeLookOutLeft = "eyeLookOutLeft", EyeLookOutRight;
    EyeLookUpLeft = "eyeLookUpLeft", EyeLookUpRight;
    EyeSquintLeft = "eyeSquintLeft", EyeSquintRight;
    EyeWideLeft = "eyeWideLeft", EyeWideRight;
    EyeBlinkRight = "eyeBlinkRight", EyeBlinkLeft;
    EyeLookDownRight = "eyeLookDownRight", EyeLookDownLeft;
    EyeLookInRight = "eyeLookInRight", EyeLookInLeft;
    EyeLookOutRight = "eyeLookOutRight", EyeLookOutLeft;
    EyeLookUpRight = "eyeLookUpRight", EyeLookUpLeft;
    EyeSquintRight = "eyeSquintRight", EyeSquintLeft;
    EyeWideRight = "eyeWideRight", EyeWideLeft;
    JawForward = "jawForward", JawForward;
    JawLeft = "jawLeft", JawRight;
    JawRight = "jawRight", JawLeft;
    JawOpen = "jawOpen", JawOpen;
    MouthClose = "mouthClose", MouthClose;
    MouthFunnel = "mouthFunnel", MouthFunnel;
    MouthPucker = "mouthPucker", MouthPucker;
    MouthLeft = "mouthLeft", MouthRight;
    MouthRight = "mouthRight", MouthLeft;
    MouthSmileLeft = "mouthSmileLeft", MouthSmileRight;
    MouthSmileRight = "mouthSmileRight", MouthSmileLeft;
    MouthFrownLeft = "mouthFrownLeft", MouthFrownRight;
    MouthFrownRight = "mouthFrownRight", MouthFrownLeft;
    MouthDimpleLeft = "mouthDimpleLeft", MouthDimpleRight;
    MouthDimpleRight = "mouthDimpleRight", MouthDimpleLeft;
    MouthStretchLeft = "mouthStretchLeft", MouthStretchRight;
    MouthStretchRight = "mouthStretchRight", MouthStretchLeft;
    MouthRollLower = "mouthRollLower", MouthRollLower;
    MouthRollUpper = "mouthRollUpper", MouthRollUpper;
    MouthShrugLower = "mouthShrugLower", MouthShrugLower;
    MouthShrugUpper = "mouthShrugUpper", MouthShrugUpper;
    MouthPressLeft = "mouthPressLeft", MouthPressRight;
    MouthPressRight = "mouthPressRight", MouthPressLeft;
    MouthLowerDownLeft = "mouthLowerDownLeft", MouthLowerDownRight;
    MouthLowerDownRight = "mouthLowerDownRight", MouthLowerDownLeft;
    MouthUpperUpLeft = "mouthUpperUpLeft", MouthUpperUpRight;
    MouthUpperUpRight = "mouthUpperUpRight", MouthUpperUpLeft;
    BrowDownLeft = "browDownLeft", BrowDownRight;
    BrowDownRight = "browDownRight", BrowDownLeft;
    BrowInnerUp = "browInnerUp", BrowInnerUp;
    BrowOuterUpLeft = "browOuterUpLeft", BrowOuterUpRight;
    BrowOuterUpRight = "browOuterUpRight", BrowOuterUpLeft;
    CheekPuff = "cheekPuff", CheekPuff;
    CheekSquintLeft = "cheekSquintLeft", CheekSquintRight;
    CheekSquintRight = "cheekSquintRight", CheekSquintLeft;
    NoseSneerLeft = "noseSneerLeft", NoseSneerRight;
    NoseSneerRight = "noseSneerRight", NoseSneerLeft;
    TongueOut = "tongueOut", TongueOut;
}

/// Which side of the face a blendshape acts on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// The person's left (positive x in ARKit's face coordinates).
    Left,
    /// The person's right (negative x).
    Right,
    /// Both sides, or the midline.
    Centre,
}

impl Blendshape {
    /// Index in Apple's documented order, `0..52`.
    pub const fn index(self) -> usize {
        self as usize
    }

    /// The blendshape at `index` in Apple's documented order, if any.
    pub fn from_index(index: usize) -> Option<Blendshape> {
        Blendshape::ALL.get(index).copied()
    }

    /// The side this shape acts on, read from its name.
    pub fn side(self) -> Side {
        let name = self.name();
        if name.ends_with("Left") {
            Side::Left
        } else if name.ends_with("Right") {
            Side::Right
        } else {
            Side::Centre
        }
    }

    /// ARKit's raw key for this shape: the string value of
    /// `ARFaceAnchor.BlendShapeLocation` (`ARBlendShapeLocationEyeBlinkLeft
    /// = "eyeBlink_L"`), which is what `ARFaceAnchor.blendShapes` and
    /// `ARFaceGeometry(blendShapes:)` are keyed by. Apple abbreviates the
    /// side to `_L` / `_R` on every sided shape but the four whose side is a
    /// direction of motion (jawLeft, jawRight, mouthLeft, mouthRight).
    pub fn arkit_key(self) -> String {
        let name = self.name();
        let directional = matches!(
            self,
            Blendshape::JawLeft
                | Blendshape::JawRight
                | Blendshape::MouthLeft
                | Blendshape::MouthRight
        );
        match (
            directional,
            name.strip_suffix("Left"),
            name.strip_suffix("Right"),
        ) {
            (false, Some(stem), _) => format!("{stem}_L"),
            (false, _, Some(stem)) => format!("{stem}_R"),
            _ => name.to_string(),
        }
    }

    /// Maps any spelling found in the wild onto an ARKit name.
    ///
    /// Accepted, case-insensitively: `eyeBlinkLeft`, `EyeBlinkLeft`,
    /// `eyeBlink_L`, `eye_blink_left`, and any of these after a dotted prefix
    /// such as `blendShape1.`. Anything else is a [`UnknownBlendshape`] error
    /// that names the offending text.
    pub fn parse(text: &str) -> Result<Blendshape, UnknownBlendshape> {
        let trimmed = text.trim();
        let last = trimmed.rsplit('.').next().unwrap_or(trimmed);
        let mut key: String = last
            .chars()
            .filter(|c| *c != '_' && *c != '-' && *c != ' ')
            .flat_map(char::to_lowercase)
            .collect();
        // ICT-FaceKit / ARKit raw values: a trailing `_L` / `_R`.
        let lower = last.to_ascii_lowercase();
        if lower.ends_with("_l") {
            key.pop();
            key.push_str("left");
        } else if lower.ends_with("_r") {
            key.pop();
            key.push_str("right");
        }
        Blendshape::ALL
            .iter()
            .copied()
            .find(|shape| shape.name().eq_ignore_ascii_case(&key))
            .ok_or_else(|| UnknownBlendshape(text.to_string()))
    }
}

impl fmt::Display for Blendshape {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Blendshape {
    type Err = UnknownBlendshape;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        Blendshape::parse(text)
    }
}

/// A name that is none of ARKit's 52 blendshapes in any known spelling.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown blendshape name {0:?}: not one of ARKit's 52 names in any known spelling")]
pub struct UnknownBlendshape(pub String);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arkit_keys_abbreviate_the_side_as_apple_does() {
        assert_eq!(Blendshape::EyeBlinkLeft.arkit_key(), "eyeBlink_L");
        assert_eq!(Blendshape::MouthSmileRight.arkit_key(), "mouthSmile_R");
        assert_eq!(Blendshape::JawLeft.arkit_key(), "jawLeft");
        assert_eq!(Blendshape::MouthRight.arkit_key(), "mouthRight");
        assert_eq!(Blendshape::BrowInnerUp.arkit_key(), "browInnerUp");
        let abbreviated = Blendshape::ALL
            .iter()
            .filter(|b| b.arkit_key().contains('_'))
            .count();
        assert_eq!(abbreviated, 36);
        for b in Blendshape::ALL {
            assert_eq!(Blendshape::parse(&b.arkit_key()), Ok(b));
        }
    }

    #[test]
    fn apple_order_starts_and_ends_where_documented() {
        assert_eq!(Blendshape::ALL[0].name(), "eyeBlinkLeft");
        assert_eq!(Blendshape::ALL[17].name(), "jawOpen");
        assert_eq!(Blendshape::ALL[51].name(), "tongueOut");
        for (i, shape) in Blendshape::ALL.iter().enumerate() {
            assert_eq!(shape.index(), i);
            assert_eq!(Blendshape::from_index(i), Some(*shape));
        }
        assert_eq!(Blendshape::from_index(52), None);
    }

    #[test]
    fn names_are_unique() {
        let mut names: Vec<_> = Blendshape::ALL.iter().map(|s| s.name()).collect();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), BLENDSHAPE_COUNT);
    }

    #[test]
    fn mirrors_pair_left_with_right_and_are_involutions() {
        for shape in Blendshape::ALL {
            let m = shape.mirror();
            assert_eq!(m.mirror(), shape);
            match shape.side() {
                Side::Left => {
                    assert_eq!(m.side(), Side::Right);
                    assert_eq!(m.name().replace("Right", "Left"), shape.name());
                }
                Side::Right => assert_eq!(m.side(), Side::Left),
                Side::Centre => assert_eq!(m, shape),
            }
        }
        assert_eq!(Blendshape::JawLeft.mirror(), Blendshape::JawRight);
        assert_eq!(Blendshape::MouthLeft.mirror(), Blendshape::MouthRight);
        let unpaired = Blendshape::ALL.iter().filter(|s| s.mirror() == **s).count();
        assert_eq!(unpaired, 12);
    }

    #[test]
    fn parses_the_spellings_found_in_the_wild() {
        for shape in Blendshape::ALL {
            let name = shape.name();
            assert_eq!(Blendshape::parse(name), Ok(shape));
            let capitalized = name[..1].to_uppercase() + &name[1..];
            assert_eq!(Blendshape::parse(&capitalized), Ok(shape));
            assert_eq!(Blendshape::parse(&name.to_uppercase()), Ok(shape));
            assert_eq!(Blendshape::parse(&format!("blendShape1.{name}")), Ok(shape));
            let ict = name
                .strip_suffix("Left")
                .map(|s| format!("{s}_L"))
                .or_else(|| name.strip_suffix("Right").map(|s| format!("{s}_R")))
                .unwrap_or_else(|| name.to_string());
            assert_eq!(Blendshape::parse(&ict), Ok(shape), "{ict}");
        }
        assert_eq!(
            Blendshape::parse(" mouth_smile_left "),
            Ok(Blendshape::MouthSmileLeft)
        );
    }

    #[test]
    fn unknown_names_are_errors_naming_the_text() {
        for bad in [
            "",
            "eyeBlink",
            "eyeBlinkMiddle",
            "HeadYaw",
            "LeftEyePitch",
            "eyeBlink_X",
        ] {
            let err = Blendshape::parse(bad).unwrap_err();
            assert_eq!(err.0, bad);
            assert!(err.to_string().contains(&format!("{bad:?}")));
        }
    }
}
