//! A new rest written back: positions replaced through the node's
//! transform, normals and tangents turned with the surface.

use super::*;

/// Appends `values` (floats) to the buffer as an accessor of `kind`; its
/// index.
fn push_floats(doc: &mut Value, bin: &mut Vec<u8>, values: &[f32], kind: &str) -> usize {
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let offset = bin.len();
    bin.extend(values.iter().flat_map(|x| x.to_le_bytes()));
    let width = if kind == "VEC4" { 4 } else { 3 };
    let views = doc["bufferViews"].as_array_mut().unwrap();
    views.push(json!({ "buffer": 0, "byteOffset": offset, "byteLength": 4 * values.len() }));
    let view = views.len() - 1;
    let accessors = doc["accessors"].as_array_mut().unwrap();
    accessors.push(json!({
        "bufferView": view, "componentType": 5126, "count": values.len() / width, "type": kind,
    }));
    accessors.len() - 1
}

#[test]
fn a_new_rest_replaces_positions_and_turns_normals_with_the_surface() {
    let (mut doc, mut bin) = fixture();
    // The head's first primitive (triangles 0-1-2 in z = 0 and 0-2-3 in
    // x = 0, local) gets each vertex's face normal and a tangent.
    let normals = [0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, -1.0, 0.0, 0.0];
    let tangents = [1.0, 0.0, 0.0, -1.0].repeat(4);
    let n = push_floats(&mut doc, &mut bin, &normals, "VEC3");
    let t = push_floats(&mut doc, &mut bin, &tangents, "VEC4");
    doc["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = json!(n);
    doc["meshes"][0]["primitives"][0]["attributes"]["TANGENT"] = json!(t);
    doc["buffers"][0]["byteLength"] = json!(bin.len());
    let g = read_avatar_bytes(&glb(&doc, &bin), "rest.glb").unwrap();

    // Vertex 3 of the head moves in world space; nothing else does.
    let mut rest: Vec<Vec<Vec3>> = g
        .avatar
        .parts()
        .iter()
        .map(|p| p.positions.clone())
        .collect();
    let world = head_world();
    rest[0][3] = world.transform_point3(Vec3::new(-0.5, 0.0, 1.0));
    let mut shapes = NewShapes::new();
    shapes.set_rest(rest.clone());
    let bytes = written_back_glb(&g, &shapes, TargetEncoding::Smallest, Path::new("rest.glb"))
        .expect("writes");
    let back = read_avatar_bytes(&bytes, "back.glb").expect("reads");
    for (got, want) in back.avatar.parts().iter().zip(&rest) {
        assert!(got.positions.iter().zip(want).all(|(a, b)| close(*a, *b)));
    }
    // Targets are kept as they were.
    assert_eq!(back.avatar.parts()[0].targets, g.avatar.parts()[0].targets);

    let prim = &back.json()["meshes"][0]["primitives"][0]["attributes"];
    let normals = floats(&back, &prim["NORMAL"]);
    let normal = |v: usize| Vec3::from_slice(&normals[3 * v..3 * v + 3]);
    // Unmoved vertices keep their normals exactly.
    assert_eq!(normal(1), Vec3::Z);
    assert_eq!(normal(2), Vec3::Z);
    // Vertex 3's triangle 0-2-3 spanned (0,1,0) and (0,0,1) locally, its
    // geometric normal +x, the stored one -x; it now spans (0,1,0) and
    // (-0.5,0,1), geometric normal (1,0,0.5): the stored one turns alike.
    let want = -Vec3::new(1.0, 0.0, 0.5).normalize();
    assert!(
        (normal(3) - want).length() < 1e-5,
        "{} against {want}",
        normal(3)
    );
    let tangents = floats(&back, &prim["TANGENT"]);
    for v in 0..4 {
        let t = Vec3::from_slice(&tangents[4 * v..4 * v + 3]);
        assert!((t.length() - 1.0).abs() < 1e-6);
        assert_eq!(tangents[4 * v + 3], -1.0, "handedness kept");
    }
}

#[test]
fn new_targets_carry_normal_deltas_where_the_primitive_has_normals() {
    let (mut doc, mut bin) = fixture();
    // The head's first primitive gets normals (as in the test above); its
    // second (the jaw) has none.
    let normals = [0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, -1.0, 0.0, 0.0];
    let n = push_floats(&mut doc, &mut bin, &normals, "VEC3");
    doc["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] = json!(n);
    doc["buffers"][0]["byteLength"] = json!(bin.len());
    let g = read_avatar_bytes(&glb(&doc, &bin), "normals.glb").unwrap();
    // jawOpen (new to the mesh) moves the head's vertex 3 in world space as
    // the new rest above does: its stored normal turns alike.
    let world = head_world();
    let mut open: Vec<Vec<Vec3>> = g
        .avatar
        .parts()
        .iter()
        .map(|p| vec![Vec3::ZERO; p.positions.len()])
        .collect();
    open[0][3] =
        world.transform_point3(Vec3::new(-0.5, 0.0, 1.0)) - g.avatar.parts()[0].positions[3];
    let mut shapes = NewShapes::new();
    shapes.set(Blendshape::JawOpen, open);
    let bytes = written_back_glb(&g, &shapes, TargetEncoding::Dense, Path::new("n.glb")).unwrap();
    let back = read_avatar_bytes(&bytes, "back.glb").unwrap();
    let names = &back.avatar.meshes()[0].target_names;
    let t = names.iter().position(|n| n == "jawOpen").unwrap();
    let head = &back.json()["meshes"][0]["primitives"][0]["targets"][t];
    let deltas = floats(&back, &head["NORMAL"]);
    let turned = Vec3::from_slice(&normals[9..]) + Vec3::from_slice(&deltas[9..]);
    let want = -Vec3::new(1.0, 0.0, 0.5).normalize();
    assert!((turned - want).length() < 1e-5, "{turned} against {want}");
    assert_eq!(&deltas[3..6], [0.0; 3], "vertex 1's triangle did not turn");
    // Targets kept as they were keep their attributes; the jaw, without
    // normals, gets none.
    let jaw = &back.json()["meshes"][0]["primitives"][1]["targets"][t];
    assert!(jaw.get("NORMAL").is_none() && jaw.get("POSITION").is_some());
    let kept = &back.json()["meshes"][0]["primitives"][0]["targets"][0];
    assert!(kept.get("NORMAL").is_none());
}

#[test]
fn a_new_rest_of_the_wrong_size_is_refused() {
    let g = read_fixture();
    let mut shapes = NewShapes::new();
    shapes.set_rest(vec![vec![Vec3::ZERO; 2]]);
    let err = written_back_glb(&g, &shapes, TargetEncoding::Smallest, Path::new("x.glb"))
        .expect_err("refused");
    assert!(err.to_string().contains("new rest"), "{err}");
}
