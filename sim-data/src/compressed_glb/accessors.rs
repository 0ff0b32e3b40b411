//! Reading a plain glTF 2.0 accessor (glTF 2.0 spec, "Accessors", "Sparse
//! Accessors") as raw little-endian elements: what the encoder starts
//! from. Every range is checked; a malformed file is an error, never a
//! panic.

use serde_json::Value;

/// Bytes of one component of glTF `componentType`.
pub fn component_size(component_type: u64) -> Result<usize, String> {
    match component_type {
        5120 | 5121 => Ok(1),
        5122 | 5123 => Ok(2),
        5125 | 5126 => Ok(4),
        other => Err(format!("componentType {other}")),
    }
}

/// Components of an accessor `type` (vectors and scalars only).
pub fn width(kind: &str) -> Result<usize, String> {
    match kind {
        "SCALAR" => Ok(1),
        "VEC2" => Ok(2),
        "VEC3" => Ok(3),
        "VEC4" => Ok(4),
        other => Err(format!("accessor type {other:?} is not a vertex attribute")),
    }
}

fn get(v: &Value, key: &str) -> usize {
    v[key].as_u64().unwrap_or(0) as usize
}

/// `count` elements of `size` bytes at `offset` in view `view`, tightly
/// packed.
fn view_elements(
    doc: &Value,
    buffers: &[Vec<u8>],
    view: usize,
    offset: usize,
    count: usize,
    size: usize,
) -> Result<Vec<u8>, String> {
    let v = &doc["bufferViews"][view];
    let buffer = buffers
        .get(get(v, "buffer"))
        .ok_or_else(|| format!("buffer view {view}: no buffer"))?;
    let stride = v["byteStride"].as_u64().map_or(size, |s| s as usize);
    let start = get(v, "byteOffset") + offset;
    let mut out = Vec::with_capacity(count * size);
    for i in 0..count {
        let at = start + i * stride;
        let bytes = buffer
            .get(at..at + size)
            .ok_or_else(|| format!("buffer view {view}: element {i} outside its buffer"))?;
        out.extend_from_slice(bytes);
    }
    Ok(out)
}

/// Every element of accessor `index` as raw bytes (`count · size`), sparse
/// substitution applied; and the element size.
pub fn raw(doc: &Value, buffers: &[Vec<u8>], index: usize) -> Result<(Vec<u8>, usize), String> {
    let a = &doc["accessors"][index];
    let size = component_size(a["componentType"].as_u64().unwrap_or(0))?
        * width(a["type"].as_str().unwrap_or(""))?;
    let count = get(a, "count");
    let mut out = match a["bufferView"].as_u64() {
        Some(view) => view_elements(
            doc,
            buffers,
            view as usize,
            get(a, "byteOffset"),
            count,
            size,
        )?,
        None => vec![0; count * size],
    };
    if let Some(sparse) = a.get("sparse") {
        let n = get(sparse, "count");
        let (ix, vals) = (&sparse["indices"], &sparse["values"]);
        let isize = component_size(ix["componentType"].as_u64().unwrap_or(0))?;
        let ix = view_elements(
            doc,
            buffers,
            get(ix, "bufferView"),
            get(ix, "byteOffset"),
            n,
            isize,
        )?;
        let vals = view_elements(
            doc,
            buffers,
            get(vals, "bufferView"),
            get(vals, "byteOffset"),
            n,
            size,
        )?;
        for k in 0..n {
            let i = ix[k * isize..(k + 1) * isize]
                .iter()
                .rev()
                .fold(0usize, |acc, &b| (acc << 8) | usize::from(b));
            out.get_mut(i * size..(i + 1) * size)
                .ok_or_else(|| format!("accessor {index}: sparse index {i} past its count"))?
                .copy_from_slice(&vals[k * size..(k + 1) * size]);
        }
    }
    Ok((out, size))
}

/// Accessor `index` as `VEC3` floats.
pub fn vec3(doc: &Value, buffers: &[Vec<u8>], index: usize) -> Result<Vec<[f32; 3]>, String> {
    let a = &doc["accessors"][index];
    if a["componentType"] != 5126 || a["type"] != "VEC3" {
        return Err(format!("accessor {index}: not VEC3 of floats"));
    }
    let (bytes, _) = raw(doc, buffers, index)?;
    let f = |c: &[u8]| f32::from_le_bytes([c[0], c[1], c[2], c[3]]);
    Ok(bytes
        .chunks_exact(12)
        .map(|c| [f(&c[0..4]), f(&c[4..8]), f(&c[8..12])])
        .collect())
}

/// Accessor `index` (unsigned integer scalars) as indices.
pub fn indices(doc: &Value, buffers: &[Vec<u8>], index: usize) -> Result<Vec<u32>, String> {
    let (bytes, size) = raw(doc, buffers, index)?;
    Ok(bytes
        .chunks_exact(size)
        .map(|c| {
            c.iter()
                .rev()
                .fold(0u32, |acc, &b| (acc << 8) | u32::from(b))
        })
        .collect())
}
