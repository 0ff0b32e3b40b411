//! Buffer views compressed with `EXT_meshopt_compression`
//! (<https://github.com/KhronosGroup/glTF/blob/main/extensions/2.0/Vendor/EXT_meshopt_compression/README.md>),
//! decoded once, before any accessor is read.
//!
//! Such a view (spec, "Properties") carries `extensions.EXT_meshopt_compression`
//! `{buffer, byteOffset, byteLength, byteStride, count, mode, filter}`: the
//! compressed bytes lie in `buffer`, and decode to `count · byteStride`
//! bytes, which stand where the view itself points (the "fallback" data).
//! Modes (spec, "Compression modes"): `ATTRIBUTES` (meshoptimizer's vertex
//! codec, `byteStride` a multiple of 4 up to 256), `TRIANGLES` (its index
//! buffer codec, `count` a multiple of 3) and `INDICES` (its index
//! sequence codec), the last two with `byteStride` 2 or 4. A filter
//! (`meshopt_filters.rs`) may then transform `ATTRIBUTES` data.
//!
//! A buffer whose views all carry the extension, or flagged
//! `extensions.EXT_meshopt_compression.fallback` (spec, "Fallback
//! buffers"), need not hold data: it is not loaded.
//!
//! Each decoded view gets a buffer of its own (appended to the file's
//! buffers, `byteLength` only) and loses the extension, so everything after
//! this reads and writes plain views; the extension leaves
//! `extensionsUsed` and `extensionsRequired`.
//!
//! Every field is checked before meshoptimizer is called (its C++ asserts
//! on a bad stride or count), and decoded sizes are bounded: a view may
//! decode to at most [`MAX_RATIO`] times its compressed size (the codecs
//! never reach it: the vertex codec spends at least 2 bits per byte lane
//! per block of at most 256 vertices), all views together to at most
//! [`MAX_DECODED_BYTES`].

use super::GlbError;
use super::meshopt_filters::{Filter, apply_filter};
use serde_json::{Value, json};
use std::path::Path;

/// The extension's name.
pub(crate) const EXTENSION: &str = "EXT_meshopt_compression";

/// Largest ratio of a view's decoded size to its compressed size.
pub const MAX_RATIO: u64 = 2048;

/// Largest total of decoded bytes in one file (1 GiB).
pub const MAX_DECODED_BYTES: u64 = 1 << 30;

fn extension(view: &Value) -> Option<&Value> {
    view.get("extensions")?.get(EXTENSION)
}

/// Which buffers need not be loaded: flagged `fallback`, or referred to
/// only by views that carry the extension.
pub(crate) fn fallback_buffers(json: &Value) -> Vec<bool> {
    let buffers = json["buffers"].as_array().map_or(&[][..], Vec::as_slice);
    let views = json["bufferViews"]
        .as_array()
        .map_or(&[][..], Vec::as_slice);
    // Per buffer: views in it, views in it that carry the extension, and
    // whether compressed data lies in it.
    let mut plain = vec![0usize; buffers.len()];
    let mut compressed = vec![0usize; buffers.len()];
    let mut holds_streams = vec![false; buffers.len()];
    let slot = |v: &Value| {
        v.as_u64()
            .map(|b| b as usize)
            .filter(|&b| b < buffers.len())
    };
    for view in views {
        let ext = extension(view);
        if let Some(b) = slot(&view["buffer"]) {
            if ext.is_some() {
                compressed[b] += 1;
            } else {
                plain[b] += 1;
            }
        }
        if let Some(b) = ext.and_then(|e| slot(&e["buffer"])) {
            holds_streams[b] = true;
        }
    }
    (0..buffers.len())
        .map(|b| {
            let flagged = buffers[b]["extensions"][EXTENSION]["fallback"] == json!(true);
            flagged || (compressed[b] > 0 && plain[b] == 0 && !holds_streams[b])
        })
        .collect()
}

/// Whether any view carries the extension.
pub(crate) fn used(json: &Value) -> bool {
    json["bufferViews"]
        .as_array()
        .is_some_and(|v| v.iter().any(|v| extension(v).is_some()))
}

