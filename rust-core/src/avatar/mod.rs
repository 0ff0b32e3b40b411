//! §3.3, the avatar: reading it, finding its face, retargeting ARKit's
//! shapes onto its own blendshapes, and writing it back with new shapes.
//!
//! | paper | what | file |
//! |---|---|---|
//! | §3.3 "the provided full-body avatar" | meshes in world space, their morph targets | [`model`] |
//! | §3.3 "the avatar's blendshapes" | target names to ARKit's 52, split halves | [`target_names`] |
//! | (glTF 2.0, not in the paper) | glTF / GLB read, written back with new targets, written new | [`glb`] |
//! | §3.3 "non-rigid registration \[1\]", "ICP with scaling \[52\]" | finding the face, the map `M` | [`registration`] |
//! | beyond §3.3 | the avatar's own shapes seen through the registration, `S_j` (the round trip) | [`own_shapes`] |
//! | §3.3, Eq. (4) | automatic retargeting `A_j`, the 52 × k weight map | [`retargeting`] |
//! | §3.3, Fig. 3 | seamless partial deformation transfer: the person's shapes implanted | [`partial_transfer`] |
//! | beyond §3.3 | the person's own face at rest: the skin laid on the scanned neutral, the head, eyes and teeth following | [`person_face`] |
//! | §3.3 end to end | the person's avatar as GLB bytes, steps skipped said, progress and cancel | [`personal_avatar`] |
//! | (beyond the paper) the product checks its output | torn edges, folds, the blink, lids in eyes, the inside through the skin, Eq. (4)'s residual | [`implant_check`] |
//! | (beyond the paper) the inside of the head in front of the skin | [`showing_through`] |
//! | | the head's skin as the checks see it: edges, triangles, eyeballs | [`head_skin`] |
//! | (beyond the paper) the face at rest checked | spikes and creases leave the avatar's own face | [`rest_check`] |
//! | §4.2, Fig. 7 and 8 | manual, automatic and personalized animation against the person's expression on the face region | [`likeness_check`] |
//! | | what was made, in a few sentences for the app | [`avatar_summary`] |
//! | Eq. (1) on the avatar | the avatar posed by ARKit weights (the app's live preview) | [`avatar_pose`] |

pub mod avatar_pose;
pub mod avatar_summary;
pub mod glb;
pub mod head_skin;
pub mod implant_check;
pub mod likeness_check;
pub mod model;
pub mod own_shapes;
pub mod partial_transfer;
pub mod person_face;
pub mod personal_avatar;
pub mod registration;
pub mod rest_check;
pub mod retargeting;
pub mod showing_through;
pub mod target_names;

pub use model::{Avatar, AvatarMesh, AvatarPart, InvalidAvatar};
pub use target_names::{ArkitTargets, TargetName, parse_target_name};
