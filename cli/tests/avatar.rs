//! `likeness avatar` and `likeness default-avatar` as a person uses them:
//! a session and an avatar in, a GLB (and the retarget map) out, a summary,
//! the registration cached, and clear errors on a bad avatar file.

use likeness::Blendshape;
use likeness::avatar::glb::{check_avatar, read_avatar};
use std::path::{Path, PathBuf};
use std::process::Command;

mod common;
use common::{likeness, s, text};

/// A fresh scratch folder for one test.
fn scratch(name: &str) -> PathBuf {
    common::scratch("cli-avatar", name)
}

#[test]
fn a_session_onto_a_user_avatar_gives_a_glb_a_map_and_a_summary() {
    let dir = scratch("user");
    let avatar = dir.join("avatar.glb");
    let out = likeness(&["default-avatar", "--out", &s(&avatar)]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(text(&out.stdout).contains("52 ARKit shapes"));

    let session = likeness_tests::committed::path(1);
    let (glb, map, cache) = (dir.join("out.glb"), dir.join("map.json"), dir.join("cache"));
    let args = [
        "avatar",
        &s(&session),
        "--avatar",
        &s(&avatar),
        "--out",
        &s(&glb),
        "--retarget-map",
        &s(&map),
        "--cache-dir",
        &s(&cache),
        "--json",
    ];
    let first = likeness(&args);
    assert!(first.status.success(), "{}", text(&first.stderr));
    let v: serde_json::Value = serde_json::from_slice(&first.stdout).expect("JSON");
    assert_eq!(v["arkit_found"], 52);
    // The default avatar lacks nothing: no step skipped, nothing to warn.
    assert_eq!(v["warnings"], serde_json::json!([]), "{v}");
    assert!(
        !text(&first.stderr).contains("warning"),
        "{}",
        text(&first.stderr)
    );
    assert_eq!(v["registration_cached"], false);
    // The whole command's time covers the steps after reading the
    // session, and the avatar's own (read, its face found) that run
    // beside it.
    let seconds = &v["seconds"];
    let step = |k: &str| seconds[k].as_f64().unwrap_or(f64::NAN);
    let after_reading: f64 = ["take_face", "retargeting", "implant", "write"]
        .iter()
        .map(|k| step(k))
        .sum();
    assert!(
        step("total") >= step("read_session") + step("personalize") + after_reading,
        "{seconds}"
    );
    assert!(
        step("total") >= step("read_avatar") + step("registration") + after_reading,
        "{seconds}"
    );
    // The residual printed is the floored one, with its shape.
    let worst = v["retarget_worst_shape"].as_str().unwrap_or_default();
    assert!(
        likeness::arkit::Blendshape::parse(worst).is_ok(),
        "{worst:?}"
    );
    let floored = v["retarget_worst_floored_residual"].as_f64().unwrap();
    let relative = v["retarget_worst_relative_residual"].as_f64().unwrap();
    // The floor only ever lowers a residual (every shape moves the face).
    assert!(floored.is_finite() && floored <= relative, "{v}");
    // An avatar the user brings keeps its own face unless asked.
    assert_eq!(v["rest_face"], "stock", "{v}");
    assert_eq!(v["face_fit_mm"], serde_json::Value::Null, "{v}");
    assert!(v["face_vertices"].as_u64().unwrap() > 5000, "{v}");
    assert!(
        v["registration_residual_mean_mm"].as_f64().unwrap() < 0.1,
        "{v}"
    );
    assert!(
        v["shapes"].as_str().unwrap().starts_with("personalized"),
        "{v}"
    );
    assert!(v["implant_face_vertices"].as_u64().unwrap() > 5000, "{v}");
    assert!(
        v["implant_adjacent_vertices"].as_u64().unwrap() > 500,
        "{v}"
    );

    // The GLB reads back with all 52 shapes in ARKit's spelling.
    let written = read_avatar(&glb).expect("the written GLB reads");
    let found = check_avatar(&written).expect("an avatar");
    assert_eq!(found.found(), 52);
    let head = &written.avatar.meshes()[0];
    for shape in Blendshape::ALL {
        assert!(
            head.target_names.iter().any(|n| n == shape.name()),
            "{shape}"
        );
    }

    // The map: 52 rows of k weights, in the documented format.
    let m: serde_json::Value = serde_json::from_slice(&std::fs::read(&map).unwrap()).unwrap();
    assert_eq!(m["format"], "likeness-retarget-map");
    assert_eq!(m["version"], 1);
    let k = m["targets"].as_array().unwrap().len();
    assert_eq!(m["arkit"].as_array().unwrap().len(), 52);
    let rows = m["weights"].as_array().unwrap();
    assert_eq!(rows.len(), 52);
    assert!(rows.iter().all(|r| r.as_array().unwrap().len() == k));

    // The second run finds the registration in the cache; --retargeted
    // writes Eq. (4)'s A_j instead, and says so.
    let mut again = args.to_vec();
    again.push("--retargeted");
    let second = likeness(&again);
    assert!(second.status.success(), "{}", text(&second.stderr));
    let v: serde_json::Value = serde_json::from_slice(&second.stdout).unwrap();
    assert_eq!(v["registration_cached"], true);
    assert!(
        v["shapes"]
            .as_str()
            .unwrap()
            .contains("automatic retargeting"),
        "{v}"
    );
    assert_eq!(v["implant_face_vertices"], 0);

    // --take-face gives it the person's face all the same.
    let mut taking = args.to_vec();
    taking.push("--take-face");
    let third = likeness(&taking);
    assert!(third.status.success(), "{}", text(&third.stderr));
    let v: serde_json::Value = serde_json::from_slice(&third.stdout).unwrap();
    assert_eq!(v["rest_face"], "person", "{v}");
    // The scanned neutral within 0.1 mm of the new skin on average, 0.3
    // mm at the 95th percentile.
    assert!(v["face_surface_mm"][0].as_f64().unwrap() < 0.1, "{v}");
    assert!(v["face_surface_mm"][1].as_f64().unwrap() < 0.3, "{v}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_default_avatar_takes_the_persons_face_unless_told_to_keep_its_own() {
    let dir = scratch("face");
    let session = likeness_tests::committed::path(3);
    let run = |extra: &[&str], out: &Path| -> serde_json::Value {
        let mut args = vec!["avatar", &s(&session), "--out", &s(out), "--json"]
            .into_iter()
            .map(String::from)
            .collect::<Vec<_>>();
        args.extend(extra.iter().map(|a| a.to_string()));
        args.extend(["--cache-dir".to_string(), s(&dir.join("cache"))]);
        let refs: Vec<&str> = args.iter().map(String::as_str).collect();
        let out = likeness(&refs);
        assert!(out.status.success(), "{}", text(&out.stderr));
        serde_json::from_slice(&out.stdout).expect("JSON")
    };
    let (own, kept) = (dir.join("own.glb"), dir.join("kept.glb"));
    let v = run(&[], &own);
    assert_eq!(v["rest_face"], "person", "{v}");
    // The scanned neutral within 0.1 mm of the new skin on average, 0.3
    // mm at the 95th percentile.
    assert!(v["face_surface_mm"][0].as_f64().unwrap() < 0.1, "{v}");
    assert!(v["face_surface_mm"][1].as_f64().unwrap() < 0.3, "{v}");
    // A real face differs from the stock one by millimetres.
    assert!(v["face_largest_change_mm"].as_f64().unwrap() > 2.0, "{v}");
    let v = run(&["--keep-face"], &kept);
    assert_eq!(v["rest_face"], "stock", "{v}");
    let (own, kept) = (
        read_avatar(&own).expect("reads"),
        read_avatar(&kept).expect("reads"),
    );
    let moved = own
        .avatar
        .positions()
        .iter()
        .zip(kept.avatar.positions())
        .map(|(a, b)| a.distance(b))
        .fold(0.0f32, f32::max);
    assert!(moved > 0.002, "the rests differ by {moved} m at most");
    let clash = likeness(&[
        "avatar",
        &s(&session),
        "--keep-face",
        "--take-face",
        "--out",
        &s(&dir.join("x.glb")),
    ]);
    assert!(
        !clash.status.success(),
        "--keep-face and --take-face together"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A person on ARKit's own mesh (`../shared/arkit-face/`; skipped where it
/// is absent, but not under CI): the default avatar takes the person's
/// face, within 0.3 mm of the scan on average, with nothing past a limit
/// and no warning.
#[test]
fn a_person_on_arkits_mesh_gives_the_default_avatar_their_face() {
    let Some(_) = likeness_sim::arkit_face::shared_arkit_face() else {
        eprintln!(
            "skipped: {} is absent (it is never committed)",
            likeness_sim::arkit_face::shared_arkit_face_dir().display()
        );
        return;
    };
    let dir = scratch("arkit-face");
    let session = dir.join("person.lks");
    let face_dir = likeness_sim::arkit_face::shared_arkit_face_dir();
    let made = likeness(&[
        "simulate",
        "--seed",
        "1",
        "--topology",
        "arkit",
        "--arkit-face",
        &s(&face_dir),
        "--geometry-window",
        "0.4",
        "--out",
        &s(&session),
    ]);
    assert!(made.status.success(), "{}", text(&made.stderr));
    let out = likeness(&[
        "avatar",
        &s(&session),
        "--out",
        &s(&dir.join("me.glb")),
        "--json",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert_eq!(v["rest_face"], "person", "{v}");
    assert_eq!(v["warnings"].as_array().map(Vec::len), Some(0), "{v}");
    assert_eq!(v["checked_faults"].as_u64(), Some(0), "{v}");
    let surface = v["face_surface_mm"][0].as_f64().expect("the face's fit");
    assert!(surface <= 0.3, "{v}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_file_that_is_not_an_avatar_is_a_clear_error() {
    let dir = scratch("bad");
    let bad = dir.join("notes.glb");
    std::fs::write(&bad, b"these are not the bytes of a glTF file").unwrap();
    let session = likeness_tests::committed::path(1);
    let out = likeness(&[
        "avatar",
        &s(&session),
        "--avatar",
        &s(&bad),
        "--out",
        &s(&dir.join("out.glb")),
    ]);
    assert!(!out.status.success());
    let err = text(&out.stderr);
    assert!(err.contains("notes.glb"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(!dir.join("out.glb").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_mask_alone_is_a_glb_of_the_persons_52_shapes() {
    let dir = scratch("mask");
    let out = dir.join("mask.glb");
    let session = likeness_tests::committed::path(2);
    let run = likeness(&["avatar", &s(&session), "--mask-only", "--out", &s(&out)]);
    assert!(run.status.success(), "{}", text(&run.stderr));
    let written = read_avatar(&out).expect("reads");
    assert_eq!(written.avatar.vertex_count(), 1220);
    assert_eq!(check_avatar(&written).expect("an avatar").found(), 52);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_demo_ends_with_the_persons_avatar_in_the_current_folder() {
    let dir = scratch("demo");
    let run = Command::new(env!("CARGO_BIN_EXE_likeness"))
        .arg("demo")
        .current_dir(&dir)
        .output()
        .expect("runs");
    assert!(run.status.success(), "{}", text(&run.stderr));
    let stdout = text(&run.stdout);
    let glb = dir.join("likeness-demo-avatar.glb");
    assert!(stdout.contains("likeness-demo-avatar.glb"), "{stdout}");
    let written = read_avatar(&glb).expect("the demo's avatar reads");
    assert_eq!(check_avatar(&written).expect("an avatar").found(), 52);
    // The preview of the faces: the stock one and two people's, side by side.
    assert!(stdout.contains("likeness-demo-faces.png"), "{stdout}");
    assert!(stdout.contains("subject 1's and subject 2's"), "{stdout}");
    let png = std::fs::read(dir.join("likeness-demo-faces.png")).expect("the faces");
    assert_eq!(&png[1..4], b"PNG");
    let width = u32::from_be_bytes([png[16], png[17], png[18], png[19]]);
    let height = u32::from_be_bytes([png[20], png[21], png[22], png[23]]);
    assert!(
        width > height,
        "three faces side by side: {width} × {height}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_session_that_cannot_be_personalized_writes_nothing() {
    let dir = scratch("no-captures");
    let mut parts = likeness_tests::committed::read(1)
        .expect("reads")
        .into_parts();
    parts.captures.clear();
    parts.truth = None;
    let session = likeness::Session::new(parts).expect("a session without captures is valid");
    let path = dir.join("empty.likeness");
    likeness::session::file::write(&path, &session).expect("writes");
    let glb = dir.join("out.glb");
    let out = likeness(&["avatar", &s(&path), "--out", &s(&glb)]);
    assert!(!out.status.success());
    let err = text(&out.stderr);
    assert!(err.contains("capture"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(!glb.exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// A compressed avatar (`EXT_meshopt_compression` and
/// `KHR_mesh_quantization` required, as VRoid and web-optimised exports
/// are) is personalized like any other and written back decompressed.
#[test]
fn a_compressed_avatar_is_personalized_and_written_back_plain() {
    let dir = scratch("compressed");
    let plain = likeness_sim::default_avatar::default_avatar_glb().expect("the default avatar");
    let compressed = likeness_sim::compressed_glb::meshopt_compressed(&plain).expect("compressed");
    let avatar = dir.join("compressed.glb");
    std::fs::write(&avatar, &compressed).unwrap();
    let glb = dir.join("x.glb");
    let session = likeness_tests::committed::path(1);
    let out = likeness(&[
        "avatar",
        &s(&session),
        "--avatar",
        &s(&avatar),
        "--out",
        &s(&glb),
        "--cache-dir",
        &s(&dir.join("cache")),
        "--json",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert_eq!(v["arkit_found"], 52, "{v}");
    let written = read_avatar(&glb).expect("the written GLB reads");
    assert_eq!(check_avatar(&written).expect("an avatar").found(), 52);
    let doc = written.json();
    for key in ["extensionsUsed", "extensionsRequired"] {
        let list = doc[key].as_array().cloned().unwrap_or_default();
        assert!(
            list.iter()
                .all(|e| e != "EXT_meshopt_compression" && e != "KHR_mesh_quantization"),
            "{key}: {list:?}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Two targets on one mesh that read as the same ARKit shape: the one
/// with ARKit's plain name is taken, and `--json` and the summary say which
/// was passed over and why.
#[test]
fn a_shape_named_twice_says_which_target_was_taken() {
    use likeness_sim::{avatar_variants::avatar_variants, glb_edit::Glb};
    let dir = scratch("named-twice");
    let vendor = avatar_variants()
        .into_iter()
        .find(|v| v.name == "vendor-export")
        .expect("listed");
    let mut edited = Glb::parse(&vendor.glb);
    let names = &mut edited.json["meshes"][0]["extras"]["targetNames"];
    let close = names
        .as_array()
        .unwrap()
        .iter()
        .position(|n| n == "AK_19_MouthClose")
        .expect("the head's mouthClose");
    names[close] = serde_json::json!("mouthFunnel");
    let avatar = dir.join("named-twice.glb");
    std::fs::write(&avatar, edited.to_bytes()).unwrap();
    let session = likeness_tests::committed::path(1);
    let run = |json: bool| {
        let (glb, cache) = (dir.join("x.glb"), dir.join("cache"));
        let mut args = vec![
            "avatar".to_string(),
            s(&session),
            "--avatar".into(),
            s(&avatar),
            "--out".into(),
            s(&glb),
            "--cache-dir".into(),
            s(&cache),
        ];
        args.extend(json.then(|| "--json".to_string()));
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let out = likeness(&args);
        assert!(out.status.success(), "{}", text(&out.stderr));
        out
    };
    let v: serde_json::Value = serde_json::from_slice(&run(true).stdout).expect("JSON");
    let passed = v["arkit_passed_over"].as_array().expect("a list");
    assert_eq!(passed.len(), 1, "{v}");
    assert_eq!(passed[0]["name"], "AK_20_MouthFunnel");
    assert_eq!(passed[0]["shape"], "mouthFunnel");
    assert_eq!(passed[0]["taken_name"], "mouthFunnel");
    assert_eq!(passed[0]["mesh"], 0);
    assert!(
        passed[0]["why"]
            .as_str()
            .unwrap()
            .contains("without a prefix")
    );
    let said = text(&run(false).stdout);
    assert!(
        said.contains("Not taken: mesh 0 target 19 \"AK_20_MouthFunnel\" reads as mouthFunnel, but \"mouthFunnel\" (target 18) is"),
        "{said}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
