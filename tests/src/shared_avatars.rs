//! The real avatar in `../shared/avatars/` (ICT-FaceKit, MIT), measured on
//! where it is present and never committed, nor anything derived from it.

use likeness::avatar::glb::read::{GlbAvatar, read_avatar};
use std::path::Path;

/// ICT-FaceKit read, or `None` with a notice on stderr where `../shared/`
/// is absent (a fresh clone, CI): a test that needs it then skips.
pub fn ict_facekit() -> Option<GlbAvatar> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/avatars/ict-facekit.glb");
    if !path.exists() {
        eprintln!(
            "skipped: {} is absent (it is never committed)",
            path.display()
        );
        return None;
    }
    Some(read_avatar(&path).expect("ICT-FaceKit reads"))
}
