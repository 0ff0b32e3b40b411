//! Every GLB Likeness writes passes the Khronos glTF-Validator with no
//! error, warning or info: a new avatar of three meshes with sparse and
//! dense targets, and that file as a `.gltf` with a scaled, rotated,
//! translated node, a skinned mesh and normal deltas on its targets, read
//! and written back with new shapes. The validator runs under Node from
//! `tests/js` (`likeness_tests::gltf_validator`): without it this test
//! skips, unless `LIKENESS_REQUIRE_TOOLS=1`.

use glam::{Quat, Vec3};
use likeness::Blendshape;
use likeness::avatar::glb::{
    MeshLook, NewGlbOptions, NewShapes, read_avatar, write_avatar, write_new_avatar,
};
use likeness::avatar::{Avatar, AvatarPart};
use likeness_sim::grid_avatar;
use likeness_tests::gltf_validator::validate;
use serde_json::{Value, json};
use std::path::PathBuf;

/// A `w × h` grid (1 cm apart) at depth `z`, as a part of mesh `mesh`:
/// its target 0 moves every tenth vertex (sparse), its target 1 every
/// vertex but every third (dense), any further one nothing.
fn grid(mesh: usize, w: u32, h: u32, z: f32, targets: usize) -> AvatarPart {
    grid_avatar::part(
        mesh,
        grid_avatar::grid(w, h, 0.01, z),
        targets,
        |t, v, _| match t {
            0 if v % 10 == 0 => Vec3::new(0.0, -0.004, 0.001),
            1 => Vec3::new(0.0, 0.0, 0.002 * (v % 3) as f32),
            _ => Vec3::ZERO,
        },
    )
}

/// Head, teeth and eyes: targets in several spellings, one not ARKit's.
fn avatar() -> Avatar {
    grid_avatar::avatar(
        &[
            ("Head", &["JawOpen", "eyeBlink_L", "Fcl_custom"][..]),
            ("Teeth", &["jawOpen"]),
            ("Eyes", &[]),
        ],
        vec![
            grid(0, 30, 30, 0.0, 3),
            grid(1, 5, 4, -0.01, 1),
            grid(2, 4, 4, 0.01, 0),
        ],
    )
}

/// Appends `bytes` as a buffer view and an accessor over it; the
/// accessor's index.
fn push_accessor(doc: &mut Value, bin: &mut Vec<u8>, bytes: &[u8], accessor: Value) -> usize {
    bin.resize(bin.len().next_multiple_of(4), 0);
    let views = doc["bufferViews"].as_array_mut().unwrap();
    let mut view = json!({ "buffer": 0, "byteOffset": bin.len(), "byteLength": bytes.len() });
    if accessor["type"] != "MAT4" {
        view["target"] = json!(34962); // vertex data
    }
    views.push(view);
    let mut accessor = accessor;
    accessor["bufferView"] = json!(views.len() - 1);
    bin.extend_from_slice(bytes);
    let accessors = doc["accessors"].as_array_mut().unwrap();
    accessors.push(accessor);
    accessors.len() - 1
}

/// The teeth become skinned to one joint at y = 1.5 whose inverse bind
/// matrix undoes it: their bind placement is the identity, whatever their
/// node says.
fn add_skin_to_teeth(doc: &mut Value, bin: &mut Vec<u8>) {
    let n = 20; // the teeth grid's vertices
    let joints: Vec<u8> = (0..n).flat_map(|_| [0u8, 0, 0, 0]).collect();
    let weights: Vec<u8> = (0..n)
        .flat_map(|_| [1.0f32, 0.0, 0.0, 0.0])
        .flat_map(f32::to_le_bytes)
        .collect();
    let ibm: Vec<u8> = glam::Mat4::from_translation(Vec3::new(0.0, -1.5, 0.0))
        .to_cols_array()
        .into_iter()
        .flat_map(f32::to_le_bytes)
        .collect();
    let j = push_accessor(
        doc,
        bin,
        &joints,
        json!({ "componentType": 5121, "count": n, "type": "VEC4" }),
    );
    let w = push_accessor(
        doc,
        bin,
        &weights,
        json!({ "componentType": 5126, "count": n, "type": "VEC4" }),
    );
    let i = push_accessor(
        doc,
        bin,
        &ibm,
        json!({ "componentType": 5126, "count": 1, "type": "MAT4" }),
    );
    let attributes = &mut doc["meshes"][1]["primitives"][0]["attributes"];
    attributes["JOINTS_0"] = json!(j);
    attributes["WEIGHTS_0"] = json!(w);
    let nodes = doc["nodes"].as_array_mut().unwrap();
    nodes.push(json!({ "name": "Jaw", "translation": [0.0, 1.5, 0.0] }));
    let joint = nodes.len() - 1;
    nodes[1]["skin"] = json!(0);
    doc["skins"] = json!([{ "joints": [joint], "inverseBindMatrices": i }]);
    doc["scenes"][0]["nodes"]
        .as_array_mut()
        .unwrap()
        .push(json!(joint));
}

