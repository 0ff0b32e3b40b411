//! `likeness replay`: a recorded frame stream through the guided capture,
//! as the app would feed it live.

use crate::CliResult;
use likeness::capture::guided_capture::{GuidedCaptureConfig, Step};
use likeness::capture::replay::{ReplayReport, ReplayedStep, replay_frames, replay_session};
use serde::Serialize;
use std::io::Read;
use std::path::Path;
use std::time::Instant;

/// One step in `replay --json`.
#[derive(Serialize)]
struct StepJson {
    name: String,
    kind: &'static str,
    frame: Option<u64>,
    true_frame: Option<u64>,
    frame_error: Option<i64>,
    has_mesh: bool,
    weak: bool,
    dominated_by: Option<String>,
    tracking_lost: bool,
}

/// What `replay --json` prints.
#[derive(Serialize)]
struct ReplayJson {
    input: &'static str,
    frames: u64,
    finished: bool,
    captured: usize,
    skipped: usize,
    /// Wall time of the replay alone, file reading excluded (ms).
    elapsed_ms: f64,
    /// Largest |capture − true peak| over the 52 prompts (simulated only).
    max_frame_error: Option<u64>,
    max_test_frame_error: Option<u64>,
    steps: Vec<StepJson>,
}

/// Runs `likeness replay FILE [--json]`: a session file, or a Live Link Face
/// (or `timestamp,<names>`) CSV of weights.
pub fn replay_command(file: &Path, json: bool) -> CliResult {
    let is_session = {
        let mut head = [0u8; 8];
        let mut f = std::fs::File::open(file)
            .map_err(|e| format!("cannot open {}: {e}", file.display()))?;
        f.read_exact(&mut head).is_ok() && head == likeness::session::file::MAGIC
    };
    let config = GuidedCaptureConfig::default();
    let (input, report, elapsed) = if is_session {
        let session = crate::info::read_session(file)?;
        let start = Instant::now();
        let report = replay_session(session, config)?;
        ("session", report, start.elapsed())
    } else {
        let frames = likeness::session::interchange::read_frames(file)?;
        let start = Instant::now();
        let report = replay_frames(frames, config, |_| None)?;
        ("weights-csv", report, start.elapsed())
    };
    let elapsed_ms = elapsed.as_secs_f64() * 1e3;
    if json {
        let out = ReplayJson {
            input,
            frames: report.frames,
            finished: report.finished,
            captured: report.captured(),
            skipped: report.skipped(),
            elapsed_ms,
            max_frame_error: report.max_frame_error(),
            max_test_frame_error: report.max_test_frame_error(),
            steps: report.steps.iter().map(step_json).collect(),
        };
        println!("{}", serde_json::to_string_pretty(&out)?);
    } else {
        print_table(&report, input, elapsed_ms);
    }
    Ok(())
}

fn step_json(s: &ReplayedStep) -> StepJson {
    StepJson {
        name: s.name.clone(),
        kind: match s.step {
            Step::Neutral => "neutral",
            Step::Expression(_) => "prompt",
            Step::Test(_) => "test",
        },
        frame: s.frame,
        true_frame: s.true_frame,
        frame_error: s.frame_error(),
        has_mesh: s.has_mesh,
        weak: s.quality.weak,
        dominated_by: s.quality.dominated_by.map(|b| b.name().to_string()),
        tracking_lost: s.quality.tracking_lost,
    }
}

fn print_table(report: &ReplayReport, input: &str, elapsed_ms: f64) {
    println!(
        "{:<22} {:>7} {:>7} {:>6}  flags",
        "step", "frame", "truth", "error"
    );
    for s in &report.steps {
        let cell = |v: Option<String>| v.unwrap_or_else(|| "-".into());
        let mut flags = Vec::new();
        if s.frame.is_none() {
            flags.push("skipped".to_string());
        }
        if s.quality.weak {
            flags.push("weak".into());
        }
        if let Some(d) = s.quality.dominated_by {
            flags.push(format!("dominated by {d}"));
        }
        if s.quality.tracking_lost {
            flags.push("tracking lost".into());
        }
        if s.frame.is_some() && !s.has_mesh {
            flags.push("no mesh".into());
        }
        println!(
            "{:<22} {:>7} {:>7} {:>6}  {}",
            s.name,
            cell(s.frame.map(|f| f.to_string())),
            cell(s.true_frame.map(|f| f.to_string())),
            cell(s.frame_error().map(|e| format!("{e:+}"))),
            flags.join(", ")
        );
    }
    let worst = report
        .max_frame_error()
        .map(|e| format!(", prompts within ±{e} frames of the true peak"))
        .unwrap_or_default();
    println!(
        "\n{input}: {} frames, {} captured, {} skipped{}{worst}; replay took {elapsed_ms:.1} ms",
        report.frames,
        report.captured(),
        report.skipped(),
        if report.finished {
            ", finished"
        } else {
            ", not finished"
        },
    );
}
