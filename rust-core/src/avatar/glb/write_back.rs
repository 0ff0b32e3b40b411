//! Writing a read avatar back with new ARKit shapes, everything else as it
//! was.
//!
//! Rules, per glTF mesh the scene places:
//! - a target with one of ARKit's names (any spelling) whose shape has new
//!   data gets that data and ARKit's exact name;
//! - halves of a shape with new data (`browInnerUp_L` / `_R`) become one
//!   whole target at the first half's place; the other halves go;
//! - a shape with new data that the mesh lacks is added (Apple's order,
//!   after the existing targets) if it moves any vertex of the mesh; every
//!   primitive of the mesh gets it (zeros where it moves nothing);
//! - ARKit targets without new data keep their data and take ARKit's exact
//!   name; every other target is kept untouched;
//! - primitives that shared their vertices and targets (one part, see
//!   `read.rs`) share the new rest and targets as well: written once, for
//!   the first, and referred to by the others.
//!
//! New data is world space; it is taken back to the primitive's own space
//! through the inverse of its node's linear part (a mesh placed twice is
//! written from its first placement). New targets carry `POSITION` and,
//! where the primitive has normals, `NORMAL` deltas: its normals turned as
//! the surface turns under the target (`surface_turn.rs`); the tangent
//! displacements of a replaced target would no longer fit it and are
//! dropped. `mesh.weights` and the `weights` of the
//! nodes placing the mesh follow the targets (kept weights kept, new ones
//! 0); an animation of those weights cannot follow a change in the number
//! of targets, so that is an error. Names go to the mesh's
//! `extras.targetNames` and to each primitive's.
//!
//! The file is always written as GLB with one buffer: every buffer view
//! still referred to is copied (4-byte aligned) from whichever buffer held
//! it, then the new views follow. Accessors and views only the replaced
//! targets used are dropped; new ones take their indices, so every other
//! accessor and view keeps its index unless more were dropped than added
//! (a replaced target that also had normals, halves made whole), when the
//! last ones move into the remaining gaps and every reference is renumbered
//! (`refs.rs`). Everything else (nodes but for their `weights`, skins,
//! materials, textures, images, animations, unknown extensions and extras)
//! is left as it was, up to those renumbered references.

use super::accessor::Source;
use super::encode::{Builder, TargetEncoding};
use super::new_rest::write_rest;
use super::read::document_of;
use super::refs::{Kind, filling, place, renumber, used};
use super::surface_turn::{WeldedSurface, all_normal_deltas};
use super::{GlbAvatar, GlbError, container};
use crate::arkit::{BLENDSHAPE_COUNT, Blendshape};
use crate::avatar::target_names::{TargetName, resolve_mesh};
use crate::io::atomic_write::write_atomically;
use glam::Vec3;
use serde_json::{Value, json};
use std::path::Path;

/// New world-space displacements for some of ARKit's 52 shapes: for each,
/// one list per part of the avatar (in [`Avatar::parts`] order), one
/// displacement per vertex.
///
/// [`Avatar::parts`]: crate::avatar::Avatar::parts
///
/// It may also carry a new rest: world positions of every vertex, one list
/// per part (the person's face taken, [`crate::avatar::person_face`]),
/// written in place of each primitive's `POSITION`, its normals and
/// tangents turned with the surface (`new_rest.rs`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct NewShapes {
    shapes: Vec<Option<Vec<Vec<Vec3>>>>,
    rest: Option<Vec<Vec<Vec3>>>,
}

impl NewShapes {
    /// No new shapes.
    pub fn new() -> Self {
        NewShapes {
            shapes: vec![None; BLENDSHAPE_COUNT],
            rest: None,
        }
    }

    /// Sets `shape`'s displacements, one list per part.
    pub fn set(&mut self, shape: Blendshape, per_part: Vec<Vec<Vec3>>) {
        if self.shapes.len() < BLENDSHAPE_COUNT {
            self.shapes.resize(BLENDSHAPE_COUNT, None);
        }
        self.shapes[shape.index()] = Some(per_part);
    }

