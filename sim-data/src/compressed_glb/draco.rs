//! Avatars compressed as Draco exporters write them
//! (`KHR_draco_mesh_compression`), made from a plain GLB for testing the
//! reader: each mesh primitive's vertex attributes and indices become one
//! Draco mesh (`draco-core`'s encoder) in a buffer view of its own, and
//! the primitive's accessors lose their buffer views.
//!
//! The encoding is sequential and unquantized: sequential keeps the
//! vertices in their order, which the uncompressed morph targets need (as
//! Blender's exporter encodes morphed primitives), and without
//! quantization the decoded floats are the input's to the bit, so an
//! avatar read from the compressed file is the plain one's exactly.
//! Primitives that share their vertices each carry the whole vertex set
//! (Draco meshes do not share). The plain data the compressed accessors
//! had is dropped from the binary chunk (`drop_unused_views`).

use super::accessors::raw;
use draco_core::draco_types::DataType;
use draco_core::geometry_attribute::{GeometryAttributeType, PointAttribute};
use draco_core::{EncoderBuffer, EncoderOptions, Mesh, MeshEncoder};
use serde_json::{Value, json};

/// The extension's name.
pub const EXTENSION: &str = "KHR_draco_mesh_compression";

/// Draco's sequential connectivity method (`MESH_SEQUENTIAL_ENCODING`).
const SEQUENTIAL: i32 = 0;

/// Draco's data type for a glTF component type.
fn data_type(component_type: u64) -> Result<DataType, String> {
    Ok(match component_type {
        5120 => DataType::Int8,
        5121 => DataType::Uint8,
        5122 => DataType::Int16,
        5123 => DataType::Uint16,
        5125 => DataType::Uint32,
        5126 => DataType::Float32,
        other => return Err(format!("componentType {other}")),
    })
}

/// Draco's kind of attribute for a glTF attribute name.
fn attribute_type(name: &str) -> GeometryAttributeType {
    match name {
        "POSITION" => GeometryAttributeType::Position,
        "NORMAL" => GeometryAttributeType::Normal,
        n if n.starts_with("TEXCOORD") => GeometryAttributeType::TexCoord,
        n if n.starts_with("COLOR") => GeometryAttributeType::Color,
        _ => GeometryAttributeType::Generic,
    }
}

/// The Draco mesh of primitive `primitive` (JSON) over `buffers`, and the
/// unique id of each of its attributes by glTF name.
fn draco_mesh(
    doc: &Value,
    buffers: &[Vec<u8>],
    primitive: &Value,
) -> Result<(Mesh, Vec<(String, u32)>), String> {
    let mut mesh = Mesh::new();
    let mut ids = Vec::new();
    let attributes = primitive["attributes"].as_object().ok_or("no attributes")?;
    for (name, index) in attributes {
        let index = index.as_u64().ok_or("an attribute without an accessor")? as usize;
        let a = &doc["accessors"][index];
        let kind = data_type(a["componentType"].as_u64().unwrap_or(0))?;
        let (bytes, size) = raw(doc, buffers, index)?;
        let components = (size / kind.byte_length()) as u8;
        let count = bytes.len() / size;
        let mut attribute = PointAttribute::new();
        let normalized = a["normalized"].as_bool().unwrap_or(false);
        attribute.init(attribute_type(name), components, kind, normalized, count);
        attribute.buffer_mut().write(0, &bytes);
        ids.push((name.clone(), mesh.add_attribute(attribute) as u32));
    }
    let indices = primitive["indices"].as_u64().ok_or("no indices")? as usize;
    let triangles = super::accessors::indices(doc, buffers, indices)?;
    mesh.set_num_faces(triangles.len() / 3);
    mesh.set_faces_from_flat_indices(&triangles);
    Ok((mesh, ids))
}

