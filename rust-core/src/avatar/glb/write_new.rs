//! Writing an [`Avatar`] as a new GLB: one glTF mesh per [`AvatarMesh`]
//! (each placed by a node of its own at the origin, since the avatar is
//! already in world space), one primitive per part (more where the caller
//! splits a part between materials, sharing its vertices), a plain PBR
//! material per mesh, or per part where the caller gives a part its own, in
//! a colour the caller gives, and smooth vertex normals: the caller's shading normals
//! where it gives a part its own, else the surface's.
//!
//! A vertex's normal is the sum of `(b − a) × (c − a)` over the triangles
//! around it, normalized: each face weighs by twice its area, so slivers
//! barely tilt it (pmp-library's area-weighted vertex normal). A vertex on
//! no triangle gets +Y (the spec requires unit normals).
//!
//! Target names are written in ARKit's exact spelling where they are one of
//! ARKit's 52 (other names as they are), in the mesh's `extras.targetNames`
//! and each primitive's (UniVRM reads the primitive's).

use super::GlbError;
use super::container;
use super::encode::{Builder, TargetEncoding};
pub use super::surface_turn::vertex_normals;
use super::surface_turn::{WeldedSurface, all_normal_deltas};
use crate::avatar::target_names::{TargetName, resolve_mesh};
use crate::avatar::{Avatar, AvatarMesh};
use crate::io::atomic_write::write_atomically;
use glam::{Mat3, Vec3};
use serde_json::{Value, json};
use std::path::Path;

/// A mesh's material: metallic-roughness PBR with one colour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshLook {
    /// Linear RGBA base colour, each in 0..=1.
    pub base_colour: [f32; 4],
    /// 0 for skin, teeth and eyes.
    pub metallic: f32,
    /// 0 mirror-like ..= 1 matte.
    pub roughness: f32,
}

impl MeshLook {
    /// A light skin tone.
    pub const SKIN: MeshLook = MeshLook::plain([0.80, 0.57, 0.46, 1.0], 0.6);
    /// The white of the eye.
    pub const EYE_WHITE: MeshLook = MeshLook::plain([0.92, 0.92, 0.90, 1.0], 0.2);
    /// Teeth.
    pub const TOOTH: MeshLook = MeshLook::plain([0.90, 0.88, 0.80, 1.0], 0.3);
    /// Gums and tongue.
    pub const GUM: MeshLook = MeshLook::plain([0.75, 0.35, 0.38, 1.0], 0.4);
    /// Grey, for meshes no look is given for.
    pub const GREY: MeshLook = MeshLook::plain([0.6, 0.6, 0.6, 1.0], 0.7);

    /// A non-metallic material of `base_colour` and `roughness`.
    pub const fn plain(base_colour: [f32; 4], roughness: f32) -> MeshLook {
        MeshLook {
            base_colour,
            metallic: 0.0,
            roughness,
        }
    }
}

/// A material for the later triangles of a part: from `first_triangle` up
/// to the next split (or the end), the part's triangles are written as a
/// primitive of their own in the material `name`, sharing the part's
/// vertex attributes and targets (glTF 2.0, "Meshes": primitives may share
/// accessors), so the surface stays one welded surface, read back as one
/// part (`read.rs`).
#[derive(Clone, Debug, PartialEq)]
pub struct MaterialSplit {
    /// Index of the first triangle in the material.
    pub first_triangle: usize,
    /// The material's name; parts and splits naming one material share it.
    pub name: String,
    /// The material's look (its first look counts).
    pub look: MeshLook,
}

/// How [`write_new_avatar`] writes.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct NewGlbOptions {
    /// The material of each mesh, in [`Avatar::meshes`] order; meshes past
    /// the end are [`MeshLook::GREY`]. The material takes the mesh's name.
    pub looks: Vec<MeshLook>,
    /// A part's own material, in [`Avatar::parts`] order, where it is not
    /// its mesh's: the material's name and look (an eye's iris and pupil,
    /// the skin and the mouth's lining in one head mesh). Parts naming the
    /// same material share it (its first look counts); parts past the end
    /// or `None` take their mesh's.
    pub part_looks: Vec<Option<(String, MeshLook)>>,
    /// A part's vertex colours, in [`Avatar::parts`] order: linear RGB per
    /// vertex, written as `COLOR_0`, which glTF multiplies into the
    /// material's base colour (a tint: 1 keeps the material's colour). A
    /// list of the wrong length is refused.
    pub part_colours: Vec<Option<Vec<Vec3>>>,
    /// A part's own shading normals, in [`Avatar::parts`] order: a unit
    /// vector per vertex, written as `NORMAL` in place of the surface's
    /// area-weighted normals (a surface sampled from a coarser one shades
    /// smoothly with the coarser one's normals interpolated). A list of the
    /// wrong length, or a normal not of unit length, is refused.
    pub part_normals: Vec<Option<Vec<Vec3>>>,
    /// Materials within a part, in [`Avatar::parts`] order: the lips of a
    /// skin. Each part's splits are in increasing order of their first
    /// triangle, within its triangles and past its first; other lists are
    /// refused.
    pub part_splits: Vec<Vec<MaterialSplit>>,
    /// Dense or smallest targets.
    pub encoding: TargetEncoding,
}

