//! Accessors and buffer views as they are written: one binary buffer, every
//! view starting on a 4-byte boundary (the spec asks accessors to be
//! aligned to their component size; 4 covers every type used here), and
//! morph targets dense or sparse, whichever is smaller.
//!
//! A target moving `k` of `n` vertices costs `12 n` bytes dense and
//! `pad₄(k · s) + 12 k` sparse, `s` the size of the smallest unsigned type
//! that holds `n − 1` (1, 2 or 4 bytes): a shape that moves a tenth of a
//! body is about 8 times smaller sparse. A target that moves nothing is
//! sparse with one zero entry (16 bytes): the spec would also take an
//! accessor with neither view nor sparse part as zeros, but common readers
//! (the `gltf` crate among them) reject that.
//! `POSITION` accessors carry exact `min` / `max` (the spec requires them;
//! an `f32` widened to `f64` prints as a decimal that reads back to the same
//! `f32`).

use glam::Vec3;
use serde_json::{Value, json};

/// `ARRAY_BUFFER`: a view of vertex attributes.
pub(crate) const ARRAY_BUFFER: u32 = 34962;
/// `ELEMENT_ARRAY_BUFFER`: a view of triangle indices.
pub(crate) const ELEMENT_ARRAY_BUFFER: u32 = 34963;
const FLOAT: u32 = 5126;
const UNSIGNED_BYTE: u32 = 5121;
const UNSIGNED_SHORT: u32 = 5123;
const UNSIGNED_INT: u32 = 5125;

/// How morph targets are stored.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TargetEncoding {
    /// Sparse where that is smaller than dense, dense otherwise.
    #[default]
    Smallest,
    /// Always dense (for comparison and for readers without sparse support).
    Dense,
}

/// The binary buffer being written and the JSON arrays that describe it.
pub(crate) struct Builder {
    pub bin: Vec<u8>,
    pub views: Vec<Value>,
    pub accessors: Vec<Value>,
}

fn num(x: f32) -> Value {
    Value::from(f64::from(x))
}

fn vec3_json(v: Vec3) -> Value {
    json!([num(v.x), num(v.y), num(v.z)])
}

/// Bytes of an index type and its glTF component type, for indices up to
/// `max`.
fn index_type(max: u32) -> (usize, u32) {
    match max {
        0..=0xFF => (1, UNSIGNED_BYTE),
        0x100..=0xFFFF => (2, UNSIGNED_SHORT),
        _ => (4, UNSIGNED_INT),
    }
}

fn push_index(bytes: &mut Vec<u8>, i: u32, size: usize) {
    bytes.extend_from_slice(&i.to_le_bytes()[..size]);
}

/// Whether a target of `n` vertices moving `moved` of them is smaller
/// sparse.
pub(crate) fn sparse_is_smaller(n: usize, moved: usize) -> bool {
    let (s, _) = index_type(n.saturating_sub(1) as u32);
    (moved * s).next_multiple_of(4) + 12 * moved < 12 * n
}

impl Builder {
    pub fn new() -> Self {
        Builder {
            bin: Vec::new(),
            views: Vec::new(),
            accessors: Vec::new(),
        }
    }

    /// Appends `bytes` as a new view (4-byte aligned); its index.
    pub fn view(&mut self, bytes: &[u8], target: Option<u32>) -> usize {
        self.bin.resize(self.bin.len().next_multiple_of(4), 0);
        let mut v = json!({
            "buffer": 0,
            "byteOffset": self.bin.len(),
            "byteLength": bytes.len(),
        });
        if let Some(t) = target {
            v["target"] = json!(t);
        }
        self.bin.extend_from_slice(bytes);
        self.views.push(v);
        self.views.len() - 1
    }

    /// Appends an accessor; its index.
    pub fn accessor(&mut self, a: Value) -> usize {
        self.accessors.push(a);
        self.accessors.len() - 1
    }

    /// A dense `VEC3` float accessor with `min` / `max`.
    pub fn vec3(&mut self, values: &[Vec3]) -> usize {
        let bytes: Vec<u8> = values
            .iter()
            .flat_map(|v| v.to_array())
            .flat_map(f32::to_le_bytes)
            .collect();
        let view = self.view(&bytes, Some(ARRAY_BUFFER));
        let (min, max) = bounds(values);
        self.accessor(json!({
            "bufferView": view, "componentType": FLOAT, "count": values.len(),
            "type": "VEC3", "min": vec3_json(min), "max": vec3_json(max),
        }))
    }

    /// A dense `VEC4` float accessor (tangents: no bounds required).
    pub fn vec4(&mut self, values: &[[f32; 4]]) -> usize {
        let bytes: Vec<u8> = values
            .iter()
            .flatten()
            .flat_map(|x| x.to_le_bytes())
            .collect();
        let view = self.view(&bytes, Some(ARRAY_BUFFER));
        self.accessor(json!({
            "bufferView": view, "componentType": FLOAT, "count": values.len(), "type": "VEC4",
        }))
    }

