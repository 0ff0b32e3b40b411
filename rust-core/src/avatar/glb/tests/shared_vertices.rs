//! A surface in several materials: primitives sharing one set of vertices
//! and targets are written, read as one part, coloured and written back
//! still sharing them.

use super::*;
use crate::avatar::glb::look::part_colours;

/// A square of two triangles with one jawOpen target, the second triangle
/// in a material of its own ("lips").
fn square_in_two_materials() -> (Avatar, NewGlbOptions) {
    let avatar = Avatar::new(
        vec![AvatarMesh {
            name: Some("head".into()),
            target_names: vec!["jawOpen".into()],
        }],
        vec![AvatarPart {
            name: "skin".into(),
            mesh: 0,
            primitive: 0,
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y],
            triangles: vec![[0, 1, 2], [0, 2, 3]],
            targets: vec![vec![Vec3::ZERO, Vec3::ZERO, Vec3::Z, Vec3::Z]],
        }],
    )
    .unwrap();
    let options = NewGlbOptions {
        looks: vec![MeshLook::SKIN],
        part_splits: vec![vec![MaterialSplit {
            first_triangle: 1,
            name: "lips".into(),
            look: MeshLook::GUM,
        }]],
        ..Default::default()
    };
    (avatar, options)
}

#[test]
fn a_part_split_between_materials_is_two_primitives_sharing_its_vertices() {
    let (avatar, options) = square_in_two_materials();
    let bytes = new_avatar_glb(&avatar, &options, Path::new("s.glb")).unwrap();
    let back = read_avatar_bytes(&bytes, "s.glb").unwrap();
    let primitives = back.json()["meshes"][0]["primitives"].as_array().unwrap();
    assert_eq!(primitives.len(), 2);
    assert_eq!(primitives[0]["attributes"], primitives[1]["attributes"]);
    assert_eq!(primitives[0]["targets"], primitives[1]["targets"]);
    assert_ne!(primitives[0]["material"], primitives[1]["material"]);
    // Read back: one part, the same triangles, the split remembered.
    assert_eq!(back.avatar.parts().len(), 1);
    assert_eq!(
        back.avatar.parts()[0].triangles,
        avatar.parts()[0].triangles
    );
    assert_eq!(back.avatar.parts()[0].targets, avatar.parts()[0].targets);
    assert_eq!(
        back.splits,
        [vec![PrimitiveSplit {
            primitive: 1,
            first_triangle: 1
        }]]
    );
    // Colours: vertex 1 is on the skin only, 3 on the lips only, 0 and 2
    // on both (the mean).
    let colours = part_colours(&back)[0].clone().unwrap();
    let rgb = |l: MeshLook| Vec3::from_slice(&l.base_colour[..3]);
    let (skin, lips) = (rgb(MeshLook::SKIN), rgb(MeshLook::GUM));
    assert_eq!(colours[1], skin);
    assert_eq!(colours[3], lips);
    assert!((colours[0] - 0.5 * (skin + lips)).length() < 1e-6);
    // Splits out of order, at the first triangle or past the last are
    // refused, naming the part.
    for first in [0, 2] {
        let mut bad = options.clone();
        bad.part_splits[0][0].first_triangle = first;
        let err = new_avatar_glb(&avatar, &bad, Path::new("s.glb")).unwrap_err();
        assert!(err.to_string().contains("part 0"), "{err}");
    }
}

#[test]
fn primitives_sharing_vertices_share_the_written_back_targets() {
    let (avatar, options) = square_in_two_materials();
    let bytes = new_avatar_glb(&avatar, &options, Path::new("s.glb")).unwrap();
    let glb = read_avatar_bytes(&bytes, "s.glb").unwrap();
    let mut shapes = NewShapes::new();
    let lift = vec![Vec3::ZERO, Vec3::Y, Vec3::Y, Vec3::ZERO];
    shapes.set(Blendshape::JawOpen, vec![lift.clone()]);
    shapes.set(Blendshape::EyeBlinkLeft, vec![lift.clone()]);
    let written =
        written_back_glb(&glb, &shapes, TargetEncoding::Dense, Path::new("w.glb")).unwrap();
    let again = read_avatar_bytes(&written, "w.glb").unwrap();
    let primitives = again.json()["meshes"][0]["primitives"].as_array().unwrap();
    assert_eq!(primitives[0]["attributes"], primitives[1]["attributes"]);
    assert_eq!(primitives[0]["targets"], primitives[1]["targets"]);
    assert_eq!(
        primitives[0]["extras"]["targetNames"],
        primitives[1]["extras"]["targetNames"]
    );
    assert_eq!(again.avatar.parts().len(), 1, "still one part");
    let names = &again.avatar.meshes()[0].target_names;
    for shape in ["jawOpen", "eyeBlinkLeft"] {
        let t = names.iter().position(|n| n == shape).unwrap();
        assert_eq!(again.avatar.parts()[0].targets[t], lift, "{shape}");
    }
    // With a new rest, both primitives take it.
    let mut rest = NewShapes::new();
    let moved: Vec<Vec3> = avatar.parts()[0]
        .positions
        .iter()
        .map(|p| *p + Vec3::Z)
        .collect();
    rest.set_rest(vec![moved.clone()]);
    let written = written_back_glb(&glb, &rest, TargetEncoding::Dense, Path::new("r.glb")).unwrap();
    let again = read_avatar_bytes(&written, "r.glb").unwrap();
    assert_eq!(again.avatar.parts().len(), 1);
    assert_eq!(again.avatar.parts()[0].positions, moved);
}
