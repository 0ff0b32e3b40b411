//! `vendor-export`: the default avatar with its targets named as vendors
//! export ARKit's shapes, not as Apple spells them: a numbered prefix on
//! the head (`AK_18_JawOpen`, as Microsoft Rocketbox's HeadBox rigs name
//! them), Character Creator's numbered words on the eyes
//! (`A01_Eye_Look_Up_Left`), and a Maya blendShape node's prefix and
//! Apple's raw key on the rest (`blendShape3.eyeBlink_L`). The geometry is
//! the default avatar's, to the bit, so the shapes made on it must be the
//! default avatar's too.
//!
//! The numbers are Apple's order from 1; vendors number their own way (the
//! names are read by their words, not their numbers).
//!
//! Its skin is textured as VRoid and web exports texture it: a WebP image
//! (`EXT_texture_webp`, required, so the texture has no `source` of its
//! own) placed by `KHR_texture_transform`, on UVs the skin's primitives
//! share. A reader must pass both through untouched.
//!
//! Its geometry is Draco-compressed (`KHR_draco_mesh_compression`,
//! [`crate::compressed_glb::draco`]), losslessly, so that what is read is
//! still the default avatar's to the bit.

use super::parts::{base, base_face_vertices, glb_of, plain_truth};
use super::truth::VariantTruth;
use crate::glb_edit::Glb;
use likeness::arkit::Blendshape;
use serde_json::{Value, json};

/// `shape`'s name with a capital first letter: `JawOpen`.
fn capitalised(shape: Blendshape) -> String {
    let name = shape.name();
    name[..1].to_uppercase() + &name[1..]
}

/// `shape`'s name in Character Creator's words: `Eye_Look_Up_Left`.
fn cc_words(shape: Blendshape) -> String {
    let mut out = String::new();
    for (i, c) in capitalised(shape).chars().enumerate() {
        if i > 0 && c.is_uppercase() {
            out.push('_');
        }
        out.push(c);
    }
    out
}

/// The vendor's name for the target named `name` on mesh `mesh` (by the
/// mesh's name), or `name` where it is not one of ARKit's.
pub fn vendor_name(mesh: &str, name: &str) -> String {
    let Ok(shape) = Blendshape::parse(name) else {
        return name.to_string();
    };
    let number = shape.index() + 1;
    match mesh {
        m if m.contains("Head") || m.contains("head") => {
            format!("AK_{number:02}_{}", capitalised(shape))
        }
        m if m.contains("Eye") || m.contains("eye") => format!("A{number:02}_{}", cc_words(shape)),
        _ => format!("blendShape3.{}", shape.arkit_key()),
    }
}

/// A 4 × 4 lossless WebP of one skin tone (RGB 200, 150, 120), as Pillow
/// 13.0 writes it: `RIFF`, `WEBP`, one `VP8L` chunk.
pub const SKIN_WEBP: [u8; 38] = [
    82, 73, 70, 70, 30, 0, 0, 0, 87, 69, 66, 80, 86, 80, 56, 76, 17, 0, 0, 0, 47, 3, 192, 0, 0, 7,
    80, 203, 34, 23, 175, 255, 129, 136, 232, 127, 0, 0,
];

/// UVs of the head's vertices: a cylinder about the vertical through the
/// head's centre (u round it, v down it over 30 cm), as a quick unwrap
/// gives them.
fn cylinder_uvs(positions: &[glam::Vec3]) -> Vec<u8> {
    positions
        .iter()
        .flat_map(|p| {
            let u = 0.5 + p.x.atan2(p.z) / std::f32::consts::TAU;
            let v = 0.5 - p.y / 0.3;
            [u, v]
        })
        .flat_map(f32::to_le_bytes)
        .collect()
}

