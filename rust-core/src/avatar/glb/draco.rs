//! Primitives compressed with `KHR_draco_mesh_compression`
//! (<https://github.com/KhronosGroup/glTF/blob/main/extensions/2.0/Khronos/KHR_draco_mesh_compression/README.md>),
//! decoded once, before any accessor is read.
//!
//! Such a primitive carries `extensions.KHR_draco_mesh_compression
//! {bufferView, attributes}`: the view holds one Draco mesh, and
//! `attributes` maps each glTF attribute name (`POSITION`, `NORMAL`, …) to
//! the unique id of its Draco attribute. The primitive's own accessors
//! (their buffer views absent or ignored) describe the decoded data: its
//! count, component type and type; the indices are the mesh's faces.
//! Decoding (the `draco-core` crate, a Rust port of Google's decoder,
//! Apache-2.0) gives each of those accessors a buffer view of plain data
//! in a buffer of the primitive's own (appended to the file's buffers,
//! `byteLength` only), the indices as 32-bit integers, and the extension
//! leaves the primitive, `extensionsUsed` and `extensionsRequired`: the
//! file written back is plain glTF 2.0.
//!
//! Morph targets are not compressed by the extension: they apply to the
//! decoded vertices in their order, which exporters keep by encoding a
//! morphed primitive sequentially (Blender's glTF exporter does). A
//! decoded vertex count that is not the accessors' is refused, as is a
//! Draco attribute the map names but the mesh lacks, or one with fewer
//! components than its accessor. Decoded bytes count against the same
//! budget as meshopt's ([`super::meshopt::MAX_DECODED_BYTES`]).

use super::GlbError;
use super::meshopt::{MAX_DECODED_BYTES, forget_extension};
use super::refs::{self, Kind};
use draco_core::data_buffer::DataBuffer;
use draco_core::draco_types::DataType;
use draco_core::geometry_indices::{FaceIndex, PointIndex};
use draco_core::{DecoderBuffer, Mesh, MeshDecoder};
use serde_json::{Value, json};
use std::path::Path;

/// The extension's name.
pub(crate) const EXTENSION: &str = "KHR_draco_mesh_compression";

/// glTF's component types (spec, "Accessor Data Types").
const FLOAT: u64 = 5126;
const UNSIGNED_INT: u64 = 5125;

/// Buffer view targets (spec, "Buffer Views"): vertex attributes, indices.
const ARRAY_BUFFER: u64 = 34962;
const ELEMENT_ARRAY_BUFFER: u64 = 34963;

/// Whether any primitive of `json` is compressed.
pub(crate) fn used(json: &Value) -> bool {
    primitives(json).next().is_some()
}

/// `(mesh, primitive)` of every compressed primitive.
fn primitives(json: &Value) -> impl Iterator<Item = (usize, usize)> + '_ {
    let meshes = json["meshes"].as_array().into_iter().flatten().enumerate();
    meshes.flat_map(|(m, mesh)| {
        let list = mesh["primitives"]
            .as_array()
            .into_iter()
            .flatten()
            .enumerate();
        list.filter(|(_, p)| !p["extensions"][EXTENSION].is_null())
            .map(move |(p, _)| (m, p))
    })
}

/// Decodes every compressed primitive of `json` (module docs), appending
/// one buffer per primitive to `buffers`; the buffer views that held the
/// streams and that nothing refers to any more, for the writer to leave
/// out.
pub(crate) fn decode_primitives(
    json: &mut Value,
    buffers: &mut Vec<Vec<u8>>,
    file: &Path,
) -> Result<Vec<usize>, GlbError> {
    let mut budget = MAX_DECODED_BYTES;
    let list: Vec<(usize, usize)> = primitives(json).collect();
    let mut streams = Vec::new();
    // An accessor two primitives share (a surface in several materials)
    // is given its data once.
    let mut done = std::collections::HashSet::new();
    for (m, p) in list {
        let ext = json["meshes"][m]["primitives"][p]["extensions"][EXTENSION].clone();
        let view = ext["bufferView"].as_u64().unwrap_or(u64::MAX) as usize;
        let error = |what: String| GlbError::Compressed {
            file: file.to_path_buf(),
            view,
            what: format!("meshes[{m}].primitives[{p}] ({EXTENSION}): {what}"),
        };
        let mesh = decode_view(json, buffers, view).map_err(error)?;
        streams.push(view);
        let decoded = plain_data(json, (m, p), &ext, &mesh, &mut budget).map_err(error)?;
        let buffer = buffers.len();
        let mut bytes = Vec::new();
        for plain in decoded {
            if !done.insert(plain.accessor) {
                continue;
            }
            bytes.resize(bytes.len().next_multiple_of(4), 0);
            let views = json["bufferViews"].as_array_mut();
            let views = views.ok_or_else(|| error("the file has no bufferViews".into()))?;
            views.push(json!({
                "buffer": buffer,
                "byteOffset": bytes.len(),
                "byteLength": plain.bytes.len(),
                "target": plain.target,
            }));
            let new_view = views.len() - 1;
            let a = &mut json["accessors"][plain.accessor];
            a["bufferView"] = json!(new_view);
            a["componentType"] = json!(plain.component_type);
            if let Some(o) = a.as_object_mut() {
                o.remove("byteOffset");
            }
            bytes.extend(plain.bytes);
        }
        if let Some(list) = json["buffers"].as_array_mut() {
            list.push(json!({ "byteLength": bytes.len() }));
        }
        buffers.push(bytes);
        let primitive = &mut json["meshes"][m]["primitives"][p];
        if let Some(exts) = primitive["extensions"].as_object_mut() {
            exts.remove(EXTENSION);
            if exts.is_empty() {
                primitive.as_object_mut().map(|o| o.remove("extensions"));
            }
        }
    }
    forget_extension(json, EXTENSION);
    let views = json["bufferViews"].as_array().map_or(0, Vec::len);
    let still = refs::used(json, Kind::View, views);
    streams.sort_unstable();
    streams.dedup();
    streams.retain(|&v| !still.get(v).copied().unwrap_or(true));
    Ok(streams)
}

