//! The real avatars in `../shared/avatars/` (ICT-FaceKit, MIT; the
//! MPFB/MakeHuman body, CC0 and MIT), measured on where they are present
//! and never committed, nor anything derived from them.

use likeness::avatar::glb::read::{GlbAvatar, read_avatar};
use std::path::{Path, PathBuf};

/// ICT-FaceKit read ([`shared_avatar`]).
pub fn ict_facekit() -> Option<GlbAvatar> {
    shared_avatar("ict-facekit.glb")
}

/// The MPFB/MakeHuman body read ([`shared_avatar`]): one mesh for the whole
/// body, the eyeballs open shells at the back, `noseSneer` between the
/// brows.
pub fn mpfb_makehuman() -> Option<GlbAvatar> {
    shared_avatar("mpfb-makehuman.glb")
}

/// Every real avatar present, ICT-FaceKit first.
pub fn shared_avatars() -> Vec<GlbAvatar> {
    ict_facekit().into_iter().chain(mpfb_makehuman()).collect()
}

/// `../shared/avatars/NAME` read, or `None` with a notice on stderr where
/// it is absent ([`shared_avatar_path`]).
pub fn shared_avatar(name: &str) -> Option<GlbAvatar> {
    let path = shared_avatar_path(name)?;
    Some(read_avatar(&path).unwrap_or_else(|e| panic!("{name} reads: {e}")))
}

/// The path of `../shared/avatars/NAME`, or `None` with a notice on stderr
/// where it is absent (a fresh clone): a test that needs it then skips.
/// Under CI (`CI=true`), which has `../shared/`, its absence fails.
pub fn shared_avatar_path(name: &str) -> Option<PathBuf> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../shared/avatars")
        .join(name);
    if !path.exists() {
        assert!(
            !std::env::var("CI").is_ok_and(|v| v == "true"),
            "CI=true but {} is absent",
            path.display()
        );
        eprintln!(
            "skipped: {} is absent (it is never committed)",
            path.display()
        );
        return None;
    }
    Some(path)
}
