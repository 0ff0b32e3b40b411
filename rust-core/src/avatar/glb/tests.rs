//! The glTF reader and writers on a hand-built file: a transformed node
//! hierarchy, two meshes, ARKit names in odd spellings and split halves,
//! other targets, extensions and extras to be kept; and every error case.

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

#[test]
fn reads_world_positions_through_the_node_hierarchy() {
    let g = read_fixture();
    let a = &g.avatar;
    assert_eq!(a.parts.len(), 3);
    assert_eq!(a.meshes[0].target_names, TARGET_NAMES);
    let world = head_world();
    for (v, p) in HEAD.iter().zip(&a.parts[0].positions) {
        assert!(close(world.transform_point3(*v), *p));
    }
    // A displacement moves through the linear part only.
    let d = world.transform_vector3(local_target(0, 4)[1]);
    assert!(close(a.parts[0].targets[0][1], d));
    assert_eq!(a.parts[0].triangles, [[0, 1, 2], [0, 2, 3]]);
    // The teeth by their column-major matrix.
    assert!(close(a.parts[2].positions[0], Vec3::new(2.0, -1.0, 0.0)));
    assert_eq!(a.parts[2].name, "Teeth");
    let found = check_avatar(&g).unwrap();
    assert_eq!(found.of(Blendshape::BrowInnerUp), [(0, 1), (0, 2)]);
}

fn new_shapes(g: &GlbAvatar) -> NewShapes {
    let mut shapes = NewShapes::new();
    let moving = |k: usize, scale: f32| -> Vec<Vec<Vec3>> {
        g.avatar
            .parts
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let n = p.positions.len();
                (0..n)
                    .map(|v| {
                        if i == k && v == 1 {
                            Vec3::new(scale, 0.0, -scale)
                        } else {
                            Vec3::ZERO
                        }
                    })
                    .collect()
            })
            .collect()
    };
    shapes.set(Blendshape::EyeBlinkLeft, moving(0, 0.3));
    shapes.set(Blendshape::BrowInnerUp, moving(1, 0.2));
    shapes.set(Blendshape::JawOpen, moving(2, 0.4)); // only the teeth move
    shapes
}

/// The JSON without what a write-back may change, each reference to an
/// accessor replaced by the accessor (its view by the view's bytes), since
/// dropping replaced targets' accessors renumbers the rest.
fn untouched_part(g: &GlbAvatar) -> Value {
    let original = g.json().clone();
    let mut doc = original.clone();
    let resolved = |i: &Value| {
        let doc = &original;
        let mut a = doc["accessors"][i.as_u64().unwrap() as usize].clone();
        let view = &doc["bufferViews"][a["bufferView"].as_u64().unwrap() as usize];
        let at = view["byteOffset"].as_u64().unwrap_or(0) as usize;
        let len = view["byteLength"].as_u64().unwrap() as usize;
        let buffer = &g.buffers()[view["buffer"].as_u64().unwrap() as usize];
        a["bufferView"] = json!(buffer[at..at + len]);
        a
    };
    for m in 0..doc["meshes"].as_array().unwrap().len() {
        for p in 0..doc["meshes"][m]["primitives"].as_array().unwrap().len() {
            let prim = doc["meshes"][m]["primitives"][p].clone();
            let mut attributes = prim["attributes"].clone();
            for (_, v) in attributes.as_object_mut().unwrap() {
                *v = resolved(v);
            }
            doc["meshes"][m]["primitives"][p]["attributes"] = attributes;
            if let Some(i) = prim.get("indices") {
                doc["meshes"][m]["primitives"][p]["indices"] = resolved(i);
            }
        }
    }
    let o = doc.as_object_mut().unwrap();
    for key in ["accessors", "bufferViews", "buffers"] {
        o.remove(key);
    }
    for mesh in doc["meshes"].as_array_mut().unwrap() {
        strip_targets(mesh);
        for p in mesh["primitives"].as_array_mut().unwrap() {
            strip_targets(p);
        }
    }
    for node in doc["nodes"].as_array_mut().unwrap() {
        node.as_object_mut().unwrap().remove("weights");
    }
    doc
}