/// Decodes every view carrying the extension into a buffer of its own,
/// appended to `buffers` and to the JSON's `buffers`, and points the view
/// there without the extension.
pub(crate) fn decode_views(
    json: &mut Value,
    buffers: &mut Vec<Vec<u8>>,
    file: &Path,
) -> Result<(), GlbError> {
    let Some(views) = json["bufferViews"].as_array() else {
        return Ok(());
    };
    let mut budget = MAX_DECODED_BYTES;
    let mut decoded = Vec::new();
    for (i, view) in views.iter().enumerate() {
        let Some(ext) = extension(view) else {
            continue;
        };
        let bytes =
            decode_view(view, ext, buffers, &mut budget).map_err(|what| GlbError::Compressed {
                file: file.to_path_buf(),
                view: i,
                what,
            })?;
        decoded.push((i, bytes));
    }
    for (i, bytes) in decoded {
        let index = buffers.len();
        if let Some(list) = json["buffers"].as_array_mut() {
            list.push(json!({ "byteLength": bytes.len() }));
        }
        let view = &mut json["bufferViews"][i];
        view["buffer"] = json!(index);
        view["byteLength"] = json!(bytes.len());
        if let Some(o) = view.as_object_mut() {
            o.remove("byteOffset");
        }
        remove_extension(view);
        buffers.push(bytes);
    }
    for buffer in json["buffers"].as_array_mut().into_iter().flatten() {
        remove_extension(buffer);
    }
    forget_extension(json, EXTENSION);
    Ok(())
}

/// Removes `extensions.EXT_meshopt_compression` (and `extensions` if it is
/// left empty).
fn remove_extension(object: &mut Value) {
    let Some(o) = object.as_object_mut() else {
        return;
    };
    if let Some(exts) = o.get_mut("extensions").and_then(Value::as_object_mut) {
        exts.remove(EXTENSION);
        if exts.is_empty() {
            o.remove("extensions");
        }
    }
}

/// Drops `name` from `extensionsUsed` and `extensionsRequired` (and either
/// list if it is left empty).
pub(crate) fn forget_extension(json: &mut Value, name: &str) {
    let Some(o) = json.as_object_mut() else {
        return;
    };
    for key in ["extensionsUsed", "extensionsRequired"] {
        if let Some(list) = o.get_mut(key).and_then(Value::as_array_mut) {
            list.retain(|e| e != name);
            if list.is_empty() {
                o.remove(key);
            }
        }
    }
}

/// A non-negative integer field of the extension object.
fn field(ext: &Value, key: &str, default: Option<u64>) -> Result<u64, String> {
    match ext.get(key) {
        None => default.ok_or_else(|| format!("{EXTENSION}.{key} missing")),
        Some(v) => v
            .as_u64()
            .ok_or_else(|| format!("{EXTENSION}.{key} is not a non-negative integer")),
    }
}

/// A string field, shortened for messages.
fn name<'a>(ext: &'a Value, key: &str, default: Option<&'a str>) -> Result<&'a str, String> {
    match ext.get(key) {
        None => default.ok_or_else(|| format!("{EXTENSION}.{key} missing")),
        Some(v) => v
            .as_str()
            .ok_or_else(|| format!("{EXTENSION}.{key} is not a string")),
    }
}

fn short(s: &str) -> String {
    s.chars().take(40).collect()
}

/// The decoded bytes of one view (spec, "Compression modes" and
/// "Filters"), at least the view's `byteLength` long.
fn decode_view(
    view: &Value,
    ext: &Value,
    buffers: &[Vec<u8>],
    budget: &mut u64,
) -> Result<Vec<u8>, String> {
    let buffer = field(ext, "buffer", None)?;
    let offset = field(ext, "byteOffset", Some(0))?;
    let length = field(ext, "byteLength", None)?;
    let stride = field(ext, "byteStride", None)?;
    let count = field(ext, "count", None)?;
    let mode = name(ext, "mode", None)?;
    let filter = name(ext, "filter", Some("NONE"))?;
    let view_length = view["byteLength"].as_u64().unwrap_or(0);
    let source = buffers
        .get(buffer as usize)
        .ok_or_else(|| format!("compressed data in buffer {buffer}, which does not exist"))?;
    let encoded = usize::try_from(offset)
        .ok()
        .zip(usize::try_from(offset.saturating_add(length)).ok())
        .and_then(|(a, b)| source.get(a..b))
        .ok_or_else(|| {
            format!(
                "compressed bytes {offset}..+{length} lie outside buffer {buffer} ({} bytes loaded)",
                source.len()
            )
        })?;
    let stride_ok = match mode {
        "ATTRIBUTES" => stride.is_multiple_of(4) && (4..=256).contains(&stride),
        "TRIANGLES" | "INDICES" => stride == 2 || stride == 4,
        other => return Err(format!("unknown mode {:?}", short(other))),
    };
    if !stride_ok {
        return Err(format!("byteStride {stride} is not allowed in mode {mode}"));
    }
    if count == 0 || (mode == "TRIANGLES" && !count.is_multiple_of(3)) {
        return Err(format!("count {count} in mode {mode}"));
    }
    let total = count.saturating_mul(stride);
    if view_length < total {
        return Err(format!(
            "count {count} × byteStride {stride} = {total} bytes, more than the view's byteLength {view_length}"
        ));
    }
    let limit = length.saturating_mul(MAX_RATIO).saturating_add(4096);
    if view_length > limit || view_length > *budget {
        return Err(format!(
            "{view_length} bytes from {length} compressed bytes: beyond what the codec can produce, or past {MAX_DECODED_BYTES} decoded bytes in all"
        ));
    }
    *budget -= view_length;
    let filter = Filter::parse(filter, stride as usize)
        .map_err(|what| format!("filter {:?}: {what}", short(filter)))?;
    if filter != Filter::None && mode != "ATTRIBUTES" {
        return Err(format!("a filter in mode {mode}"));
    }
    let (count, stride) = (count as usize, stride as usize);
    let fail = |e: meshopt::Error| format!("meshoptimizer cannot decode the {mode} stream: {e}");
    let mut bytes = match (mode, stride) {
        ("ATTRIBUTES", _) => decode_vertices(encoded, count, stride),
        ("TRIANGLES", 2) => le(meshopt::encoding::decode_index_buffer::<u16>(
            encoded, count,
        )),
        ("TRIANGLES", _) => le(meshopt::encoding::decode_index_buffer::<u32>(
            encoded, count,
        )),
        ("INDICES", 2) => le(meshopt::encoding::decode_index_sequence::<u16>(
            encoded, count,
        )),
        (_, _) => le(meshopt::encoding::decode_index_sequence::<u32>(
            encoded, count,
        )),
    }
    .map_err(fail)?;
    apply_filter(filter, &mut bytes, stride);
    bytes.resize(view_length as usize, 0);
    Ok(bytes)
}

