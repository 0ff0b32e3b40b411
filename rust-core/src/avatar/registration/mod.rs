//! §3.3, finding the face on an avatar: the ARKit mask registered onto the
//! avatar's face, rigidly with scale and then non-rigidly, and the
//! correspondence map `M` read off the result.
//!
//! | paper | what | file |
//! |---|---|---|
//! | §3.3 "ICP with scaling \[52\]" | least-squares similarity of point pairs (Umeyama 1991) | [`similarity`] |
//! | §3.3, beyond the paper: no hand-placed landmarks | where eyeBlink, jawOpen, … move most on each rig | [`features`] |
//! | (beyond the paper) an artist's shape placed elsewhere on the face left out of the placement | the features' robust similarity | [`feature_fit`] |
//! | §3.3 "ICP with scaling \[52\]" (Zinßer et al. 2005) | the mask placed on the avatar by a similarity | [`rigid_icp`] |
//! | §3.3 "non-rigid registration \[1\]"; optimal-step NICP (Amberg et al. 2007) | the mask laid onto the avatar's skin, features as landmarks | [`nonrigid`] |
//! | §3.3 "eye balls", on any rig | eyeballs found by their shape, behind the lids | [`eyeballs`] |
//! | §3.3 "correspondence map M" | avatar face vertices → mask triangle + barycentrics | [`correspondence`] |
//! | §3.3, the mask's own shape | its outline, eye openings and mouth slit | [`mask_holes`] |
//! | (beyond the paper) each lip takes its own lip's motion at the mouth's slit | which lip a mask triangle at the slit belongs to | [`lip_sides`] |
//! | (beyond the paper) each lip takes its own lip's motion behind the slit too (ARKit's curled lips) | both rigs' jawOpen agree on a vertex's lip | [`jaw_agreement`] |
//! | (beyond the paper) the mask's slit held where the avatar's lips part | the parting, by the avatar's own jawOpen | [`lips_parting`] |
//! | (beyond the paper) what each part is: skin, eyeball, teeth, tongue | by the registration and the avatar's own shapes | [`part_roles`] |
//! | §3.3, once per avatar topology | the whole search, its report and errors, the cache key | [`mod@find_face`] |
//! | §3.3, the map `M` and what else was found | the registration checked against its avatar, and its parts' roles | [`face_registration`] |
//! | §3.3 "computed only once" | the registration kept in a file per avatar | [`cache`] |
pub mod cache;
pub mod correspondence;
pub mod eyeballs;
pub mod face_registration;
pub mod feature_fit;
pub mod features;
pub mod find_face;
pub mod jaw_agreement;
pub mod lip_sides;
pub mod lips_parting;
pub mod mask_holes;
pub mod nonrigid;
pub mod part_roles;
pub mod rigid_icp;
pub mod similarity;

pub use correspondence::{CorrespondenceMap, FaceVertex};
pub use face_registration::{FaceRegistration, FoundFace, InvalidRegistration};
pub use find_face::{RegistrationError, find_face};
pub use part_roles::PartRole;
pub use similarity::Similarity;
