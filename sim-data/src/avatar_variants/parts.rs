//! Building blocks shared by the test avatars: the default avatar's parts
//! by role, parts from `f64` geometry, merging parts into one primitive,
//! the GLB of an avatar, and the truth every variant computes alike.

use super::truth::{Piece, UpAxis, VariantTruth};
use crate::default_avatar::{DefaultAvatar, default_avatar, looks};
use glam::{DVec3, Vec3};
use likeness::Blendshape;
use likeness::avatar::glb::{MeshLook, NewGlbOptions, new_avatar_glb};
use likeness::avatar::{Avatar, AvatarMesh, AvatarPart};
use std::path::Path;

/// The default avatar (built once per process).
pub fn base() -> &'static DefaultAvatar {
    default_avatar()
}

/// A copy of the default avatar's part `k`, moved to mesh `mesh` as its
/// primitive `primitive`.
pub fn base_part(k: usize, mesh: usize, primitive: usize) -> AvatarPart {
    let mut p = base().avatar.parts()[k].clone();
    p.mesh = mesh;
    p.primitive = primitive;
    p
}

/// A part from `f64` geometry and targets.
pub fn dpart(
    name: &str,
    mesh: usize,
    primitive: usize,
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    targets: &[Vec<DVec3>],
) -> AvatarPart {
    let f = |v: &[DVec3]| v.iter().map(|p| p.as_vec3()).collect::<Vec<Vec3>>();
    AvatarPart {
        name: name.to_string(),
        mesh,
        primitive,
        positions: f(positions),
        triangles: triangles.to_vec(),
        targets: targets.iter().map(|t| f(t)).collect(),
    }
}

/// A mix of ARKit shapes at weights: a viseme or an action unit as a rig
/// makes it from its ARKit targets.
pub type ShapeMix = &'static [(Blendshape, f32)];

/// `part` with one target appended per mix of `mixes`, each the mix of its
/// ARKit targets (the part's first 52, in Apple's order).
pub fn with_mixes(mut part: AvatarPart, mixes: &[ShapeMix]) -> AvatarPart {
    let added: Vec<Vec<Vec3>> = mixes
        .iter()
        .map(|mix| {
            (0..part.positions.len())
                .map(|v| {
                    mix.iter()
                        .map(|(s, w)| *w * part.targets[s.index()][v])
                        .sum()
                })
                .collect()
        })
        .collect();
    part.targets.extend(added);
    part
}

/// `parts` concatenated into one primitive (their targets concatenated
/// too: every part must have the same number).
pub fn merge(name: &str, mesh: usize, primitive: usize, parts: &[AvatarPart]) -> AvatarPart {
    let targets = parts.first().map_or(0, |p| p.targets.len());
    let mut out = AvatarPart {
        name: name.to_string(),
        mesh,
        primitive,
        positions: Vec::new(),
        triangles: Vec::new(),
        targets: vec![Vec::new(); targets],
    };
    for p in parts {
        assert_eq!(p.targets.len(), targets, "merged parts' target counts");
        let o = out.positions.len() as u32;
        out.positions.extend(&p.positions);
        out.triangles
            .extend(p.triangles.iter().map(|t| t.map(|i| i + o)));
        for (all, own) in out.targets.iter_mut().zip(&p.targets) {
            all.extend(own);
        }
    }
    out
}

/// A mesh named `name` with ARKit's 52 targets in Apple's order, then
/// `extra` names.
pub fn arkit_mesh(name: &str, extra: &[&str]) -> AvatarMesh {
    AvatarMesh {
        name: Some(name.to_string()),
        target_names: Blendshape::ALL
            .iter()
            .map(|s| s.name().to_string())
            .chain(extra.iter().map(|s| s.to_string()))
            .collect(),
    }
}

/// A mesh named `name` without targets.
pub fn plain_mesh(name: &str) -> AvatarMesh {
    AvatarMesh {
        name: Some(name.to_string()),
        target_names: Vec::new(),
    }
}

/// The GLB the core writes for `avatar` (parts sorted by mesh, then
/// primitive, as the reader returns them), with `looks` (one per mesh;
/// `None`: the default avatar's rule by mesh name).
pub fn glb_of(avatar: &Avatar, looks_given: Option<Vec<MeshLook>>) -> Vec<u8> {
    let options = NewGlbOptions {
        looks: looks_given.unwrap_or_else(|| looks(avatar)),
        ..NewGlbOptions::default()
    };
    new_avatar_glb(avatar, &options, Path::new("variant.glb")).expect("a test avatar is writable")
}

/// Sorts parts by mesh then primitive, the order the core's writer and
/// reader keep.
pub fn sorted(avatar: Avatar) -> Avatar {
    let (meshes, mut parts) = avatar.into_parts();
    parts.sort_by_key(|p| (p.mesh, p.primitive));
    Avatar::new(meshes, parts).expect("reordering parts keeps an avatar valid")
}

/// Bounding box `[min, max]` of every part's positions, each mapped by
/// `to_world`.
pub fn bounds(avatar: &Avatar, to_world: impl Fn(Vec3) -> Vec3) -> [Vec3; 2] {
    avatar
        .parts()
        .iter()
        .flat_map(|p| p.positions.iter().map(|&v| to_world(v)))
        .fold(
            [Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)],
            |[lo, hi], v| [lo.min(v), hi.max(v)],
        )
}

/// The default avatar's eye centres' distance (m).
pub fn base_eye_distance() -> f32 {
    let [l, r] = base().eye_centres;
    l.distance(r)
}

/// The truth of an avatar laid out as the default one (parts in the
/// default's roles unless the variant says otherwise), written with
/// identity nodes in metres, +Y up: the variants start from it and change
/// what differs.
pub fn plain_truth(avatar: &Avatar, head_part: usize, face_vertices: usize) -> VariantTruth {
    VariantTruth {
        meshes: avatar.meshes().len(),
        parts: avatar.parts().len(),
        head_part,
        head_vertices: avatar.parts()[head_part].positions.len(),
        face_vertices,
        eyeballs: base().eyes.map(|k| Piece::whole(&base().avatar, k)),
        eyes_bone_driven: false,
        eye_look_moves_eyeballs: true,
        teeth_share_mesh_with_gums: false,
        teeth: Some(Piece::whole(&base().avatar, base().teeth[0])),
        jaw_moved_vertices: 0,
        skinned: false,
        non_identity_bind_pose: false,
        unit_to_metres: 1.0,
        up: UpAxis::Y,
        world_bounds: bounds(avatar, |v| v),
        arkit_targets: 52,
        extra_targets: Vec::new(),
        meshes_without_targets: Vec::new(),
        eye_distance: base_eye_distance(),
    }
}

/// The default avatar's face vertex count (the skin's first vertices).
pub fn base_face_vertices() -> usize {
    base().true_correspondence.len()
}