    /// Triangle indices, 16-bit when every index fits below 65535 (the
    /// largest value is the primitive-restart value, which glTF forbids).
    pub fn triangles(&mut self, triangles: &[[u32; 3]]) -> usize {
        let max = triangles.iter().flatten().copied().max().unwrap_or(0);
        let (size, ty) = if max < 0xFFFF {
            (2, UNSIGNED_SHORT)
        } else {
            (4, UNSIGNED_INT)
        };
        let mut bytes = Vec::with_capacity(triangles.len() * 3 * size);
        for &i in triangles.iter().flatten() {
            push_index(&mut bytes, i, size);
        }
        let view = self.view(&bytes, Some(ELEMENT_ARRAY_BUFFER));
        self.accessor(json!({
            "bufferView": view, "componentType": ty,
            "count": triangles.len() * 3, "type": "SCALAR",
        }))
    }

    /// A morph target's `POSITION` displacements: no data when nothing
    /// moves, sparse when that is smaller (unless `encoding` says dense),
    /// dense otherwise.
    pub fn target(&mut self, d: &[Vec3], name: &str, encoding: TargetEncoding) -> usize {
        let mut moved: Vec<u32> = (0..d.len() as u32)
            .filter(|&i| d[i as usize] != Vec3::ZERO)
            .collect();
        let (min, max) = bounds(d);
        let mut a = json!({
            "componentType": FLOAT, "count": d.len(), "type": "VEC3",
            "min": vec3_json(min), "max": vec3_json(max),
        });
        if !name.is_empty() {
            a["name"] = json!(name);
        }
        if moved.is_empty() && !d.is_empty() {
            moved.push(0); // one zero entry: sparse needs at least one
        } else if encoding == TargetEncoding::Dense || !sparse_is_smaller(d.len(), moved.len()) {
            let bytes: Vec<u8> = d
                .iter()
                .flat_map(|v| v.to_array())
                .flat_map(f32::to_le_bytes)
                .collect();
            a["bufferView"] = json!(self.view(&bytes, Some(ARRAY_BUFFER)));
            return self.accessor(a);
        }
        let (size, ty) = index_type(d.len().saturating_sub(1) as u32);
        let mut ix = Vec::with_capacity(moved.len() * size);
        let mut vals = Vec::with_capacity(moved.len() * 12);
        for &i in &moved {
            push_index(&mut ix, i, size);
            vals.extend(
                d[i as usize]
                    .to_array()
                    .into_iter()
                    .flat_map(f32::to_le_bytes),
            );
        }
        let ix_view = self.view(&ix, None);
        let vals_view = self.view(&vals, None);
        a["sparse"] = json!({
            "count": moved.len(),
            "indices": { "bufferView": ix_view, "componentType": ty },
            "values": { "bufferView": vals_view },
        });
        self.accessor(a)
    }
}

/// Component-wise minimum and maximum (zero for no values).
pub(crate) fn bounds(values: &[Vec3]) -> (Vec3, Vec3) {
    if values.is_empty() {
        return (Vec3::ZERO, Vec3::ZERO);
    }
    values.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), &v| (lo.min(v), hi.max(v)),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sparse_only_when_smaller() {
        // 1000 vertices, 2-byte indices: sparse costs 14 k (+ padding).
        assert!(sparse_is_smaller(1000, 100));
        assert!(sparse_is_smaller(1000, 850));
        assert!(!sparse_is_smaller(1000, 860));
        assert!(!sparse_is_smaller(3, 3));
    }

    #[test]
    fn still_targets_are_one_zero_entry_with_zero_bounds() {
        let mut b = Builder::new();
        let a = b.target(&[Vec3::ZERO; 5], "jawOpen", TargetEncoding::Dense);
        let acc = &b.accessors[a];
        assert!(acc.get("bufferView").is_none());
        assert_eq!(acc["sparse"]["count"], json!(1));
        assert_eq!(acc["min"], json!([0.0, 0.0, 0.0]));
        assert_eq!(b.bin.len(), 16);
    }

    #[test]
    fn views_start_on_four_byte_boundaries() {
        let mut b = Builder::new();
        let mut d = vec![Vec3::ZERO; 300];
        d[7] = Vec3::X;
        b.target(&d, "a", TargetEncoding::Smallest); // 2-byte index, 12-byte value
        b.target(&d, "b", TargetEncoding::Smallest);
        for v in &b.views {
            assert_eq!(v["byteOffset"].as_u64().unwrap() % 4, 0);
        }
        assert_eq!(b.accessors[0]["sparse"]["count"], json!(1));
    }
}
