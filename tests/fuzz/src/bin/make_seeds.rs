//! Writes the generated seed corpora: `make_seeds OUT [--large]`.
//!
//! Into `OUT/<target>/`: the tiny session (`likeness_fuzz::tiny`) as a
//! file, as a payload and as a compressed stream; its folder export
//! (packed for `folder_import`, its OBJs and CSVs one by one); Live Link
//! Face text of its stream; the tiny avatar as a GLB and as a `.gltf`; a
//! capture script that takes the FFI's capture to a finished session.
//! With `--large`, also into `OUT/large/<target>/`: the committed session
//! of subject 1 with its stream cut to two seconds, its template as OBJs,
//! and the default avatar (1.8 MB), to run each target once on real-sized
//! files.

use likeness::avatar::glb::{MaterialSplit, MeshLook, NewGlbOptions, new_avatar_glb};
use likeness::session::file;
use likeness::session::interchange::export_folder;
use likeness::{Frame, Session};
use likeness_fuzz::capture_driver::{Op, TEMPLATE_SESSION};
use likeness_fuzz::{folder, payload_of, tiny};
use std::path::{Path, PathBuf};

fn main() {
    let mut args = std::env::args().skip(1);
    let out = PathBuf::from(args.next().expect("usage: make_seeds OUT [--large]"));
    let large = args.next().as_deref() == Some("--large");
    let work = std::env::temp_dir().join(format!("likeness-seeds-{}", std::process::id()));
    for (name, session) in [
        ("tiny", tiny::session(true)),
        ("tiny-no-truth", tiny::session(false)),
    ] {
        session_seeds(&out, name, &session, &work.join(name));
    }
    glb_seeds(&out);
    capture_seeds(&out);
    if large {
        let subject = file::read(TEMPLATE_SESSION).expect("committed session");
        let cut = cut_stream(subject, 120);
        session_seeds(
            &out.join("large"),
            "subject-1-cut",
            &cut,
            &work.join("large"),
        );
        let avatar = likeness_sim::default_avatar::default_avatar_glb().expect("default avatar");
        put(&out.join("large/glb"), "default-avatar.glb", &avatar);
        let compressed =
            likeness_sim::compressed_glb::meshopt_compressed(&avatar).expect("compressed");
        put(
            &out.join("large/glb"),
            "default-avatar-meshopt.glb",
            &compressed,
        );
    }
    let _ = std::fs::remove_dir_all(&work);
}

/// Writes `bytes` to `dir/name`.
fn put(dir: &Path, name: &str, bytes: &[u8]) {
    std::fs::create_dir_all(dir).expect("seed folder");
    std::fs::write(dir.join(name), bytes).expect("seed");
}

/// The session as file, payload and compressed stream; its folder export
/// packed and file by file; its stream as Live Link Face text.
fn session_seeds(out: &Path, name: &str, session: &Session, work: &Path) {
    let bytes = file::encode(session).expect("encodable");
    put(
        &out.join("session_bytes"),
        &format!("{name}.likeness"),
        &bytes,
    );
    put(&out.join("session_payload"), name, &payload_of(&bytes));
    let mut deflate = (payload_of(&bytes).len() as u32).to_le_bytes().to_vec();
    deflate.extend_from_slice(&bytes[file::HEADER_LEN..]);
    put(&out.join("session_deflate"), name, &deflate);
    let _ = std::fs::remove_dir_all(work);
    export_folder(session, work).expect("export");
    // The whole folder of a real-sized session is 9 MB: only its minimal
    // form below is a seed.
    if session.topology.vertex_count() < 100 {
        put(&out.join("folder_import"), name, &folder::pack(work));
    }
    let read = |p: &str| std::fs::read(work.join(p)).expect("exported file");
    put(
        &out.join("obj"),
        &format!("{name}-neutral.obj"),
        &read("neutral.obj"),
    );
    put(
        &out.join("obj"),
        &format!("{name}-jawOpen.obj"),
        &read("template/jawOpen.obj"),
    );
    put(
        &out.join("weights_csv"),
        &format!("{name}-expressions.csv"),
        &read("expressions/weights.csv"),
    );
    if work.join("test/weights.csv").exists() {
        put(
            &out.join("weights_csv"),
            &format!("{name}-test.csv"),
            &read("test/weights.csv"),
        );
    }
    put(
        &out.join("frames_csv"),
        &format!("{name}.csv"),
        &read("frames.csv"),
    );
    let live = likeness_tests::live_link::live_link_csv(&session.frames);
    put(
        &out.join("live_link_csv"),
        &format!("{name}.csv"),
        live.as_bytes(),
    );
    // A minimal folder: the template neutral, the scan and no capture.
    let minimal = format!(
        "@@ template/neutral.obj\n{0}@@ neutral.obj\n{0}@@ expressions/weights.csv\n{1}",
        String::from_utf8_lossy(&read("template/neutral.obj")),
        String::from_utf8_lossy(&read("expressions/weights.csv"))
            .lines()
            .next()
            .map(|h| format!("{h}\n"))
            .unwrap_or_default(),
    );
    put(
        &out.join("folder_import"),
        &format!("{name}-minimal"),
        minimal.as_bytes(),
    );
}