fn strip_targets(v: &mut Value) {
    let o = v.as_object_mut().unwrap();
    o.remove("targets");
    o.remove("weights");
    if let Some(e) = o.get_mut("extras").and_then(Value::as_object_mut) {
        e.remove("targetNames");
        if e.is_empty() {
            o.remove("extras");
        }
    }
}

#[test]
fn write_back_replaces_arkit_targets_and_keeps_the_rest() {
    let g = read_fixture();
    let shapes = new_shapes(&g);
    let bytes =
        written_back_glb(&g, &shapes, TargetEncoding::Smallest, Path::new("o.glb")).unwrap();
    let back = read_avatar_bytes(&bytes, "o.glb").unwrap();
    assert_eq!(untouched_part(&back), untouched_part(&g));
    let names = &back.avatar.meshes[0].target_names;
    assert_eq!(names, &["eyeBlinkLeft", "browInnerUp", "Fcl_custom"]);
    assert_eq!(back.avatar.meshes[1].target_names, ["jawOpen"]);
    assert_eq!(back.json()["meshes"][0]["weights"], json!([0.5, 0.0, 0.25]));
    assert_eq!(back.json()["meshes"][0]["extras"]["other"], json!(true));
    assert_eq!(
        back.json()["meshes"][0]["primitives"][1]["extras"]["targetNames"],
        json!(names)
    );
    // New data, back in world space; the kept target untouched.
    for (k, part) in back.avatar.parts.iter().enumerate() {
        let expect = [
            shapes.get(Blendshape::EyeBlinkLeft),
            shapes.get(Blendshape::BrowInnerUp),
        ];
        for (t, want) in expect.iter().enumerate().take(if k < 2 { 2 } else { 0 }) {
            let want = &want.unwrap()[k];
            assert!(part.targets[t].iter().zip(want).all(|(a, b)| close(*a, *b)));
        }
    }
    assert_eq!(
        back.avatar.parts[0].targets[2],
        g.avatar.parts[0].targets[3]
    );
    assert!(close(
        back.avatar.parts[2].targets[0][1],
        Vec3::new(0.4, 0.0, -0.4)
    ));
    // Written in the head's own space: inverse of its linear part.
    let local = &back.json()["meshes"][0]["primitives"][0]["targets"][0]["POSITION"];
    let a = &back.json()["accessors"][local.as_u64().unwrap() as usize];
    let want = head_world()
        .inverse()
        .transform_vector3(Vec3::new(0.3, 0.0, -0.3));
    let max = a["max"].as_array().unwrap();
    assert!((max[0].as_f64().unwrap() as f32 - want.x.max(0.0)).abs() < 1e-6);
    assert!(
        a.get("sparse").is_some(),
        "one moving vertex of four is sparse"
    );
    // No accessor or view left unused.
    let n = back.json()["accessors"].as_array().unwrap().len();
    assert!(
        super::refs::used(back.json(), super::refs::Kind::Accessor, n)
            .iter()
            .all(|&u| u)
    );
}

#[test]
fn writing_back_nothing_keeps_data_and_spells_names() {
    let g = read_fixture();
    let bytes = written_back_glb(
        &g,
        &NewShapes::new(),
        TargetEncoding::Smallest,
        Path::new("o.glb"),
    )
    .unwrap();
    let back = read_avatar_bytes(&bytes, "o.glb").unwrap();
    assert_eq!(back.avatar.parts, g.avatar.parts);
    // Nothing dropped, nothing renumbered.
    assert_eq!(back.json()["accessors"], g.json()["accessors"]);
    assert_eq!(back.json()["nodes"], g.json()["nodes"]);
    assert_eq!(back.avatar.meshes[0].target_names[0], "eyeBlinkLeft");
    assert_eq!(back.avatar.meshes[0].target_names[1], "browInnerUp_L");
}

