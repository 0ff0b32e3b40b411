//! `likeness info`: what a session file holds.

use crate::CliResult;
use likeness::Session;
use likeness::geometry::topology::Topology;
use likeness::session::Template;
use likeness::session::file as session_file;
use serde::Serialize;
use std::path::Path;

/// The summary `info --json` prints.
#[derive(Serialize)]
pub struct Summary {
    format_version: u32,
    file_bytes: u64,
    device: String,
    app: String,
    vertices: usize,
    triangles: usize,
    frames: usize,
    frames_with_geometry: usize,
    frames_untracked: usize,
    fps: f64,
    duration_s: f64,
    prompts: usize,
    missing_prompts: Vec<String>,
    test_expressions: usize,
    ground_truth: bool,
    /// Mean |capture frame − true peak frame| (simulated sessions only).
    #[serde(skip_serializing_if = "Option::is_none")]
    mean_capture_offset_frames: Option<f64>,
    /// RMS distance of the recorded test meshes from the noise-free truth (mm).
    #[serde(skip_serializing_if = "Option::is_none")]
    tracker_rms_mm: Option<f64>,
}

impl Summary {
    /// Summarizes `session`, stored in `file_bytes` bytes.
    pub fn of(session: &Session, file_bytes: u64) -> Summary {
        let captured: Vec<_> = session.captures.iter().map(|c| c.prompt).collect();
        let truth = session.truth.as_ref();
        let offsets: Vec<f64> = truth
            .map(|t| {
                session
                    .captures
                    .iter()
                    .filter_map(|c| {
                        let peak = t.peak_frame(c.prompt)?;
                        Some((c.frame? as f64 - peak as f64).abs())
                    })
                    .collect()
            })
            .unwrap_or_default();
        let tracker_rms = truth.filter(|t| !t.tests.is_empty()).map(|t| {
            let (sum, n) =
                session
                    .tests
                    .iter()
                    .zip(&t.tests)
                    .fold((0.0, 0usize), |(s, n), (a, b)| {
                        let sq: f64 = a
                            .vertices
                            .iter()
                            .zip(b)
                            .map(|(p, q)| (*p - *q).length_squared() as f64)
                            .sum();
                        (s + sq, n + b.len())
                    });
            (sum / n as f64).sqrt() * 1e3
        });
        Summary {
            format_version: session_file::FORMAT_VERSION,
            file_bytes,
            device: format!(
                "{} ({})",
                session.device.model, session.device.system_version
            ),
            app: session.device.app_version.clone(),
            vertices: session.topology.vertex_count(),
            triangles: session.topology.triangles().len(),
            frames: session.frames.len(),
            frames_with_geometry: session
                .frames
                .iter()
                .filter(|f| f.vertices.is_some())
                .count(),
            frames_untracked: session.frames.iter().filter(|f| !f.tracked).count(),
            fps: session.frame_rate as f64,
            duration_s: session.duration(),
            prompts: session.captures.len(),
            missing_prompts: likeness::Blendshape::ALL
                .iter()
                .filter(|s| !captured.contains(s))
                .map(|s| s.name().to_string())
                .collect(),
            test_expressions: session.tests.len(),
            ground_truth: truth.is_some(),
            mean_capture_offset_frames: (!offsets.is_empty())
                .then(|| offsets.iter().sum::<f64>() / offsets.len() as f64),
            tracker_rms_mm: tracker_rms,
        }
    }
}

/// Prints `summary` for a person.
pub fn print_summary(s: &Summary) {
    println!("format version   {}", s.format_version);
    println!("file size        {:.2} MB", s.file_bytes as f64 / 1e6);
    println!("device           {}", s.device);
    println!("recorded by      {}", s.app);
    println!(
        "mesh             {} vertices, {} triangles",
        s.vertices, s.triangles
    );
    println!(
        "stream           {} frames at {} fps, {:.1} s ({} with geometry, {} untracked)",
        s.frames, s.fps, s.duration_s, s.frames_with_geometry, s.frames_untracked
    );
    print!("captured         {} of 52 prompts", s.prompts);
    if s.missing_prompts.is_empty() {
        println!();
    } else {
        println!(" (missing: {})", s.missing_prompts.join(", "));
    }
    println!("test expressions {}", s.test_expressions);
    if let Some(offset) = s.mean_capture_offset_frames {
        println!("ground truth     captures {offset:.2} frames from the true peaks on average");
    }
    if let Some(rms) = s.tracker_rms_mm {
        println!("                 recorded test meshes {rms:.3} mm RMS from the noise-free faces");
    }
}

/// `likeness info FILE [--json]`.
pub fn info(file: &Path, json: bool) -> CliResult {
    let session = read_session(file)?;
    let bytes = std::fs::metadata(file)?.len();
    let summary = Summary::of(&session, bytes);
    if json {
        println!("{}", serde_json::to_string_pretty(&summary)?);
    } else {
        print_summary(&summary);
    }
    Ok(())
}

/// Reads a session file; every error names the file.
pub fn read_session(file: &Path) -> Result<Session, Box<dyn std::error::Error>> {
    read_session_template_first(file, |_, _| ())
}

/// [`read_session`], calling `early` with the mask's topology and the
/// template as soon as they are decoded
/// ([`session_file::read_template_first`]).
pub fn read_session_template_first(
    file: &Path,
    early: impl FnOnce(&Topology, &Template),
) -> Result<Session, Box<dyn std::error::Error>> {
    session_file::read_template_first(file, early).map_err(|e| match e {
        session_file::SessionFileError::Io { .. } | session_file::SessionFileError::File(_) => {
            e.into()
        }
        other => format!("{}: {other}", file.display()).into(),
    })
}