/// The Draco mesh in buffer view `view`.
fn decode_view(json: &Value, buffers: &[Vec<u8>], view: usize) -> Result<Mesh, String> {
    let v = &json["bufferViews"][view];
    let field = |k: &str| v[k].as_u64().map(|x| x as usize);
    let (Some(buffer), Some(length)) = (field("buffer"), field("byteLength")) else {
        return Err(format!(
            "bufferView {view} does not exist or lacks buffer or byteLength"
        ));
    };
    let offset = field("byteOffset").unwrap_or(0);
    let bytes = (buffers.get(buffer))
        .and_then(|b| b.get(offset..offset.checked_add(length)?))
        .ok_or_else(|| format!("bufferView {view} lies outside buffer {buffer}"))?;
    // The decoder checks its stream, but it is not ours: should it panic
    // on a stream it did not foresee, that is this file's error, not a
    // crash.
    let decoded = std::panic::catch_unwind(|| {
        let mut mesh = Mesh::new();
        MeshDecoder::new()
            .decode(&mut DecoderBuffer::new(bytes), &mut mesh)
            .map(|()| mesh)
    });
    match decoded {
        Ok(Ok(mesh)) => Ok(mesh),
        Ok(Err(e)) => Err(format!("Draco cannot decode it: {e}")),
        Err(_) => Err("Draco's decoder failed on it".to_string()),
    }
}

/// Decoded data for one accessor.
struct Plain {
    accessor: usize,
    /// Little-endian, as `component_type`.
    bytes: Vec<u8>,
    component_type: u64,
    /// The buffer view's target (vertex attributes or indices).
    target: u64,
}

