//! The `likeness` command as a person uses it: summaries, JSON, and clear
//! errors on bad input, never a panic.

use std::process::Output;

mod common;
use common::likeness;

fn sample() -> String {
    likeness_tests::committed::path(2).display().to_string()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn info_json_has_the_documented_fields() {
    let out = likeness(&["info", &sample(), "--json"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON on stdout");
    assert_eq!(v["format_version"], 1);
    assert_eq!(v["vertices"], 1220);
    assert_eq!(v["triangles"], 2304);
    assert_eq!(v["fps"], 60.0);
    assert_eq!(v["prompts"], 52);
    let frames = v["frames"].as_u64().unwrap();
    let duration = v["duration_s"].as_f64().unwrap();
    assert!((duration - (frames - 1) as f64 / 60.0).abs() < 1e-9);
    assert!((20..=30).contains(&v["test_expressions"].as_u64().unwrap()));
}

#[test]
fn info_prints_a_readable_summary() {
    let out = likeness(&["info", &sample()]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("1220 vertices, 2304 triangles"), "{text}");
    assert!(text.contains("52 of 52 prompts"), "{text}");
}

#[test]
fn bad_files_are_clear_errors_not_panics() {
    let dir = std::env::temp_dir().join(format!("likeness-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let garbage = dir.join("garbage.likeness");
    std::fs::write(&garbage, b"this is not a session file").unwrap();
    let truncated = dir.join("truncated.likeness");
    let bytes = std::fs::read(sample()).unwrap();
    std::fs::write(&truncated, &bytes[..bytes.len() / 2]).unwrap();
    let mut newer = bytes[..64].to_vec();
    newer[8] = 9;
    let newer_path = dir.join("newer.likeness");
    std::fs::write(&newer_path, &newer).unwrap();
    let cases = [
        (dir.join("missing.likeness"), "missing.likeness"),
        (garbage, "not a Likeness session file"),
        (truncated, "truncated"),
        (newer_path, "unsupported session format version 9"),
    ];
    for (path, expected) in cases {
        let out = likeness(&["info", path.to_str().unwrap()]);
        let err = stderr(&out);
        assert!(!out.status.success(), "{path:?} succeeded");
        assert!(!err.contains("panicked"), "{err}");
        assert!(
            err.to_lowercase().contains(&expected.to_lowercase()),
            "{path:?}: {err}"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn simulate_writes_a_session_that_info_reads() {
    let dir = std::env::temp_dir().join(format!("likeness-sim-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("s.likeness");
    let out = likeness(&[
        "simulate",
        "--seed",
        "9",
        "--geometry-window",
        "0.2",
        "--out",
        file.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        out.stdout.is_empty(),
        "progress must not go to stdout when piped"
    );
    let info = likeness(&["info", file.to_str().unwrap(), "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&info.stdout).unwrap();
    assert_eq!(v["ground_truth"], true);
    assert!(v["frames_with_geometry"].as_u64().unwrap() < v["frames"].as_u64().unwrap());
    let leftovers = std::fs::read_dir(&dir).unwrap().count();
    assert_eq!(leftovers, 1, "no temporary files left behind");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn writing_into_a_missing_folder_is_an_error() {
    let out = likeness(&[
        "simulate",
        "--seed",
        "1",
        "--out",
        "/nonexistent-likeness/x.likeness",
    ]);
    assert!(!out.status.success());
    assert!(
        stderr(&out).contains("/nonexistent-likeness/x.likeness"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn evaluate_json_has_the_documented_fields() {
    let out = likeness(&["evaluate", &sample(), "--json"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON on stdout");
    for method in ["dt", "ebfr", "paper", "paper-cv", "multi"] {
        let m = &v["methods"][method];
        for key in ["rmse_mm", "max_mm", "truth_rmse_mm"] {
            assert!(
                m[key].as_f64().is_some_and(|x| x > 0.0),
                "{method}.{key}: {m}"
            );
        }
        assert!(v["timings_ms"][method].as_f64().is_some_and(|t| t > 0.0));
    }
    assert_eq!(
        v["methods"]["paper-cv"]["lambda"].as_array().map(Vec::len),
        Some(1)
    );
    // How λ was chosen, and whether it stopped at a bound of its range.
    assert_eq!(v["methods"]["paper-cv"]["lambda_rule"], "gcv");
    assert_eq!(v["methods"]["multi"]["lambda_rule"], "gcv");
    assert_eq!(v["methods"]["paper"]["lambda_rule"], "fixed");
    assert_eq!(
        v["methods"]["paper-cv"]["lambda_at_bound"],
        serde_json::json!([null])
    );
    assert!(v["methods"]["dt"].get("lambda_rule").is_none());
    for key in [
        "rmse_paper_over_ebfr",
        "rmse_paper_over_dt",
        "max_paper_over_ebfr",
        "max_paper_over_dt",
    ] {
        assert!(v["ratios"][key].as_f64().is_some_and(|r| r > 0.0), "{key}");
    }
}

#[test]
fn personalize_writes_the_neutral_and_52_named_shapes() {
    let dir = std::env::temp_dir().join(format!("likeness-personalize-{}", std::process::id()));
    let out = likeness(&[
        "personalize",
        &sample(),
        "--method",
        "paper",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("λ = 1.000e0 (fixed)"),
        "{}",
        stderr(&out)
    );
    let files = std::fs::read_dir(&dir).unwrap().count();
    assert_eq!(files, 53);
    let smile = std::fs::read_to_string(dir.join("mouthSmileLeft.obj")).unwrap();
    assert_eq!(smile.lines().filter(|l| l.starts_with("v ")).count(), 1220);
    assert_eq!(smile.lines().filter(|l| l.starts_with("f ")).count(), 2304);
    std::fs::remove_dir_all(&dir).unwrap();
    let bad = likeness(&[
        "personalize",
        &sample(),
        "--method",
        "magic",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(!bad.status.success());
    assert!(stderr(&bad).contains("unknown method"), "{}", stderr(&bad));
}

#[test]
fn replay_json_reports_every_capture_and_its_distance_from_the_truth() {
    let out = likeness(&["replay", &sample(), "--json"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON on stdout");
    assert_eq!(v["input"], "session");
    assert_eq!(v["finished"], true);
    assert_eq!(v["skipped"], 0);
    let steps = v["steps"].as_array().unwrap();
    assert_eq!(v["captured"].as_u64().unwrap() as usize, steps.len());
    assert!(v["elapsed_ms"].as_f64().unwrap() > 0.0);
    assert!(v["max_frame_error"].as_u64().unwrap() <= 2);
    assert_eq!(steps[0]["name"], "neutral");
    assert_eq!(steps[1]["name"], "browInnerUp");
    assert_eq!(steps.iter().filter(|s| s["kind"] == "prompt").count(), 52);
    for s in steps.iter().filter(|s| s["kind"] == "prompt") {
        assert!(s["frame_error"].as_i64().unwrap().abs() <= 2, "{s}");
    }
}

#[test]
fn replay_reads_a_live_link_face_csv_and_names_bad_lines() {
    let dir = std::env::temp_dir().join(format!("likeness-cli-replay-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let session = likeness::session::file::read(sample()).unwrap();
    let csv = dir.join("take.csv");
    std::fs::write(
        &csv,
        likeness_tests::live_link::live_link_csv(&session.frames),
    )
    .unwrap();
    let out = likeness(&["replay", csv.to_str().unwrap(), "--json"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["input"], "weights-csv");
    assert_eq!(v["captured"], 53);
    assert_eq!(v["max_frame_error"], serde_json::Value::Null);
    let text = likeness(&["replay", csv.to_str().unwrap()]);
    assert!(String::from_utf8_lossy(&text.stdout).contains("53 captured"));

    let broken = likeness_tests::live_link::live_link_csv(&session.frames[..10]);
    let bad = dir.join("bad.csv");
    std::fs::write(
        &bad,
        broken.replace("\n10:42:31:03.000,52,", "\n10:42:31:03.000,52,x"),
    )
    .unwrap();
    let out = likeness(&["replay", bad.to_str().unwrap()]);
    assert!(!out.status.success());
    let message = stderr(&out);
    // Line 5 (header + 3 good rows), the column and its name.
    assert!(
        message.contains("bad.csv:5: column 3 (EyeBlinkLeft)"),
        "{message}"
    );
    assert!(!message.contains("panicked"), "{message}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn replay_of_a_free_performance_says_so_and_summarizes_it() {
    use likeness::{Blendshape, Frame, Weights};
    let dir = std::env::temp_dir().join(format!("likeness-cli-free-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // Twenty seconds of talking: the jaw opens and closes three times a
    // second, the brows rise once; no prompt is followed.
    let frames: Vec<Frame> = (0..1200)
        .map(|k| {
            let t = k as f64 / 60.0;
            let mut weights = Weights::ZERO;
            weights.set(
                Blendshape::JawOpen,
                (0.35 + 0.3 * (std::f64::consts::TAU * 3.0 * t).sin()) as f32,
            );
            let brow = (-(t - 12.0).powi(2) / 0.5).exp();
            weights.set(Blendshape::BrowInnerUp, (0.8 * brow) as f32);
            Frame {
                timestamp: t,
                weights,
                tracked: true,
                vertices: None,
            }
        })
        .collect();
    let csv = dir.join("talking.csv");
    std::fs::write(&csv, likeness_tests::live_link::live_link_csv(&frames)).unwrap();
    let text = likeness(&["replay", csv.to_str().unwrap()]);
    assert!(text.status.success(), "{}", stderr(&text));
    let out = String::from_utf8_lossy(&text.stdout);
    assert!(out.starts_with("No guided session found in"), "{out}");
    assert!(out.contains("free performance"), "{out}");
    let jaw = out
        .lines()
        .find(|l| l.starts_with("jawOpen"))
        .expect("jawOpen listed");
    assert!(jaw.contains("0.650"), "{jaw}");
    let json = likeness(&["replay", csv.to_str().unwrap(), "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&json.stdout).unwrap();
    assert_eq!(v["guided"], false);
    let activity = v["activity"].as_array().unwrap();
    assert_eq!(activity.len(), 52);
    let brow = activity
        .iter()
        .find(|a| a["name"] == "browInnerUp")
        .unwrap();
    assert!(
        (brow["peak_time"].as_f64().unwrap() - 12.0).abs() < 0.05,
        "{brow}"
    );
    // A guided session replays as before.
    let session = likeness(&["replay", &sample(), "--json"]);
    let v: serde_json::Value = serde_json::from_slice(&session.stdout).unwrap();
    assert_eq!(v["guided"], true);
    assert!(v.get("activity").is_none());
    std::fs::remove_dir_all(&dir).unwrap();
}