/// The skin textured by a WebP image through `KHR_texture_transform`
/// (module docs): UVs on every primitive of mesh 0 that shares the skin's
/// vertices, the image, its texture and the skin's material.
fn webp_skin(glb: &mut Glb, positions: &[glam::Vec3]) {
    const FLOAT: u32 = 5126;
    let uv = glb.push_accessor(
        &cylinder_uvs(positions),
        json!({ "componentType": FLOAT, "count": positions.len(), "type": "VEC2" }),
        true,
    );
    let skin = glb.json["meshes"][0]["primitives"][0]["attributes"]["POSITION"].clone();
    // The skin's own material, textured: a copy, so that the head's other
    // primitives (without UVs) keep theirs untextured.
    let first = glb.json["meshes"][0]["primitives"][0]["material"]
        .as_u64()
        .unwrap_or(0);
    let mut textured = glb.json["materials"][first as usize].clone();
    let transform = json!({ "offset": [0.0, 0.0], "scale": [2.0, 2.0] });
    textured["pbrMetallicRoughness"]["baseColorTexture"] =
        json!({ "index": 0, "extensions": { "KHR_texture_transform": transform } });
    let materials = glb.json["materials"]
        .as_array_mut()
        .expect("the writer writes materials");
    materials.push(textured);
    let material = materials.len() - 1;
    let primitives = glb.json["meshes"][0]["primitives"].as_array_mut();
    for (p, primitive) in primitives
        .expect("the head has primitives")
        .iter_mut()
        .enumerate()
    {
        // The lips share the skin's vertices (and so its UVs) but keep
        // their own material.
        if primitive["attributes"]["POSITION"] == skin {
            primitive["attributes"]["TEXCOORD_0"] = json!(uv);
        }
        if p == 0 {
            primitive["material"] = json!(material);
        }
    }
    let view = glb.push_view(&SKIN_WEBP);
    glb.json["images"] = json!([{ "bufferView": view, "mimeType": "image/webp" }]);
    glb.json["samplers"] = json!([{}]);
    glb.json["textures"] =
        json!([{ "sampler": 0, "extensions": { "EXT_texture_webp": { "source": 0 } } }]);
    glb.json["extensionsUsed"] = json!(["EXT_texture_webp", "KHR_texture_transform"]);
    glb.json["extensionsRequired"] = json!(["EXT_texture_webp"]);
}

/// The GLB and its truth.
pub fn vendor_export() -> (Vec<u8>, VariantTruth) {
    let avatar = &base().avatar;
    let mut glb = Glb::parse(&glb_of(avatar, None));
    webp_skin(&mut glb, &avatar.parts()[0].positions);
    let meshes = glb.json["meshes"]
        .as_array_mut()
        .expect("the writer writes meshes");
    for mesh in meshes {
        let name = mesh["name"].as_str().unwrap_or_default().to_string();
        let renamed: Vec<String> = mesh["extras"]["targetNames"]
            .as_array()
            .into_iter()
            .flatten()
            .filter_map(Value::as_str)
            .map(|n| vendor_name(&name, n))
            .collect();
        if !renamed.is_empty() {
            mesh["extras"]["targetNames"] = json!(renamed);
        }
    }
    let truth = plain_truth(avatar, 0, base_face_vertices());
    let compressed = crate::compressed_glb::draco::draco_compressed(&glb.to_bytes())
        .unwrap_or_else(|e| panic!("the default avatar compresses: {e}"));
    (compressed, truth)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_spelt_as_each_vendor_spells_them() {
        assert_eq!(vendor_name("Head", "jawOpen"), "AK_18_JawOpen");
        assert_eq!(
            vendor_name("EyeLeft", "eyeLookUpLeft"),
            "A05_Eye_Look_Up_Left"
        );
        assert_eq!(vendor_name("Teeth", "jawOpen"), "blendShape3.jawOpen");
        assert_eq!(
            vendor_name("Teeth", "eyeBlinkLeft"),
            "blendShape3.eyeBlink_L"
        );
        assert_eq!(vendor_name("Head", "viseme_aa"), "viseme_aa");
    }
}
