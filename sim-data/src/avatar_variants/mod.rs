//! Generated test avatars of the kinds users bring, so that the avatar
//! stage is measured on more than the project's own default avatar. Each
//! variant is derived from the default avatar's geometry and
//! changed in topology, proportion, layout or rig, and comes with what a
//! correct reader must find in it ([`VariantTruth`]).
//!
//! | variant | file | what differs from the default avatar |
//! |---|---|---|
//! | `low-poly` | [`low_poly`] | head of ~2,300 vertices (skin resampled at 4.2 / 12 mm), low-poly eyes, no mouth parts |
//! | `bone-eyes` | [`bone_eyes`] | eyeballs without targets, skinned to eye joints; eyeLook targets move only the lids |
//! | `teeth-gums-one-mesh` | [`teeth_gums`] | upper and lower teeth and gums in one primitive; jawOpen moves its lower half rigidly |
//! | `one-mesh-face` | [`one_mesh_face`] | one mesh: skin, eyes, teeth, gums and tongue its primitives |
//! | `full-body` | [`full_body`] ([`body`], [`accessories`]) | skinned body, non-identity bind pose, hair, glasses and clothes without targets, visemes besides the 52 ARKit targets; 10 meshes |
//! | `lined-sockets` | [`lined_sockets`] | the lids fold into the eye sockets: the socket lining is stitched to the eye openings in the skin's primitive, so the openings are no boundary loops |
//! | `cm-z-up` | [`cm_z_up`] | centimetres, +Z up, rotation, scale and translation on parent nodes |
//! | `other-proportions` | [`proportions`] | face 12% wider, eyes closer than that, nose 15% longer, mouth 12% narrower |
//! | `meshopt` | [`crate::compressed_glb`] | `other-proportions` with `EXT_meshopt_compression` and `KHR_mesh_quantization` required |
//! | `head-box` | [`head_box`] | one mesh for the whole character (Rocketbox with HeadBox's rig): primitives body and head, the eyeballs, teeth, gums and tongue loose pieces of the head's primitive; ARKit's names behind `AK_NN_`, then action units (`AU_26_JawDrop`) and visemes (`AA_VI_01_aa`) that move the face too |
//! | `vendor-export` | [`vendor_export`] | the default's geometry, its targets named as vendors export them (`AK_18_JawOpen`, `A05_Eye_Look_Up_Left`, `blendShape3.eyeBlink_L`), its skin textured by a WebP image (`EXT_texture_webp` required, `KHR_texture_transform`), its geometry Draco-compressed (`KHR_draco_mesh_compression`, lossless) |
//!
//! Building blocks: [`parts`] (the default's parts, merging, truth common
//! to all), [`crate::glb_edit`] (node hierarchies and skins the core's writer
//! does not write), [`truth`]. Every GLB is written by the core's
//! `new_avatar_glb` and then edited; generation is deterministic.

pub mod accessories;
pub mod body;
pub mod bone_eyes;
pub mod cm_z_up;
pub mod full_body;
pub mod head_box;
pub mod lined_sockets;
pub mod low_poly;
pub mod one_mesh_face;
pub mod parts;
pub mod proportions;
pub mod teeth_gums;
pub mod truth;
pub mod vendor_export;

pub use truth::{Piece, UpAxis, VariantTruth};

/// One test avatar: its GLB and what a reader must find in it.
#[derive(Clone, Debug)]
pub struct AvatarVariant {
    /// Short name, also the file name (`NAME.glb`).
    pub name: &'static str,
    /// What kind of avatar it stands for, in one sentence.
    pub description: &'static str,
    /// The GLB file's bytes.
    pub glb: Vec<u8>,
    /// What a correct reader must find.
    pub truth: VariantTruth,
}

fn variant(
    name: &'static str,
    description: &'static str,
    (glb, truth): (Vec<u8>, VariantTruth),
) -> AvatarVariant {
    AvatarVariant {
        name,
        description,
        glb,
        truth,
    }
}

/// The low-poly variant's GLB and truth.
fn low_poly_glb() -> (Vec<u8>, VariantTruth) {
    let (avatar, truth) = low_poly::low_poly(parts::base());
    (parts::glb_of(&avatar, None), truth)
}

/// Every test avatar, in the order of the module's table.
pub fn avatar_variants() -> Vec<AvatarVariant> {
    vec![
        variant(
            "low-poly",
            "A game or web avatar: a head of about 2,300 vertices, low-poly eyes, no teeth.",
            low_poly_glb(),
        ),
        variant(
            "bone-eyes",
            "Eyes turned by bones (skinned to eye joints), no eyeLook targets on the eyeballs.",
            bone_eyes::bone_eyes(),
        ),
        variant(
            "teeth-gums-one-mesh",
            "Upper and lower teeth and gums in one primitive; jawOpen moves only its lower half.",
            teeth_gums::teeth_gums_one_mesh(),
        ),
        variant(
            "one-mesh-face",
            "The whole face in one mesh; eyes, teeth, gums and tongue are its further primitives.",
            one_mesh_face::one_mesh_face(),
        ),
        variant(
            "full-body",
            "A skinned full body with hair, glasses and clothes without targets, and visemes.",
            full_body::full_body(),
        ),
        variant(
            "lined-sockets",
            "Lids that fold into the eye sockets, as in scanned and sculpted heads: the eye openings are no holes in the mesh.",
            lined_sockets::lined_sockets(),
        ),
        variant(
            "cm-z-up",
            "The head in centimetres with +Z up, placed by rotated, scaled, translated parents.",
            cm_z_up::cm_z_up(),
        ),
        variant(
            "other-proportions",
            "A wider face, closer eyes, a longer nose and a narrower mouth than the mask's.",
            proportions::other_proportions(),
        ),
        variant(
            "meshopt",
            "The other-proportions head as web-optimised avatars ship: EXT_meshopt_compression and KHR_mesh_quantization required.",
            meshopt_glb(),
        ),
        variant(
            "head-box",
            "A Rocketbox character with HeadBox's rig: one mesh, body and head primitives, the eyes and teeth inside the head's primitive, 62 targets.",
            head_box::head_box(),
        ),
        variant(
            "vendor-export",
            "The default head as a vendor's web export: ARKit's shapes under numbered and prefixed names, a WebP skin, Draco geometry.",
            vendor_export::vendor_export(),
        ),
    ]
}

/// The meshopt variant: `other-proportions` compressed
/// ([`crate::compressed_glb::meshopt_compressed`]); the dequantizing scale
/// and offset sit in its nodes, so what a reader must find is unchanged.
fn meshopt_glb() -> (Vec<u8>, VariantTruth) {
    let (glb, truth) = proportions::other_proportions();
    let compressed = crate::compressed_glb::meshopt_compressed(&glb)
        .unwrap_or_else(|e| panic!("the other-proportions avatar compresses: {e}"));
    (compressed, truth)
}
