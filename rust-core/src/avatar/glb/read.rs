//! Reading a `.glb` or `.gltf` avatar: every triangle primitive the default
//! scene places, in world space, with its morph targets.
//!
//! Decisions:
//! - Only mode `TRIANGLES` (4) is read; a placed primitive of any other
//!   mode is an error ([`GlbError::Primitive`]) rather than skipped, since
//!   writing targets back needs every primitive of the mesh.
//! - A triangle with an index past the vertex count or a repeated index is
//!   an error ([`GlbError::Triangle`]); a triangle of three distinct
//!   vertices at one place (zero area) is accepted, as real avatars have
//!   them at seams and the geometry code weighs by area.
//! - A mesh placed by several nodes gives one part per placement.
//! - Primitives of one mesh that share their vertex attributes and their
//!   targets (the same accessors: glTF 2.0, "Meshes", lets primitives
//!   share them, and exporters write a surface in several materials that
//!   way) are one part, the later primitives' triangles appended to the
//!   first's ([`GlbAvatar::splits`] says where), since they are one welded
//!   surface.
//! - Target names come from the mesh's `extras.targetNames`, else the first
//!   primitive's `extras.targetNames`, else the name of the target's
//!   `POSITION` accessor, else `target N`.
//! - A target without `POSITION` displaces nothing (zeros).
//! - Geometry compressed with `EXT_meshopt_compression` or
//!   `KHR_draco_mesh_compression` is decoded and geometry quantized with
//!   `KHR_mesh_quantization` turned into floats first (`meshopt.rs`,
//!   `draco.rs`, `quantization.rs`): the JSON and buffers kept for writing
//!   back are plain glTF 2.0 without those extensions.
//! - Textures are never decoded, so an image in any format
//!   (`EXT_texture_webp`, `KHR_texture_basisu`: a texture whose image is in
//!   its extension, with no `source` of its own) and any texture extension
//!   (`KHR_texture_transform`) are kept as they are.
//! - A required extension that stores or places geometry in a way this
//!   reader does not decode (GPU instancing) is an error
//!   ([`GlbError::Unsupported`], with advice on converting the file); any
//!   other (materials, textures) does not concern the geometry and is kept
//!   as it is.
//! - A triangle is read in the file's order, reversed where its placement
//!   mirrors (a negative determinant: glTF 2.0 spec, "Transformations",
//!   front faces then wind clockwise), so that it faces outward in world
//!   space either way.
//! - Morph targets and ARKit names are not required here: [`check_avatar`]
//!   asks for them when the file is to be used as an avatar.

use super::accessor::Source;
use super::scene::{Placement, placements};
use super::{GlbError, container, draco, meshopt, quantization};
use crate::avatar::{ArkitTargets, Avatar, AvatarMesh, AvatarPart, target_names::arkit_targets};
use crate::io::read_bounded;
use glam::Vec3;
use std::path::{Path, PathBuf};

/// An avatar read from a glTF file, with what is needed to write the file
/// back with new morph targets.
#[derive(Clone, Debug)]
pub struct GlbAvatar {
    /// The meshes in world space.
    pub avatar: Avatar,
    /// Where each of `avatar.parts()` is placed (same order).
    pub placements: Vec<Placement>,
    /// For each of `avatar.parts()` (same order), the further primitives that
    /// share its vertices, in file order; empty for a part of one
    /// primitive.
    pub splits: Vec<Vec<PrimitiveSplit>>,
    /// The file it came from, for messages.
    pub file: PathBuf,
    pub(crate) json: serde_json::Value,
    pub(crate) buffers: Vec<Vec<u8>>,
    /// Buffer views whose data was decoded into others (a Draco
    /// primitive's stream) and that `json` no longer refers to: the writer
    /// leaves them out.
    pub(crate) decoded_views: Vec<usize>,
}

/// A primitive whose vertices are those of an earlier primitive's part:
/// the part's triangles from `first_triangle` (up to the next split) are
/// its.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PrimitiveSplit {
    /// Index of the primitive within its glTF mesh.
    pub primitive: usize,
    /// Index in the part's triangles of the primitive's first.
    pub first_triangle: usize,
}

impl GlbAvatar {
    /// The file's JSON document as read.
    pub fn json(&self) -> &serde_json::Value {
        &self.json
    }

    /// The bytes of each buffer as read.
    pub fn buffers(&self) -> &[Vec<u8>] {
        &self.buffers
    }
}

