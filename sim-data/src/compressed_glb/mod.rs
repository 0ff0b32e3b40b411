//! Avatars compressed the way VRoid and web-optimised exporters write
//! them (`EXT_meshopt_compression` over `KHR_mesh_quantization`), made
//! from a plain GLB for testing the reader.
//!
//! | file | what |
//! |---|---|
//! | `mod.rs` | [`meshopt_compressed`]: which accessors are rewritten, how the file is laid out |
//! | [`quantize`] | positions, normals, target displacements as integers; the dequantizing node transform |
//! | [`streams`] | meshoptimizer's codecs, and the views in the extension's layout |
//! | [`accessors`] | reading the plain input's accessors (dense and sparse) |
//! | [`draco`] | [`draco::draco_compressed`]: every primitive a Draco mesh (`KHR_draco_mesh_compression`), lossless |
//! | `tests.rs` | a small avatar through the encoder; the node transforms |
//!
//! Only what a mesh primitive uses is rewritten: its `POSITION` (normalized
//! SHORT), `NORMAL` (normalized BYTE, octahedral filter), other attributes
//! as they were but compressed, its indices (`TRIANGLES` mode), and its
//! targets' `POSITION` (normalized SHORT, the mesh's scale) and `NORMAL`
//! (normalized BYTE). Every other view (images, inverse bind matrices,
//! animations) is copied uncompressed. Both extensions are added to
//! `extensionsUsed` and `extensionsRequired`. Skinned meshes are refused
//! (their dequantization would belong in the inverse bind matrices, which
//! this test encoder does not rewrite).

pub mod accessors;
pub mod draco;
pub mod quantize;
pub mod streams;
#[cfg(test)]
mod tests;

use quantize::Dequantization;
use serde_json::{Value, json};
use std::collections::{HashMap, HashSet};
use streams::Streams;

/// `glb` with its meshes' geometry quantized (`KHR_mesh_quantization`)
/// and compressed (`EXT_meshopt_compression`), as the module describes.
pub fn meshopt_compressed(glb: &[u8]) -> Result<Vec<u8>, String> {
    let read =
        likeness::avatar::glb::read_avatar_bytes(glb, "input.glb").map_err(|e| e.to_string())?;
    let buffers = read.buffers();
    let orig = read.json();
    let mut doc = orig.clone();
    let old_views = doc["bufferViews"].as_array().cloned().unwrap_or_default();
    let mut out = Streams::default();
    let mut rewritten = HashSet::new();
    let meshes = doc["meshes"].as_array().map_or(0, Vec::len);
    for m in 0..meshes {
        let d = dequantization(orig, buffers, m)?;
        let placed_by: Vec<usize> = nodes_placing(&doc, m);
        if placed_by
            .iter()
            .any(|&n| doc["nodes"][n].get("skin").is_some())
        {
            return Err(format!(
                "mesh {m} is skinned: not handled by the test encoder"
            ));
        }
        let primitives = doc["meshes"][m]["primitives"]
            .as_array()
            .map_or(0, Vec::len);
        // Vertex data shared by primitives of the mesh stays shared.
        let mut this_mesh = HashMap::new();
        for p in 0..primitives {
            let source = (orig, buffers);
            let written = (&mut rewritten, &mut this_mesh);
            rewrite_primitive(&mut doc, source, (m, p), d, &mut out, written)?;
        }
        for n in placed_by {
            quantize::fold_into(&mut doc["nodes"][n], d);
            let children: Vec<usize> = doc["nodes"][n]["children"]
                .as_array()
                .map(|c| {
                    c.iter()
                        .filter_map(|c| c.as_u64())
                        .map(|c| c as usize)
                        .collect()
                })
                .unwrap_or_default();
            for c in children {
                quantize::unfold_from_child(&mut doc["nodes"][c], d);
            }
        }
    }
    copy_other_views(&mut doc, buffers, &old_views, &rewritten, &mut out)?;
    doc["bufferViews"] = Value::Array(std::mem::take(&mut out.views));
    doc["buffers"] = json!([
        { "byteLength": out.bin.len().next_multiple_of(4) },
        { "byteLength": out.fallback.max(4), "extensions": { "EXT_meshopt_compression": { "fallback": true } } }
    ]);
    for key in ["extensionsUsed", "extensionsRequired"] {
        let list = doc[key].as_array().cloned().unwrap_or_default();
        let mut list: Vec<Value> = list;
        for e in ["KHR_mesh_quantization", "EXT_meshopt_compression"] {
            if !list.iter().any(|x| x == e) {
                list.push(json!(e));
            }
        }
        doc[key] = Value::Array(list);
    }
    let text = serde_json::to_vec(&doc).map_err(|e| e.to_string())?;
    Ok(join(&text, &out.bin))
}

