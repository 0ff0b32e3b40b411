//! `KHR_mesh_quantization`
//! (<https://github.com/KhronosGroup/glTF/blob/main/extensions/2.0/Khronos/KHR_mesh_quantization/README.md>):
//! vertex attributes stored as 8- or 16-bit integers, normalized or not,
//! turned into 32-bit floats.
//!
//! An integer becomes a float by the glTF 2.0 spec's rules
//! (`normalized.rs`). The dequantization an exporter folds into the mesh's
//! node (a scale and an offset in its `matrix` or TRS) is left there: the
//! scene places the mesh with it like any other transform (`scene.rs`).
//!
//! On reading, every accessor a primitive uses as an attribute (or a
//! target's `POSITION`, `NORMAL`, `TANGENT`) whose type core glTF 2.0 does
//! not allow for it ([`core_allows`], spec "Meshes", attribute table) is
//! rewritten dense, as floats, in a buffer of its own (with `min` / `max`
//! for `POSITION`), and the extension leaves `extensionsUsed` and
//! `extensionsRequired`: a file written back from it is plain glTF 2.0.

use super::GlbError;
use super::accessor::Source;
use super::meshopt::forget_extension;
use gltf::Semantic;
use gltf::accessor::DataType;
use serde_json::{Value, json};
use std::collections::BTreeMap;
use std::path::Path;

/// The extension's name.
pub(crate) const EXTENSION: &str = "KHR_mesh_quantization";

const FLOAT: u32 = 5126;
const ARRAY_BUFFER: u32 = 34962;

/// Whether core glTF 2.0 allows `data_type` (normalized or not) for the
/// attribute `semantic` of a primitive (`target`: of a morph target).
pub(crate) fn core_allows(
    semantic: &Semantic,
    target: bool,
    data_type: DataType,
    normalized: bool,
) -> bool {
    use DataType::{F32, U8, U16};
    let float = data_type == F32;
    let unsigned_normalized = normalized && matches!(data_type, U8 | U16);
    match semantic {
        Semantic::Positions | Semantic::Normals | Semantic::Tangents => float,
        _ if target => float,
        Semantic::TexCoords(_) | Semantic::Colors(_) | Semantic::Weights(_) => {
            float || unsigned_normalized
        }
        Semantic::Joints(_) => !normalized && matches!(data_type, U8 | U16),
        // Application-specific (`_NAME`) attributes: anything goes.
        _ => true,
    }
}