/// Largest avatar file read, and largest buffer file beside a `.gltf`
/// (512 MiB): avatars in common use, textures included, are 5–100 MB. The
/// file is read whole (it is held while its targets are written back) and
/// its images are never decoded.
pub const MAX_GLB_BYTES: u64 = 512 << 20;

/// Reads a `.glb`, or a `.gltf` with its buffers in `data:` URIs or in
/// files beside it; only regular files of at most [`MAX_GLB_BYTES`].
pub fn read_avatar(path: &Path) -> Result<GlbAvatar, GlbError> {
    let bytes = read_bounded(path, MAX_GLB_BYTES, "a glTF file")?;
    read(&bytes, path, path.parent())
}

/// Reads a GLB, or a `.gltf` whose buffers are all `data:` URIs, from
/// memory; `name` stands for the file in messages.
pub fn read_avatar_bytes(bytes: &[u8], name: &str) -> Result<GlbAvatar, GlbError> {
    read(bytes, Path::new(name), None)
}

/// Required extensions that store or place geometry in a way this reader
/// does not decode, with what to do about each.
const UNSUPPORTED: [(&str, &str); 1] = [(
    "EXT_mesh_gpu_instancing",
    "re-export the avatar with its instances as ordinary nodes \
     (`npx @gltf-transform/cli uninstance in.glb out.glb`)",
)];

fn read(bytes: &[u8], file: &Path, folder: Option<&Path>) -> Result<GlbAvatar, GlbError> {
    let invalid = |what: String| GlbError::Invalid {
        file: file.to_path_buf(),
        what,
    };
    let parts = container::split(bytes, file)?;
    let mut json: serde_json::Value =
        serde_json::from_slice(parts.json).map_err(|e| invalid(e.to_string()))?;
    let root: gltf::json::Root =
        gltf::json::deserialize::from_slice(parts.json).map_err(|e| invalid(e.to_string()))?;
    if let Some((extension, advice)) = UNSUPPORTED
        .iter()
        .find(|(e, _)| root.extensions_required.iter().any(|r| r == e))
    {
        return Err(GlbError::Unsupported {
            file: file.to_path_buf(),
            extension: extension.to_string(),
            advice: advice.to_string(),
        });
    }
    let fallback = meshopt::fallback_buffers(&json);
    let mut buffers = container::load_buffers(&root, parts.bin, folder, file, &fallback)?;
    // Compressed and quantized geometry is made plain before anything is
    // read (draco.rs, meshopt.rs, quantization.rs). Draco's accessors have
    // no data until decoded, which validation would refuse: they are
    // decoded first.
    let mut decoded_views = Vec::new();
    let mut document = match draco::used(&json) {
        true => {
            decoded_views = draco::decode_primitives(&mut json, &mut buffers, file)?;
            document_of(&json, file)?
        }
        false => document(root, file)?,
    };
    if meshopt::used(&json) {
        meshopt::decode_views(&mut json, &mut buffers, file)?;
        document = document_of(&json, file)?;
    }
    if mentions(&json, quantization::EXTENSION) {
        quantization::dequantize(&mut json, &mut buffers, &document, file)?;
        document = document_of(&json, file)?;
    }
    meshopt::forget_extension(&mut json, meshopt::EXTENSION);
    let source = Source {
        file,
        buffers: &buffers,
    };
    let mut placed = placements(&document, &source)?;
    placed.sort_by_key(|p| p.mesh); // parts grouped by mesh, stable
    let mut meshes = Vec::new();
    for mesh in document.meshes() {
        check_target_counts(&mesh, file)?;
        meshes.push(AvatarMesh {
            name: mesh.name().map(str::to_string),
            target_names: target_names(&mesh, &json),
        });
    }
    let mut out_parts: Vec<AvatarPart> = Vec::new();
    let mut out_placements = Vec::new();
    let mut splits: Vec<Vec<PrimitiveSplit>> = Vec::new();
    for placement in &placed {
        let Some(mesh) = document.meshes().nth(placement.mesh) else {
            continue;
        };
        let node = document.nodes().nth(placement.node);
        let name = node
            .and_then(|n| n.name().map(str::to_string))
            .or_else(|| mesh.name().map(str::to_string))
            .unwrap_or_else(|| format!("mesh {}", mesh.index()));
        let first_part = out_parts.len();
        for primitive in mesh.primitives() {
            let vertices = &json["meshes"][mesh.index()]["primitives"];
            let shares = |q: usize| {
                let (a, b) = (&vertices[q], &vertices[primitive.index()]);
                a["attributes"] == b["attributes"] && a["targets"] == b["targets"]
            };
            let earlier = (first_part..out_parts.len()).find(|&k| shares(out_parts[k].primitive));
            let Some(k) = earlier else {
                out_parts.push(read_part(&source, &mesh, &primitive, placement, &name)?);
                out_placements.push(*placement);
                splits.push(Vec::new());
                continue;
            };
            let n = out_parts[k].positions.len();
            let more = read_triangles(&source, &primitive, n, placement)?;
            splits[k].push(PrimitiveSplit {
                primitive: primitive.index(),
                first_triangle: out_parts[k].triangles.len(),
            });
            out_parts[k].triangles.extend(more);
        }
    }
    if out_parts.is_empty() {
        return Err(GlbError::NoMesh {
            file: file.to_path_buf(),
        });
    }
    Ok(GlbAvatar {
        avatar: Avatar::new(meshes, out_parts).map_err(|source| GlbError::Avatar {
            file: file.to_path_buf(),
            source,
        })?,
        placements: out_placements,
        splits,
        file: file.to_path_buf(),
        json,
        buffers,
        decoded_views,
    })
}