/// Indices as little-endian bytes.
fn le<T: ToLe>(indices: meshopt::Result<Vec<T>>) -> meshopt::Result<Vec<u8>> {
    indices.map(|v| {
        let mut out = Vec::with_capacity(v.len() * 4);
        for &i in &v {
            i.push_le(&mut out);
        }
        out
    })
}

/// An index type meshoptimizer decodes.
trait ToLe: Copy {
    fn push_le(self, out: &mut Vec<u8>);
}

impl ToLe for u16 {
    fn push_le(self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.to_le_bytes());
    }
}

impl ToLe for u32 {
    fn push_le(self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.to_le_bytes());
    }
}

/// One vertex of `N` bytes, as the vertex codec writes it.
#[derive(Clone, Copy)]
struct Vertex<const N: usize>([u8; N]);

impl<const N: usize> Default for Vertex<N> {
    fn default() -> Self {
        Vertex([0; N])
    }
}

fn decode_n<const N: usize>(encoded: &[u8], count: usize) -> meshopt::Result<Vec<u8>> {
    let vertices = meshopt::encoding::decode_vertex_buffer::<Vertex<N>>(encoded, count)?;
    let mut out = Vec::with_capacity(count * N);
    for v in &vertices {
        out.extend_from_slice(&v.0);
    }
    Ok(out)
}

macro_rules! by_stride {
    ($stride:expr, $encoded:expr, $count:expr; $($n:literal)*) => {
        match $stride {
            $($n => decode_n::<$n>($encoded, $count),)*
            _ => Err(meshopt::Error::Parse(format!("byteStride {}", $stride))),
        }
    };
}

/// `count` vertices of `stride` bytes (a multiple of 4, at most 256) from
/// meshoptimizer's vertex codec.
fn decode_vertices(encoded: &[u8], count: usize, stride: usize) -> meshopt::Result<Vec<u8>> {
    by_stride!(stride, encoded, count;
        4 8 12 16 20 24 28 32 36 40 44 48 52 56 60 64
        68 72 76 80 84 88 92 96 100 104 108 112 116 120 124 128
        132 136 140 144 148 152 156 160 164 168 172 176 180 184 188 192
        196 200 204 208 212 216 220 224 228 232 236 240 244 248 252 256)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fallback_buffers_are_flagged_or_only_behind_compressed_views() {
        let ext = |b: u64| json!({ "EXT_meshopt_compression": { "buffer": b } });
        let json = json!({
            "buffers": [
                { "byteLength": 8 },
                { "byteLength": 64 },
                { "byteLength": 64, "extensions": { "EXT_meshopt_compression": { "fallback": true } } },
                { "byteLength": 4 },
            ],
            "bufferViews": [
                { "buffer": 1, "byteLength": 64, "extensions": ext(0) },
                { "buffer": 2, "byteLength": 64, "extensions": ext(0) },
                { "buffer": 3, "byteLength": 4 },
                { "buffer": 3, "byteLength": 4, "extensions": ext(0) },
            ],
        });
        assert_eq!(fallback_buffers(&json), [false, true, true, false]);
        assert!(used(&json));
    }

    #[test]
    fn forgetting_an_extension_drops_empty_lists() {
        let mut json =
            json!({ "extensionsUsed": ["A", EXTENSION], "extensionsRequired": [EXTENSION] });
        forget_extension(&mut json, EXTENSION);
        assert_eq!(json, json!({ "extensionsUsed": ["A"] }));
    }
}
