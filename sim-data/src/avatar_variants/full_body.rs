//! `full-body`: a skinned full-body avatar as Ready Player Me, VRoid and
//! Mixamo deliver them: the default head (lifted to a standing adult's
//! height) on a generated body ([`super::body`]), hair, glasses and clothes
//! without morph targets ([`super::accessories`]), a skeleton whose bind
//! pose is not the identity, and Oculus-style visemes on the head's meshes
//! besides the 52 ARKit targets.
//!
//! Meshes (10): `Head` (skin, ears, sockets, mouth lining), `EyeLeft`,
//! `EyeRight`, `Teeth` (upper, lower), `Gums` (upper, lower), `Tongue`,
//! `Body`, `Hair`, `Glasses`, `Outfit` (shirt, trousers, shoes). Every
//! mesh is skinned to one skeleton: the head's parts, hair and glasses
//! rigidly to the head joint (its shoulders below [`NECK_CUT`] to the
//! nearest bone), the eyes to their eye joints, body and clothes to the
//! nearest bone. The eyes keep their eyeLook targets (Ready Player Me's
//! have eye joints and eyeLook targets both).

use super::accessories::{glasses, hair};
use super::body::{
    EYE_JOINTS, HEAD_JOINT, HEAD_OFFSET, body, bones, nearest_joint, outfit, skeleton,
};
use super::parts::{
    arkit_mesh, base, base_part, bounds, dpart, glb_of, plain_mesh, plain_truth, with_mixes,
};
use super::truth::{Piece, VariantTruth};
use crate::glb_edit::Glb;
use glam::Vec3;
use likeness::Blendshape;
use likeness::avatar::glb::MeshLook;
use likeness::avatar::{Avatar, AvatarPart};
use serde_json::json;

/// Visemes: Oculus (Meta) lip-sync names, each a mix of ARKit shapes at
/// the given weights. The mixes are a judgement: open jaw for "aa", a
/// spread mouth for "E" and "I", rounded lips for "O" and "U".
pub const VISEMES: [(&str, &[(Blendshape, f32)]); 5] = [
    ("viseme_aa", &[(Blendshape::JawOpen, 0.6)]),
    (
        "viseme_E",
        &[
            (Blendshape::JawOpen, 0.3),
            (Blendshape::MouthStretchLeft, 0.4),
            (Blendshape::MouthStretchRight, 0.4),
        ],
    ),
    (
        "viseme_I",
        &[
            (Blendshape::JawOpen, 0.2),
            (Blendshape::MouthSmileLeft, 0.4),
            (Blendshape::MouthSmileRight, 0.4),
        ],
    ),
    (
        "viseme_O",
        &[(Blendshape::JawOpen, 0.4), (Blendshape::MouthFunnel, 0.7)],
    ),
    (
        "viseme_U",
        &[(Blendshape::JawOpen, 0.15), (Blendshape::MouthPucker, 0.8)],
    ),
];

/// Below this height the head mesh's skin (the top of the shoulders) is
/// skinned to the nearest bone, not to the head (m, world).
pub const NECK_CUT: f32 = HEAD_OFFSET.y - 0.10;

/// A head part lifted by [`HEAD_OFFSET`], its targets followed by the
/// visemes.
fn head_part(k: usize, mesh: usize, primitive: usize) -> AvatarPart {
    let mut p = with_mixes(base_part(k, mesh, primitive), &VISEMES.map(|v| v.1));
    p.positions.iter_mut().for_each(|v| *v += HEAD_OFFSET);
    p
}