/// Each accessor of primitive `(m, p)` that `ext` maps to a Draco
/// attribute, and its indices, decoded.
fn plain_data(
    json: &Value,
    (m, p): (usize, usize),
    ext: &Value,
    mesh: &Mesh,
    budget: &mut u64,
) -> Result<Vec<Plain>, String> {
    let primitive = &json["meshes"][m]["primitives"][p];
    let mut spend = |bytes: usize| {
        *budget = budget.checked_sub(bytes as u64).ok_or_else(|| {
            format!("decodes to more than {MAX_DECODED_BYTES} bytes in the whole file")
        })?;
        Ok::<(), String>(())
    };
    let mut out = Vec::new();
    let map = ext["attributes"].as_object().ok_or("no attributes map")?;
    for (name, id) in map {
        let accessor = primitive["attributes"][name]
            .as_u64()
            .ok_or_else(|| format!("attribute {name} is compressed but has no accessor"))?
            as usize;
        let a = accessor_at(json, accessor, name)?;
        let count = a["count"].as_u64().unwrap_or(0) as usize;
        if count != mesh.num_points() {
            return Err(format!(
                "accessor {accessor} ({name}) has count {count}, the Draco mesh {} vertices",
                mesh.num_points()
            ));
        }
        let components = components(a["type"].as_str().unwrap_or_default())
            .ok_or_else(|| format!("accessor {accessor} ({name}) has no known type"))?;
        let component_type = a["componentType"].as_u64().unwrap_or(FLOAT);
        let size = component_size(component_type).ok_or_else(|| {
            format!("accessor {accessor} ({name}): component type {component_type}")
        })?;
        let attribute = (id
            .as_u64()
            .and_then(|id| mesh.attribute_by_unique_id(id as u32)))
        .ok_or_else(|| format!("{name}: the Draco mesh has no attribute {id}"))?;
        if (attribute.num_components() as usize) < components {
            return Err(format!(
                "{name}: the Draco attribute has {} components, accessor {accessor} {components}",
                attribute.num_components()
            ));
        }
        spend(count * components * size)?;
        let kind = attribute.data_type();
        let width = kind.byte_length();
        let stride = attribute.byte_stride().max(0) as usize;
        let mut data = Vec::with_capacity(count * components * size);
        for point in 0..count {
            let value = attribute.mapped_index(PointIndex(point as u32)).0 as usize;
            for c in 0..components {
                // An attribute owns its buffer: values from byte 0.
                let at = value * stride + c * width;
                let x = component(attribute.buffer(), at, kind)
                    .ok_or_else(|| format!("{name}: vertex {point} lies outside its data"))?;
                push_component(&mut data, x, component_type);
            }
        }
        out.push(Plain {
            accessor,
            bytes: data,
            component_type,
            target: ARRAY_BUFFER,
        });
    }
    if let Some(indices) = primitive["indices"].as_u64() {
        let faces = mesh.num_faces();
        spend(faces * 12)?;
        let data: Vec<u8> = (0..faces)
            .flat_map(|f| mesh.face(FaceIndex(f as u32)))
            .flat_map(|v| v.0.to_le_bytes())
            .collect();
        let declared = accessor_at(json, indices as usize, "indices")?["count"].as_u64();
        if declared != Some(3 * faces as u64) {
            return Err(format!(
                "accessor {indices} (indices) has count {declared:?}, the Draco mesh {} triangles",
                faces
            ));
        }
        out.push(Plain {
            accessor: indices as usize,
            bytes: data,
            component_type: UNSIGNED_INT,
            target: ELEMENT_ARRAY_BUFFER,
        });
    }
    Ok(out)
}

/// Accessor `index` (an object in `accessors`), which `what` refers to.
fn accessor_at<'a>(json: &'a Value, index: usize, what: &str) -> Result<&'a Value, String> {
    let a = &json["accessors"][index];
    match a.is_object() {
        true => Ok(a),
        false => Err(format!(
            "{what} refers to accessor {index}, which does not exist"
        )),
    }
}

/// Components of an accessor type.
fn components(kind: &str) -> Option<usize> {
    Some(match kind {
        "SCALAR" => 1,
        "VEC2" => 2,
        "VEC3" => 3,
        "VEC4" | "MAT2" => 4,
        "MAT3" => 9,
        "MAT4" => 16,
        _ => return None,
    })
}

/// Bytes of a component type.
fn component_size(component_type: u64) -> Option<usize> {
    Some(match component_type {
        5120 | 5121 => 1,
        5122 | 5123 => 2,
        5125 | 5126 => 4,
        _ => return None,
    })
}

/// One Draco component at byte `at` of `buffer`, as a number.
fn component(buffer: &DataBuffer, at: usize, kind: DataType) -> Option<f64> {
    let mut b = [0u8; 8];
    let width = kind.byte_length();
    if width == 0 || !buffer.try_read(at, &mut b[..width]) {
        return None;
    }
    Some(match kind {
        DataType::Int8 => i8::from_le_bytes([b[0]]) as f64,
        DataType::Uint8 | DataType::Bool => b[0] as f64,
        DataType::Int16 => i16::from_le_bytes([b[0], b[1]]) as f64,
        DataType::Uint16 => u16::from_le_bytes([b[0], b[1]]) as f64,
        DataType::Int32 => i32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
        DataType::Uint32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
        DataType::Int64 => i64::from_le_bytes(b) as f64,
        DataType::Uint64 => u64::from_le_bytes(b) as f64,
        DataType::Float32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
        DataType::Float64 => f64::from_le_bytes(b),
        DataType::Invalid => return None,
    })
}

/// `x` appended as glTF component type `component_type` (a float exactly
/// as decoded; an integer rounded and clamped to its type).
fn push_component(out: &mut Vec<u8>, x: f64, component_type: u64) {
    match component_type {
        5120 => out.extend((x.round().clamp(-128.0, 127.0) as i8).to_le_bytes()),
        5121 => out.extend((x.round().clamp(0.0, 255.0) as u8).to_le_bytes()),
        5122 => out.extend((x.round().clamp(-32768.0, 32767.0) as i16).to_le_bytes()),
        5123 => out.extend((x.round().clamp(0.0, 65535.0) as u16).to_le_bytes()),
        5125 => out.extend((x.round().clamp(0.0, u32::MAX as f64) as u32).to_le_bytes()),
        _ => out.extend((x as f32).to_le_bytes()),
    }
}
