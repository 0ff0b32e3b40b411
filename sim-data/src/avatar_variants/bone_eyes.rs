//! `bone-eyes`: eyeballs turned by bones, as in Mixamo-, VRM- and
//! MetaHuman-style rigs, not by morph targets.
//!
//! The default avatar with its eye meshes stripped of targets and skinned,
//! each to an eye joint at its centre (weight one); the head mesh is
//! skinned to a head joint. The skeleton is `Neck → Head → {LeftEye,
//! RightEye}`, its inverse bind matrices the inverses of the joints' rest
//! transforms (not the identity: the joints are not at the origin). The
//! head's eyeLook targets stay: they move only the lids, as the template's
//! do; nothing else has them.

use super::parts::{base, glb_of, plain_truth};
use super::truth::VariantTruth;
use crate::default_avatar::head::CENTRE;
use crate::glb_edit::{Glb, Joint};
use glam::Vec3;
use likeness::avatar::Avatar;
use serde_json::json;

/// Height of the neck joint below the head joint (m): the atlanto-occipital
/// joint sits about 12 cm above the base of the neck.
pub const NECK_LENGTH: f32 = 0.12;

/// The skeleton: neck, head at the head's centre, one joint per eye at its
/// centre.
pub fn skeleton(eye_centres: [Vec3; 2]) -> Vec<Joint> {
    let head = CENTRE.as_vec3();
    vec![
        Joint::at("Neck", None, head - Vec3::Y * NECK_LENGTH),
        Joint::at("Head", Some(0), Vec3::Y * NECK_LENGTH),
        Joint::at("LeftEye", Some(1), eye_centres[0] - head),
        Joint::at("RightEye", Some(1), eye_centres[1] - head),
    ]
}

/// The avatar as the core writes it: the default's, eyes without targets.
fn avatar() -> Avatar {
    let (mut meshes, mut parts) = base().avatar.clone().into_parts();
    for m in [1, 2] {
        meshes[m].target_names.clear();
    }
    for p in parts.iter_mut().filter(|p| p.mesh == 1 || p.mesh == 2) {
        p.targets.clear();
    }
    Avatar::new(meshes, parts).expect("the bone-eyes variant's parts make an avatar")
}

/// Skins every primitive of mesh `mesh` (node `mesh`) wholly to `joint`.
pub fn skin_mesh_to(glb: &mut Glb, avatar: &Avatar, mesh: usize, joint: u16, skin: usize) {
    for part in avatar.parts().iter().filter(|p| p.mesh == mesh) {
        let n = part.positions.len();
        glb.skin_primitive(
            mesh,
            part.primitive,
            &vec![[joint, 0, 0, 0]; n],
            &vec![[1.0, 0.0, 0.0, 0.0]; n],
        );
    }
    glb.json["nodes"][mesh]["skin"] = json!(skin);
}

/// The GLB and its truth.
pub fn bone_eyes() -> (Vec<u8>, VariantTruth) {
    let avatar = avatar();
    let mut glb = Glb::parse(&glb_of(&avatar, None));
    let (root, skin) = glb.push_skeleton(&skeleton(base().eye_centres));
    for (mesh, joint) in [(0, 1), (1, 2), (2, 3)] {
        skin_mesh_to(&mut glb, &avatar, mesh, joint, skin);
    }
    let mut roots: Vec<usize> = (0..avatar.meshes().len()).collect();
    roots.push(root);
    glb.set_scene_roots(&roots);
    let mut truth = plain_truth(&avatar, 0, base().true_correspondence.len());
    truth.eyes_bone_driven = true;
    truth.eye_look_moves_eyeballs = false;
    truth.skinned = true;
    truth.non_identity_bind_pose = true;
    truth.meshes_without_targets = vec!["eyeLeft", "eyeRight"];
    (glb.to_bytes(), truth)
}
