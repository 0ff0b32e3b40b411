//! Prebuilt bytes the phone ships, so the app links neither the simulator
//! (`likeness-sim`) nor spends a second building them on every run.
//!
//! | what | file | made by |
//! |---|---|---|
//! | the default avatar, a GLB | `default-avatar.glb` | `likeness default-avatar --out bindings/likeness-assets/default-avatar.glb` |
//!
//! `tests/tests/assets.rs` fails when the file is no longer what sim-data
//! builds (after a change to the default avatar): regenerate it with the
//! command above.

/// The project's default avatar as GLB bytes: what
/// `likeness_sim::default_avatar::default_avatar_glb` builds, prebuilt.
pub const DEFAULT_AVATAR_GLB: &[u8] = include_bytes!("../default-avatar.glb");
