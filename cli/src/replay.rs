//! `likeness replay`: a recorded frame stream through the guided capture,
//! as the app would feed it live.

use crate::CliResult;
use likeness::capture::guided_capture::{GuidedCaptureConfig, Step};
use likeness::capture::replay::{ReplayReport, ReplayedStep, replay_frames, replay_session};
use likeness::capture::stream_summary::{ShapeActivity, is_guided, shape_activity};
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
    /// Neutral scan: the shape the face rests highest on, when it rests
    /// high.
    high_rest: Option<String>,
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
    /// Whether the stream followed the guided capture; when it did not
    /// (a free performance), `activity` says what it holds.
    guided: bool,
    steps: Vec<StepJson>,
    #[serde(skip_serializing_if = "Option::is_none")]
    activity: Option<Vec<ActivityJson>>,
}

/// One shape of a stream that is no guided session.
#[derive(Serialize)]
struct ActivityJson {
    name: &'static str,
    peak: f32,
    peak_frame: usize,
    peak_time: f64,
    active_frames: usize,
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
    let (input, report, elapsed, activity) = if is_session {
        let session = crate::info::read_session(file)?;
        let activity = shape_activity(&session.frames);
        let start = Instant::now();
        let report = replay_session(session, config)?;
        ("session", report, start.elapsed(), activity)
    } else {
        let frames = likeness::session::interchange::read_frames(file)?;
        let activity = shape_activity(&frames);
        let start = Instant::now();
        let report = replay_frames(frames, config, |_| None)?;
        ("weights-csv", report, start.elapsed(), activity)
    };
    let elapsed_ms = elapsed.as_secs_f64() * 1e3;
    let guided = is_guided(&report);
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
            guided,
            steps: report.steps.iter().map(step_json).collect(),
            activity: (!guided).then(|| activity.iter().map(activity_json).collect()),
        };
        println!("{}", serde_json::to_string_pretty(&out)?);
    } else if guided {
        print_table(&report, input, elapsed_ms);
    } else {
        print_activity(file, &report, &activity);
    }
    Ok(())
}

fn activity_json(a: &ShapeActivity) -> ActivityJson {
    ActivityJson {
        name: a.shape.name(),
        peak: a.peak,
        peak_frame: a.peak_frame,
        peak_time: a.peak_time,
        active_frames: a.active_frames,
    }
}

/// For a stream that is no guided session: says so, then each shape that
/// moved, by peak.
fn print_activity(file: &Path, report: &ReplayReport, activity: &[ShapeActivity]) {
    let prompts = report
        .steps
        .iter()
        .filter(|s| matches!(s.step, Step::Expression(_)));
    let captured = prompts.clone().filter(|s| s.frame.is_some()).count();
    println!(
        "No guided session found in {}: the guided capture took only {captured} of its {} \
         prompts (each waits up to 10 s for its own expression), so this is a free \
         performance, not a guided session.\n\
         What its {} frames hold, by peak (active: weight ≥ 0.5):\n",
        file.display(),
        prompts.count(),
        report.frames
    );
    println!(
        "{:<22} {:>6} {:>8} {:>9} {:>13}",
        "shape", "peak", "frame", "time s", "active frames"
    );
    let mut moved: Vec<&ShapeActivity> = activity.iter().filter(|a| a.peak >= 0.05).collect();
    moved.sort_by(|a, b| b.peak.total_cmp(&a.peak));
    for a in &moved {
        println!(
            "{:<22} {:>6.3} {:>8} {:>9.2} {:>13}",
            a.shape.name(),
            a.peak,
            a.peak_frame,
            a.peak_time,
            a.active_frames
        );
    }
    println!(
        "\n{} of 52 shapes reached 0.05; the others stayed below.",
        moved.len()
    );
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
        high_rest: s.quality.high_rest.map(|b| b.name().to_string()),
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
        if let Some(r) = s.quality.high_rest {
            flags.push(format!("rests high on {r}"));
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