    /// Sets a new rest: world positions, one list per part.
    pub fn set_rest(&mut self, per_part: Vec<Vec<Vec3>>) {
        self.rest = Some(per_part);
    }

    /// The new rest, if given.
    pub fn rest(&self) -> Option<&[Vec<Vec3>]> {
        self.rest.as_deref()
    }

    /// `shape`'s displacements, if given.
    pub fn get(&self, shape: Blendshape) -> Option<&[Vec<Vec3>]> {
        self.shapes.get(shape.index())?.as_deref()
    }
}

/// One target of a mesh as written.
struct Planned {
    /// The old target it keeps (untouched data) or takes the place of.
    from: Option<usize>,
    /// New data, if any.
    shape: Option<Blendshape>,
    name: String,
}

/// Writes `avatar`'s file back to `path` (atomically, as GLB) with
/// `shapes` in place of its ARKit targets.
pub fn write_avatar(avatar: &GlbAvatar, shapes: &NewShapes, path: &Path) -> Result<(), GlbError> {
    let bytes = written_back_glb(avatar, shapes, TargetEncoding::Smallest, path)?;
    write_atomically(path, &bytes).map_err(|source| GlbError::Io {
        file: path.to_path_buf(),
        source,
    })
}

/// The GLB [`write_avatar`] writes, in memory; `file` names it in messages.
pub fn written_back_glb(
    avatar: &GlbAvatar,
    shapes: &NewShapes,
    encoding: TargetEncoding,
    file: &Path,
) -> Result<Vec<u8>, GlbError> {
    let err = |what: String| GlbError::Write {
        file: file.to_path_buf(),
        what,
    };
    check_shapes(avatar, shapes).map_err(err)?;
    let mut doc = avatar.json.clone();
    let old_accessors = doc["accessors"].as_array().map_or(0, Vec::len);
    let old_views = doc["bufferViews"].as_array().map_or(0, Vec::len);
    let mut b = Builder::new();
    let document = document_of(&avatar.json, file)?;
    let source = Source {
        file,
        buffers: &avatar.buffers,
    };
    for m in 0..avatar.avatar.meshes().len() {
        if !avatar.avatar.parts().iter().any(|p| p.mesh == m) {
            continue;
        }
        let plan = plan_mesh(avatar, shapes, m);
        let old_count = avatar.avatar.meshes()[m].target_names.len();
        if plan.len() != old_count && weights_animated(&doc, m) {
            return Err(err(format!(
                "mesh {m}: its morph weights are animated and its target count would change ({old_count} → {})",
                plan.len()
            )));
        }
        let names: Vec<String> = plan.iter().map(|p| p.name.clone()).collect();
        let primitives = doc["meshes"][m]["primitives"]
            .as_array()
            .map_or(0, Vec::len);
        for p in 0..primitives {
            let of_mesh = |k: &usize| avatar.avatar.parts()[*k].mesh == m;
            let own = (0..avatar.avatar.parts().len())
                .filter(of_mesh)
                .find(|&k| avatar.avatar.parts()[k].primitive == p);
            let Some(k) = own else {
                // A primitive sharing an earlier one's vertices (read.rs)
                // shares its new accessors too.
                let sharing = (0..avatar.avatar.parts().len())
                    .filter(of_mesh)
                    .find(|&k| avatar.splits[k].iter().any(|s| s.primitive == p));
                let Some(k) = sharing else {
                    return Err(err(format!("mesh {m} primitive {p}: not read")));
                };
                let first =
                    doc["meshes"][m]["primitives"][avatar.avatar.parts()[k].primitive].clone();
                let prim = &mut doc["meshes"][m]["primitives"][p];
                for key in ["attributes", "targets"] {
                    if !first[key].is_null() {
                        prim[key] = first[key].clone();
                    }
                }
                if !first["targets"].is_null() {
                    set_target_names(prim, &names);
                }
                continue;
            };
            let linear = avatar.placements[k].linear();
            let inverse = linear.inverse();
            let part = &avatar.avatar.parts()[k];
            let primitive = document
                .meshes()
                .nth(m)
                .and_then(|mesh| mesh.primitives().nth(p))
                .ok_or_else(|| err(format!("mesh {m} primitive {p}: not in the file")))?;
            let prim = &mut doc["meshes"][m]["primitives"][p];
            let (rest, normals) = match shapes.rest() {
                Some(rest) => {
                    let normals = write_rest(
                        prim,
                        &primitive,
                        &source,
                        &mut b,
                        old_accessors,
                        avatar.placements[k].world,
                        &part.positions,
                        &rest[k],
                        &part.triangles,
                    )?;
                    (&rest[k][..], normals)
                }
                None => {
                    let normals = match primitive.get(&gltf::Semantic::Normals) {
                        Some(a) => Some(source.vec3(&a, Some(part.positions.len()))?),
                        None => None,
                    };
                    (&part.positions[..], normals)
                }
            };
            // The normal deltas of every target with new data, worked out
            // together (in parallel), where the primitive has normals.
            let mut turns = match &normals {
                Some(normals) => {
                    let surface = WeldedSurface::new(rest, &part.triangles);
                    let moved: Vec<&[Vec3]> = plan
                        .iter()
                        .filter_map(|planned| Some(&shapes.get(planned.shape?)?[k][..]))
                        .collect();
                    all_normal_deltas(&surface, rest, &moved, normals, linear)
                }
                None => Vec::new(),
            }
            .into_iter();
            let old = prim["targets"].as_array().cloned().unwrap_or_default();
            let mut targets = Vec::with_capacity(plan.len());
            for planned in &plan {
                let target = match (planned.shape, planned.from) {
                    (Some(shape), _) => {
                        let world = shapes.get(shape).map(|s| &s[k][..]).unwrap_or(&[]);
                        let local: Vec<Vec3> = world.iter().map(|&d| inverse * d).collect();
                        let a = b.target(&local, &planned.name, encoding);
                        let mut target = json!({ "POSITION": old_accessors + a });
                        if let Some(turn) = turns.next() {
                            target["NORMAL"] = json!(old_accessors + b.target(&turn, "", encoding));
                        }
                        target
                    }
                    (None, Some(t)) => old.get(t).cloned().unwrap_or_else(|| json!({})),
                    (None, None) => json!({}),
                };
                targets.push(target);
            }
            if targets.is_empty() {
                continue;
            }
            prim["targets"] = Value::Array(targets);
            set_target_names(prim, &names);
        }
        let mesh = &mut doc["meshes"][m];
        if !names.is_empty() {
            set_target_names(mesh, &names);
        }
        follow_weights(mesh, &plan);
        let nodes = doc["nodes"].as_array_mut().map(|n| n.iter_mut());
        for node in nodes.into_iter().flatten() {
            if node["mesh"].as_u64() == Some(m as u64) {
                follow_weights(node, &plan);
            }
        }
    }
    assemble(avatar, doc, b, old_accessors, old_views).map_err(err)
}

