//! Reading: world placement, target names, skins, `.gltf` buffers, and a
//! typed error for every broken file.

use super::*;

#[test]
fn reads_world_positions_through_the_node_hierarchy() {
    let g = read_fixture();
    let a = &g.avatar;
    assert_eq!(a.parts().len(), 3);
    assert_eq!(a.meshes()[0].target_names, TARGET_NAMES);
    let world = head_world();
    for (v, p) in HEAD.iter().zip(&a.parts()[0].positions) {
        assert!(close(world.transform_point3(*v), *p));
    }
    // A displacement moves through the linear part only.
    let d = world.transform_vector3(local_target(0, 4)[1]);
    assert!(close(a.parts()[0].targets[0][1], d));
    assert_eq!(a.parts()[0].triangles, [[0, 1, 2], [0, 2, 3]]);
    // The teeth by their column-major matrix.
    assert!(close(a.parts()[2].positions[0], Vec3::new(2.0, -1.0, 0.0)));
    assert_eq!(a.parts()[2].name, "Teeth");
    let found = check_avatar(&g).unwrap();
    assert_eq!(found.of(Blendshape::BrowInnerUp), [(0, 1), (0, 2)]);
}

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
    // gltf-json would index past its accessors here: checked first.
    let e = error_of(|d, _| d["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = json!(999));
    assert!(matches!(e, GlbError::Invalid { .. }), "{e}");
    let e = error_of(|d, _| d["nodes"][1]["mesh"] = json!(7));
    assert!(matches!(e, GlbError::Invalid { .. }), "{e}");
    let e = error_of(|d, _| d["extensionsRequired"] = json!(["EXT_mesh_gpu_instancing"]));
    assert!(matches!(e, GlbError::Unsupported { .. }), "{e}");
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
        g.avatar.meshes()[0].target_names,
        ["jawOpen", "cheekPuff", "target 2", "target 3"]
    );
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
        g.avatar.parts()[2].positions[0],
        Vec3::new(2.0, 0.5, 0.0)
    ));
    assert_eq!(g.placements[2].node, 2);
}

/// Body → Head → Body: the file reads, every mesh once, and the cycle is
/// cut where it closes: the head, reached first from the body, keeps only
/// its own transform (the body's is left out of it).
#[test]
fn a_cycle_in_the_hierarchy_is_cut_where_it_closes() {
    let (mut doc, bin) = fixture();
    doc["nodes"][1]["children"] = json!([0]);
    let g = read_avatar_bytes(&glb(&doc, &bin), "cycle.glb").expect("reads");
    let plain = read_fixture();
    assert_eq!(g.avatar.parts().len(), plain.avatar.parts().len());
    let head_alone = Mat4::from_translation(Vec3::new(0.0, 0.5, 0.0));
    let to_cycle = head_alone * head_world().inverse();
    for (p, q) in g.avatar.parts()[0]
        .positions
        .iter()
        .zip(&plain.avatar.parts()[0].positions)
    {
        assert!(close(*p, to_cycle.transform_point3(*q)), "{p} vs {q}");
    }
    assert_eq!(
        g.avatar.parts()[0].triangles,
        plain.avatar.parts()[0].triangles
    );
}

#[test]
fn no_corrupted_byte_panics() {
    let (doc, bin) = fixture();
    let good = glb(&doc, &bin);
    for at in 0..good.len() {
        for flip in [0x01u8, 0x80, 0xFF] {
            let mut bad = good.clone();
            bad[at] ^= flip;
            // An error or a read; never a panic or a huge allocation.
            let _ = read_avatar_bytes(&bad, "flipped.glb");
        }
    }
}

#[test]
fn a_mirroring_node_reverses_the_winding() {
    let (mut doc, bin) = fixture();
    doc["nodes"][1]["scale"] = json!([-1.0, 1.0, 1.0]);
    let g = read_avatar_bytes(&glb(&doc, &bin), "mirrored.glb").unwrap();
    assert_eq!(g.avatar.parts()[0].triangles, [[0, 2, 1], [0, 3, 2]]);
    // Still facing the same way in world space as the unmirrored file.
    let plain = read_fixture();
    let normal = |p: &crate::avatar::AvatarPart| {
        let [a, b, c] = p.triangles[0].map(|i| p.positions[i as usize]);
        (b - a).cross(c - a).normalize()
    };
    let mirror = |v: Vec3| Vec3::new(-v.x, v.y, v.z);
    let (m, u) = (
        normal(&g.avatar.parts()[0]),
        normal(&plain.avatar.parts()[0]),
    );
    // Mirroring the head in its own x: the face normal mirrors with it.
    let world = head_world();
    let axis = world.transform_vector3(Vec3::X).normalize();
    let reflected = u - 2.0 * u.dot(axis) * axis;
    assert!(close(m, reflected), "{m} vs {reflected} ({})", mirror(u));
}

#[test]
fn quantized_positions_read_as_floats_and_write_back_as_floats() {
    let (mut doc, mut bin) = fixture();
    // The teeth's 3 positions as normalized SHORT, stride 8 (KHR_mesh_quantization).
    let q: [[i16; 3]; 3] = [[32767, 0, 0], [0, -32767, 0], [0, 0, 16384]];
    bin.resize(bin.len().next_multiple_of(4), 0);
    let offset = bin.len();
    for v in q {
        for c in v {
            bin.extend_from_slice(&c.to_le_bytes());
        }
        bin.extend_from_slice(&[0, 0]);
    }
    doc["buffers"][0]["byteLength"] = json!(bin.len());
    let views = doc["bufferViews"].as_array_mut().unwrap();
    views.push(json!({ "buffer": 0, "byteOffset": offset, "byteLength": 24, "byteStride": 8 }));
    let view = views.len() - 1;
    let accessors = doc["accessors"].as_array_mut().unwrap();
    accessors.push(
        json!({ "bufferView": view, "componentType": 5122, "normalized": true,
        "count": 3, "type": "VEC3", "min": [0, -32767, 0], "max": [32767, 0, 16384] }),
    );
    let a = accessors.len() - 1;
    doc["meshes"][1]["primitives"][0]["attributes"]["POSITION"] = json!(a);
    doc["extensionsUsed"] = json!(["EXT_made_up", "KHR_mesh_quantization"]);
    doc["extensionsRequired"] = json!(["KHR_mesh_quantization"]);
    let g = read_avatar_bytes(&glb(&doc, &bin), "quantized.glb").unwrap();
    let teeth = &g.avatar.parts()[2].positions;
    // The teeth's matrix moves them by y − 1.
    assert!(close(teeth[0], Vec3::new(1.0, -1.0, 0.0)), "{}", teeth[0]);
    assert!(close(teeth[1], Vec3::new(0.0, -2.0, 0.0)), "{}", teeth[1]);
    assert!(
        close(teeth[2], Vec3::new(0.0, -1.0, 16384.0 / 32767.0)),
        "{}",
        teeth[2]
    );
    assert!(g.json().get("extensionsRequired").is_none());
    let back = written_back_glb(
        &g,
        &NewShapes::new(),
        TargetEncoding::Smallest,
        Path::new("b.glb"),
    )
    .unwrap();
    let again = read_avatar_bytes(&back, "b.glb").unwrap();
    let position = again.json()["meshes"][1]["primitives"][0]["attributes"]["POSITION"]
        .as_u64()
        .unwrap();
    assert_eq!(
        again.json()["accessors"][position as usize]["componentType"],
        5126
    );
    assert_eq!(again.avatar.parts()[2].positions, *teeth);
    assert_eq!(again.json()["extensionsUsed"], json!(["EXT_made_up"]));
}
