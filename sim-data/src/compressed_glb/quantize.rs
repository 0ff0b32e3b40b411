//! `KHR_mesh_quantization` as the encoder writes it
//! (<https://github.com/KhronosGroup/glTF/blob/main/extensions/2.0/Khronos/KHR_mesh_quantization/README.md>):
//! positions and target displacements as normalized SHORT, normals as
//! normalized BYTE through meshopt's octahedral filter, and the
//! dequantization folded into the nodes that place the mesh.
//!
//! A mesh's positions `p` become `q = round((p − o) / s · 32767)`, `o` the
//! centre of its bounding box and `s` half its longest side (one scale for
//! all three axes, so normals need no correction); the node then maps
//! `q / 32767` back by `T(o) · S(s)` (`s` larger where a target moves a
//! vertex further than that, as a tongue sticking out does), so the error per coordinate is at
//! most `s / 32767 / 2` (half a step), plus float rounding. Target
//! displacements `d` become `round(d / s · 32767)`: the same step.

use serde_json::{Value, json};

/// The dequantization `p = o + s · q / 32767` of one mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dequantization {
    /// `o`, the bounding box's centre.
    pub offset: [f32; 3],
    /// `s`, half the bounding box's longest side.
    pub scale: f32,
}

impl Dequantization {
    /// The dequantization that fits `positions`, with a scale large enough
    /// for every coordinate of `displacements` too.
    pub fn fitting<'a>(
        positions: impl Iterator<Item = &'a [f32; 3]>,
        displacements: impl Iterator<Item = &'a [f32; 3]>,
    ) -> Dequantization {
        let mut lo = [f32::INFINITY; 3];
        let mut hi = [f32::NEG_INFINITY; 3];
        for p in positions {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let offset = std::array::from_fn(|k| {
            if lo[k] <= hi[k] {
                (lo[k] + hi[k]) / 2.0
            } else {
                0.0
            }
        });
        let half = (0..3).map(|k| (hi[k] - lo[k]) / 2.0).fold(0.0f32, f32::max);
        let longest = displacements
            .flat_map(|d| d.iter().map(|x| x.abs()))
            .fold(0.0f32, f32::max);
        let half = half.max(longest);
        Dequantization {
            offset,
            scale: if half > 0.0 && half.is_finite() {
                half
            } else {
                1.0
            },
        }
    }
}

fn snorm16(x: f32) -> i16 {
    (x.clamp(-1.0, 1.0) * 32767.0).round() as i16
}

/// Normalized SHORT `VEC3`s padded to 8 bytes, and their per-component
/// `min` and `max` (as stored: the spec's `min`/`max` ignore `normalized`).
fn pack16(values: impl Iterator<Item = [i16; 3]>) -> (Vec<u8>, Value, Value) {
    let mut bytes = Vec::new();
    let mut lo = [i16::MAX; 3];
    let mut hi = [i16::MIN; 3];
    for q in values {
        for k in 0..3 {
            lo[k] = lo[k].min(q[k]);
            hi[k] = hi[k].max(q[k]);
            bytes.extend_from_slice(&q[k].to_le_bytes());
        }
        bytes.extend_from_slice(&[0, 0]);
    }
    (bytes, json!(lo), json!(hi))
}

/// Positions as normalized SHORT (stride 8), with `min` and `max`.
pub fn positions(p: &[[f32; 3]], d: Dequantization) -> (Vec<u8>, Value, Value) {
    pack16(
        p.iter()
            .map(|p| std::array::from_fn(|k| snorm16((p[k] - d.offset[k]) / d.scale))),
    )
}

/// Target displacements as normalized SHORT (stride 8), with `min` and
/// `max`; an error if one is longer than the scale allows.
pub fn displacements(t: &[[f32; 3]], d: Dequantization) -> Result<(Vec<u8>, Value, Value), String> {
    if let Some(v) = t
        .iter()
        .find(|v| v.iter().any(|x| (x / d.scale).abs() > 1.0))
    {
        return Err(format!("a displacement {v:?} beyond the scale {}", d.scale));
    }
    Ok(pack16(
        t.iter()
            .map(|v| std::array::from_fn(|k| snorm16(v[k] / d.scale))),
    ))
}