/// Every new shape fits the avatar's parts and is finite.
fn check_shapes(avatar: &GlbAvatar, shapes: &NewShapes) -> Result<(), String> {
    let parts = avatar.avatar.parts();
    if let Some(rest) = shapes.rest() {
        if rest.len() != parts.len() {
            return Err(format!(
                "new rest: {} parts of data, the avatar has {}",
                rest.len(),
                parts.len()
            ));
        }
        for (k, (p, part)) in rest.iter().zip(parts).enumerate() {
            if p.len() != part.positions.len() || p.iter().any(|v| !v.is_finite()) {
                return Err(format!(
                    "new rest part {k}: not {} finite positions",
                    part.positions.len()
                ));
            }
        }
    }
    for shape in Blendshape::ALL {
        let Some(per_part) = shapes.get(shape) else {
            continue;
        };
        if per_part.len() != parts.len() {
            return Err(format!(
                "{}: {} parts of data, the avatar has {}",
                shape.name(),
                per_part.len(),
                parts.len()
            ));
        }
        for (k, (d, part)) in per_part.iter().zip(parts).enumerate() {
            if d.len() != part.positions.len() || d.iter().any(|v| !v.is_finite()) {
                return Err(format!(
                    "{} part {k}: not {} finite displacements",
                    shape.name(),
                    part.positions.len()
                ));
            }
        }
    }
    Ok(())
}

