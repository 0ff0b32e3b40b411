//! OBJ + CSV interchange: a committed session survives export → import, a
//! Live Link Face recording imports with the right weights, and every kind of
//! bad input is an error that names the file and the line.

use glam::Vec3;
use likeness::session::interchange::{FileError, InterchangeError, export_folder, import_folder};
use likeness::{
    Blendshape, CapturedExpression, DeviceInfo, Frame, Session, SessionParts, Template,
    TestExpression, Topology, Weights,
};
use likeness_tests::live_link::{LIVE_LINK_NAMES, live_link_header};
use std::fs;
use std::path::{Path, PathBuf};

/// A fresh, empty scratch folder for one test.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "likeness-interchange-{}-{name}",
        std::process::id()
    ));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).unwrap();
    dir
}

fn weights(pairs: &[(Blendshape, f32)]) -> Weights {
    let mut w = Weights::ZERO;
    for (s, v) in pairs {
        w.set(*s, *v);
    }
    w
}

/// A four-vertex session with two captures, one test and three frames.
fn tiny_session() -> Session {
    let quad = |z: f32| {
        vec![
            Vec3::new(0.0, 0.0, z),
            Vec3::new(0.1, 0.0, z),
            Vec3::new(0.1, 0.1, z),
            Vec3::new(0.0, 0.1, z),
        ]
    };
    Session::new(SessionParts {
        device: DeviceInfo::default(),
        frame_rate: 60.0,
        topology: Topology::new(4, vec![[0, 1, 2], [0, 2, 3]]).unwrap(),
        template: Template {
            neutral: quad(0.0),
            shapes: std::array::from_fn(|j| quad(0.001 * j as f32)),
        },
        neutral: quad(0.0005),
        frames: (0..3)
            .map(|k| Frame {
                timestamp: k as f64 / 30.0,
                weights: weights(&[(Blendshape::JawOpen, 0.25 * k as f32)]),
                tracked: true,
                vertices: None,
            })
            .collect(),
        captures: vec![
            CapturedExpression {
                prompt: Blendshape::JawOpen,
                frame: None,
                weights: weights(&[(Blendshape::JawOpen, 0.9)]),
                vertices: quad(0.01),
            },
            CapturedExpression {
                prompt: Blendshape::EyeBlinkLeft,
                frame: None,
                weights: weights(&[(Blendshape::EyeBlinkLeft, 1.0)]),
                vertices: quad(0.02),
            },
        ],
        tests: vec![TestExpression {
            id: "smile-squint".to_string(),
            frame: None,
            weights: weights(&[(Blendshape::MouthSmileLeft, 0.5)]),
            vertices: quad(0.03),
        }],
        truth: None,
    })
    .unwrap()
}

fn assert_close(what: &str, a: &[Vec3], b: &[Vec3]) {
    assert_eq!(a.len(), b.len(), "{what}");
    let worst = a
        .iter()
        .zip(b)
        .map(|(p, q)| (*p - *q).abs().max_element())
        .fold(0.0f32, f32::max);
    assert!(worst <= 1e-7, "{what}: off by {worst} m");
}

