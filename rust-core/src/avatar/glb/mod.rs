//! glTF 2.0 avatars in and out: `.glb` and `.gltf` read into an
//! [`Avatar`](crate::avatar::Avatar) in world space, written back with new
//! ARKit morph targets, or written new.
//!
//! | glTF 2.0 spec section | what | file |
//! |---|---|---|
//! | GLB File Format; Buffers and Buffer Views | the GLB container, `data:` URIs and `.bin` files | `container.rs` |
//! | Accessors; Sparse Accessors | accessor data, lengths checked before use | `accessor.rs` |
//! | Nodes and Hierarchy; Transformations; Skins | where the scene places each mesh | [`scene`] |
//! | Meshes; Morph Targets | reading an avatar, checking it has ARKit's names | [`read`] |
//! | `EXT_meshopt_compression` | compressed buffer views, decoded before reading | `meshopt.rs` |
//! | `EXT_meshopt_compression`, "Filters" | octahedral, quaternion, exponential filters | `meshopt_filters.rs` |
//! | `KHR_draco_mesh_compression` | Draco-compressed primitives, decoded before reading | `draco.rs` |
//! | `KHR_mesh_quantization` | quantized attributes rewritten as floats | `quantization.rs` |
//! | Animations (normalized integers) | one integer component as a float | `normalized.rs` |
//! | Accessors; Data Alignment; Accessor Bounds | accessors and views as written, dense or sparse | [`encode`] |
//! | | where accessors and views are referred to, renumbering | `refs.rs` |
//! | Morph Targets | writing a read file back with new targets | [`write_back`] |
//! | Meshes (`POSITION`, `NORMAL`, `TANGENT`) | a new rest written back, normals turned with the surface | `new_rest.rs` |
//! | Morph Targets (`NORMAL`) | how normals turn as the surface moves; targets' normal deltas | `surface_turn.rs` |
//! | Meshes; Materials | writing an avatar as a new GLB | [`write_new`] |
//! | Materials (`baseColorFactor`); Meshes (`COLOR_0`) | each vertex's colour, for pictures drawn without textures | [`look`] |
//! | | the one error type | [`error`] |

mod accessor;
mod container;
mod draco;
pub mod encode;
pub mod error;
pub mod look;
mod meshopt;
mod meshopt_filters;
mod new_rest;
mod normalized;
mod quantization;
pub mod read;
mod refs;
pub mod scene;
mod surface_turn;
pub mod write_back;
pub mod write_new;

#[cfg(test)]
mod tests;

pub use encode::TargetEncoding;
pub use error::GlbError;
pub use read::{GlbAvatar, PrimitiveSplit, check_avatar, read_avatar, read_avatar_bytes};
pub use scene::Placement;
pub use write_back::{NewShapes, write_avatar, written_back_glb};
pub use write_new::{MaterialSplit, MeshLook, NewGlbOptions, new_avatar_glb, write_new_avatar};