/// Rewrites, as floats, every accessor a primitive uses in a way core
/// glTF 2.0 does not allow (the module's rules); the new data goes to one
/// new buffer appended to `buffers` and to the JSON's `buffers`.
pub(crate) fn dequantize(
    json: &mut Value,
    buffers: &mut Vec<Vec<u8>>,
    document: &gltf::Document,
    file: &Path,
) -> Result<(), GlbError> {
    let source = Source {
        file,
        buffers: buffers.as_slice(),
    };
    // accessor → whether it is a POSITION (needs min and max)
    let mut convert = BTreeMap::new();
    for mesh in document.meshes() {
        for primitive in mesh.primitives() {
            for (semantic, a) in primitive.attributes() {
                if !core_allows(&semantic, false, a.data_type(), a.normalized()) {
                    *convert.entry(a.index()).or_insert(false) |= semantic == Semantic::Positions;
                }
            }
            for target in primitive.morph_targets() {
                for (semantic, a) in [
                    (Semantic::Positions, target.positions()),
                    (Semantic::Normals, target.normals()),
                    (Semantic::Tangents, target.tangents()),
                ] {
                    if let Some(a) = a.filter(|a| a.data_type() != DataType::F32) {
                        *convert.entry(a.index()).or_insert(false) |=
                            semantic == Semantic::Positions;
                    }
                }
            }
        }
    }
    let accessors: Vec<gltf::Accessor> = document.accessors().collect();
    let mut bin = Vec::new();
    let mut changes = Vec::new();
    for (&index, &position) in &convert {
        let Some(accessor) = accessors.get(index) else {
            continue;
        };
        let values = source.floats(accessor)?;
        let width = accessor.dimensions().multiplicity();
        let offset = bin.len();
        bin.reserve(4 * values.len());
        for v in &values {
            bin.extend_from_slice(&v.to_le_bytes());
        }
        let had_bounds = json["accessors"][index].get("min").is_some();
        let bounds = (position || had_bounds).then(|| bounds(&values, width));
        changes.push((index, offset, bin.len() - offset, bounds));
    }
    if changes.is_empty() {
        forget_extension(json, EXTENSION);
        return Ok(());
    }
    let buffer = buffers.len();
    if let Some(list) = json["buffers"].as_array_mut() {
        list.push(json!({ "byteLength": bin.len() }));
    }
    buffers.push(bin);
    let mut users = view_users(json);
    for (index, offset, length, bounds) in changes {
        let new_view = json!({
            "buffer": buffer, "byteOffset": offset, "byteLength": length, "target": ARRAY_BUFFER
        });
        // The accessor's old view takes the new data if nothing else uses
        // it (no view is left unused); else the data gets a new view.
        let old = json["accessors"][index]["bufferView"]
            .as_u64()
            .map(|v| v as usize);
        let Some(views) = json
            .as_object_mut()
            .and_then(|o| o.entry("bufferViews").or_insert(json!([])).as_array_mut())
        else {
            continue;
        };
        let view = match old.filter(|&v| v < users.len()) {
            Some(v) if users[v] == 1 => {
                views[v] = new_view;
                v
            }
            other => {
                if let Some(v) = other {
                    users[v] -= 1;
                }
                views.push(new_view);
                views.len() - 1
            }
        };
        let a = &mut json["accessors"][index];
        if let Some(o) = a.as_object_mut() {
            for key in ["normalized", "byteOffset", "sparse", "min", "max"] {
                o.remove(key);
            }
            o.insert("componentType".into(), json!(FLOAT));
            o.insert("bufferView".into(), json!(view));
            if let Some((min, max)) = bounds {
                o.insert("min".into(), min);
                o.insert("max".into(), max);
            }
        }
    }
    forget_extension(json, EXTENSION);
    Ok(())
}

/// How many accessors (as data or sparse parts) and images use each
/// buffer view.
fn view_users(json: &Value) -> Vec<usize> {
    let mut users = vec![0; json["bufferViews"].as_array().map_or(0, Vec::len)];
    let mut count = |v: &Value| {
        if let Some(slot) = v.as_u64().and_then(|v| users.get_mut(v as usize)) {
            *slot += 1;
        }
    };
    for a in json["accessors"].as_array().into_iter().flatten() {
        count(&a["bufferView"]);
        count(&a["sparse"]["indices"]["bufferView"]);
        count(&a["sparse"]["values"]["bufferView"]);
    }
    for image in json["images"].as_array().into_iter().flatten() {
        count(&image["bufferView"]);
    }
    users
}

/// Per-component `min` and `max` of `values`, `width` components an
/// element.
fn bounds(values: &[f32], width: usize) -> (Value, Value) {
    let mut min = vec![f32::INFINITY; width];
    let mut max = vec![f32::NEG_INFINITY; width];
    for element in values.chunks_exact(width) {
        for (k, &x) in element.iter().enumerate() {
            min[k] = min[k].min(x);
            max[k] = max[k].max(x);
        }
    }
    let list = |v: Vec<f32>| {
        Value::Array(
            v.into_iter()
                .map(|x| Value::from(f64::from(if x.is_finite() { x } else { 0.0 })))
                .collect(),
        )
    };
    (list(min), list(max))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn core_types_per_attribute() {
        assert!(!core_allows(
            &Semantic::Positions,
            false,
            DataType::I16,
            true
        ));
        assert!(!core_allows(&Semantic::Normals, false, DataType::I8, true));
        assert!(core_allows(
            &Semantic::TexCoords(0),
            false,
            DataType::U16,
            true
        ));
        assert!(!core_allows(
            &Semantic::TexCoords(0),
            false,
            DataType::I16,
            false
        ));
        assert!(core_allows(
            &Semantic::Joints(0),
            false,
            DataType::U8,
            false
        ));
        assert!(core_allows(
            &Semantic::Weights(0),
            false,
            DataType::U8,
            true
        ));
    }
}
