//! What colour each vertex of a read avatar is, as far as a picture drawn
//! without textures can tell (the preview's contact sheet and the demo's
//! faces): glTF 2.0, "Materials" (`pbrMetallicRoughness.baseColorFactor`)
//! and "Meshes" (`COLOR_0`, which multiplies the base colour).
//!
//! A vertex's colour is `baseColorFactor.rgb × COLOR_0.rgb` (linear; `COLOR_0`
//! as `VEC3` or `VEC4`, floats or normalized integers). On a part whose
//! primitives share its vertices in several materials, the base colour of
//! a vertex is the mean of its triangles' materials' (a border vertex
//! blends them). A part has none when
//! its colour lives elsewhere: a `baseColorTexture` (images are never
//! decoded), no material (the spec's default is plain white, which says
//! nothing), or a `COLOR_0` that cannot be read as one colour per vertex.

use super::accessor::Source;
use super::read::document_of;
use super::{GlbAvatar, PrimitiveSplit};
use glam::Vec3;

/// Each part's vertex colours (linear RGB, one per vertex), in
/// [`crate::avatar::Avatar::parts`] order; `None` where the file does not
/// say (module docs).
pub fn part_colours(glb: &GlbAvatar) -> Vec<Option<Vec<Vec3>>> {
    let Ok(document) = document_of(&glb.json, &glb.file) else {
        return vec![None; glb.avatar.parts().len()];
    };
    let source = Source {
        file: &glb.file,
        buffers: &glb.buffers,
    };
    glb.avatar
        .parts()
        .iter()
        .zip(&glb.splits)
        .map(|(part, splits)| {
            let mesh = document.meshes().nth(part.mesh)?;
            let base_of = |p: usize| {
                let material = mesh.primitives().nth(p)?.material();
                material.index()?;
                let pbr = material.pbr_metallic_roughness();
                if pbr.base_color_texture().is_some() {
                    return None;
                }
                let [r, g, b, _] = pbr.base_color_factor();
                Some(Vec3::new(r, g, b))
            };
            let base = base_of(part.primitive)?;
            let n = part.positions.len();
            let mut colours = vec![base; n];
            if !splits.is_empty() {
                let bases: Vec<Vec3> = splits
                    .iter()
                    .map(|s| base_of(s.primitive))
                    .collect::<Option<_>>()?;
                colours = blended(n, &part.triangles, base, splits, &bases);
            }
            let primitive = mesh.primitives().nth(part.primitive)?;
            let Some(accessor) = primitive.get(&gltf::Semantic::Colors(0)) else {
                return Some(colours);
            };
            let width = accessor.dimensions().multiplicity();
            let values = source.floats(&accessor).ok()?;
            if !matches!(width, 3 | 4) || values.len() != n * width {
                return None;
            }
            let tint = values.chunks_exact(width);
            Some(
                colours
                    .iter()
                    .zip(tint)
                    .map(|(c, t)| *c * Vec3::new(t[0], t[1], t[2]))
                    .collect(),
            )
        })
        .collect()
}

/// Each vertex's colour on a part in several materials: the mean of the
/// base colours of the triangles around it (`base` up to the first split,
/// then `bases[i]` from `splits[i]` on), `base` on no triangle.
fn blended(
    n: usize,
    triangles: &[[u32; 3]],
    base: Vec3,
    splits: &[PrimitiveSplit],
    bases: &[Vec3],
) -> Vec<Vec3> {
    let mut sum = vec![(Vec3::ZERO, 0u32); n];
    for (k, t) in triangles.iter().enumerate() {
        let colour = splits
            .iter()
            .zip(bases)
            .rev()
            .find(|(s, _)| k >= s.first_triangle)
            .map_or(base, |(_, c)| *c);
        for &v in t {
            if let Some(s) = sum.get_mut(v as usize) {
                s.0 += colour;
                s.1 += 1;
            }
        }
    }
    sum.into_iter()
        .map(|(c, k)| if k == 0 { base } else { c / k as f32 })
        .collect()
}

/// `linear` (0..=1 per channel) in sRGB, 8 bits a channel, as a picture
/// stores it (IEC 61966-2-1's transfer function).
pub fn srgb8(linear: Vec3) -> [u8; 3] {
    linear.to_array().map(|c| {
        let c = c.clamp(0.0, 1.0);
        let s = if c <= 0.003_130_8 {
            12.92 * c
        } else {
            1.055 * c.powf(1.0 / 2.4) - 0.055
        };
        (s * 255.0).round() as u8
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::avatar::glb::{MeshLook, NewGlbOptions, new_avatar_glb, read_avatar_bytes};
    use crate::avatar::{Avatar, AvatarMesh, AvatarPart};
    use std::path::Path;

    #[test]
    fn colours_are_the_material_times_the_vertex_tint() {
        let triangle = |mesh| AvatarPart {
            name: "p".into(),
            mesh,
            primitive: 0,
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            triangles: vec![[0, 1, 2]],
            targets: Vec::new(),
        };
        let mesh = |name: &str| AvatarMesh {
            name: Some(name.into()),
            target_names: Vec::new(),
        };
        let avatar = Avatar::new(
            vec![mesh("skin"), mesh("eye")],
            vec![triangle(0), triangle(1)],
        )
        .unwrap();
        let tint = vec![Vec3::ONE, Vec3::new(1.0, 0.5, 0.5), Vec3::splat(0.25)];
        let options = NewGlbOptions {
            looks: vec![MeshLook::SKIN, MeshLook::EYE_WHITE],
            part_colours: vec![Some(tint.clone())],
            ..Default::default()
        };
        let bytes = new_avatar_glb(&avatar, &options, Path::new("c.glb")).unwrap();
        let mut glb = read_avatar_bytes(&bytes, "c.glb").unwrap();
        let colours = part_colours(&glb);
        let [r, g, b, _] = MeshLook::SKIN.base_colour;
        let skin = Vec3::new(r, g, b);
        let want: Vec<Vec3> = tint.iter().map(|t| skin * *t).collect();
        assert_eq!(colours[0].as_deref(), Some(&want[..]));
        let [r, g, b, _] = MeshLook::EYE_WHITE.base_colour;
        assert_eq!(colours[1], Some(vec![Vec3::new(r, g, b); 3]));
        // A texture carries the eye's colour: the file does not say; the
        // skin's is still read.
        glb.json["materials"][1]["pbrMetallicRoughness"]["baseColorTexture"] =
            serde_json::json!({ "index": 0 });
        glb.json["textures"] = serde_json::json!([{ "source": 0 }]);
        glb.json["images"] = serde_json::json!([{ "uri": "eye.png" }]);
        let colours = part_colours(&glb);
        assert_eq!((colours[0].is_some(), colours[1].is_none()), (true, true));
    }

    #[test]
    fn srgb_encodes_the_ends_and_middle_grey() {
        assert_eq!(srgb8(Vec3::ZERO), [0; 3]);
        assert_eq!(srgb8(Vec3::ONE), [255; 3]);
        // Linear 0.216 is sRGB 0.502, 128 of 255: the perceptual middle.
        assert_eq!(srgb8(Vec3::splat(0.216)), [128; 3]);
        assert_eq!(srgb8(Vec3::splat(2.0)), [255; 3], "clamped");
    }
}
