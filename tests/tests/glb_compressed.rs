//! Compressed avatars: the default avatar compressed by
//! `likeness_sim::compressed_glb` (positions and target displacements as
//! `KHR_mesh_quantization` normalized SHORT with a dequantizing node
//! transform, normals as normalized BYTE through the octahedral filter,
//! everything in `EXT_meshopt_compression` views) reads back as the same
//! geometry within the quantization step; what is written back from it is
//! plain glTF 2.0 the Khronos validator takes; a corrupt stream is a typed error, never a panic.
//!
//! Tolerance: a mesh stores each coordinate in steps of `s / 32767`, `s`
//! its dequantization scale (half its bounding box's longest side, or the
//! longest displacement if larger: the node's scale in the compressed
//! file), so a position or a displacement is off by at most half a step,
//! `s / 65534`, plus float rounding (taken as `s · 1e-6`).

use glam::Vec3;
use likeness::Blendshape;
use likeness::avatar::glb::{GlbError, NewShapes, check_avatar, read_avatar_bytes};
use likeness::avatar::glb::{TargetEncoding, written_back_glb};
use likeness_sim::compressed_glb::meshopt_compressed;
use likeness_sim::default_avatar::default_avatar_glb;
use likeness_tests::gltf_validator::validate;
use serde_json::{Value, json};
use std::path::{Path, PathBuf};
use std::time::Instant;

fn plain_and_compressed() -> (Vec<u8>, Vec<u8>) {
    let plain = default_avatar_glb().expect("the default avatar");
    let compressed = meshopt_compressed(&plain).expect("compressed");
    (plain, compressed)
}

/// Each mesh's dequantization scale `s`, from the scale of the node that
/// places it in the compressed file (the plain file's nodes have none).
fn scales(compressed: &Value, meshes: usize) -> Vec<f32> {
    let nodes = compressed["nodes"].as_array().unwrap();
    (0..meshes)
        .map(|m| {
            let node = nodes.iter().find(|n| n["mesh"] == json!(m)).unwrap();
            node["scale"][0].as_f64().unwrap() as f32
        })
        .collect()
}

/// A triangle turned so that its smallest index comes first (same winding).
fn canonical(t: [u32; 3]) -> [u32; 3] {
    let k = (0..3).min_by_key(|&k| t[k]).unwrap_or(0);
    [t[k], t[(k + 1) % 3], t[(k + 2) % 3]]
}

fn json_of(glb: &[u8]) -> Value {
    let n = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
    serde_json::from_slice(&glb[20..20 + n]).unwrap()
}

#[test]
fn the_compressed_default_avatar_reads_back_the_same_geometry() {
    let (plain, compressed) = plain_and_compressed();
    let doc = json_of(&compressed);
    for ext in ["EXT_meshopt_compression", "KHR_mesh_quantization"] {
        assert!(
            doc["extensionsRequired"]
                .as_array()
                .unwrap()
                .contains(&json!(ext))
        );
    }
    assert_eq!(
        doc["accessors"][0]["componentType"], 5122,
        "positions as SHORT"
    );
    eprintln!(
        "default avatar: {} bytes plain, {} bytes compressed",
        plain.len(),
        compressed.len()
    );
    let a = read_avatar_bytes(&plain, "plain.glb").unwrap();
    let start = Instant::now();
    let b = read_avatar_bytes(&compressed, "compressed.glb").unwrap();
    let compressed_time = start.elapsed();
    let start = Instant::now();
    read_avatar_bytes(&plain, "plain.glb").unwrap();
    eprintln!(
        "read: compressed {:.1} ms, plain {:.1} ms",
        compressed_time.as_secs_f64() * 1e3,
        start.elapsed().as_secs_f64() * 1e3
    );
    assert_eq!(check_avatar(&b).unwrap().found(), 52);
    assert_eq!(
        a.avatar.meshes(),
        b.avatar.meshes(),
        "names and target names"
    );
    assert_eq!(a.avatar.parts().len(), b.avatar.parts().len());
    let s = scales(&doc, a.avatar.meshes().len());
    eprintln!("dequantization scales (m): {s:?}");
    let mut worst = 0.0f32;
    for (pa, pb) in a.avatar.parts().iter().zip(b.avatar.parts()) {
        let tol = s[pa.mesh] / 65534.0 + s[pa.mesh] * 1e-6;
        let ta: Vec<_> = pa.triangles.iter().map(|&t| canonical(t)).collect();
        let tb: Vec<_> = pb.triangles.iter().map(|&t| canonical(t)).collect();
        assert_eq!(ta, tb, "{}: triangles", pa.name);
        assert_eq!(pa.targets.len(), 52);
        assert_eq!(pb.targets.len(), 52);
        let pairs = pa.positions.iter().zip(&pb.positions);
        let targets = pa
            .targets
            .iter()
            .zip(&pb.targets)
            .flat_map(|(x, y)| x.iter().zip(y));
        for (x, y) in pairs.chain(targets) {
            let e = (*x - *y).abs().max_element();
            worst = worst.max(e / tol);
            assert!(e <= tol, "{}: {x} vs {y}, tolerance {tol}", pa.name);
        }
    }
    eprintln!("worst error: {worst:.3} of the tolerance");
}

