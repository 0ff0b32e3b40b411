//! Writing: the write-back rules, everything else kept, sparse and dense
//! targets decoded exactly.

use super::*;

fn new_shapes(g: &GlbAvatar) -> NewShapes {
    let mut shapes = NewShapes::new();
    let moving = |k: usize, scale: f32| -> Vec<Vec<Vec3>> {
        g.avatar
            .parts()
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
    let names = &back.avatar.meshes()[0].target_names;
    assert_eq!(names, &["eyeBlinkLeft", "browInnerUp", "Fcl_custom"]);
    assert_eq!(back.avatar.meshes()[1].target_names, ["jawOpen"]);
    assert_eq!(back.json()["meshes"][0]["weights"], json!([0.5, 0.0, 0.25]));
    assert_eq!(back.json()["meshes"][0]["extras"]["other"], json!(true));
    assert_eq!(
        back.json()["meshes"][0]["primitives"][1]["extras"]["targetNames"],
        json!(names)
    );
    // New data, back in world space; the kept target untouched.
    for (k, part) in back.avatar.parts().iter().enumerate() {
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
        back.avatar.parts()[0].targets[2],
        g.avatar.parts()[0].targets[3]
    );
    assert!(close(
        back.avatar.parts()[2].targets[0][1],
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
    assert_eq!(back.avatar.parts(), g.avatar.parts());
    // Nothing dropped, nothing renumbered.
    assert_eq!(back.json()["accessors"], g.json()["accessors"]);
    assert_eq!(back.json()["nodes"], g.json()["nodes"]);
    assert_eq!(back.avatar.meshes()[0].target_names[0], "eyeBlinkLeft");
    assert_eq!(back.avatar.meshes()[0].target_names[1], "browInnerUp_L");
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
    let avatar = Avatar::new(
        vec![AvatarMesh {
            name: Some("m".into()),
            target_names: vec!["JawOpen".into(), "mouthClose".into()],
        }],
        vec![AvatarPart {
            name: "m".into(),
            mesh: 0,
            primitive: 0,
            positions,
            triangles,
            targets: vec![few.clone(), all.clone()],
        }],
    )
    .unwrap();
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
    assert_eq!(back.avatar.parts()[0].targets, [few, all]);
    assert_eq!(
        back.avatar.meshes()[0].target_names,
        ["jawOpen", "mouthClose"]
    );
    assert_eq!(
        back.avatar.parts()[0].positions,
        avatar.parts()[0].positions
    );
    let dense = NewGlbOptions {
        encoding: TargetEncoding::Dense,
        ..Default::default()
    };
    let bigger = new_avatar_glb(&avatar, &dense, Path::new("d.glb")).unwrap();
    assert!(bigger.len() > bytes.len());
    assert_eq!(
        read_avatar_bytes(&bigger, "d.glb").unwrap().avatar.parts()[0].targets,
        avatar.parts()[0].targets
    );
}

/// Reads a modified fixture, expecting an error.

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
        read_avatar(&out).unwrap().avatar.meshes()[1].target_names,
        ["jawOpen"]
    );
    // The same buffer as a base64 data URI, read from memory.
    doc["buffers"][0]["uri"] = json!(format!(
        "data:application/octet-stream;base64,{}",
        base64(&bin)
    ));
    let from_uri = read_avatar_bytes(&serde_json::to_vec(&doc).unwrap(), "b.gltf").unwrap();
    assert_eq!(from_uri.avatar, from_file.avatar);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Standard base64 with padding.
fn base64(bytes: &[u8]) -> String {
    const ABC: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = u32::from_be_bytes([0, b[0], b[1], b[2]]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(ABC[(n >> (18 - 6 * k)) as usize & 63] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

#[test]
fn parts_get_their_own_materials_and_vertex_tints() {
    let part = |primitive: usize, x: f32| AvatarPart {
        name: format!("p{primitive}"),
        mesh: 0,
        primitive,
        positions: vec![Vec3::new(x, 0.0, 0.0), Vec3::X, Vec3::Y],
        triangles: vec![[0, 1, 2]],
        targets: Vec::new(),
    };
    let avatar = Avatar::new(
        vec![AvatarMesh {
            name: Some("eye".into()),
            target_names: Vec::new(),
        }],
        vec![part(0, 0.0), part(1, 0.1), part(2, 0.2)],
    )
    .unwrap();
    let tint = vec![Vec3::ONE, Vec3::new(0.5, 0.2, 0.2), Vec3::ONE];
    let options = NewGlbOptions {
        looks: vec![MeshLook::EYE_WHITE],
        part_looks: vec![None, Some(("iris".into(), MeshLook::GUM)), None],
        part_colours: vec![None, Some(tint.clone())],
        ..Default::default()
    };
    let bytes = new_avatar_glb(&avatar, &options, Path::new("e.glb")).unwrap();
    let back = read_avatar_bytes(&bytes, "e.glb").unwrap();
    let doc = back.json();
    let names: Vec<&str> = doc["materials"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["name"].as_str().unwrap())
        .collect();
    assert_eq!(
        names,
        ["eye", "iris"],
        "parts without their own share the mesh's"
    );
    let primitives = doc["meshes"][0]["primitives"].as_array().unwrap();
    let materials: Vec<u64> = primitives
        .iter()
        .map(|p| p["material"].as_u64().unwrap())
        .collect();
    assert_eq!(materials, [0, 1, 0]);
    let colour = primitives[1]["attributes"]["COLOR_0"].as_u64().unwrap() as usize;
    assert_eq!(doc["accessors"][colour]["count"], 3);
    assert!(primitives[0]["attributes"].get("COLOR_0").is_none());
    // A tint list of the wrong length is refused, naming the part.
    let wrong = NewGlbOptions {
        part_colours: vec![Some(vec![Vec3::ONE])],
        ..Default::default()
    };
    let err = new_avatar_glb(&avatar, &wrong, Path::new("e.glb")).unwrap_err();
    assert!(err.to_string().contains("part 0"), "{err}");
}

#[test]
fn parts_given_shading_normals_keep_them_and_bad_ones_are_refused() {
    let avatar = Avatar::one_triangle("skin");
    // The flat triangle's own normal is +z everywhere; a surface it was
    // sampled from leans its corners outwards.
    let own = [
        Vec3::new(-0.3, -0.3, 1.0),
        Vec3::new(0.3, 0.0, 1.0),
        Vec3::new(0.0, 0.3, 1.0),
    ]
    .map(Vec3::normalize)
    .to_vec();
    let with = |normals: Vec<Vec3>| NewGlbOptions {
        part_normals: vec![Some(normals)],
        ..Default::default()
    };
    let bytes = new_avatar_glb(&avatar, &with(own.clone()), Path::new("s.glb")).unwrap();
    let back = read_avatar_bytes(&bytes, "s.glb").unwrap();
    let written = floats(
        &back,
        &back.json()["meshes"][0]["primitives"][0]["attributes"]["NORMAL"],
    );
    assert_eq!(
        written,
        own.iter().flat_map(|n| n.to_array()).collect::<Vec<_>>()
    );
    // Without them, the surface's own.
    let plain = new_avatar_glb(&avatar, &NewGlbOptions::default(), Path::new("s.glb")).unwrap();
    let plain = read_avatar_bytes(&plain, "s.glb").unwrap();
    let flat = floats(
        &plain,
        &plain.json()["meshes"][0]["primitives"][0]["attributes"]["NORMAL"],
    );
    assert_eq!(flat, [0.0, 0.0, 1.0].repeat(3));
    for bad in [own[..2].to_vec(), vec![Vec3::Z, Vec3::Z, 2.0 * Vec3::Z]] {
        let err = new_avatar_glb(&avatar, &with(bad), Path::new("s.glb")).unwrap_err();
        assert!(
            err.to_string().contains("part 0: not one unit normal"),
            "{err}"
        );
    }
}

#[test]
fn every_target_carries_the_normal_change_it_causes() {
    // The unit square in z = 0, two triangles; jawOpen lifts one corner,
    // mouthClose moves nothing.
    let positions = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(1.0, 1.0, 0.0)];
    let triangles = vec![[0, 1, 2], [1, 3, 2]];
    let mut lift = vec![Vec3::ZERO; 4];
    lift[3] = Vec3::new(0.0, 0.0, 0.5);
    let avatar = Avatar::new(
        vec![AvatarMesh {
            name: Some("skin".into()),
            target_names: vec!["jawOpen".into(), "mouthClose".into()],
        }],
        vec![AvatarPart {
            name: "skin".into(),
            mesh: 0,
            primitive: 0,
            positions: positions.clone(),
            triangles: triangles.clone(),
            targets: vec![lift.clone(), vec![Vec3::ZERO; 4]],
        }],
    )
    .unwrap();
    let lifted: Vec<Vec3> = positions.iter().zip(&lift).map(|(p, d)| *p + *d).collect();
    let want = write_new::vertex_normals(&lifted, &triangles);
    // With the surface's own normals and with given shading normals (the
    // flat square's, so the same turn applies), both densely written.
    for shading in [None, Some(vec![Vec3::Z; 4])] {
        let options = NewGlbOptions {
            part_normals: vec![shading],
            encoding: TargetEncoding::Dense,
            ..Default::default()
        };
        let bytes = new_avatar_glb(&avatar, &options, Path::new("n.glb")).unwrap();
        let back = read_avatar_bytes(&bytes, "n.glb").unwrap();
        let prim = &back.json()["meshes"][0]["primitives"][0];
        let base = floats(&back, &prim["attributes"]["NORMAL"]);
        let open = floats(&back, &prim["targets"][0]["NORMAL"]);
        for v in 0..4 {
            let n = Vec3::from_slice(&base[3 * v..]) + Vec3::from_slice(&open[3 * v..]);
            assert!(
                (n - want[v]).length() < 1e-5,
                "vertex {v}: {n} against {}",
                want[v]
            );
        }
        assert_eq!(&open[..3], [0.0; 3], "vertex 0's one triangle stays flat");
        // A target that moves nothing: all zero (one sparse zero entry).
        let still = prim["targets"][1]["NORMAL"].as_u64().unwrap() as usize;
        let still = &back.json()["accessors"][still];
        assert_eq!(
            (&still["min"], &still["max"]),
            (&json!([0.0, 0.0, 0.0]), &json!([0.0, 0.0, 0.0]))
        );
    }
}

/// Texture extensions whose image lives in the extension (a texture with
/// no `source`: `KHR_texture_basisu`, `EXT_texture_webp`, both required),
/// a texture transform and a material extension: read, and written back
/// as they were.
#[test]
fn texture_and_material_extensions_pass_through() {
    let (mut doc, bin) = fixture();
    doc["images"] = json!([
        { "uri": "skin.ktx2", "mimeType": "image/ktx2" },
        { "uri": "skin.webp", "mimeType": "image/webp" },
    ]);
    doc["textures"] = json!([
        { "extensions": { "KHR_texture_basisu": { "source": 0 } } },
        { "extensions": { "EXT_texture_webp": { "source": 1 } } },
    ]);
    let transform = json!({ "offset": [0.5, 0.0], "rotation": 0.1, "scale": [2.0, 2.0] });
    doc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"] =
        json!({ "index": 0, "extensions": { "KHR_texture_transform": transform } });
    doc["materials"][0]["emissiveTexture"] = json!({ "index": 1 });
    doc["materials"][0]["extensions"] =
        json!({ "KHR_materials_emissive_strength": { "emissiveStrength": 2.0 } });
    let used = [
        "KHR_texture_basisu",
        "EXT_texture_webp",
        "KHR_texture_transform",
        "KHR_materials_emissive_strength",
    ];
    doc["extensionsUsed"] = json!(used);
    doc["extensionsRequired"] = json!(["KHR_texture_basisu", "EXT_texture_webp"]);
    let g = read_avatar_bytes(&glb(&doc, &bin), "textured.glb").unwrap();
    let shapes = new_shapes(&g);
    let bytes =
        written_back_glb(&g, &shapes, TargetEncoding::Smallest, Path::new("o.glb")).unwrap();
    let back = read_avatar_bytes(&bytes, "o.glb").unwrap();
    for key in [
        "images",
        "textures",
        "materials",
        "extensionsUsed",
        "extensionsRequired",
    ] {
        assert_eq!(back.json()[key], doc[key], "{key}");
    }
}
