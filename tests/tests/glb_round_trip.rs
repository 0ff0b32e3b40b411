//! The avatar's glTF path through the public API: an avatar written new,
//! read back (geometry exact, names in ARKit's spelling whatever they were
//! given in, mesh names kept), then written back with a personalized set
//! in which one split shape becomes whole and a shape the avatar lacked is
//! added where it moves something.

use glam::Vec3;
use likeness::Blendshape;
use likeness::avatar::glb::{
    GlbError, MeshLook, NewGlbOptions, NewShapes, check_avatar, read_avatar, write_avatar,
    write_new_avatar,
};
use likeness::avatar::{Avatar, AvatarPart};
use likeness_sim::grid_avatar;

/// A fan of `n` triangles around a centre at depth `z`, as a part of mesh
/// `mesh` whose target `t` lifts rim vertex `t + 1` by a millimetre.
fn fan(mesh: usize, n: u32, z: f32, targets: usize) -> AvatarPart {
    let mut positions = vec![Vec3::new(0.0, 0.0, z)];
    positions.extend((0..n).map(|i| {
        let a = i as f32 / n as f32 * std::f32::consts::TAU;
        Vec3::new(a.cos() * 0.05, a.sin() * 0.05, z)
    }));
    let triangles = (0..n).map(|i| [0, 1 + i, 1 + (i + 1) % n]).collect();
    grid_avatar::part(mesh, (positions, triangles), targets, |t, v, _| {
        if v == t + 1 {
            Vec3::new(0.0, 0.001, 0.0)
        } else {
            Vec3::ZERO
        }
    })
}

/// A face whose targets are named in several spellings, and eyes.
fn avatar() -> Avatar {
    let face = [
        "EyeBlinkLeft",
        "blendShape1.eyeBlink_R",
        "cheekPuff_L",
        "cheekPuff_R",
        "Fcl_MTH_A",
    ];
    grid_avatar::avatar(
        &[("Face", &face[..]), ("Eyes", &[])],
        vec![fan(0, 12, 0.0, 5), fan(1, 8, -0.02, 0)],
    )
}

#[test]
fn written_new_read_and_written_back() {
    let dir = std::env::temp_dir().join(format!("likeness-glb-round-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("avatar.glb");
    let options = NewGlbOptions {
        looks: vec![MeshLook::SKIN, MeshLook::EYE_WHITE],
        ..Default::default()
    };
    let avatar = avatar();
    write_new_avatar(&avatar, &options, &path).unwrap();
    let read = read_avatar(&path).unwrap();
    for (a, b) in read.avatar.parts().iter().zip(avatar.parts()) {
        assert_eq!(
            (&a.positions, &a.triangles, &a.targets),
            (&b.positions, &b.triangles, &b.targets)
        );
    }
    assert_eq!(read.avatar.meshes()[0].name.as_deref(), Some("Face"));
    assert_eq!(read.avatar.meshes()[1].name.as_deref(), Some("Eyes"));
    assert_eq!(
        read.avatar.meshes()[0].target_names,
        [
            "eyeBlinkLeft",
            "eyeBlinkRight",
            "cheekPuff_L",
            "cheekPuff_R",
            "Fcl_MTH_A"
        ]
    );
    assert_eq!(read.json()["materials"][1]["name"], "Eyes");
    let found = check_avatar(&read).unwrap();
    assert_eq!(found.found(), 3);

    // Personalized: cheekPuff whole, eyeLookInLeft new (moves the eyes only).
    let zeros = |p: &AvatarPart| vec![Vec3::ZERO; p.positions.len()];
    let parts = read.avatar.parts();
    let mut shapes = NewShapes::new();
    let mut puff: Vec<Vec<Vec3>> = parts.iter().map(zeros).collect();
    puff[0][3] = Vec3::new(0.0, 0.0, 0.004);
    shapes.set(Blendshape::CheekPuff, puff.clone());
    let mut look: Vec<Vec<Vec3>> = parts.iter().map(zeros).collect();
    look[1]
        .iter_mut()
        .for_each(|d| *d = Vec3::new(0.002, 0.0, 0.0));
    shapes.set(Blendshape::EyeLookInLeft, look.clone());
    let out = dir.join("personalized.glb");
    write_avatar(&read, &shapes, &out).unwrap();
    let back = read_avatar(&out).unwrap();
    assert_eq!(
        back.avatar.meshes()[0].target_names,
        ["eyeBlinkLeft", "eyeBlinkRight", "cheekPuff", "Fcl_MTH_A"]
    );
    assert_eq!(back.avatar.meshes()[1].target_names, ["eyeLookInLeft"]);
    assert_eq!(back.avatar.parts()[0].targets[2], puff[0]);
    assert_eq!(
        back.avatar.parts()[0].targets[3],
        read.avatar.parts()[0].targets[4]
    );
    assert_eq!(back.avatar.parts()[1].targets[0], look[1]);
    assert_eq!(
        back.json()["meshes"][0]["weights"]
            .as_array()
            .unwrap()
            .len(),
        4
    );
    assert!(
        back.json()["meshes"][1].get("weights").is_none(),
        "absent stays absent"
    );
    assert_eq!(
        back.avatar.parts()[1].positions,
        avatar.parts()[1].positions
    );

    // Data that does not fit the avatar is refused, and nothing is written.
    let mut short = NewShapes::new();
    short.set(Blendshape::JawOpen, vec![vec![Vec3::ZERO; 2]]);
    let refused = dir.join("refused.glb");
    assert!(matches!(
        write_avatar(&read, &short, &refused),
        Err(GlbError::Write { .. })
    ));
    assert!(!refused.exists());
    std::fs::remove_dir_all(&dir).unwrap();
}