/// The avatar (bind pose, world space).
fn avatar() -> Avatar {
    let b = base();
    let mut parts = vec![
        head_part(b.skin, 0, 0),
        head_part(b.ears, 0, 1),
        head_part(b.sockets, 0, 2),
        head_part(b.mouth_cavity, 0, 3),
        head_part(b.eyes[0], 1, 0),
        head_part(b.eyes[1], 2, 0),
        head_part(b.teeth[0], 3, 0),
        head_part(b.teeth[1], 3, 1),
        head_part(b.gums[0], 4, 0),
        head_part(b.gums[1], 4, 1),
        head_part(b.tongue, 5, 0),
    ];
    let lift = |(p, t): (Vec<glam::DVec3>, Vec<[u32; 3]>)| {
        let off = HEAD_OFFSET.as_dvec3();
        (p.into_iter().map(|v| v + off).collect::<Vec<_>>(), t)
    };
    let (bp, bt) = body();
    parts.push(dpart("Body", 6, 0, &bp, &bt, &[]));
    let (hp, ht) = lift(hair());
    parts.push(dpart("Hair", 7, 0, &hp, &ht, &[]));
    let (gp, gt) = lift(glasses());
    parts.push(dpart("Glasses", 8, 0, &gp, &gt, &[]));
    for (k, (op, ot)) in outfit().iter().enumerate() {
        parts.push(dpart(["Shirt", "Trousers", "Shoes"][k], 9, k, op, ot, &[]));
    }
    let names: Vec<&str> = VISEMES.iter().map(|v| v.0).collect();
    let mut meshes: Vec<_> = ["Head", "EyeLeft", "EyeRight", "Teeth", "Gums", "Tongue"]
        .iter()
        .map(|n| arkit_mesh(n, &names))
        .collect();
    meshes.extend(["Body", "Hair", "Glasses", "Outfit"].map(plain_mesh));
    Avatar::new(meshes, parts).expect("the full-body variant's parts make an avatar")
}

/// The materials, one per mesh.
fn looks() -> Vec<MeshLook> {
    let hair = MeshLook::plain([0.12, 0.07, 0.04, 1.0], 0.8);
    let frame = MeshLook {
        base_colour: [0.05, 0.05, 0.06, 1.0],
        metallic: 1.0,
        roughness: 0.3,
    };
    let cloth = MeshLook::plain([0.15, 0.25, 0.45, 1.0], 0.9);
    vec![
        MeshLook::SKIN,
        MeshLook::EYE_WHITE,
        MeshLook::EYE_WHITE,
        MeshLook::TOOTH,
        MeshLook::GUM,
        MeshLook::GUM,
        MeshLook::SKIN,
        hair,
        frame,
        cloth,
    ]
}

/// The GLB and its truth.
pub fn full_body() -> (Vec<u8>, VariantTruth) {
    let b = base();
    let avatar = avatar();
    let mut glb = Glb::parse(&glb_of(&avatar, Some(looks())));
    let joints = skeleton(b.eye_centres);
    let bones = bones(&joints);
    let (root, skin) = glb.push_skeleton(&joints);
    for part in avatar.parts() {
        let joint_of = |p: Vec3| match part.mesh {
            1 | 2 => EYE_JOINTS[part.mesh - 1],
            0 if p.y < NECK_CUT => nearest_joint(&bones, p),
            0 | 3 | 4 | 5 | 7 | 8 => HEAD_JOINT,
            _ => nearest_joint(&bones, p),
        };
        let joints: Vec<[u16; 4]> = part
            .positions
            .iter()
            .map(|&p| [joint_of(p), 0, 0, 0])
            .collect();
        let weights = vec![[1.0, 0.0, 0.0, 0.0]; joints.len()];
        glb.skin_primitive(part.mesh, part.primitive, &joints, &weights);
    }
    let mut roots: Vec<usize> = (0..avatar.meshes().len()).collect();
    for node in &roots {
        glb.json["nodes"][*node]["skin"] = json!(skin);
    }
    roots.push(root);
    glb.set_scene_roots(&roots);
    let mut truth = plain_truth(&avatar, 0, b.true_correspondence.len());
    // Its eyes are the default's eyeballs alone (no iris or pupil parts).
    truth.eyeballs = [4, 5].map(|k| Piece::whole(&avatar, k));
    truth.teeth = Some(Piece::whole(&avatar, 6));
    truth.eyes_bone_driven = true;
    truth.skinned = true;
    truth.non_identity_bind_pose = true;
    truth.world_bounds = bounds(&avatar, |v| v);
    truth.extra_targets = VISEMES.iter().map(|v| v.0).collect();
    truth.meshes_without_targets = vec!["Body", "Hair", "Glasses", "Outfit"];
    (glb.to_bytes(), truth)
}