/// Unit normals through meshopt's octahedral filter, 8 bits (stride 4).
pub fn normals(n: &[[f32; 3]]) -> Vec<u8> {
    let unit: Vec<[f32; 4]> = n
        .iter()
        .map(|v| {
            let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            if len > 0.0 && len.is_finite() {
                [v[0] / len, v[1] / len, v[2] / len, 0.0]
            } else {
                [0.0, 0.0, 1.0, 0.0]
            }
        })
        .collect();
    meshopt::encoding::encode_filter_oct::<i8>(&unit, 8)
        .into_iter()
        .flat_map(|e| e.map(|x| x as u8))
        .collect()
}

/// Target normal displacements as normalized BYTE (stride 4).
pub fn normal_displacements(t: &[[f32; 3]]) -> Vec<u8> {
    t.iter()
        .flat_map(|v| {
            let b = |x: f32| ((x.clamp(-1.0, 1.0) * 127.0).round() as i8) as u8;
            [b(v[0]), b(v[1]), b(v[2]), 0]
        })
        .collect()
}

fn floats<const N: usize>(v: &Value, default: [f32; N]) -> [f32; N] {
    std::array::from_fn(|k| v[k].as_f64().map_or(default[k], |x| x as f32))
}

/// Folds `d` into a node's transform: `M · T(o) · S(s)`. A TRS node stays
/// TRS (`t + R(sc ⊙ o)`, `sc · s`).
pub fn fold_into(node: &mut Value, d: Dequantization) {
    if let Some(m) = node.get("matrix").filter(|m| m.is_array()) {
        let m = floats::<16>(m, [0.0; 16]);
        let mut out = m;
        // Column-major: new column k (k < 3) = s · old column k;
        // new column 3 = M · (o, 1).
        for c in 0..3 {
            for r in 0..4 {
                out[4 * c + r] = m[4 * c + r] * d.scale;
            }
        }
        for r in 0..4 {
            out[12 + r] = (0..3).map(|c| m[4 * c + r] * d.offset[c]).sum::<f32>() + m[12 + r];
        }
        node["matrix"] = json!(out);
        return;
    }
    let t = floats::<3>(&node["translation"], [0.0; 3]);
    let r = floats::<4>(&node["rotation"], [0.0, 0.0, 0.0, 1.0]);
    let sc = floats::<3>(&node["scale"], [1.0; 3]);
    let v: [f32; 3] = std::array::from_fn(|k| sc[k] * d.offset[k]);
    let rv = rotate(r, v);
    node["translation"] = json!([t[0] + rv[0], t[1] + rv[1], t[2] + rv[2]]);
    node["scale"] = json!(sc.map(|x| x * d.scale));
}

/// Undoes [`fold_into`] for a child of a node `d` was folded into:
/// `T(o) · S(s)`⁻¹ `· M`.
pub fn unfold_from_child(node: &mut Value, d: Dequantization) {
    let inv = 1.0 / d.scale;
    if let Some(m) = node.get("matrix").filter(|m| m.is_array()) {
        let mut m = floats::<16>(m, [0.0; 16]);
        for c in 0..4 {
            for r in 0..3 {
                let w = m[4 * c + 3];
                m[4 * c + r] = (m[4 * c + r] - d.offset[r] * w) * inv;
            }
        }
        node["matrix"] = json!(m);
        return;
    }
    let t = floats::<3>(&node["translation"], [0.0; 3]);
    let sc = floats::<3>(&node["scale"], [1.0; 3]);
    node["translation"] = json!(std::array::from_fn::<f32, 3, _>(
        |k| (t[k] - d.offset[k]) * inv
    ));
    node["scale"] = json!(sc.map(|x| x * inv));
}

/// `v` rotated by the unit quaternion `q` (x, y, z, w).
fn rotate(q: [f32; 4], v: [f32; 3]) -> [f32; 3] {
    let (x, y, z, w) = (q[0], q[1], q[2], q[3]);
    // v + 2w(u × v) + 2u × (u × v), u = (x, y, z)
    let cross = |a: [f32; 3], b: [f32; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let u = [x, y, z];
    let uv = cross(u, v);
    let uuv = cross(u, uv);
    std::array::from_fn(|k| v[k] + 2.0 * (w * uv[k] + uuv[k]))
}