/// Writes `avatar` as a new GLB at `path` (atomically).
pub fn write_new_avatar(
    avatar: &Avatar,
    options: &NewGlbOptions,
    path: &Path,
) -> Result<(), GlbError> {
    let bytes = new_avatar_glb(avatar, options, path)?;
    write_atomically(path, &bytes).map_err(|source| GlbError::Io {
        file: path.to_path_buf(),
        source,
    })
}

/// The GLB [`write_new_avatar`] writes, in memory; `file` names it in
/// messages.
pub fn new_avatar_glb(
    avatar: &Avatar,
    options: &NewGlbOptions,
    file: &Path,
) -> Result<Vec<u8>, GlbError> {
    check(avatar, file)?;
    let mut b = Builder::new();
    let mut meshes = Vec::new();
    let mut materials = Materials::default();
    for (m, mesh) in avatar.meshes().iter().enumerate() {
        let names = arkit_spelling(m, mesh);
        let name = mesh.name.clone().unwrap_or_else(|| format!("mesh {m}"));
        let mesh_look = options.looks.get(m).copied().unwrap_or(MeshLook::GREY);
        let mut primitives = Vec::new();
        for (k, part) in avatar
            .parts()
            .iter()
            .enumerate()
            .filter(|(_, p)| p.mesh == m)
        {
            let material = match options.part_looks.get(k) {
                Some(Some((own, look))) => materials.index(own, *look),
                _ => materials.index(&name, mesh_look),
            };
            let position = b.vec3(&part.positions);
            let surface_normals;
            let normals: &[Vec3] = match options.part_normals.get(k) {
                Some(Some(own)) => {
                    let unit = |n: &Vec3| (n.length() - 1.0).abs() < 1e-3;
                    if own.len() != part.positions.len() || !own.iter().all(unit) {
                        return Err(GlbError::Write {
                            file: file.to_path_buf(),
                            what: format!("part {k}: not one unit normal per vertex"),
                        });
                    }
                    own
                }
                _ => {
                    surface_normals = vertex_normals(&part.positions, &part.triangles);
                    &surface_normals
                }
            };
            let normal = b.vec3(normals);
            let surface = WeldedSurface::new(&part.positions, &part.triangles);
            let moved: Vec<&[Vec3]> = part.targets.iter().map(Vec::as_slice).collect();
            let turns =
                all_normal_deltas(&surface, &part.positions, &moved, normals, Mat3::IDENTITY);
            let mut targets = Vec::with_capacity(part.targets.len());
            for ((d, turn), name) in part.targets.iter().zip(&turns).zip(&names) {
                targets.push(json!({
                    "POSITION": b.target(d, name, options.encoding),
                    "NORMAL": b.target(turn, "", options.encoding),
                }));
            }
            let splits = options.part_splits.get(k).map_or(&[][..], Vec::as_slice);
            let ends: Vec<usize> = splits.iter().map(|s| s.first_triangle).collect();
            let increasing = ends.windows(2).all(|w| w[0] < w[1]);
            if !increasing
                || ends.first().is_some_and(|&f| f == 0)
                || ends.last().is_some_and(|&l| l >= part.triangles.len())
            {
                return Err(GlbError::Write {
                    file: file.to_path_buf(),
                    what: format!(
                        "part {k}: material splits {ends:?} not increasing within its {} triangles",
                        part.triangles.len()
                    ),
                });
            }
            let first_end = ends.first().copied().unwrap_or(part.triangles.len());
            let indices = b.triangles(&part.triangles[..first_end]);
            let mut p = json!({
                "attributes": { "POSITION": position, "NORMAL": normal },
                "indices": indices, "material": material, "mode": 4,
            });
            if let Some(Some(colours)) = options.part_colours.get(k) {
                if colours.len() != part.positions.len() || colours.iter().any(|c| !c.is_finite()) {
                    return Err(GlbError::Write {
                        file: file.to_path_buf(),
                        what: format!("part {k}: not one finite colour per vertex"),
                    });
                }
                p["attributes"]["COLOR_0"] = json!(b.vec3(colours));
            }
            if !targets.is_empty() {
                p["targets"] = Value::Array(targets);
                p["extras"] = json!({ "targetNames": names });
            }
            let first = p.clone();
            primitives.push(p);
            for (i, split) in splits.iter().enumerate() {
                let end = ends.get(i + 1).copied().unwrap_or(part.triangles.len());
                let mut shared = first.clone();
                shared["indices"] = json!(b.triangles(&part.triangles[split.first_triangle..end]));
                shared["material"] = json!(materials.index(&split.name, split.look));
                primitives.push(shared);
            }
        }
        let mut out = json!({ "name": name, "primitives": primitives });
        if !names.is_empty() {
            out["weights"] = json!(vec![0.0; names.len()]);
            out["extras"] = json!({ "targetNames": names });
        }
        meshes.push(out);
    }
    let nodes: Vec<Value> = meshes
        .iter()
        .enumerate()
        .map(|(m, mesh)| json!({ "name": mesh["name"], "mesh": m }))
        .collect();
    let mut doc = json!({
        "asset": { "version": "2.0", "generator": "Likeness" },
        "scene": 0,
        "scenes": [{ "nodes": (0..nodes.len()).collect::<Vec<_>>() }],
        "nodes": nodes, "meshes": meshes, "materials": materials.written,
        "accessors": b.accessors, "bufferViews": b.views,
    });
    if !b.bin.is_empty() {
        doc["buffers"] = json!([{ "byteLength": b.bin.len() }]);
    }
    let text = serde_json::to_vec(&doc).map_err(|e| GlbError::Write {
        file: file.to_path_buf(),
        what: e.to_string(),
    })?;
    Ok(container::join(&text, &b.bin))
}