#[test]
fn sparse_when_smaller_dense_otherwise_both_exact() {
    let n = 300;
    let positions: Vec<Vec3> = (0..n)
        .map(|i| Vec3::new(i as f32, (i % 7) as f32, 0.0))
        .collect();
    let triangles: Vec<[u32; 3]> = (0..n as u32 - 2).map(|i| [i, i + 1, i + 2]).collect();
    let few: Vec<Vec3> = (0..n)
        .map(|i| {
            if i % 50 == 3 {
                Vec3::new(0.1, -0.2, 1e-7)
            } else {
                Vec3::ZERO
            }
        })
        .collect();
    let all: Vec<Vec3> = (0..n)
        .map(|i| Vec3::new(i as f32 * 1e-3, 0.5, -0.25))
        .collect();
    let avatar = Avatar {
        meshes: vec![AvatarMesh {
            name: Some("m".into()),
            target_names: vec!["JawOpen".into(), "mouthClose".into()],
        }],
        parts: vec![AvatarPart {
            name: "m".into(),
            mesh: 0,
            primitive: 0,
            positions,
            triangles,
            targets: vec![few.clone(), all.clone()],
        }],
    };
    let bytes = new_avatar_glb(&avatar, &NewGlbOptions::default(), Path::new("n.glb")).unwrap();
    let back = read_avatar_bytes(&bytes, "n.glb").unwrap();
    let acc = &back.json()["accessors"];
    let t = &back.json()["meshes"][0]["primitives"][0]["targets"];
    assert!(
        acc[t[0]["POSITION"].as_u64().unwrap() as usize]
            .get("sparse")
            .is_some()
    );
    assert!(
        acc[t[1]["POSITION"].as_u64().unwrap() as usize]
            .get("sparse")
            .is_none()
    );
    assert_eq!(back.avatar.parts[0].targets, [few, all]);
    assert_eq!(
        back.avatar.meshes[0].target_names,
        ["jawOpen", "mouthClose"]
    );
    assert_eq!(back.avatar.parts[0].positions, avatar.parts[0].positions);
    let dense = NewGlbOptions {
        encoding: TargetEncoding::Dense,
        ..Default::default()
    };
    let bigger = new_avatar_glb(&avatar, &dense, Path::new("d.glb")).unwrap();
    assert!(bigger.len() > bytes.len());
    assert_eq!(
        read_avatar_bytes(&bigger, "d.glb").unwrap().avatar.parts[0].targets,
        avatar.parts[0].targets
    );
}

/// Reads a modified fixture, expecting an error.
fn error_of(edit: impl FnOnce(&mut Value, &mut Vec<u8>)) -> GlbError {
    let (mut doc, mut bin) = fixture();
    edit(&mut doc, &mut bin);
    match read_avatar_bytes(&glb(&doc, &bin), "bad.glb") {
        Err(e) => e,
        Ok(_) => panic!("read a broken file"),
    }
}

/// Byte offset of accessor `a`'s first element.
fn offset_of(doc: &Value, a: usize) -> usize {
    let view = &doc["bufferViews"][doc["accessors"][a]["bufferView"].as_u64().unwrap() as usize];
    view["byteOffset"].as_u64().unwrap() as usize
}