#[test]
fn decoding_the_default_avatar_is_fast() {
    let (_, compressed) = plain_and_compressed();
    read_avatar_bytes(&compressed, "warm.glb").unwrap();
    let runs = 10;
    let start = Instant::now();
    for _ in 0..runs {
        read_avatar_bytes(&compressed, "compressed.glb").unwrap();
    }
    let each = start.elapsed().as_secs_f64() / runs as f64;
    eprintln!(
        "reading the compressed default avatar: {:.1} ms",
        each * 1e3
    );
    // Generous (debug builds, shared CPUs): the release build reads it in
    // a few milliseconds.
    assert!(each < 2.0, "{each} s");
}

fn temp_dir() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("likeness-glb-compressed-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn the_avatar_written_back_from_a_compressed_one_is_plain_and_valid() {
    let (_, compressed) = plain_and_compressed();
    let read = read_avatar_bytes(&compressed, "compressed.glb").unwrap();
    let mut shapes = NewShapes::new();
    let per_part: Vec<Vec<Vec3>> = read
        .avatar
        .parts()
        .iter()
        .map(|p| {
            p.positions
                .iter()
                .map(|x| Vec3::new(0.0, -0.05 * x.x.abs(), 0.0))
                .collect()
        })
        .collect();
    shapes.set(Blendshape::JawOpen, per_part.clone());
    let file = Path::new("back.glb");
    let back = written_back_glb(&read, &shapes, TargetEncoding::Smallest, file).unwrap();
    let doc = json_of(&back);
    for key in ["extensionsUsed", "extensionsRequired"] {
        let list = doc[key].as_array().cloned().unwrap_or_default();
        assert!(
            !list
                .iter()
                .any(|e| e == "EXT_meshopt_compression" || e == "KHR_mesh_quantization"),
            "{key}: {list:?}"
        );
    }
    assert_eq!(doc["buffers"].as_array().unwrap().len(), 1);
    for v in doc["bufferViews"].as_array().unwrap() {
        assert!(v.get("extensions").is_none(), "{v}");
    }
    for m in doc["meshes"].as_array().unwrap() {
        for p in m["primitives"].as_array().unwrap() {
            let mut used: Vec<u64> = p["attributes"]
                .as_object()
                .unwrap()
                .values()
                .filter_map(Value::as_u64)
                .collect();
            for t in p["targets"].as_array().into_iter().flatten() {
                used.extend(t.as_object().unwrap().values().filter_map(Value::as_u64));
            }
            for a in used {
                assert_eq!(
                    doc["accessors"][a as usize]["componentType"], 5126,
                    "accessor {a}"
                );
            }
        }
    }
    // The new shape reads back in world space.
    let again = read_avatar_bytes(&back, "back.glb").unwrap();
    let jaw = again.avatar.meshes()[0]
        .target_names
        .iter()
        .position(|n| n == "jawOpen")
        .unwrap();
    for (k, part) in again
        .avatar
        .parts()
        .iter()
        .enumerate()
        .filter(|(_, p)| p.mesh == 0)
    {
        for (x, y) in part.targets[jaw].iter().zip(&per_part[k]) {
            assert!((*x - *y).length() < 1e-5, "{x} vs {y}");
        }
    }
    let dir = temp_dir();
    let path = dir.join("back.glb");
    std::fs::write(&path, &back).unwrap();
    if let Some(reports) = validate("glb_compressed", std::slice::from_ref(&path)) {
        let issues = &reports[0]["issues"];
        for m in issues["messages"].as_array().unwrap() {
            eprintln!("{m}");
        }
        eprintln!(
            "validator {}: {} errors, {} warnings, {} infos, {} hints",
            reports[0]["validatorVersion"],
            issues["numErrors"],
            issues["numWarnings"],
            issues["numInfos"],
            issues["numHints"]
        );
        for kind in ["numErrors", "numWarnings", "numInfos", "numHints"] {
            assert_eq!(issues[kind], json!(0), "{kind}");
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `glb` with its JSON replaced by `f(json)`.
fn with_json(glb: &[u8], f: impl FnOnce(&mut Value)) -> Vec<u8> {
    let n = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
    let mut doc: Value = serde_json::from_slice(&glb[20..20 + n]).unwrap();
    f(&mut doc);
    let mut text = serde_json::to_vec(&doc).unwrap();
    text.resize(text.len().next_multiple_of(4), b' ');
    let bin = &glb[20 + n..];
    let mut out = Vec::new();
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&((20 + text.len() + bin.len()) as u32).to_le_bytes());
    out.extend_from_slice(&(text.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&text);
    out.extend_from_slice(bin);
    out
}

#[test]
fn a_corrupt_stream_is_a_typed_error_naming_the_view() {
    let (_, compressed) = plain_and_compressed();
    // The compressed bytes of view 0 cut short.
    let short = with_json(&compressed, |doc| {
        doc["bufferViews"][0]["extensions"]["EXT_meshopt_compression"]["byteLength"] = json!(9);
    });
    match read_avatar_bytes(&short, "short.glb") {
        Err(GlbError::Compressed { view: 0, what, .. }) => eprintln!("{what}"),
        other => panic!("{other:?}"),
    }
    // Fields out of range, each a typed error.
    for (key, value) in [
        ("mode", json!("SPIRAL")),
        ("byteStride", json!(6)),
        ("count", json!(1u64 << 40)),
        ("buffer", json!(7)),
        ("filter", json!("QUATERNION")),
        ("byteOffset", json!(-1)),
    ] {
        let bad = with_json(&compressed, |doc| {
            doc["bufferViews"][0]["extensions"]["EXT_meshopt_compression"][key] = value.clone();
        });
        match read_avatar_bytes(&bad, "bad.glb") {
            Err(GlbError::Compressed { view: 0, what, .. }) => eprintln!("{key}: {what}"),
            other => panic!("{key}: {other:?}"),
        }
    }
    // Random bytes overwritten anywhere in the binary chunk: an error or a
    // (garbled) avatar, never a panic.
    let n = u32::from_le_bytes(compressed[12..16].try_into().unwrap()) as usize;
    let bin = 20 + n + 8;
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let (mut errors, mut reads) = (0, 0);
    for _ in 0..300 {
        let mut bad = compressed.clone();
        for _ in 0..1 + next() % 8 {
            let at = bin + (next() as usize) % (bad.len() - bin);
            bad[at] = next() as u8;
        }
        match read_avatar_bytes(&bad, "bad.glb") {
            Ok(_) => reads += 1,
            Err(_) => errors += 1,
        }
    }
    eprintln!("300 corrupted files: {errors} errors, {reads} read");
}