/// `glb` with every mesh primitive Draco-compressed, as the module
/// describes.
pub fn draco_compressed(glb: &[u8]) -> Result<Vec<u8>, String> {
    let mut edited = crate::glb_edit::Glb::parse(glb);
    let doc = edited.json.clone();
    let buffers = vec![edited.bin.clone()];
    let meshes = doc["meshes"].as_array().map_or(0, Vec::len);
    for m in 0..meshes {
        let primitives = doc["meshes"][m]["primitives"]
            .as_array()
            .map_or(0, Vec::len);
        for p in 0..primitives {
            let primitive = &doc["meshes"][m]["primitives"][p];
            let (mesh, ids) = draco_mesh(&doc, &buffers, primitive)?;
            let mut encoder = MeshEncoder::new();
            encoder.set_mesh(mesh);
            let mut options = EncoderOptions::new();
            options.set_encoding_method(SEQUENTIAL);
            let mut out = EncoderBuffer::new();
            encoder
                .encode(&options, &mut out)
                .map_err(|e| format!("mesh {m} primitive {p}: {e}"))?;
            let view = edited.push_view(out.data());
            let attributes: serde_json::Map<String, Value> =
                ids.into_iter().map(|(n, id)| (n, json!(id))).collect();
            let target = &mut edited.json["meshes"][m]["primitives"][p];
            target["extensions"] =
                json!({ EXTENSION: { "bufferView": view, "attributes": attributes } });
            let compressed = target["attributes"]
                .as_object()
                .cloned()
                .unwrap_or_default();
            let indices = target["indices"].clone();
            for index in compressed.values().chain([&indices]) {
                if let Some(a) = index.as_u64() {
                    let accessor = &mut edited.json["accessors"][a as usize];
                    accessor.as_object_mut().map(|o| o.remove("bufferView"));
                    accessor.as_object_mut().map(|o| o.remove("byteOffset"));
                }
            }
        }
    }
    drop_unused_views(&mut edited);
    for key in ["extensionsUsed", "extensionsRequired"] {
        let list = edited.json[key].as_array().cloned().unwrap_or_default();
        let mut list: Vec<Value> = list.into_iter().filter(|e| e != EXTENSION).collect();
        list.push(json!(EXTENSION));
        edited.json[key] = json!(list);
    }
    Ok(edited.to_bytes())
}

/// Where a core-written GLB and this encoder refer to buffer views.
const VIEW_REFERENCES: [&str; 3] = ["accessors", "images", "meshes"];

/// Every buffer view index `json` refers to (`VIEW_REFERENCES`: accessors'
/// `bufferView` and their sparse parts', images', the Draco extension's),
/// each through `f`.
fn each_view_reference(json: &mut Value, f: &mut dyn FnMut(&mut Value)) {
    for key in VIEW_REFERENCES {
        let list = json.get_mut(key).and_then(Value::as_array_mut);
        for item in list.into_iter().flatten() {
            if key == "meshes" {
                let primitives = item.get_mut("primitives").and_then(Value::as_array_mut);
                for p in primitives.into_iter().flatten() {
                    if let Some(e) = p.pointer_mut("/extensions/KHR_draco_mesh_compression") {
                        f(&mut e["bufferView"]);
                    }
                }
            } else {
                for at in [
                    "/bufferView",
                    "/sparse/indices/bufferView",
                    "/sparse/values/bufferView",
                ] {
                    if let Some(view) = item.pointer_mut(at) {
                        f(view);
                    }
                }
            }
        }
    }
}

/// Drops the buffer views nothing refers to any more, and their bytes,
/// renumbering the rest.
fn drop_unused_views(glb: &mut crate::glb_edit::Glb) {
    let views = glb.json["bufferViews"]
        .as_array()
        .cloned()
        .unwrap_or_default();
    let mut used = vec![false; views.len()];
    each_view_reference(&mut glb.json, &mut |v| {
        if let Some(i) = v.as_u64() {
            used[i as usize] = true;
        }
    });
    let mut new_index = vec![0; views.len()];
    let (mut kept, mut bin) = (Vec::new(), Vec::new());
    for (i, mut view) in views.into_iter().enumerate() {
        if !used[i] {
            continue;
        }
        let start = view["byteOffset"].as_u64().unwrap_or(0) as usize;
        let length = view["byteLength"].as_u64().unwrap_or(0) as usize;
        bin.resize(bin.len().next_multiple_of(4), 0);
        view["byteOffset"] = json!(bin.len());
        bin.extend_from_slice(&glb.bin[start..start + length]);
        new_index[i] = kept.len();
        kept.push(view);
    }
    each_view_reference(&mut glb.json, &mut |v| {
        if let Some(i) = v.as_u64() {
            *v = json!(new_index[i as usize]);
        }
    });
    glb.json["bufferViews"] = json!(kept);
    glb.bin = bin;
}