/// The materials written so far, by name, in the order first used.
#[derive(Default)]
struct Materials {
    names: Vec<String>,
    written: Vec<Value>,
}

impl Materials {
    /// The index of the material `name`, written with `look` if new.
    fn index(&mut self, name: &str, look: MeshLook) -> usize {
        if let Some(i) = self.names.iter().position(|n| n == name) {
            return i;
        }
        self.names.push(name.to_string());
        self.written.push(json!({
            "name": name,
            "pbrMetallicRoughness": {
                "baseColorFactor": look.base_colour.map(f64::from),
                "metallicFactor": look.metallic, "roughnessFactor": look.roughness,
            },
        }));
        self.names.len() - 1
    }
}

/// Target names, in ARKit's spelling where they are taken for one of its
/// shapes whole (halves and targets passed over keep theirs).
fn arkit_spelling(m: usize, mesh: &AvatarMesh) -> Vec<String> {
    let (taken, _) = resolve_mesh(m, &mesh.target_names);
    mesh.target_names
        .iter()
        .zip(taken)
        .map(|(n, read)| match read {
            TargetName::Arkit(shape) => shape.name().to_string(),
            _ => n.clone(),
        })
        .collect()
}

/// The avatar is one a GLB can hold: every mesh has parts, every part has
/// finite positions, triangles within range and one displacement per
/// vertex for each of its mesh's targets.
fn check(avatar: &Avatar, file: &Path) -> Result<(), GlbError> {
    let err = |what: String| {
        Err(GlbError::Write {
            file: file.to_path_buf(),
            what,
        })
    };
    for m in 0..avatar.meshes().len() {
        if !avatar.parts().iter().any(|p| p.mesh == m) {
            return err(format!("mesh {m} has no parts"));
        }
    }
    for (k, part) in avatar.parts().iter().enumerate() {
        let n = part.positions.len();
        let Some(mesh) = avatar.meshes().get(part.mesh) else {
            return err(format!("part {k}: mesh {} does not exist", part.mesh));
        };
        if n == 0 || part.triangles.is_empty() {
            return err(format!("part {k}: no vertices or no triangles"));
        }
        if let Some(v) = part.positions.iter().position(|p| !p.is_finite()) {
            return err(format!("part {k} vertex {v}: position not finite"));
        }
        if let Some(t) = part
            .triangles
            .iter()
            .position(|t| t.iter().any(|&i| i as usize >= n))
        {
            return err(format!("part {k} triangle {t}: index past {n} vertices"));
        }
        if part.targets.len() != mesh.target_names.len() {
            return err(format!(
                "part {k}: {} targets, its mesh names {}",
                part.targets.len(),
                mesh.target_names.len()
            ));
        }
        for (t, d) in part.targets.iter().enumerate() {
            if d.len() != n || d.iter().any(|v| !v.is_finite()) {
                return err(format!("part {k} target {t}: not {n} finite displacements"));
            }
        }
    }
    Ok(())
}