/// Whether `extensionsUsed` or `extensionsRequired` names `extension`.
fn mentions(json: &serde_json::Value, extension: &str) -> bool {
    ["extensionsUsed", "extensionsRequired"].iter().any(|k| {
        json[k]
            .as_array()
            .is_some_and(|l| l.iter().any(|e| e == extension))
    })
}

/// The validated document of a (rewritten) JSON.
pub(crate) fn document_of(
    json: &serde_json::Value,
    file: &Path,
) -> Result<gltf::Document, GlbError> {
    let root =
        gltf::json::deserialize::from_value(json.clone()).map_err(|e| GlbError::Invalid {
            file: file.to_path_buf(),
            what: e.to_string(),
        })?;
    document(root, file)
}

/// Validates a glTF root (with every required extension accepted: those
/// [`UNSUPPORTED`] lists were refused before).
fn document(mut root: gltf::json::Root, file: &Path) -> Result<gltf::Document, GlbError> {
    let invalid = |what: String| GlbError::Invalid {
        file: file.to_path_buf(),
        what,
    };
    // The `gltf` crate refuses every required extension it was not built
    // with; those that matter here were handled.
    root.extensions_required.clear();
    // gltf-json 1.4's validation indexes `accessors` with each POSITION
    // before checking the index: check it first.
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            let semantic = gltf::json::validation::Checked::Valid(gltf::Semantic::Positions);
            if let Some(a) = primitive.attributes.get(&semantic)
                && a.value() >= root.accessors.len()
            {
                return Err(invalid(format!(
                    "meshes[{m}].primitives[{p}].attributes.POSITION: accessor {} does not exist",
                    a.value()
                )));
            }
        }
    }
    gltf::Document::from_json(root).map_err(|e| match e {
        gltf::Error::Validation(list) => invalid(
            list.iter()
                .take(5)
                .map(|(path, e)| format!("{}: {e}", path.as_str()))
                .collect::<Vec<_>>()
                .join("; "),
        ),
        other => invalid(other.to_string()),
    })
}

/// The spec's rule: every primitive of a mesh has the same number of
/// targets.
fn check_target_counts(mesh: &gltf::Mesh, file: &Path) -> Result<(), GlbError> {
    let mut primitives = mesh.primitives();
    let expected = primitives.next().map_or(0, |p| p.morph_targets().len());
    for p in primitives {
        let found = p.morph_targets().len();
        if found != expected {
            return Err(GlbError::TargetCount {
                file: file.to_path_buf(),
                mesh: mesh.index(),
                primitive: p.index(),
                expected,
                found,
            });
        }
    }
    Ok(())
}

fn target_names(mesh: &gltf::Mesh, json: &serde_json::Value) -> Vec<String> {
    let count = mesh
        .primitives()
        .next()
        .map_or(0, |p| p.morph_targets().len());
    let m = &json["meshes"][mesh.index()];
    let from_extras = |extras: &serde_json::Value, t: usize| {
        extras["targetNames"][t].as_str().map(str::to_string)
    };
    let first = mesh.primitives().next();
    (0..count)
        .map(|t| {
            from_extras(&m["extras"], t)
                .or_else(|| from_extras(&m["primitives"][0]["extras"], t))
                .or_else(|| {
                    let target = first.as_ref()?.morph_targets().nth(t)?;
                    target.positions()?.name().map(str::to_string)
                })
                .unwrap_or_else(|| format!("target {t}"))
        })
        .collect()
}

