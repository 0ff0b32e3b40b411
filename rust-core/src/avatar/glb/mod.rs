//! glTF 2.0 avatars in and out: `.glb` and `.gltf` read into an
//! [`Avatar`](crate::avatar::Avatar) in world space, written back with new
//! ARKit morph targets, or written new.
//!
//! | spec (glTF 2.0) | what | file |
//! |---|---|---|
//! | §4.4 GLB, §3.6.1 buffers | the GLB container, `data:` URIs and `.bin` files | [`container`] |
//! | §3.6.2 accessors, sparse | accessor data, lengths checked before use | [`accessor`] |
//! | §3.5 nodes, §3.7.3 skins | where the scene places each mesh | [`scene`] |
//! | §3.7.2 meshes, morph targets | reading an avatar, checking it has ARKit's names | [`read`] |
//! | §3.6.2, §3.7.2.2 | accessors and views as written, dense or sparse | [`encode`] |
//! | | where accessors and views are referred to, renumbering | [`refs`] |
//! | §3.7.2.2 morph targets | writing a read file back with new targets | [`write_back`] |
//! | §3.7.2, §3.9 materials | writing an avatar as a new GLB | [`write_new`] |
//! | | the one error type | [`error`] |

mod accessor;
mod container;
pub mod encode;
pub mod error;
pub mod read;
mod refs;
pub mod scene;
pub mod write_back;
pub mod write_new;

pub use error::GlbError;
pub use read::{GlbAvatar, check_avatar, read_avatar, read_avatar_bytes};
#[cfg(test)]
mod tests;

pub use encode::TargetEncoding;
pub use scene::Placement;
pub use write_back::{NewShapes, write_avatar, written_back_glb};
pub use write_new::{MeshLook, NewGlbOptions, new_avatar_glb, write_new_avatar};
