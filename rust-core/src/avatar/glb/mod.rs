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
//! | | the one error type | [`error`] |

mod accessor;
mod container;
pub mod error;
pub mod read;
pub mod scene;

pub use error::GlbError;
pub use read::{GlbAvatar, check_avatar, read_avatar, read_avatar_bytes};
pub use scene::Placement;
