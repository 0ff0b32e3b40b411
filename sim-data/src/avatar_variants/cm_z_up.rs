//! `cm-z-up`: the default head in centimetres with +Z up, placed by
//! transforms on parent nodes, as a Blender or 3ds Max export without the
//! glTF axis conversion and with scene units of centimetres comes out.
//!
//! Vertices are stored in millimetres in a frame turned by
//! [`YAW_DEGREES`] about the vertical; the node `Head` (translation
//! [`HEAD_HEIGHT_MM`] up, rotation [`YAW_DEGREES`]) turns them back and
//! lifts them, the root node `Root` (rotation +90° about x, scale 0.1)
//! turns +Y up into +Z up and millimetres into centimetres. In world
//! space a point `p` of the default avatar (m, ARKit's frame) is at
//! `Rx(90°) · (100 p + (0, 150, 0))` cm: +Z up, the face looking down −Y
//! (Blender's front view), the eyes about 153 cm above the floor.

use super::parts::{base, bounds, glb_of, plain_truth};
use super::truth::{UpAxis, VariantTruth};
use crate::glb_edit::Glb;
use glam::{Quat, Vec3};
use likeness::avatar::Avatar;
use serde_json::json;

/// Millimetres per metre: the mesh data's unit.
pub const MM_PER_M: f32 = 1000.0;
/// The root's scale: millimetres to centimetres.
pub const ROOT_SCALE: f32 = 0.1;
/// Height of the head node above the root (mm): 1.5 m, so the eyes sit at
/// a standing adult's eye height (1.5 m + 28 mm).
pub const HEAD_HEIGHT_MM: f32 = 1500.0;
/// The head node's turn about the vertical (degrees), undone by the mesh
/// data: a transform that matters only together with its node.
pub const YAW_DEGREES: f32 = 20.0;

/// World position (cm, +Z up) of a default-avatar point `p` (m).
pub fn to_world(p: Vec3) -> Vec3 {
    Quat::from_rotation_x(90f32.to_radians())
        * (100.0 * p + Vec3::Y * (HEAD_HEIGHT_MM * ROOT_SCALE))
}

/// The GLB and its truth.
pub fn cm_z_up() -> (Vec<u8>, VariantTruth) {
    let (meshes, mut parts) = base().avatar.clone().into_parts();
    let unturn = Quat::from_rotation_y(-YAW_DEGREES.to_radians());
    for part in &mut parts {
        part.positions
            .iter_mut()
            .for_each(|p| *p = unturn * (MM_PER_M * *p));
        for t in &mut part.targets {
            t.iter_mut().for_each(|d| *d = unturn * (MM_PER_M * *d));
        }
    }
    let avatar = Avatar::new(meshes, parts).expect("turning and scaling keeps an avatar valid");
    let mut glb = Glb::parse(&glb_of(&avatar, None));
    let meshes: Vec<usize> = (0..avatar.meshes().len()).collect();
    let turn = Quat::from_rotation_y(YAW_DEGREES.to_radians());
    let head = glb.push_node(json!({
        "name": "Head",
        "translation": [0.0, HEAD_HEIGHT_MM, 0.0],
        "rotation": turn.to_array(),
        "children": meshes,
    }));
    let up = Quat::from_rotation_x(90f32.to_radians());
    let root = glb.push_node(json!({
        "name": "Root",
        "rotation": up.to_array(),
        "scale": [ROOT_SCALE, ROOT_SCALE, ROOT_SCALE],
        "children": [head],
    }));
    glb.set_scene_roots(&[root]);
    let mut truth = plain_truth(&base().avatar, 0, base().true_correspondence.len());
    truth.unit_to_metres = 0.01;
    truth.up = UpAxis::Z;
    truth.world_bounds = bounds(&base().avatar, to_world);
    (glb.to_bytes(), truth)
}