/// The targets mesh `m` is written with (the module's rules).
fn plan_mesh(avatar: &GlbAvatar, shapes: &NewShapes, m: usize) -> Vec<Planned> {
    let names = &avatar.avatar.meshes()[m].target_names;
    // What each target is taken as: one passed over for another target of
    // its shape is kept as the avatar's own.
    let (parsed, _) = resolve_mesh(m, names);
    let has_whole = |s: Blendshape| parsed.contains(&TargetName::Arkit(s));
    let mut done = [false; BLENDSHAPE_COUNT];
    let mut plan = Vec::new();
    for (t, (name, parsed)) in names.iter().zip(&parsed).enumerate() {
        let keep = |name: &str| Planned {
            from: Some(t),
            shape: None,
            name: name.to_string(),
        };
        let whole = match *parsed {
            TargetName::Arkit(s) => Some(s),
            TargetName::Half(s, _) if !has_whole(s) && shapes.get(s).is_some() => Some(s),
            _ => None,
        };
        match whole {
            Some(s) if done[s.index()] && matches!(parsed, TargetName::Half(..)) => {} // dropped half
            Some(s) if !done[s.index()] => {
                done[s.index()] = true;
                let shape = shapes.get(s).is_some().then_some(s);
                plan.push(Planned {
                    from: Some(t),
                    shape,
                    name: s.name().to_string(),
                });
            }
            _ => plan.push(keep(name)),
        }
    }
    for s in Blendshape::ALL {
        let Some(per_part) = shapes.get(s) else {
            continue;
        };
        let moves = avatar
            .avatar
            .parts()
            .iter()
            .zip(per_part)
            .any(|(part, d)| part.mesh == m && d.iter().any(|v| *v != Vec3::ZERO));
        if !done[s.index()] && !has_half(&parsed, s) && moves {
            plan.push(Planned {
                from: None,
                shape: Some(s),
                name: s.name().to_string(),
            });
        }
    }
    plan
}

fn has_half(parsed: &[TargetName], s: Blendshape) -> bool {
    parsed
        .iter()
        .any(|n| matches!(n, TargetName::Half(h, _) if *h == s))
}

/// Whether an animation drives the morph weights of a node placing mesh
/// `m`.
fn weights_animated(doc: &Value, m: usize) -> bool {
    let channels = doc["animations"].as_array().into_iter().flatten();
    channels
        .flat_map(|a| a["channels"].as_array().into_iter().flatten())
        .filter(|c| c["target"]["path"] == "weights")
        .filter_map(|c| c["target"]["node"].as_u64())
        .any(|n| doc["nodes"][n as usize]["mesh"].as_u64() == Some(m as u64))
}

/// `extras.targetNames` of a mesh or primitive (other extras kept; extras
/// that are not an object are left alone).
fn set_target_names(object: &mut Value, names: &[String]) {
    let Some(object) = object.as_object_mut() else {
        return;
    };
    let extras = object.entry("extras").or_insert_with(|| json!({}));
    if let Some(extras) = extras.as_object_mut() {
        extras.insert("targetNames".into(), json!(names));
    }
}

/// A `weights` array, if present, follows the planned targets.
fn follow_weights(object: &mut Value, plan: &[Planned]) {
    let Some(old) = object["weights"].as_array().cloned() else {
        return;
    };
    let new: Vec<Value> = plan
        .iter()
        .map(|p| {
            p.from
                .and_then(|t| old.get(t).cloned())
                .unwrap_or(json!(0.0))
        })
        .collect();
    object["weights"] = Value::Array(new);
}