/// Nodes whose `mesh` is `m`.
fn nodes_placing(doc: &Value, m: usize) -> Vec<usize> {
    let nodes = doc["nodes"].as_array().map_or(&[][..], Vec::as_slice);
    (0..nodes.len())
        .filter(|&n| nodes[n]["mesh"].as_u64() == Some(m as u64))
        .collect()
}

/// The dequantization fitting every position and displacement of mesh `m`.
fn dequantization(doc: &Value, buffers: &[Vec<u8>], m: usize) -> Result<Dequantization, String> {
    let (mut all, mut moves) = (Vec::new(), Vec::new());
    for prim in doc["meshes"][m]["primitives"]
        .as_array()
        .into_iter()
        .flatten()
    {
        if let Some(a) = prim["attributes"]["POSITION"].as_u64() {
            all.extend(accessors::vec3(doc, buffers, a as usize)?);
        }
        for target in prim["targets"].as_array().into_iter().flatten() {
            if let Some(a) = target["POSITION"].as_u64() {
                moves.extend(accessors::vec3(doc, buffers, a as usize)?);
            }
        }
    }
    Ok(Dequantization::fitting(all.iter(), moves.iter()))
}

/// Rewrites accessor `index` in place to point at `view`; if another
/// primitive already rewrote it, a new accessor is appended instead. The
/// index used.
fn set_accessor(
    doc: &mut Value,
    rewritten: &mut HashSet<usize>,
    index: usize,
    new: Value,
) -> usize {
    let list = doc["accessors"].as_array_mut().expect("accessors");
    if rewritten.insert(index) {
        let name = list[index].get("name").cloned();
        list[index] = new;
        if let Some(name) = name {
            list[index]["name"] = name;
        }
        index
    } else {
        list.push(new);
        rewritten.insert(list.len() - 1);
        list.len() - 1
    }
}

/// Rewrites primitive `p` of mesh `m` in `doc`, reading its data from the
/// untouched input `(orig, buffers)`. A vertex attribute or target accessor
/// an earlier primitive of the mesh shares is not encoded again: it takes
/// the accessor written for that one (`this_mesh`: old index to new).
fn rewrite_primitive(
    doc: &mut Value,
    (orig, buffers): (&Value, &[Vec<u8>]),
    (m, p): (usize, usize),
    d: Dequantization,
    out: &mut Streams,
    (rewritten, this_mesh): (&mut HashSet<usize>, &mut HashMap<usize, usize>),
) -> Result<(), String> {
    let prim = orig["meshes"][m]["primitives"][p].clone();
    let mut prim_new = prim.clone();
    let mut count = 0;
    let attributes = prim["attributes"].as_object().cloned().unwrap_or_default();
    for (semantic, a) in &attributes {
        let a = a.as_u64().ok_or("attribute not an index")? as usize;
        count = count.max(orig["accessors"][a]["count"].as_u64().unwrap_or(0) as usize);
        if let Some(&index) = this_mesh.get(&a) {
            prim_new["attributes"][semantic] = json!(index);
            continue;
        }
        let old = orig["accessors"][a].clone();
        let new = match semantic.as_str() {
            "POSITION" => {
                let v = accessors::vec3(orig, buffers, a)?;
                count = v.len();
                let (bytes, min, max) = quantize::positions(&v, d);
                let view = out.vertices(&bytes, 8, "NONE")?;
                json!({ "bufferView": view, "componentType": 5122, "normalized": true,
                        "count": v.len(), "type": "VEC3", "min": min, "max": max })
            }
            "NORMAL" => {
                let v = accessors::vec3(orig, buffers, a)?;
                let view = out.vertices(&quantize::normals(&v), 4, "OCTAHEDRAL")?;
                json!({ "bufferView": view, "componentType": 5120, "normalized": true,
                        "count": v.len(), "type": "VEC3" })
            }
            _ => {
                let (bytes, size) = accessors::raw(orig, buffers, a)?;
                let stride = size.next_multiple_of(4);
                let padded: Vec<u8> = bytes
                    .chunks_exact(size)
                    .flat_map(|c| {
                        let mut e = c.to_vec();
                        e.resize(stride, 0);
                        e
                    })
                    .collect();
                let view = out.vertices(&padded, stride, "NONE")?;
                let mut new = old.clone();
                if let Some(o) = new.as_object_mut() {
                    o.remove("sparse");
                    o.remove("byteOffset");
                }
                new["bufferView"] = json!(view);
                new
            }
        };
        let index = set_accessor(doc, rewritten, a, new);
        this_mesh.insert(a, index);
        prim_new["attributes"][semantic] = json!(index);
    }
    if let Some(a) = prim["indices"].as_u64() {
        let indices = accessors::indices(orig, buffers, a as usize)?;
        let (view, component) = out.triangles(&indices, count)?;
        let new = json!({ "bufferView": view, "componentType": component,
                          "count": indices.len(), "type": "SCALAR" });
        prim_new["indices"] = json!(set_accessor(doc, rewritten, a as usize, new));
    }
    for (t, target) in prim["targets"].as_array().into_iter().flatten().enumerate() {
        for (semantic, a) in target.as_object().into_iter().flatten() {
            let a = a.as_u64().ok_or("target attribute not an index")? as usize;
            if let Some(&index) = this_mesh.get(&a) {
                prim_new["targets"][t][semantic] = json!(index);
                continue;
            }
            let v = accessors::vec3(orig, buffers, a)?;
            let new = match semantic.as_str() {
                "POSITION" => {
                    let (bytes, min, max) = quantize::displacements(&v, d)
                        .map_err(|e| format!("mesh {m} primitive {p} target {t}: {e}"))?;
                    let view = out.vertices(&bytes, 8, "NONE")?;
                    json!({ "bufferView": view, "componentType": 5122, "normalized": true,
                            "count": v.len(), "type": "VEC3", "min": min, "max": max })
                }
                "NORMAL" | "TANGENT" => {
                    let view = out.vertices(&quantize::normal_displacements(&v), 4, "NONE")?;
                    json!({ "bufferView": view, "componentType": 5120, "normalized": true,
                            "count": v.len(), "type": "VEC3" })
                }
                other => return Err(format!("target attribute {other} not handled")),
            };
            let index = set_accessor(doc, rewritten, a, new);
            this_mesh.insert(a, index);
            prim_new["targets"][t][semantic] = json!(index);
        }
    }
    doc["meshes"][m]["primitives"][p] = prim_new;
    Ok(())
}