#[test]
fn every_broken_file_gives_its_typed_error() {
    let (doc, bin) = fixture();
    let good = glb(&doc, &bin);
    let e = read_avatar_bytes(&good[..good.len() - 10], "cut.glb").unwrap_err();
    assert!(matches!(e, GlbError::Truncated { .. }), "{e}");
    let mut bad = good.clone();
    bad[0] = b'x';
    assert!(matches!(
        read_avatar_bytes(&bad, "m.glb"),
        Err(GlbError::NotGltf { .. })
    ));
    let e = error_of(|d, _| d["accessors"][8]["count"] = json!(1_000_000_000u64));
    assert!(matches!(e, GlbError::Accessor { accessor: 8, .. }), "{e}");
    let e = error_of(|d, b| {
        let at = offset_of(
            d,
            d["meshes"][0]["primitives"][0]["attributes"]["POSITION"]
                .as_u64()
                .unwrap() as usize,
        );
        b[at + 16..at + 20].copy_from_slice(&f32::NAN.to_le_bytes());
    });
    assert!(
        matches!(
            e,
            GlbError::NotFinite {
                mesh: 0,
                primitive: 0,
                vertex: 1,
                ..
            }
        ),
        "{e}"
    );
    let index_at = |d: &Value| {
        offset_of(
            d,
            d["meshes"][0]["primitives"][0]["indices"].as_u64().unwrap() as usize,
        )
    };
    let e = error_of(|d, b| {
        let at = index_at(d);
        b[at + 2..at + 4].copy_from_slice(&9u16.to_le_bytes());
    });
    assert!(matches!(e, GlbError::Triangle { triangle: 0, .. }), "{e}");
    let e = error_of(|d, b| {
        let at = index_at(d);
        b[at + 8..at + 10].copy_from_slice(&0u16.to_le_bytes());
    });
    assert!(matches!(e, GlbError::Triangle { triangle: 1, .. }), "{e}");
    let e = error_of(|d, _| {
        d["meshes"][0]["primitives"][1]["targets"]
            .as_array_mut()
            .unwrap()
            .pop();
    });
    assert!(
        matches!(
            e,
            GlbError::TargetCount {
                mesh: 0,
                primitive: 1,
                expected: 4,
                found: 3,
                ..
            }
        ),
        "{e}"
    );
    let e = error_of(|d, _| d["meshes"][1]["primitives"][0]["mode"] = json!(1));
    assert!(matches!(e, GlbError::Primitive { mesh: 1, .. }), "{e}");
    let e = error_of(|d, _| d["scenes"][0]["nodes"] = json!([]));
    assert!(matches!(e, GlbError::NoMesh { .. }), "{e}");
    let e = error_of(|d, _| d["nodes"][1]["mesh"] = json!(7));
    assert!(matches!(e, GlbError::Invalid { .. }), "{e}");
    let e = error_of(|d, _| d["extensionsRequired"] = json!(["KHR_draco_mesh_compression"]));
    assert!(matches!(e, GlbError::Invalid { .. }), "{e}");
    let e = error_of(|d, _| d["buffers"][0]["byteLength"] = json!(1 << 30));
    assert!(matches!(e, GlbError::Buffer { buffer: 0, .. }), "{e}");
}

#[test]
fn check_avatar_wants_targets_with_arkit_names() {
    let (mut doc, bin) = fixture();
    doc["meshes"][0]["extras"]["targetNames"] = json!(["a", "b", "c", "d"]);
    let g = read_avatar_bytes(&glb(&doc, &bin), "x.glb").unwrap();
    assert!(matches!(
        check_avatar(&g),
        Err(GlbError::NoArkitTargets { .. })
    ));
    let teeth_only = json!({ "asset": { "version": "2.0" }, "scenes": [{ "nodes": [0] }],
        "nodes": [{ "mesh": 0 }], "meshes": [doc["meshes"][1].clone()],
        "accessors": doc["accessors"], "bufferViews": doc["bufferViews"], "buffers": doc["buffers"] });
    let g = read_avatar_bytes(&glb(&teeth_only, &bin), "t.glb").unwrap();
    assert!(matches!(
        check_avatar(&g),
        Err(GlbError::NoMorphTargets { .. })
    ));
}

#[test]
fn names_fall_back_to_primitive_extras_then_accessor_names() {
    let (mut doc, bin) = fixture();
    doc["meshes"][0]["extras"] = json!({});
    doc["meshes"][0]["primitives"][0]["extras"] = json!({ "targetNames": ["jawOpen"] });
    let a = doc["meshes"][0]["primitives"][0]["targets"][1]["POSITION"]
        .as_u64()
        .unwrap() as usize;
    doc["accessors"][a]["name"] = json!("cheekPuff");
    let g = read_avatar_bytes(&glb(&doc, &bin), "x.glb").unwrap();
    assert_eq!(
        g.avatar.meshes[0].target_names,
        ["jawOpen", "cheekPuff", "target 2", "target 3"]
    );
}