/// Drops what the replaced targets alone used, renumbers, lays out the
/// single binary buffer and joins the GLB.
fn assemble(
    avatar: &GlbAvatar,
    mut doc: Value,
    b: Builder,
    old_accessors: usize,
    old_views: usize,
) -> Result<Vec<u8>, String> {
    // New accessors' views follow the old views.
    let mut new_accessors = b.accessors;
    for a in &mut new_accessors {
        for path in [
            &["bufferView"][..],
            &["sparse", "indices", "bufferView"],
            &["sparse", "values", "bufferView"],
        ] {
            if let Some(v) = path.iter().try_fold(&mut *a, |v, k| v.get_mut(*k))
                && let Some(i) = v.as_u64()
            {
                *v = json!(i as usize + old_views);
            }
        }
    }
    let total = old_accessors + new_accessors.len();
    let before = used(&avatar.json, Kind::Accessor, total);
    let mut accessors = doc["accessors"].as_array().cloned().unwrap_or_default();
    accessors.extend(new_accessors);
    let after = used(&doc, Kind::Accessor, total);
    let drop: Vec<bool> = (0..total).map(|i| before[i] && !after[i]).collect();
    let map = filling(&drop, old_accessors);
    renumber(&mut doc, Kind::Accessor, &map);
    doc["accessors"] = Value::Array(place(accessors, &map));

    // Views: the old ones with their bytes, then the new ones.
    let views_total = old_views + b.views.len();
    let views_before = used(&avatar.json, Kind::View, views_total);
    let views_after = used(&doc, Kind::View, views_total);
    let drop: Vec<bool> = (0..views_total)
        .map(|i| {
            let was_used = views_before[i] || avatar.decoded_views.contains(&i);
            i < old_views && was_used && !views_after[i]
        })
        .collect();
    let mut views: Vec<(Value, &[u8])> = Vec::with_capacity(views_total);
    let old = doc["bufferViews"].as_array().cloned().unwrap_or_default();
    for (i, view) in old.into_iter().enumerate() {
        let buffer = view["buffer"].as_u64().unwrap_or(0) as usize;
        let offset = view["byteOffset"].as_u64().unwrap_or(0) as usize;
        let length = view["byteLength"].as_u64().unwrap_or(0) as usize;
        let bytes = match avatar.buffers.get(buffer) {
            _ if drop[i] => &[][..],
            Some(d) => d
                .get(offset..offset.saturating_add(length))
                .ok_or_else(|| format!("buffer view {i} lies outside buffer {buffer}"))?,
            None => return Err(format!("buffer view {i}: no buffer {buffer}")),
        };
        views.push((view, bytes));
    }
    for view in b.views {
        let offset = view["byteOffset"].as_u64().unwrap_or(0) as usize;
        let length = view["byteLength"].as_u64().unwrap_or(0) as usize;
        views.push((view, &b.bin[offset..offset + length]));
    }
    let map = filling(&drop, old_views);
    renumber(&mut doc, Kind::View, &map);
    let mut bin = Vec::new();
    let views: Vec<Value> = place(views, &map)
        .into_iter()
        .map(|(view, bytes)| relocate(view, &mut bin, bytes))
        .collect();
    if !views.is_empty() || doc.get("bufferViews").is_some() {
        doc["bufferViews"] = Value::Array(views);
    }
    let mut buffer = doc["buffers"][0].as_object().cloned().unwrap_or_default();
    buffer.remove("uri");
    buffer.insert("byteLength".into(), json!(bin.len()));
    if bin.is_empty() {
        if let Some(o) = doc.as_object_mut() {
            o.remove("buffers");
        }
    } else {
        doc["buffers"] = json!([buffer]);
    }
    let text = serde_json::to_vec(&doc).map_err(|e| e.to_string())?;
    Ok(container::join(&text, &bin))
}

/// Copies a view's bytes to the end of `bin` (4-byte aligned) and points
/// the view there, in buffer 0.
fn relocate(mut view: Value, bin: &mut Vec<u8>, bytes: &[u8]) -> Value {
    bin.resize(bin.len().next_multiple_of(4), 0);
    view["buffer"] = json!(0);
    view["byteOffset"] = json!(bin.len());
    bin.extend_from_slice(bytes);
    view
}
