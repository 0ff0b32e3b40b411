//! The generated test avatars (`likeness_sim::avatar_variants`)
//! are valid GLBs that the core's reader
//! (`likeness::avatar::glb::read_avatar_bytes`) reads into what each
//! variant's `VariantTruth` says: meshes and parts, the head's vertices,
//! ARKit and other targets, skins and bind poses, eyes turned by bones or
//! targets, teeth and gums in one primitive, and units and up axis as
//! they show in the bounding box after node transforms. With the Node
//! glTF-Validator installed (`npm ci` in tests/js), each has 0 errors and 0 warnings;
//! without it that check is skipped with a notice, unless
//! `LIKENESS_REQUIRE_TOOLS=1`.

use glam::{Mat4, Vec3};
use likeness::avatar::glb::{GlbAvatar, check_avatar, read_avatar_bytes};
use likeness::avatar::{TargetName, parse_target_name};
use likeness_sim::avatar_variants::{AvatarVariant, Piece, UpAxis, VariantTruth, avatar_variants};
use likeness_tests::gltf_validator::validate;
use std::sync::OnceLock;

fn variants() -> &'static [AvatarVariant] {
    static V: OnceLock<Vec<AvatarVariant>> = OnceLock::new();
    V.get_or_init(avatar_variants)
}

fn read(v: &AvatarVariant) -> GlbAvatar {
    read_avatar_bytes(&v.glb, v.name).unwrap_or_else(|e| panic!("{}: {e}", v.name))
}

fn variant(name: &str) -> &'static AvatarVariant {
    variants().iter().find(|v| v.name == name).unwrap()
}

fn bounds(points: impl Iterator<Item = Vec3>) -> [Vec3; 2] {
    points.fold(
        [Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)],
        |[lo, hi], p| [lo.min(p), hi.max(p)],
    )
}

/// A world point in metres, +Y up, by the truth's unit and up axis.
fn y_up_metres(t: &VariantTruth, p: Vec3) -> Vec3 {
    let q = p * t.unit_to_metres;
    match t.up {
        UpAxis::Y => q,
        UpAxis::Z => Vec3::new(q.x, q.z, -q.y),
    }
}

/// Centre of a part's bounding box, in metres, +Y up.
fn centre(t: &VariantTruth, a: &GlbAvatar, part: usize) -> Vec3 {
    piece_centre(t, a, &Piece::whole(&a.avatar, part))
}

/// The centre of `piece`'s bounding box in metres, +Y up.
fn piece_centre(t: &VariantTruth, a: &GlbAvatar, piece: &Piece) -> Vec3 {
    let [lo, hi] = bounds(
        a.avatar.parts()[piece.part].positions[piece.vertices.clone()]
            .iter()
            .map(|&p| y_up_metres(t, p)),
    );
    0.5 * (lo + hi)
}

#[test]
fn the_variants_are_the_eleven_listed() {
    let names: Vec<&str> = variants().iter().map(|v| v.name).collect();
    assert_eq!(
        names,
        [
            "low-poly",
            "bone-eyes",
            "teeth-gums-one-mesh",
            "one-mesh-face",
            "full-body",
            "lined-sockets",
            "cm-z-up",
            "other-proportions",
            "meshopt",
            "head-box",
            "vendor-export"
        ]
    );
    assert!(variants().iter().all(|v| !v.description.is_empty()));
}