fn read_part(
    source: &Source,
    mesh: &gltf::Mesh,
    primitive: &gltf::Primitive,
    placement: &Placement,
    name: &str,
) -> Result<AvatarPart, GlbError> {
    let (m, p) = (mesh.index(), primitive.index());
    let prim_err = |what: &str| primitive_error(source.file, m, p, what);
    let accessor = primitive
        .get(&gltf::Semantic::Positions)
        .ok_or_else(|| prim_err("no POSITION"))?;
    let local = source.vec3(&accessor, None)?;
    check_finite(&local, source.file, m, p, "position")?;
    let n = local.len();
    let triangles = read_triangles(source, primitive, n, placement)?;
    let linear = placement.linear();
    let mut targets = Vec::new();
    for (t, target) in primitive.morph_targets().enumerate() {
        let d = match target.positions() {
            Some(a) => source.vec3(&a, Some(n))?,
            None => vec![Vec3::ZERO; n],
        };
        check_finite(&d, source.file, m, p, &format!("target {t}"))?;
        targets.push(d.into_iter().map(|v| linear * v).collect());
    }
    Ok(AvatarPart {
        name: name.to_string(),
        mesh: m,
        primitive: p,
        positions: local
            .iter()
            .map(|&v| placement.world.transform_point3(v))
            .collect(),
        triangles,
        targets,
    })
}

/// A primitive's triangles over its `n` vertices, each reversed where the
/// placement mirrors (module docs): an error for a mode other than
/// `TRIANGLES`, an index count not a multiple of 3, an index past `n` or a
/// repeated index.
fn read_triangles(
    source: &Source,
    primitive: &gltf::Primitive,
    n: usize,
    placement: &Placement,
) -> Result<Vec<[u32; 3]>, GlbError> {
    let (m, p) = (placement.mesh, primitive.index());
    let prim_err = |what: &str| primitive_error(source.file, m, p, what);
    if primitive.mode() != gltf::mesh::Mode::Triangles {
        return Err(prim_err(&format!(
            "mode {:?}; only TRIANGLES is read",
            primitive.mode()
        )));
    }
    let indices = match primitive.indices() {
        Some(a) => source.indices(&a)?,
        None => (0..n as u32).collect(),
    };
    if indices.len() % 3 != 0 {
        return Err(prim_err(&format!(
            "{} indices, not a multiple of 3",
            indices.len()
        )));
    }
    let mut triangles = Vec::with_capacity(indices.len() / 3);
    let mirrored = placement.linear().determinant() < 0.0;
    for (k, t) in indices.chunks_exact(3).enumerate() {
        let tri = [t[0], t[1], t[2]];
        let what = if let Some(&i) = tri.iter().find(|&&i| i as usize >= n) {
            format!("index {i} past the {n} vertices")
        } else if tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2] {
            format!("repeated index {tri:?}")
        } else {
            triangles.push(if mirrored { [t[0], t[2], t[1]] } else { tri });
            continue;
        };
        return Err(GlbError::Triangle {
            file: source.file.to_path_buf(),
            mesh: m,
            primitive: p,
            triangle: k,
            what,
        });
    }
    Ok(triangles)
}

/// What is wrong with primitive `primitive` of mesh `mesh`.
fn primitive_error(file: &Path, mesh: usize, primitive: usize, what: &str) -> GlbError {
    GlbError::Primitive {
        file: file.to_path_buf(),
        mesh,
        primitive,
        what: what.to_string(),
    }
}

fn check_finite(
    values: &[Vec3],
    file: &Path,
    mesh: usize,
    primitive: usize,
    which: &str,
) -> Result<(), GlbError> {
    match values.iter().position(|v| !v.is_finite()) {
        Some(vertex) => Err(GlbError::NotFinite {
            file: file.to_path_buf(),
            mesh,
            primitive,
            which: which.to_string(),
            vertex,
        }),
        None => Ok(()),
    }
}

/// What a read file offers as an avatar: which (mesh, target) pairs carry
/// each of ARKit's 52 shapes ([`ArkitTargets::missing`] lists the rest).
/// An error if no placed mesh has morph targets or no target has one of
/// ARKit's names.
pub fn check_avatar(avatar: &GlbAvatar) -> Result<ArkitTargets, GlbError> {
    let file = avatar.file.clone();
    if avatar.avatar.parts().iter().all(|p| p.targets.is_empty()) {
        return Err(GlbError::NoMorphTargets { file });
    }
    let found = arkit_targets(&avatar.avatar);
    if found.found() == 0 {
        return Err(GlbError::NoArkitTargets { file });
    }
    Ok(found)
}