#[test]
fn a_committed_session_survives_export_and_import() {
    let session = likeness_tests::committed::read(1).unwrap();
    let dir = scratch("round-trip");
    export_folder(&session, &dir).unwrap();
    let (back, warnings) = import_folder(&dir).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    // What import returns is a session, so it passed every check.
    assert_eq!(back.device.model, "imported");
    assert_eq!(back.topology, session.topology);
    assert_close(
        "template neutral",
        &back.template.neutral,
        &session.template.neutral,
    );
    for (j, (a, b)) in back
        .template
        .shapes
        .iter()
        .zip(&session.template.shapes)
        .enumerate()
    {
        assert_close(&format!("template shape {j}"), a, b);
    }
    assert_close("neutral", &back.neutral, &session.neutral);
    assert_eq!(back.captures.len(), session.captures.len());
    for (a, b) in back.captures.iter().zip(&session.captures) {
        assert_eq!(a.prompt, b.prompt);
        assert_eq!(a.weights, b.weights);
        assert_eq!(a.frame, None);
        assert_close(&format!("capture {}", b.prompt), &a.vertices, &b.vertices);
    }
    assert_eq!(back.tests.len(), session.tests.len());
    for (a, b) in back.tests.iter().zip(&session.tests) {
        assert_eq!(a.id, b.id);
        assert_eq!(a.weights, b.weights);
        assert_close(&format!("test {}", b.id), &a.vertices, &b.vertices);
    }
    assert_eq!(back.frames.len(), session.frames.len());
    for (a, b) in back.frames.iter().zip(&session.frames) {
        assert_eq!(a.timestamp, b.timestamp);
        assert_eq!(a.weights, b.weights);
        assert!(a.vertices.is_none());
    }
    assert!((back.frame_rate - session.frame_rate).abs() < 0.01 * session.frame_rate);
    // The default method chooses λ from the captures, not the stream: the
    // imported session, which has no stream meshes, gets the same λ (up to
    // the 7 decimals of the OBJ coordinates) by the same rule.
    let method = likeness::personalize::Method::DEFAULT;
    let as_recorded = likeness::personalize::personalize(&session, method).unwrap();
    let imported = likeness::personalize::personalize(&back, method).unwrap();
    let (a, b) = (
        as_recorded.lambda_choice.unwrap(),
        imported.lambda_choice.unwrap(),
    );
    assert_eq!(a.rule, b.rule);
    assert!((a.lambda / b.lambda).ln().abs() < 0.05, "{a:?} vs {b:?}");
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_live_link_face_recording_imports_with_the_right_weights() {
    let dir = scratch("live-link");
    export_folder(&tiny_session(), &dir).unwrap();
    let names: Vec<&str> = LIVE_LINK_NAMES.split(',').collect();
    assert_eq!(names.len(), 52);
    // The app's spelling of the count column varies; a BOM and CRLF too.
    let mut csv = format!(
        "\u{feff}{}",
        live_link_header()
            .replace("BlendshapeCount", "BlendShapeCount")
            .replace('\n', "\r\n")
    );
    let timecodes = [
        "10:42:31:12.456",
        "10:42:31:13.456",
        "10:42:31:14.456",
        "10:42:31:59.456",
    ];
    for (k, tc) in timecodes.iter().enumerate() {
        // Column i holds (i + 1) / 100 + k / 1000; rotations are out of range
        // and must be ignored.
        let cells: Vec<String> = (0..52)
            .map(|i| format!("{}", (i + 1) as f32 / 100.0 + k as f32 / 1000.0))
            .collect();
        csv.push_str(&format!(
            "{tc},52,{},-0.3,0.2,1.7,0.1,-0.1,0,0.1,-0.1,0\r\n",
            cells.join(",")
        ));
    }
    fs::write(dir.join("frames.csv"), csv).unwrap();
    let (session, _) = import_folder(&dir).unwrap();
    assert_eq!(session.frames.len(), 4);
    for (k, frame) in session.frames.iter().enumerate() {
        for (i, name) in names.iter().enumerate() {
            let shape = Blendshape::parse(name).unwrap();
            let expected = (i + 1) as f32 / 100.0 + k as f32 / 1000.0;
            assert_eq!(frame.weights.get(shape), expected, "frame {k} {name}");
        }
        assert!(frame.tracked && frame.vertices.is_none());
    }
    // Frame numbers up to 59: a 60 fps timecode, starting at zero.
    let times: Vec<f64> = session.frames.iter().map(|f| f.timestamp).collect();
    for (t, expected) in times.iter().zip([0.0, 1.0 / 60.0, 2.0 / 60.0, 47.0 / 60.0]) {
        assert!((t - expected).abs() < 1e-9, "{times:?}");
    }
    assert!((session.frame_rate - 60.0).abs() < 1e-3);
    // Live Link's JawLeft/JawRight order differs from Apple's.
    assert_eq!(session.frames[0].weights.get(Blendshape::JawLeft), 0.17);
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_plain_tiny_session_round_trips_and_a_missing_template_shape_warns() {
    let dir = scratch("tiny");
    let session = tiny_session();
    export_folder(&session, &dir).unwrap();
    let (back, warnings) = import_folder(&dir).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!(back.frames.len(), 3);
    assert!((back.frame_rate - 30.0).abs() < 1e-3);
    assert_eq!(back.tests[0].id, "smile-squint");

    fs::remove_file(dir.join("template/cheekPuff.obj")).unwrap();
    // Another accepted spelling of a file stem still counts.
    fs::rename(
        dir.join("template/jawOpen.obj"),
        dir.join("template/JawOpen.obj"),
    )
    .unwrap();
    let (back, warnings) = import_folder(&dir).unwrap();
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(warnings[0].contains("cheekPuff.obj"), "{warnings:?}");
    assert_eq!(
        back.template.delta(Blendshape::CheekPuff),
        vec![Vec3::ZERO; 4]
    );
    assert_close(
        "jawOpen",
        &back.template.shapes[Blendshape::JawOpen.index()],
        &session.template.shapes[Blendshape::JawOpen.index()],
    );
    fs::remove_dir_all(&dir).unwrap();
}

/// Exports the tiny session to a fresh folder, lets `spoil` break it, and
/// returns the import error's message.
fn import_error(name: &str, spoil: impl FnOnce(&Path)) -> (InterchangeError, String) {
    let dir = scratch(name);
    export_folder(&tiny_session(), &dir).unwrap();
    spoil(&dir);
    let err = import_folder(&dir).expect_err(name);
    let message = err.to_string();
    fs::remove_dir_all(&dir).unwrap();
    (err, message)
}

/// Replaces the first occurrence of `from` in file `rel` of `dir`.
fn edit(dir: &Path, rel: &str, from: &str, to: &str) {
    let path = dir.join(rel);
    let text = fs::read_to_string(&path).unwrap();
    assert!(text.contains(from), "{rel} lacks {from:?}");
    fs::write(&path, text.replacen(from, to, 1)).unwrap();
}

fn expect(message: &str, file: &str, parts: &[&str]) {
    let at = message
        .find(file)
        .unwrap_or_else(|| panic!("{message:?} does not name {file}"));
    let rest = &message[at + file.len()..];
    for part in parts {
        assert!(rest.contains(part), "{message:?} lacks {part:?}");
    }
}

#[test]
fn bad_inputs_name_the_file_and_line() {
    // Missing files.
    let (err, m) = import_error("missing-template", |d| {
        fs::remove_file(d.join("template/neutral.obj")).unwrap()
    });
    assert!(matches!(
        err,
        InterchangeError::File(FileError::Missing { .. })
    ));
    expect(&m, "template/neutral.obj", &[": missing"]);
    let (_, m) = import_error("missing-neutral", |d| {
        fs::remove_file(d.join("neutral.obj")).unwrap()
    });
    expect(&m, "/neutral.obj", &[": missing"]);
    let (_, m) = import_error("missing-weights", |d| {
        fs::remove_file(d.join("expressions/weights.csv")).unwrap()
    });
    expect(&m, "expressions/weights.csv", &[": missing"]);

    // I/O error: a folder where a file should be.
    let (err, m) = import_error("io", |d| {
        fs::remove_file(d.join("neutral.obj")).unwrap();
        fs::create_dir(d.join("neutral.obj")).unwrap();
    });
    assert!(
        matches!(
            err,
            InterchangeError::File(FileError::NotAFile {
                kind: "a directory",
                ..
            })
        ),
        "{m}"
    );
    expect(&m, "neutral.obj", &["a directory, not a regular file"]);

    // Geometry that does not match the template.
    let (err, m) = import_error("vertex-count", |d| {
        edit(d, "expressions/jawOpen.obj", "f 1 2 3", "v 0 0 0\nf 1 2 3")
    });
    assert!(matches!(err, InterchangeError::VertexCount { .. }));
    expect(&m, "expressions/jawOpen.obj", &["5 vertices", "has 4"]);
    let (err, m) = import_error("faces", |d| {
        edit(d, "expressions/eyeBlinkLeft.obj", "f 1 3 4", "f 1 4 3")
    });
    assert!(matches!(err, InterchangeError::Faces { .. }));
    expect(&m, "expressions/eyeBlinkLeft.obj", &[":7:", "triangle 2"]);
    let (_, m) = import_error("face-count", |d| edit(d, "neutral.obj", "f 1 3 4\n", ""));
    expect(&m, "/neutral.obj", &["1 triangles", "has 2"]);
    let (_, m) = import_error("bad-coordinate", |d| {
        edit(
            d,
            "template/tongueOut.obj",
            "v 0.0000000 0.1000000",
            "v 0.0000000 NaN",
        )
    });
    expect(
        &m,
        "template/tongueOut.obj",
        &[":5:", "not a finite number"],
    );

    // Weight tables. Line 1 is the header; row k is line k + 1.
    let weights_csv = "expressions/weights.csv";
    let (err, m) = import_error("non-numeric", |d| edit(d, weights_csv, ",0.9,", ",0.9x,"));
    assert!(
        matches!(
            err,
            InterchangeError::NotANumber {
                line: 2,
                column: 19,
                ..
            }
        ),
        "{m}"
    );
    expect(&m, weights_csv, &[":2: column 19 (jawOpen)", "\"0.9x\""]);
    let (_, m) = import_error("nan", |d| {
        edit(d, weights_csv, "eyeBlinkLeft,1.0,", "eyeBlinkLeft,NaN,")
    });
    expect(
        &m,
        weights_csv,
        &[":3: column 2 (eyeBlinkLeft)", "not a finite number"],
    );
    let (err, m) = import_error("range", |d| edit(d, weights_csv, ",0.9,", ",1.5,"));
    assert!(matches!(err, InterchangeError::WeightRange { .. }), "{m}");
    expect(
        &m,
        weights_csv,
        &[":2: column 19 (jawOpen)", "outside [0, 1]"],
    );
    let (_, m) = import_error("range-negative", |d| {
        edit(
            d,
            "test/weights.csv",
            "smile-squint,0.0,",
            "smile-squint,-0.01,",
        )
    });
    expect(&m, "test/weights.csv", &[":2: column 2", "outside"]);
    let (err, m) = import_error("duplicate-column", |d| {
        edit(d, weights_csv, "eyeBlinkRight", "EyeBlinkLeft")
    });
    assert!(
        matches!(err, InterchangeError::DuplicateColumn { .. }),
        "{m}"
    );
    expect(
        &m,
        weights_csv,
        &[":1: column 9", "duplicate", "first at column 2"],
    );
    let (err, m) = import_error("unknown-column", |d| {
        edit(d, weights_csv, "jawOpen,", "jawShut,")
    });
    assert!(matches!(err, InterchangeError::UnknownColumn { .. }), "{m}");
    expect(&m, weights_csv, &[":1: column 19", "\"jawShut\""]);
    let (err, m) = import_error("missing-column", |d| {
        let path = d.join("test/weights.csv");
        let text = fs::read_to_string(&path).unwrap();
        let cut: Vec<String> = text
            .lines()
            .map(|l| l.rsplit_once(',').unwrap().0.to_string() + "\n")
            .collect();
        fs::write(&path, cut.concat()).unwrap();
    });
    assert!(matches!(err, InterchangeError::MissingColumn { .. }), "{m}");
    expect(&m, "test/weights.csv", &["missing column tongueOut"]);
    let (_, m) = import_error("missing-key", |d| edit(d, weights_csv, "prompt,", "name,"));
    expect(&m, weights_csv, &[":1: column 1", "\"name\""]);
    let (err, m) = import_error("field-count", |d| {
        edit(d, weights_csv, "eyeBlinkLeft,1.0,", "eyeBlinkLeft,")
    });
    assert!(
        matches!(err, InterchangeError::FieldCount { line: 3, .. }),
        "{m}"
    );
    expect(&m, weights_csv, &[":3:", "52 fields", "header has 53"]);

    // Rows that name no mesh, an unknown or a repeated prompt.
    let (err, m) = import_error("no-mesh", |d| {
        fs::remove_file(d.join("expressions/jawOpen.obj")).unwrap()
    });
    assert!(
        matches!(err, InterchangeError::NoMesh { line: 2, .. }),
        "{m}"
    );
    expect(
        &m,
        weights_csv,
        &[":2:", "expressions/jawOpen.obj is missing"],
    );
    let (_, m) = import_error("no-test-mesh", |d| {
        fs::remove_file(d.join("test/smile-squint.obj")).unwrap()
    });
    expect(
        &m,
        "test/weights.csv",
        &[":2:", "smile-squint.obj is missing"],
    );
    let (_, m) = import_error("unknown-prompt", |d| {
        edit(d, weights_csv, "\njawOpen,", "\njawShut,")
    });
    expect(&m, weights_csv, &[":2: column 1", "\"jawShut\""]);
    let (_, m) = import_error("repeated-prompt", |d| {
        edit(d, weights_csv, "\neyeBlinkLeft,", "\njaw_open,")
    });
    expect(&m, weights_csv, &[":3: column 1", "twice", "line 2"]);

    // The stream.
    let (_, m) = import_error("backwards", |d| edit(d, "frames.csv", "\n0.0,", "\n0.5,"));
    expect(&m, "frames.csv", &[":3: column 1", "earlier"]);
    let (_, m) = import_error("bad-timestamp", |d| {
        edit(d, "frames.csv", "\n0.0,", "\nsoon,")
    });
    expect(&m, "frames.csv", &[":2: column 1", "\"soon\""]);
    let (_, m) = import_error("bad-timecode", |d| {
        edit(d, "frames.csv", "timestamp,", "Timecode,");
        edit(d, "frames.csv", "\n0.0,", "\n10:42:31,");
    });
    expect(&m, "frames.csv", &[":2: column 1", "timecode"]);
}

#[test]
fn errors_say_where_and_quote_little() {
    // A coordinate a session file cannot store is the OBJ's fault, at its line.
    let (err, m) = import_error("far-coordinate", |d| {
        edit(d, "neutral.obj", "v 0.1000000", "v 1000.0")
    });
    assert!(matches!(err, InterchangeError::Obj { .. }), "{m}");
    expect(
        &m,
        "/neutral.obj",
        &[":3:", "1000 m is outside the range ±100 m"],
    );
    // A 10 KB cell is quoted by its first 40 characters.
    let long = "9".repeat(10_000);
    let (_, m) = import_error("long-cell", |d| {
        edit(d, "expressions/weights.csv", ",0.9,", &format!(",x{long},"))
    });
    expect(&m, "expressions/weights.csv", &[":2: column 19", "…"]);
    assert!(m.len() < 200, "{} bytes: {m}", m.len());
    // A 309-digit timecode is refused on its own line.
    let (_, m) = import_error("huge-timecode", |d| {
        let row = |tc: &str| format!("{tc},52{}\n", ",0".repeat(52 + 9));
        let huge = format!("{}:00:00:00", "9".repeat(309));
        let text = format!(
            "{}{}{}",
            live_link_header(),
            row("00:00:00:00.000"),
            row(&huge)
        );
        fs::write(d.join("frames.csv"), text).unwrap();
    });
    expect(&m, "frames.csv", &[":3: column 1", "is not a timecode"]);
    assert!(m.len() < 200, "{m}");
}

#[test]
fn obj_files_are_found_in_any_case() {
    let dir = scratch("upper-case");
    export_folder(&tiny_session(), &dir).unwrap();
    for rel in [
        "expressions/jawOpen",
        "test/smile-squint",
        "template/tongueOut",
    ] {
        fs::rename(
            dir.join(format!("{rel}.obj")),
            dir.join(format!("{rel}.OBJ")),
        )
        .unwrap();
    }
    let (back, warnings) = import_folder(&dir).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    assert_eq!(back, import_folder(&dir).unwrap().0);
    assert_eq!(back.captures.len(), tiny_session().captures.len());
    assert_eq!(back.tests.len(), tiny_session().tests.len());
    fs::remove_dir_all(&dir).unwrap();
}