#[test]
fn every_variant_reads_with_the_52_arkit_targets_and_its_layout() {
    for v in variants() {
        let (a, t) = (read(v), &v.truth);
        let arkit = check_avatar(&a).unwrap_or_else(|e| panic!("{}: {e}", v.name));
        assert_eq!(arkit.found(), t.arkit_targets, "{}", v.name);
        assert_eq!(t.arkit_targets, 52, "{}", v.name);
        assert_eq!(a.avatar.meshes().len(), t.meshes, "{}: meshes", v.name);
        assert_eq!(a.avatar.parts().len(), t.parts, "{}: parts", v.name);
        let head = &a.avatar.parts()[t.head_part];
        assert_eq!(head.positions.len(), t.head_vertices, "{}: head", v.name);
        assert!(0 < t.face_vertices && t.face_vertices < t.head_vertices);
        let json = a.json();
        assert_eq!(json.get("skins").is_some(), t.skinned, "{}: skin", v.name);
        assert_eq!(
            bind_matrices(&a)
                .iter()
                .any(|m| !m.abs_diff_eq(Mat4::IDENTITY, 1e-6)),
            t.non_identity_bind_pose,
            "{}: bind pose",
            v.name
        );
        for (m, mesh) in a.avatar.meshes().iter().enumerate() {
            let name = mesh.name.as_deref().unwrap_or_default();
            assert_eq!(
                mesh.target_names.is_empty(),
                t.meshes_without_targets.contains(&name),
                "{}: mesh {m} {name}",
                v.name
            );
        }
        let extra: Vec<&str> = a.avatar.meshes()[a.avatar.parts()[t.head_part].mesh]
            .target_names
            .iter()
            .filter(|n| !matches!(parse_target_name(n), TargetName::Arkit(_)))
            .map(String::as_str)
            .collect();
        assert_eq!(extra, t.extra_targets, "{}: extra targets", v.name);
    }
}

/// Every skin's inverse bind matrices as stored.
fn bind_matrices(a: &GlbAvatar) -> Vec<Mat4> {
    let json = a.json();
    let mut out = Vec::new();
    for skin in json["skins"].as_array().into_iter().flatten() {
        let accessor = &json["accessors"][skin["inverseBindMatrices"].as_u64().unwrap() as usize];
        let view = &json["bufferViews"][accessor["bufferView"].as_u64().unwrap() as usize];
        let at = view["byteOffset"].as_u64().unwrap_or(0) as usize
            + accessor["byteOffset"].as_u64().unwrap_or(0) as usize;
        let bytes = &a.buffers()[0][at..];
        for k in 0..accessor["count"].as_u64().unwrap() as usize {
            let f: Vec<f32> = (0..16)
                .map(|i| {
                    let o = 64 * k + 4 * i;
                    f32::from_le_bytes(bytes[o..o + 4].try_into().unwrap())
                })
                .collect();
            out.push(Mat4::from_cols_slice(&f));
        }
    }
    out
}

#[test]
fn world_bounds_units_and_up_axis_are_as_built() {
    for v in variants() {
        let (a, t) = (read(v), &v.truth);
        let [lo, hi] = bounds(a.avatar.positions().into_iter());
        let size = (t.world_bounds[1] - t.world_bounds[0]).max_element();
        for (found, truth) in [(lo, t.world_bounds[0]), (hi, t.world_bounds[1])] {
            assert!(
                found.abs_diff_eq(truth, 1e-5 * size),
                "{}: bounds {found} ≠ {truth}",
                v.name
            );
        }
        // In metres with +Y up: a head-sized or body-sized box, the eyes
        // above the mouth and in front of the head's middle.
        let [mlo, mhi] = bounds(a.avatar.positions().into_iter().map(|p| y_up_metres(t, p)));
        let height = mhi.y - mlo.y;
        assert!(
            (0.2..2.0).contains(&height),
            "{}: height {height} m",
            v.name
        );
        let eyes = t.eyeballs.each_ref().map(|e| piece_centre(t, &a, e));
        let head = centre(t, &a, t.head_part);
        for e in eyes {
            assert!(e.z > head.z, "{}: eyes face +z after conversion", v.name);
            if let Some(teeth) = &t.teeth {
                assert!(
                    e.y > piece_centre(t, &a, teeth).y + 0.04,
                    "{}: eyes above teeth",
                    v.name
                );
            }
        }
        assert!(eyes[0].x > eyes[1].x, "{}: left eye at +x", v.name);
        let distance = eyes[0].distance(eyes[1]);
        assert!(
            (distance - t.eye_distance).abs() < 2e-4,
            "{}: eye distance {distance} ≠ {}",
            v.name,
            t.eye_distance
        );
    }
    // cm-z-up is the default head: the same box in metres, +Y up, 1.5 m up.
    let cm = variant("cm-z-up");
    let default = read_avatar_bytes(
        &likeness_sim::default_avatar::default_avatar_glb().unwrap(),
        "default",
    )
    .unwrap();
    let [dlo, dhi] = bounds(default.avatar.positions().into_iter());
    let [clo, chi] = bounds(
        read(cm)
            .avatar
            .positions()
            .into_iter()
            .map(|p| y_up_metres(&cm.truth, p)),
    );
    let lift = Vec3::Y * 1.5;
    assert!(clo.abs_diff_eq(dlo + lift, 1e-4) && chi.abs_diff_eq(dhi + lift, 1e-4));
}

