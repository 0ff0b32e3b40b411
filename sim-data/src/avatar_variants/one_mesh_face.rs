//! `one-mesh-face`: the whole face in one glTF mesh, as Character Creator,
//! Daz and many VRoid exports have it: the skin (with ears, sockets and
//! mouth lining) one primitive, the eyes, teeth, gums and tongue further
//! primitives of the same mesh, each with its own material, all sharing
//! the mesh's 52 targets.
//!
//! Primitives of mesh `Face`: 0 skin, 1 left eye, 2 right eye, 3 teeth
//! (both rows), 4 gums (both rows), 5 tongue.

use super::parts::{arkit_mesh, base, base_part, glb_of, merge, plain_truth};
use super::truth::{Piece, VariantTruth};
use crate::glb_edit::Glb;
use likeness::avatar::Avatar;
use likeness::avatar::glb::MeshLook;
use serde_json::json;

/// The avatar: one mesh, six primitives.
fn avatar() -> Avatar {
    let b = base();
    let group = |name: &str, primitive: usize, ks: &[usize]| {
        let parts: Vec<_> = ks.iter().map(|&k| base_part(k, 0, primitive)).collect();
        merge(name, 0, primitive, &parts)
    };
    let parts = vec![
        group("skin", 0, &[b.skin, b.ears, b.sockets, b.mouth_cavity]),
        base_part(b.eyes[0], 0, 1),
        base_part(b.eyes[1], 0, 2),
        group("teeth", 3, &b.teeth),
        group("gums", 4, &b.gums),
        base_part(b.tongue, 0, 5),
    ];
    Avatar::new(vec![arkit_mesh("Face", &[])], parts)
        .expect("the one-mesh variant's parts make an avatar")
}

/// Gives each primitive of mesh 0 its own material: the core's writer
/// gives a mesh one.
fn materials(glb: &mut Glb) {
    let looks = [
        ("skin", MeshLook::SKIN),
        ("eye", MeshLook::EYE_WHITE),
        ("tooth", MeshLook::TOOTH),
        ("gum", MeshLook::GUM),
    ];
    glb.json["materials"] = json!(
        looks
            .iter()
            .map(|(name, l)| json!({
                "name": name,
                "pbrMetallicRoughness": {
                    "baseColorFactor": l.base_colour.map(f64::from),
                    "metallicFactor": l.metallic, "roughnessFactor": l.roughness,
                },
            }))
            .collect::<Vec<_>>()
    );
    for (p, material) in [0, 1, 1, 2, 3, 3].into_iter().enumerate() {
        glb.json["meshes"][0]["primitives"][p]["material"] = json!(material);
    }
}

/// The GLB and its truth.
pub fn one_mesh_face() -> (Vec<u8>, VariantTruth) {
    let avatar = avatar();
    let mut glb = Glb::parse(&glb_of(&avatar, None));
    materials(&mut glb);
    let mut truth = plain_truth(&avatar, 0, base().true_correspondence.len());
    truth.eyeballs = [1, 2].map(|k| Piece::whole(&avatar, k));
    truth.teeth = Some(Piece::whole(&avatar, 3));
    truth.jaw_moved_vertices = base().avatar.parts()[base().teeth[1]].positions.len();
    (glb.to_bytes(), truth)
}
