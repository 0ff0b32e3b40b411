//! The encoder on a small avatar, and the dequantization folded into
//! nodes of either kind (matrix, TRS) and undone for their children.

use super::quantize::{Dequantization, fold_into, unfold_from_child};
use super::*;
use glam::{Mat4, Quat, Vec3};
use likeness::avatar::glb::{NewGlbOptions, new_avatar_glb, read_avatar_bytes};
use likeness::avatar::{Avatar, AvatarMesh, AvatarPart};

fn node_matrix(node: &Value) -> Mat4 {
    let f = |v: &Value, k: usize, d: f32| v[k].as_f64().map_or(d, |x| x as f32);
    if node.get("matrix").is_some() {
        return Mat4::from_cols_array(&std::array::from_fn(|k| f(&node["matrix"], k, 0.0)));
    }
    let t = Vec3::new(
        f(&node["translation"], 0, 0.0),
        f(&node["translation"], 1, 0.0),
        f(&node["translation"], 2, 0.0),
    );
    let r = Quat::from_xyzw(
        f(&node["rotation"], 0, 0.0),
        f(&node["rotation"], 1, 0.0),
        f(&node["rotation"], 2, 0.0),
        f(&node["rotation"], 3, 1.0),
    );
    let s = Vec3::new(
        f(&node["scale"], 0, 1.0),
        f(&node["scale"], 1, 1.0),
        f(&node["scale"], 2, 1.0),
    );
    Mat4::from_scale_rotation_translation(s, r, t)
}

#[test]
fn folding_appends_the_dequantization_and_unfolding_prepends_its_inverse() {
    let d = Dequantization {
        offset: [0.1, -0.2, 0.3],
        scale: 0.25,
    };
    let dm = Mat4::from_translation(Vec3::from(d.offset)) * Mat4::from_scale(Vec3::splat(d.scale));
    let q = Quat::from_rotation_y(0.7);
    let trs = json!({ "translation": [1.0, 2.0, 3.0], "rotation": [q.x, q.y, q.z, q.w], "scale": [2.0, 2.0, 2.0] });
    let matrix = json!({ "matrix": Mat4::from_rotation_x(0.3).mul_mat4(&Mat4::from_translation(Vec3::ONE)).to_cols_array() });
    for node in [trs, matrix] {
        let before = node_matrix(&node);
        let mut folded = node.clone();
        fold_into(&mut folded, d);
        assert!(node_matrix(&folded).abs_diff_eq(before * dm, 1e-5));
        let mut child = node.clone();
        unfold_from_child(&mut child, d);
        assert!(node_matrix(&child).abs_diff_eq(dm.inverse() * before, 1e-5));
    }
}

#[test]
fn a_small_avatar_compresses_and_reads_back() {
    let positions: Vec<Vec3> = (0..16)
        .map(|k| {
            Vec3::new(
                (k % 4) as f32 * 0.01,
                (k / 4) as f32 * 0.01,
                0.002 * (k % 3) as f32,
            )
        })
        .collect();
    let mut triangles = Vec::new();
    for y in 0..3u32 {
        for x in 0..3u32 {
            let i = y * 4 + x;
            triangles.push([i, i + 1, i + 5]);
            triangles.push([i, i + 5, i + 4]);
        }
    }
    let target: Vec<Vec3> = (0..16)
        .map(|k| Vec3::new(0.0, -0.001 * k as f32, 0.0))
        .collect();
    let avatar = Avatar::new(
        vec![AvatarMesh {
            name: Some("face".into()),
            target_names: vec!["jawOpen".into()],
        }],
        vec![AvatarPart {
            name: "face".into(),
            mesh: 0,
            primitive: 0,
            positions: positions.clone(),
            triangles: triangles.clone(),
            targets: vec![target.clone()],
        }],
    )
    .unwrap();
    let plain = new_avatar_glb(
        &avatar,
        &NewGlbOptions::default(),
        std::path::Path::new("a.glb"),
    )
    .unwrap();
    let compressed = meshopt_compressed(&plain).unwrap();
    let read = read_avatar_bytes(&compressed, "c.glb").unwrap();
    let part = &read.avatar.parts()[0];
    // Half the longest side is 0.015 m (the target moves 0.015 m too):
    // half a step of 0.015 / 32767.
    let tol = 0.015 / 65534.0 + 1e-7;
    for (a, b) in positions.iter().zip(&part.positions) {
        assert!((*a - *b).abs().max_element() <= tol, "{a} vs {b}");
    }
    for (a, b) in target.iter().zip(&part.targets[0]) {
        assert!((*a - *b).abs().max_element() <= tol, "{a} vs {b}");
    }
    assert_eq!(part.triangles.len(), triangles.len());
}