/// The ARKit name a target's name reads as (`AK_05_EyeLookUpLeft` →
/// `eyeLookUpLeft`), or the name itself.
fn arkit_name(name: &str) -> &str {
    parse_target_name(name).shape().map_or(name, |s| s.name())
}

/// Largest displacement of `piece` under every target whose ARKit name
/// starts with `prefix`.
fn moved_by(a: &GlbAvatar, piece: &Piece, prefix: &str) -> f32 {
    let part = &a.avatar.parts()[piece.part];
    let names = &a.avatar.meshes()[part.mesh].target_names;
    names
        .iter()
        .zip(&part.targets)
        .filter(|(n, _)| arkit_name(n).starts_with(prefix))
        .flat_map(|(_, d)| d[piece.vertices.clone()].iter().map(|v| v.length()))
        .fold(0.0, f32::max)
}

#[test]
fn eyes_turn_by_targets_or_by_bones_as_built() {
    for v in variants() {
        let (a, t) = (read(v), &v.truth);
        for eye in &t.eyeballs {
            let k = eye.part;
            let moves = moved_by(&a, eye, "eyeLook") * t.unit_to_metres > 1e-3;
            assert_eq!(moves, t.eye_look_moves_eyeballs, "{}: part {k}", v.name);
            let node = &a.json()["nodes"][a.placements[k].node];
            let skinned_to_eye = node["skin"].as_u64().is_some_and(|s| {
                a.json()["skins"][s as usize]["joints"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .any(|j| {
                        let name = a.json()["nodes"][j.as_u64().unwrap() as usize]["name"].as_str();
                        name.is_some_and(|n| n.ends_with("Eye"))
                    })
            });
            assert_eq!(skinned_to_eye, t.eyes_bone_driven, "{}: part {k}", v.name);
        }
    }
    // bone-eyes: eyeLook targets remain on the head and move only skin
    // near the eyes (the lids).
    let v = variant("bone-eyes");
    let a = read(v);
    let head = &a.avatar.parts()[v.truth.head_part];
    let names = &a.avatar.meshes()[head.mesh].target_names;
    for (n, d) in names.iter().zip(&head.targets) {
        if arkit_name(n).starts_with("eyeLook") {
            for (p, d) in head.positions.iter().zip(d) {
                if d.length() > 1e-5 {
                    assert!(p.y > 0.0 && p.z > -0.03, "{n} moves {p} (not a lid)");
                }
            }
        }
    }
}

#[test]
fn jaw_open_moves_the_lower_half_of_shared_teeth_rigidly() {
    for v in variants() {
        let (a, t) = (read(v), &v.truth);
        let Some(teeth) = &t.teeth else { continue };
        let part = &a.avatar.parts()[teeth.part];
        let jaw = a.avatar.meshes()[part.mesh]
            .target_names
            .iter()
            .position(|n| arkit_name(n) == "jawOpen")
            .unwrap();
        let moved: Vec<usize> = teeth
            .vertices
            .clone()
            .filter(|&i| part.targets[jaw][i].length() > 1e-6)
            .collect();
        assert_eq!(
            moved.len(),
            t.jaw_moved_vertices,
            "{}: jawOpen moves",
            v.name
        );
        // Rigid: distances between moved vertices are kept.
        for w in moved.windows(2).step_by(7) {
            let (i, j) = (w[0], w[1]);
            let before = part.positions[i].distance(part.positions[j]);
            let after = (part.positions[i] + part.targets[jaw][i])
                .distance(part.positions[j] + part.targets[jaw][j]);
            assert!((before - after).abs() < 2e-6, "{}: not rigid", v.name);
        }
    }
    assert!(
        variant("teeth-gums-one-mesh")
            .truth
            .teeth_share_mesh_with_gums
    );
}

#[test]
fn the_variants_differ_from_the_default_avatar() {
    let low = &variant("low-poly").truth;
    assert!(
        (2_000..=3_000).contains(&low.head_vertices),
        "{}",
        low.head_vertices
    );
    let body = &variant("full-body").truth;
    assert!((9..=11).contains(&body.meshes));
    assert!(
        body.world_bounds[1].y - body.world_bounds[0].y > 1.5,
        "a standing body"
    );
    let other = &variant("other-proportions").truth;
    let default = &variant("cm-z-up").truth; // the default head's eyes
    let ratio = other.eye_distance / default.eye_distance;
    assert!((ratio - 1.0).abs() > 0.03, "eye spacing ratio {ratio}");
    let width = |t: &VariantTruth| (t.world_bounds[1].x - t.world_bounds[0].x) * t.unit_to_metres;
    let wider = width(other) / width(&variant("bone-eyes").truth);
    assert!((1.08..1.16).contains(&wider), "face width ratio {wider}");
    let one = &variant("one-mesh-face").truth;
    assert_eq!((one.meshes, one.parts), (1, 6));
}

#[test]
fn generation_is_deterministic() {
    let again = avatar_variants();
    for (a, b) in variants().iter().zip(&again) {
        assert!(a.glb == b.glb, "{} differs between two builds", a.name);
    }
}

#[test]
fn every_variant_passes_the_khronos_validator() {
    let dir = std::env::temp_dir().join(format!("likeness-avatar-variants-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let files: Vec<_> = variants()
        .iter()
        .map(|v| {
            let f = dir.join(format!("{}.glb", v.name));
            std::fs::write(&f, &v.glb).unwrap();
            f
        })
        .collect();
    let reports = validate("every_variant_passes_the_khronos_validator", &files);
    std::fs::remove_dir_all(&dir).unwrap();
    let Some(reports) = reports else {
        return;
    };
    for r in &reports {
        let issues = &r["issues"];
        for m in issues["messages"].as_array().unwrap() {
            if m["severity"].as_u64() == Some(0) {
                eprintln!("{}: {m}", r["file"]);
            }
        }
        eprintln!(
            "{}: {} errors, {} warnings, {} infos",
            r["file"], issues["numErrors"], issues["numWarnings"], issues["numInfos"]
        );
        assert_eq!(issues["numErrors"], 0, "{}", r["file"]);
        assert_eq!(issues["numWarnings"], 0, "{}", r["file"]);
    }
}

/// `lined-sockets` is what it stands for: no boundary loop of its head
/// part lies at an eye (within the eyeball's radius of its centre), so
/// nothing in the topology says where its lids end; the default avatar
/// has one at each eye.
#[test]
fn lined_sockets_have_no_hole_at_the_eyes() {
    use likeness::geometry::Topology;
    use likeness::geometry::mesh_boundary::boundary_loops;
    let loops_at_eyes = |name: &str| {
        let v = variants().iter().find(|v| v.name == name).expect("listed");
        let a = read_avatar_bytes(&v.glb, v.name).expect("reads");
        let head = &a.avatar.parts()[v.truth.head_part];
        let topology =
            Topology::new(head.positions.len(), head.triangles.clone()).expect("a checked part");
        let eyes = v.truth.eyeballs.each_ref().map(|e| {
            let p = &a.avatar.parts()[e.part].positions[e.vertices.clone()];
            let c = p.iter().copied().sum::<Vec3>() / p.len() as f32;
            let r = p.iter().map(|q| q.distance(c)).fold(0.0, f32::max);
            (c, r)
        });
        boundary_loops(&topology)
            .expect("a manifold head")
            .iter()
            .filter(|l| {
                let c =
                    l.iter().map(|&i| head.positions[i as usize]).sum::<Vec3>() / l.len() as f32;
                eyes.iter().any(|(e, r)| c.distance(*e) < *r)
            })
            .count()
    };
    assert_eq!(loops_at_eyes("lined-sockets"), 0);
    assert_eq!(loops_at_eyes("bone-eyes"), 2, "the check finds eye holes");
}