/// `session` with its stream cut to the first `keep` frames (and the
/// references past them dropped).
fn cut_stream(session: Session, keep: usize) -> Session {
    let mut parts = session.into_parts();
    parts.frames.truncate(keep);
    let fits = |f: Option<u32>| f.filter(|&f| (f as usize) < keep);
    for c in &mut parts.captures {
        c.frame = fits(c.frame);
    }
    for t in &mut parts.tests {
        t.frame = fits(t.frame);
    }
    parts.truth = None;
    let frames: &[Frame] = &parts.frames;
    assert!(frames.len() == keep.min(frames.len()));
    Session::new(parts).expect("a cut session")
}

/// The tiny avatar as a GLB: dense, smallest, and quantized and
/// meshopt-compressed.
fn glb_seeds(out: &Path) {
    let avatar = tiny::avatar();
    let dir = out.join("glb");
    for (name, encoding) in [
        (
            "tiny-smallest.glb",
            likeness::avatar::glb::TargetEncoding::Smallest,
        ),
        (
            "tiny-dense.glb",
            likeness::avatar::glb::TargetEncoding::Dense,
        ),
    ] {
        let options = NewGlbOptions {
            encoding,
            ..NewGlbOptions::default()
        };
        let glb = new_avatar_glb(&avatar, &options, Path::new(name)).expect("tiny GLB");
        put(&dir, name, &glb);
    }
    // The head in two materials: two primitives sharing its vertices.
    let options = NewGlbOptions {
        part_splits: vec![vec![MaterialSplit {
            first_triangle: avatar.parts()[0].triangles.len() / 2,
            name: "lips".into(),
            look: MeshLook::GUM,
        }]],
        ..NewGlbOptions::default()
    };
    let glb = new_avatar_glb(&avatar, &options, Path::new("s.glb")).expect("tiny GLB");
    put(&dir, "tiny-two-materials.glb", &glb);
    // The same, quantized and meshopt-compressed.
    let glb =
        new_avatar_glb(&avatar, &NewGlbOptions::default(), Path::new("t.glb")).expect("tiny GLB");
    let compressed = likeness_sim::compressed_glb::meshopt_compressed(&glb).expect("compressed");
    put(&dir, "tiny-meshopt.glb", &compressed);
}

/// Capture scripts: the neutral held still, a few gestures, a retake,
/// everything else skipped, finished, the handle read, saved and loaded.
fn capture_seeds(out: &Path) {
    let op = |o: Op| o as u8;
    let mut finished = vec![op(Op::Start), op(Op::Gesture), 255];
    for _ in 0..4 {
        finished.extend([op(Op::Gesture), 120, op(Op::Query)]);
    }
    finished.extend([op(Op::Retake), 2, 0, op(Op::Gesture), 100, op(Op::Captures)]);
    finished.extend([
        op(Op::SkipAll),
        op(Op::Query),
        op(Op::Finish),
        op(Op::Handle),
        3,
    ]);
    finished.extend([
        op(Op::SaveLoad),
        op(Op::Frame),
        9,
        0,
        5,
        0,
        op(Op::Preview),
        3,
    ]);
    put(&out.join("capture_ffi"), "finished", &finished);
    let hostile = vec![
        op(Op::Frame),
        0,
        60,
        1,
        0, // NaN time, NaN weight, wrong mesh
        op(Op::Frame),
        4,
        120,
        4,
        2, // time back, 26 weights, packed bytes
        op(Op::Skip),
        op(Op::Untracked),
        5,
        op(Op::Pause),
        200,
        op(Op::New),
        203,
        op(Op::New),
        0,
        op(Op::Finish),
    ];
    put(&out.join("capture_ffi"), "hostile", &hostile);
}
