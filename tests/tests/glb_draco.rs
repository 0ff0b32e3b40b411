//! Draco-compressed avatars (`KHR_draco_mesh_compression`): the default
//! avatar compressed by `likeness_sim::compressed_glb::draco` (every
//! primitive a sequential, unquantized Draco mesh) reads back as the same
//! geometry to the bit; what is written back from it is plain glTF 2.0
//! the Khronos validator takes with no error; a corrupt or inconsistent
//! stream is a typed error naming the view, never a panic.

use likeness::avatar::glb::{GlbError, NewShapes, read_avatar_bytes};
use likeness::avatar::glb::{TargetEncoding, written_back_glb};
use likeness_sim::compressed_glb::draco::{EXTENSION, draco_compressed};
use likeness_sim::default_avatar::default_avatar_glb;
use likeness_sim::glb_edit::Glb;
use likeness_tests::gltf_validator::validate;
use serde_json::json;
use std::path::Path;

fn plain_and_compressed() -> (Vec<u8>, Vec<u8>) {
    let plain = default_avatar_glb().expect("the default avatar");
    let compressed = draco_compressed(&plain).expect("compressed");
    (plain, compressed)
}

#[test]
fn the_draco_compressed_default_avatar_reads_back_to_the_bit() {
    let (plain, compressed) = plain_and_compressed();
    let doc = Glb::parse(&compressed).json;
    assert!(
        doc["extensionsRequired"]
            .as_array()
            .unwrap()
            .contains(&json!(EXTENSION))
    );
    eprintln!(
        "default avatar: {} bytes plain, {} with Draco",
        plain.len(),
        compressed.len()
    );
    let (a, b) = (
        read_avatar_bytes(&plain, "plain.glb").unwrap(),
        read_avatar_bytes(&compressed, "draco.glb").unwrap(),
    );
    assert_eq!(a.avatar.meshes(), b.avatar.meshes());
    assert_eq!(a.avatar.parts().len(), b.avatar.parts().len());
    for (pa, pb) in a.avatar.parts().iter().zip(b.avatar.parts()) {
        assert_eq!(pa.triangles, pb.triangles, "{}", pa.name);
        assert_eq!(pa.positions, pb.positions, "{}", pa.name);
        assert_eq!(pa.targets, pb.targets, "{}", pa.name);
    }
    for key in ["extensionsUsed", "extensionsRequired"] {
        let list = b.json()[key].as_array().cloned().unwrap_or_default();
        assert!(!list.contains(&json!(EXTENSION)), "{key}: {list:?}");
    }
}

#[test]
fn the_avatar_written_back_from_a_draco_one_is_plain_and_valid() {
    let (_, compressed) = plain_and_compressed();
    let read = read_avatar_bytes(&compressed, "draco.glb").unwrap();
    let back = written_back_glb(
        &read,
        &NewShapes::new(),
        TargetEncoding::Smallest,
        Path::new("back.glb"),
    )
    .unwrap();
    let doc = Glb::parse(&back).json;
    assert_eq!(doc["buffers"].as_array().unwrap().len(), 1);
    for m in doc["meshes"].as_array().unwrap() {
        for p in m["primitives"].as_array().unwrap() {
            assert!(p.get("extensions").is_none(), "{p}");
        }
    }
    let again = read_avatar_bytes(&back, "back.glb").unwrap();
    for (pa, pb) in read.avatar.parts().iter().zip(again.avatar.parts()) {
        assert_eq!(pa.positions, pb.positions, "{}", pa.name);
    }
    let dir = std::env::temp_dir().join(format!("likeness-glb-draco-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("back.glb");
    std::fs::write(&path, &back).unwrap();
    if let Some(reports) = validate("glb_draco", std::slice::from_ref(&path)) {
        let issues = &reports[0]["issues"];
        for m in issues["messages"].as_array().unwrap() {
            eprintln!("{m}");
        }
        for kind in ["numErrors", "numWarnings", "numInfos", "numHints"] {
            assert_eq!(issues[kind], json!(0), "{kind}");
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `glb` with its JSON edited by `f`.
fn edited(glb: &[u8], f: impl FnOnce(&mut serde_json::Value)) -> Vec<u8> {
    let mut g = Glb::parse(glb);
    f(&mut g.json);
    g.to_bytes()
}

#[test]
fn a_corrupt_or_inconsistent_draco_stream_is_a_typed_error() {
    let (_, compressed) = plain_and_compressed();
    let ext =
        |d: &serde_json::Value| d["meshes"][0]["primitives"][0]["extensions"][EXTENSION].clone();
    let view = ext(&Glb::parse(&compressed).json)["bufferView"]
        .as_u64()
        .unwrap() as usize;
    let cases: Vec<(&str, Vec<u8>)> = vec![
        (
            "cut short",
            edited(&compressed, |d| {
                d["bufferViews"][view]["byteLength"] = json!(40)
            }),
        ),
        (
            "an attribute id the mesh lacks",
            edited(&compressed, |d| {
                d["meshes"][0]["primitives"][0]["extensions"][EXTENSION]["attributes"]["POSITION"] =
                    json!(17)
            }),
        ),
        (
            "a vertex count that is not the accessor's",
            edited(&compressed, |d| {
                let a = d["meshes"][0]["primitives"][0]["attributes"]["POSITION"]
                    .as_u64()
                    .unwrap();
                d["accessors"][a as usize]["count"] = json!(3);
            }),
        ),
        (
            "a view past the buffer",
            edited(&compressed, |d| {
                d["bufferViews"][view]["byteOffset"] = json!(1u64 << 40)
            }),
        ),
    ];
    for (what, bytes) in cases {
        match read_avatar_bytes(&bytes, "bad.glb") {
            Err(GlbError::Compressed {
                view: v, what: why, ..
            }) => {
                eprintln!("{what}: {why}");
                assert_eq!(v, view, "{what}");
                assert!(why.contains("meshes[0].primitives[0]"), "{what}: {why}");
            }
            Err(GlbError::Invalid { what: why, .. }) => eprintln!("{what}: invalid: {why}"),
            other => panic!("{what}: {other:?}"),
        }
    }
}
