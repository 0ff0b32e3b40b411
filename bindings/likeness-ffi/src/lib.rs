//! The Likeness core for Swift (and Python, in the tests), through UniFFI.
//!
//! This crate decides nothing: it converts flat arrays into meshes and
//! weights, the core's errors into [`LikenessError`], and calls the core
//! (`likeness`). `bindings/README.md` lists the surface, what in the core
//! each call reaches, and what the Swift side should know.
//!
//! | what | file |
//! |---|---|
//! | ARKit's names, the methods, the version | `lib.rs` |
//! | the records and the array conversions | [`types`] |
//! | the one error type | [`error`] |
//! | the capture the app drives frame by frame | [`capture`] |
//! | a recorded session: load, save, summary, personalize | [`session`] |
//! | the person's face: pose, mask, avatar | [`personalized`] |
//! | the avatar posed by live weights (the result's preview) | [`avatar_preview`] |
//! | the foreign progress listener | [`progress`] |
//! | which exports may not fail, and why (a test) | `infallible_exports.rs` |

uniffi::setup_scaffolding!();

pub mod avatar_preview;
pub mod capture;
pub mod error;
#[cfg(test)]
mod infallible_exports;
pub mod personalized;
pub mod progress;
pub mod session;
pub mod types;

pub use avatar_preview::{AvatarPreview, PreviewFocus, PreviewMesh};
pub use capture::{CaptureEvent, CaptureSession};
pub use error::LikenessError;
pub use personalized::PersonalizedFace;
pub use progress::ProgressListener;
pub use session::SessionHandle;
pub use types::{
    AvatarResult, CaptureInfo, CaptureProgress, FaceTemplate, MethodInfo, Prompt, QualitySummary,
    RecordedFrame,
};

use likeness::Blendshape;
use likeness::personalize::Method;

/// ARKit's 52 blendshape names in the core's order (Apple's spelling, e.g.
/// `eyeBlinkLeft`): the order of every weight array crossing this API.
#[uniffi::export]
pub fn arkit_names() -> Vec<String> {
    Blendshape::ALL
        .iter()
        .map(|b| b.name().to_string())
        .collect()
}

/// ARKit's raw keys for the same 52 shapes, in the same order: the string
/// values of `ARFaceAnchor.BlendShapeLocation` (`eyeBlink_L`, `jawOpen`),
/// which `ARFaceAnchor.blendShapes` and `ARFaceGeometry(blendShapes:)` are
/// keyed by.
#[uniffi::export]
pub fn arkit_keys() -> Vec<String> {
    Blendshape::ALL.iter().map(|b| b.arkit_key()).collect()
}

/// The core's version.
#[uniffi::export]
pub fn core_version() -> String {
    likeness::VERSION.to_string()
}

/// Every personalization method, baselines first.
#[uniffi::export]
pub fn methods() -> Vec<MethodInfo> {
    Method::ALL
        .iter()
        .map(|m| MethodInfo {
            name: m.name().to_string(),
            description: m.description().to_string(),
        })
        .collect()
}

/// The method the product uses when none is named.
#[uniffi::export]
pub fn default_method() -> String {
    Method::DEFAULT.name().to_string()
}