#[test]
fn gltf_with_a_data_uri_and_a_bin_file_beside_it() {
    let (mut doc, bin) = fixture();
    let dir = std::env::temp_dir().join(format!("likeness-gltf-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("body data.bin"), &bin).unwrap();
    doc["buffers"][0]["uri"] = json!("body%20data.bin");
    let path = dir.join("a.gltf");
    std::fs::write(&path, serde_json::to_vec(&doc).unwrap()).unwrap();
    let from_file = read_avatar(&path).unwrap();
    assert_eq!(from_file.avatar, read_fixture().avatar);
    let out = dir.join("out.glb");
    write_avatar(&from_file, &new_shapes(&from_file), &out).unwrap();
    assert_eq!(
        read_avatar(&out).unwrap().avatar.meshes[1].target_names,
        ["jawOpen"]
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_skinned_mesh_is_placed_by_its_bind_pose_not_its_node() {
    let (mut doc, mut bin) = fixture();
    // Joint at y = 1 with an inverse bind matrix of y − 0.5: bind placement
    // is y + 0.5, whatever the skinned node's own matrix (y − 1) says.
    let ibm = Mat4::from_translation(Vec3::new(0.0, -0.5, 0.0));
    bin.resize(bin.len().next_multiple_of(4), 0);
    let at = bin.len();
    bin.extend(ibm.to_cols_array().iter().flat_map(|x| x.to_le_bytes()));
    doc["buffers"][0]["byteLength"] = json!(bin.len());
    let views = doc["bufferViews"].as_array_mut().unwrap();
    views.push(json!({ "buffer": 0, "byteOffset": at, "byteLength": 64 }));
    let view = views.len() - 1;
    let accessors = doc["accessors"].as_array_mut().unwrap();
    accessors
        .push(json!({ "bufferView": view, "componentType": 5126, "count": 1, "type": "MAT4" }));
    let ibm_accessor = accessors.len() - 1;
    doc["nodes"]
        .as_array_mut()
        .unwrap()
        .push(json!({ "name": "Jaw", "translation": [0.0, 1.0, 0.0] }));
    doc["scenes"][0]["nodes"] = json!([0, 2, 3]);
    doc["nodes"][2]["skin"] = json!(0);
    doc["skins"] = json!([{ "joints": [3], "inverseBindMatrices": ibm_accessor }]);
    let g = read_avatar_bytes(&glb(&doc, &bin), "skinned.glb").unwrap();
    assert!(close(
        g.avatar.parts[2].positions[0],
        Vec3::new(2.0, 0.5, 0.0)
    ));
    assert_eq!(g.placements[2].node, 2);
}

#[test]
fn required_extensions_that_leave_geometry_alone_are_read_and_kept() {
    let (mut doc, bin) = fixture();
    doc["extensionsUsed"] = json!(["EXT_made_up", "KHR_texture_transform"]);
    doc["extensionsRequired"] = json!(["KHR_texture_transform"]);
    let g = read_avatar_bytes(&glb(&doc, &bin), "x.glb").unwrap();
    let bytes = written_back_glb(
        &g,
        &NewShapes::new(),
        TargetEncoding::Smallest,
        Path::new("o"),
    )
    .unwrap();
    let back = read_avatar_bytes(&bytes, "o").unwrap();
    assert_eq!(
        back.json()["extensionsRequired"],
        json!(["KHR_texture_transform"])
    );
}

#[test]
fn a_cycle_in_the_hierarchy_does_not_hang() {
    let (mut doc, bin) = fixture();
    doc["nodes"][1]["children"] = json!([0]);
    // Either a validation error or a read; neither loops.
    let _ = read_avatar_bytes(&glb(&doc, &bin), "cycle.glb");
}
