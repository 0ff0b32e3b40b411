//! Live Link Face CSV text for tests: the app's own column order, timecodes
//! `HH:MM:SS:FF.fff` at 60 fps, and the head and eye rotation columns it
//! appends (which readers must ignore).

use likeness::{Blendshape, Frame};

/// Live Link Face's column order: the 52 names capitalized, after
/// `Timecode,BlendshapeCount`.
pub const LIVE_LINK_NAMES: &str = "EyeBlinkLeft,EyeLookDownLeft,EyeLookInLeft,EyeLookOutLeft,EyeLookUpLeft,EyeSquintLeft,EyeWideLeft,EyeBlinkRight,EyeLookDownRight,EyeLookInRight,EyeLookOutRight,EyeLookUpRight,EyeSquintRight,EyeWideRight,JawForward,JawRight,JawLeft,JawOpen,MouthClose,MouthFunnel,MouthPucker,MouthRight,MouthLeft,MouthSmileLeft,MouthSmileRight,MouthFrownLeft,MouthFrownRight,MouthDimpleLeft,MouthDimpleRight,MouthStretchLeft,MouthStretchRight,MouthRollLower,MouthRollUpper,MouthShrugLower,MouthShrugUpper,MouthPressLeft,MouthPressRight,MouthLowerDownLeft,MouthLowerDownRight,MouthUpperUpLeft,MouthUpperUpRight,BrowDownLeft,BrowDownRight,BrowInnerUp,BrowOuterUpLeft,BrowOuterUpRight,CheekPuff,CheekSquintLeft,CheekSquintRight,NoseSneerLeft,NoseSneerRight,TongueOut";

/// The header line, with the rotation columns.
pub fn live_link_header() -> String {
    format!(
        "Timecode,BlendshapeCount,{LIVE_LINK_NAMES},HeadYaw,HeadPitch,HeadRoll,\
         LeftEyeYaw,LeftEyePitch,LeftEyeRoll,RightEyeYaw,RightEyePitch,RightEyeRoll\n"
    )
}

/// A whole recording of `frames` at 60 fps, starting at 10:42:31:00.
pub fn live_link_csv(frames: &[Frame]) -> String {
    let names: Vec<Blendshape> = LIVE_LINK_NAMES
        .split(',')
        .map(|n| Blendshape::parse(n).expect("ARKit name"))
        .collect();
    let mut csv = live_link_header();
    for (k, frame) in frames.iter().enumerate() {
        let seconds = 10 * 3600 + 42 * 60 + 31 + k / 60;
        let (h, m, s) = (seconds / 3600, seconds / 60 % 60, seconds % 60);
        csv.push_str(&format!("{h:02}:{m:02}:{s:02}:{:02}.000,52", k % 60));
        for name in &names {
            csv.push_str(&format!(",{}", frame.weights.get(*name)));
        }
        csv.push_str(",0.1,-0.2,0.05,0.1,0.0,0.0,0.1,0.0,0.0\n");
    }
    csv
}
