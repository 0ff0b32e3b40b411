//! The glTF reader and writers on a hand-built file: a transformed node
//! hierarchy, two meshes, ARKit names in odd spellings and split halves,
//! other targets, extensions and extras to be kept; and every error case.
//!
//! | what | file |
//! |---|---|
//! | placement, names, skins, every error | `reading.rs` |
//! | a new rest written back, normals and tangents turned | `rest.rs` |
//! | write-back rules, JSON kept, sparse and dense, `.gltf` with a `.bin` or a data URI | `writing.rs` |
//! | a surface in several materials: primitives sharing vertices | `shared_vertices.rs` |

mod reading;
mod rest;
mod shared_vertices;
mod writing;

use super::container::join;
use super::encode::Builder;
use super::*;
use crate::arkit::Blendshape;
use crate::avatar::{Avatar, AvatarMesh, AvatarPart};
use glam::{Mat4, Quat, Vec3};
use serde_json::{Value, json};
use std::path::Path;

const HEAD: [Vec3; 4] = [
    Vec3::new(0.0, 0.0, 0.0),
    Vec3::new(1.0, 0.0, 0.0),
    Vec3::new(0.0, 1.0, 0.0),
    Vec3::new(0.0, 0.0, 1.0),
];
const JAW: [Vec3; 3] = [
    Vec3::new(2.0, 0.0, 0.0),
    Vec3::new(3.0, 0.0, 0.0),
    Vec3::new(2.0, 1.0, 0.0),
];
const TARGET_NAMES: [&str; 4] = [
    "EyeBlinkLeft",
    "browInnerUp_L",
    "browInnerUp_R",
    "Fcl_custom",
];

/// Local displacement of target `t` on a primitive of `n` vertices.
fn local_target(t: usize, n: usize) -> Vec<Vec3> {
    (0..n)
        .map(|v| match t {
            3 => Vec3::new(0.01, 0.0, 0.0),
            _ if v == t + 1 => Vec3::new(0.0, 0.1 * (t + 1) as f32, 0.02),
            _ => Vec3::ZERO,
        })
        .collect()
}

/// The head node's world transform in the fixture.
fn head_world() -> Mat4 {
    let body = Mat4::from_scale_rotation_translation(
        Vec3::splat(2.0),
        Quat::from_rotation_y(std::f32::consts::FRAC_PI_2),
        Vec3::new(1.0, 2.0, 3.0),
    );
    body * Mat4::from_translation(Vec3::new(0.0, 0.5, 0.0))
}

/// The fixture's JSON and binary buffer.
pub(super) fn fixture() -> (Value, Vec<u8>) {
    let mut b = Builder::new();
    let prim = |positions: &[Vec3], triangles: &[[u32; 3]], b: &mut Builder| {
        let targets: Vec<Value> = (0..4)
            .map(|t| json!({ "POSITION": b.target(&local_target(t, positions.len()), "", Default::default()) }))
            .collect();
        json!({
            "attributes": { "POSITION": b.vec3(positions) },
            "indices": b.triangles(triangles), "targets": targets, "material": 0,
        })
    };
    let p0 = prim(&HEAD, &[[0, 1, 2], [0, 2, 3]], &mut b);
    let p1 = prim(&JAW, &[[0, 1, 2]], &mut b);
    let teeth = json!({ "attributes": { "POSITION": b.vec3(&JAW) } });
    let q = Quat::from_rotation_y(std::f32::consts::FRAC_PI_2);
    let doc = json!({
        "asset": { "version": "2.0", "generator": "hand" },
        "extensionsUsed": ["EXT_made_up"],
        "extensions": { "EXT_made_up": { "x": [1, 2] } },
        "extras": { "note": "keep" },
        "scene": 0,
        "scenes": [{ "nodes": [0, 2] }],
        "nodes": [
            { "name": "Body", "children": [1], "translation": [1.0, 2.0, 3.0],
              "rotation": [q.x, q.y, q.z, q.w], "scale": [2.0, 2.0, 2.0] },
            { "name": "Head", "mesh": 0, "translation": [0.0, 0.5, 0.0] },
            { "name": "Teeth", "mesh": 1,
              "matrix": [1.0,0.0,0.0,0.0, 0.0,1.0,0.0,0.0, 0.0,0.0,1.0,0.0, 0.0,-1.0,0.0,1.0] },
        ],
        "meshes": [
            { "name": "Head", "primitives": [p0, p1], "weights": [0.5, 0.0, 0.0, 0.25],
              "extras": { "targetNames": TARGET_NAMES, "other": true } },
            { "name": "Teeth", "primitives": [teeth] },
        ],
        "materials": [{ "name": "skin", "extras": { "k": 1 } }],
        "accessors": b.accessors, "bufferViews": b.views,
        "buffers": [{ "byteLength": b.bin.len() }],
    });
    (doc, b.bin)
}

/// The floats of a dense float accessor of `g`.
pub(super) fn floats(g: &GlbAvatar, accessor: &Value) -> Vec<f32> {
    let a = &g.json()["accessors"][accessor.as_u64().unwrap() as usize];
    let view = &g.json()["bufferViews"][a["bufferView"].as_u64().unwrap() as usize];
    let start = view["byteOffset"].as_u64().unwrap_or(0) as usize
        + a["byteOffset"].as_u64().unwrap_or(0) as usize;
    let width = if a["type"] == "VEC4" { 4 } else { 3 };
    let count = a["count"].as_u64().unwrap() as usize * width;
    g.buffers()[0][start..start + 4 * count]
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect()
}

fn glb(doc: &Value, bin: &[u8]) -> Vec<u8> {
    join(&serde_json::to_vec(doc).unwrap(), bin)
}

fn read_fixture() -> GlbAvatar {
    let (doc, bin) = fixture();
    read_avatar_bytes(&glb(&doc, &bin), "fixture.glb").unwrap()
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).length() < 1e-5
}