/// Copies every old view still referred to (by an accessor not rewritten,
/// or an image) uncompressed into buffer 0, and points the reference there.
fn copy_other_views(
    doc: &mut Value,
    buffers: &[Vec<u8>],
    old_views: &[Value],
    rewritten: &HashSet<usize>,
    out: &mut Streams,
) -> Result<(), String> {
    let mut moved: HashMap<usize, usize> = HashMap::new();
    let mut map = |old: u64, out: &mut Streams| -> Result<usize, String> {
        let old = old as usize;
        if let Some(&new) = moved.get(&old) {
            return Ok(new);
        }
        let v = old_views
            .get(old)
            .ok_or_else(|| format!("no buffer view {old}"))?;
        let b = v["buffer"].as_u64().unwrap_or(0) as usize;
        let start = v["byteOffset"].as_u64().unwrap_or(0) as usize;
        let len = v["byteLength"].as_u64().unwrap_or(0) as usize;
        let bytes = buffers
            .get(b)
            .and_then(|d| d.get(start..start + len))
            .ok_or_else(|| format!("buffer view {old} outside its buffer"))?;
        let new = out.plain(v.clone(), bytes);
        moved.insert(old, new);
        Ok(new)
    };
    let accessors = doc["accessors"].as_array().map_or(0, Vec::len);
    for a in (0..accessors).filter(|a| !rewritten.contains(a)) {
        let acc = &mut doc["accessors"][a];
        for path in [
            &["bufferView"][..],
            &["sparse", "indices", "bufferView"],
            &["sparse", "values", "bufferView"],
        ] {
            if let Some(v) = path.iter().try_fold(&mut *acc, |v, k| v.get_mut(*k))
                && let Some(i) = v.as_u64()
            {
                *v = json!(map(i, out)?);
            }
        }
    }
    let images = doc.get_mut("images").and_then(Value::as_array_mut);
    for image in images.into_iter().flatten() {
        if let Some(i) = image["bufferView"].as_u64() {
            image["bufferView"] = json!(map(i, out)?);
        }
    }
    Ok(())
}

/// A GLB of `json` and `bin` (glTF 2.0 spec, "GLB File Format
/// Specification": JSON padded with spaces, BIN with zeros).
fn join(json: &[u8], bin: &[u8]) -> Vec<u8> {
    let json_len = json.len().next_multiple_of(4);
    let bin_len = bin.len().next_multiple_of(4);
    let total = 12 + 8 + json_len + 8 + bin_len;
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json_len as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(json);
    out.resize(20 + json_len, b' ');
    out.extend_from_slice(&(bin_len as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(bin);
    out.resize(total, 0);
    out
}