fn temp_dir() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("likeness-glb-validator-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn assert_clean(reports: &[Value]) {
    for r in reports {
        let issues = &r["issues"];
        eprintln!(
            "{} (validator {}): {} errors, {} warnings, {} infos, {} hints",
            r["file"],
            r["validatorVersion"],
            issues["numErrors"],
            issues["numWarnings"],
            issues["numInfos"],
            issues["numHints"]
        );
        for m in issues["messages"].as_array().unwrap() {
            eprintln!("{}: {m}", r["file"]);
        }
        assert_eq!(issues["numErrors"], json!(0), "{}", r["file"]);
        assert_eq!(issues["numWarnings"], json!(0), "{}", r["file"]);
        assert_eq!(issues["numInfos"], json!(0), "{}", r["file"]);
        assert_eq!(issues["numHints"], json!(0), "{}", r["file"]);
    }
}

#[test]
fn written_glbs_pass_the_khronos_validator() {
    let dir = temp_dir();
    let looks = vec![MeshLook::SKIN, MeshLook::TOOTH, MeshLook::EYE_WHITE];
    let new = dir.join("new.glb");
    write_new_avatar(
        &avatar(),
        &NewGlbOptions {
            looks,
            ..Default::default()
        },
        &new,
    )
    .unwrap();

    // The new file as a .gltf beside its .bin, its node moved, rotated and
    // scaled, then read and written back with new shapes.
    let read = read_avatar(&new).unwrap();
    let mut doc = read.json().clone();
    let q = Quat::from_rotation_x(0.3);
    doc["nodes"][0]["translation"] = json!([0.1, 1.6, 0.0]);
    doc["nodes"][0]["rotation"] = json!([q.x, q.y, q.z, q.w]);
    doc["nodes"][0]["scale"] = json!([0.5, 0.5, 0.5]);
    let mut bin = read.buffers()[0].clone();
    add_skin_to_teeth(&mut doc, &mut bin);
    doc["buffers"][0]["uri"] = json!("moved.bin");
    doc["buffers"][0]["byteLength"] = json!(bin.len());
    std::fs::write(dir.join("moved.bin"), &bin).unwrap();
    let gltf = dir.join("moved.gltf");
    std::fs::write(&gltf, serde_json::to_vec(&doc).unwrap()).unwrap();
    let moved = read_avatar(&gltf).unwrap();
    let mut shapes = NewShapes::new();
    let per_part = |f: &dyn Fn(usize, Vec3) -> Vec3| -> Vec<Vec<Vec3>> {
        moved
            .avatar
            .parts()
            .iter()
            .map(|p| {
                p.positions
                    .iter()
                    .enumerate()
                    .map(|(v, &x)| f(v, x))
                    .collect()
            })
            .collect()
    };
    shapes.set(
        Blendshape::JawOpen,
        per_part(&|_, x| Vec3::new(0.0, -0.01 * x.x, 0.0)),
    );
    shapes.set(
        Blendshape::EyeBlinkLeft,
        per_part(&|v, _| {
            if v % 17 == 0 {
                Vec3::Y * 0.003
            } else {
                Vec3::ZERO
            }
        }),
    );
    shapes.set(
        Blendshape::CheekPuff,
        per_part(&|v, _| {
            if v < 40 { Vec3::Z * 0.002 } else { Vec3::ZERO }
        }),
    );
    // A new rest too (the person's face taken): positions through the
    // moved node and the skinned teeth's bind placement, normals turned.
    let rest = per_part(&|v, x| {
        x + if v % 5 == 0 {
            Vec3::new(0.0, 0.001, 0.0005)
        } else {
            Vec3::ZERO
        }
    });
    shapes.set_rest(rest.clone());
    let teeth = &moved.avatar.parts()[1];
    assert_eq!(
        teeth.positions,
        avatar().parts()[1].positions,
        "bind placement"
    );
    let back = dir.join("back.glb");
    write_avatar(&moved, &shapes, &back).unwrap();
    let reread = read_avatar(&back).unwrap();
    for (part, want) in reread.avatar.parts().iter().zip(&rest) {
        for (got, want) in part.positions.iter().zip(want) {
            assert!((*got - *want).length() < 1e-6, "{got} against {want}");
        }
    }
    // The new file's targets carry normal deltas (`write_new_avatar`
    // writes them); replaced and new targets get their own anew (the
    // primitive has normals), the kept one keeps its.
    let targets = &reread.json()["meshes"][0]["primitives"][0]["targets"];
    assert!((0..4).all(|t| targets[t].get("NORMAL").is_some()));
    // The eyes had no targets; the new shapes move them (Apple's order).
    assert_eq!(
        reread.avatar.meshes()[2].target_names,
        ["eyeBlinkLeft", "jawOpen", "cheekPuff"]
    );
    assert_eq!(
        reread.avatar.meshes()[0].target_names,
        ["jawOpen", "eyeBlinkLeft", "Fcl_custom", "cheekPuff"]
    );

    // A control: the validator does see a wrong `max`.
    let mut wrong = doc.clone();
    wrong["accessors"][0]["max"] = json!([9.0, 9.0, 9.0]);
    let control = dir.join("wrong.gltf");
    std::fs::write(&control, serde_json::to_vec(&wrong).unwrap()).unwrap();

    let Some(reports) = validate(
        "written_glbs_pass_the_khronos_validator",
        &[new, back, control],
    ) else {
        return;
    };
    assert_eq!(reports.len(), 3);
    assert_clean(&reports[..2]);
    assert_ne!(reports[2]["issues"]["numErrors"], json!(0), "the control");
    std::fs::remove_dir_all(&dir).unwrap();
}
