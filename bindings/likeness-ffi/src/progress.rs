//! The progress listener the app implements (a UniFFI foreign trait), and
//! how the long calls report to it.

use std::sync::Arc;

/// Hears how far a long call (personalization, the avatar) has got, and
/// may stop it: the call then fails with `LikenessError.Cancelled`. Called
/// on the thread that made the call.
#[uniffi::export(foreign)]
pub trait ProgressListener: Send + Sync {
    /// `stage` (in words) starts; `fraction` of the whole call is done.
    fn on_progress(&self, stage: String, fraction: f64);
    /// Whether the person asked to stop.
    fn is_cancelled(&self) -> bool;
}

/// Tells `listener` (if any) that `stage` starts at `fraction`; whether to
/// go on.
pub(crate) fn report(
    listener: Option<&Arc<dyn ProgressListener>>,
    stage: &str,
    fraction: f64,
) -> bool {
    match listener {
        Some(l) => {
            l.on_progress(stage.to_string(), fraction);
            !l.is_cancelled()
        }
        None => true,
    }
}

/// Whether `listener` (if any) asks to stop.
pub(crate) fn cancelled(listener: Option<&Arc<dyn ProgressListener>>) -> bool {
    listener.is_some_and(|l| l.is_cancelled())
}
