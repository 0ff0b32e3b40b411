//! `likeness report SESSION [--avatar AVATAR] --out DIR`: one session as a
//! self-contained folder (`index.html`, PNG renderings and SVG charts) for
//! a researcher or for the person who just scanned themselves.
//!
//! The report draws what the core computes and decides nothing itself:
//! the capture replayed by `likeness::capture::replay`, the evaluation of
//! `likeness evaluate` (`crate::personalize::evaluate_session`), per-vertex
//! errors by `likeness::personalize::evaluation`, and the avatar by
//! `likeness::avatar::personal_avatar` and `likeness::avatar::likeness_check`.
//!
//! | section | paper | module |
//! |---|---|---|
//! | the capture: weights, peaks, flags, the neutral scan | §3.1 | [`capture`] |
//! | accuracy: per-expression RMSE and maximum, means, ratios, λ | §4.1, Fig. 4, 5 | [`accuracy`] |
//! | where the error is | Fig. 6 | [`error_maps`] |
//! | what personalization changed | Fig. 2 | [`shape_grid`] |
//! | the avatar: manual, automatic, personalized | §4.2, Fig. 7, 8 | [`avatar_check`] |
//!
//! Pictures: [`rasterizer`] (ours: z-buffer, Gouraud-shaded Lambert),
//! [`colour_map`] (blue 0 mm to red at 5 mm or more), [`image`] (PNG);
//! charts: [`charts`] (plotters, SVG); the page: [`html`]; the folder,
//! written atomically: [`output`].

mod accuracy;
mod avatar_check;
mod capture;
mod charts;
pub(crate) mod colour_map;
mod error_maps;
pub(crate) mod html;
pub(crate) mod image;
mod output;
pub(crate) mod rasterizer;
mod shape_grid;

use crate::CliResult;
use crate::evaluate::{EvaluationReport, summarize_session};
use crate::info::read_session;
use crate::personalize::evaluate_session;
use likeness::Session;
use likeness::personalize::Method;
use serde_json::json;
use std::fmt::Write;
use std::path::Path;
use std::time::Instant;

/// The size of the colour scale's legend.
pub const COLOUR_SCALE_SIZE: (u32, u32) = (480, 70);

/// Steps of the progress bar: reading, the capture, five methods and the
/// λ study, the error maps, the shapes, the avatar, writing.
const STEPS: u64 = 12;

/// Runs `likeness report`.
pub fn report_command(session_path: &Path, avatar: Option<&Path>, out: &Path) -> CliResult {
    let started = Instant::now();
    output::check_replaceable(out)?;
    let bar = crate::progress::bar("report", STEPS);
    bar.set_message("reading");
    let session = read_session(session_path)?;
    bar.inc(1);
    let mut files = output::Files::default();
    let mut sections = Vec::new();

    bar.set_message("capture");
    sections.push(capture::section(&session, &mut files)?);
    bar.inc(1);

    bar.set_message("evaluating");
    let name = session_path.display().to_string();
    let evaluation = evaluate_session(&name, &session, 1, &|| bar.inc(1))?;
    let mut summary = EvaluationReport::new(
        std::slice::from_ref(&name),
        &[summarize_session(&evaluation)],
    );
    // Times of one run are no measurement: `evaluate` takes the median of five.
    summary.timings_ms = None;
    bar.inc(1);
    sections.push(accuracy::section(&evaluation, &summary, &mut files)?);
    files.add(
        "colour-scale.svg",
        charts::colour_bar(COLOUR_SCALE_SIZE.0, COLOUR_SCALE_SIZE.1)?.into_bytes(),
    );

    bar.set_message("error maps");
    let picks = error_maps::picks(&evaluation);
    sections.push(error_maps::section(
        &session,
        &evaluation,
        &picks,
        &mut files,
    )?);
    bar.inc(1);

    bar.set_message("shapes");
    sections.push(shape_grid::section(&session, &evaluation, &mut files)?);
    bar.inc(1);

    bar.set_message("avatar");
    let status = |step: &'static str| bar.set_message(step);
    sections.push(avatar_check::section(
        &session,
        &evaluation,
        &picks,
        avatar,
        &status,
        &mut files,
    )?);
    bar.inc(1);

    bar.set_message("writing");
    let title = format!(
        "Likeness report: {}",
        session_path
            .file_name()
            .map_or(name.clone(), |n| n.to_string_lossy().into_owned())
    );
    let data = json!({ "session": name, "evaluation": summary });
    let page = html::page(
        &title,
        &intro(&session, &summary),
        &sections,
        &serde_json::to_string(&data)?,
    );
    files.add(output::INDEX, page.into_bytes());
    output::write_folder(out, &files).map_err(|e| format!("{}: {e}", out.display()))?;
    bar.finish_and_clear();
    eprintln!(
        "wrote {} ({} files, {:.1} MB) in {:.1} s: open {}",
        out.display(),
        files.entries().len(),
        files.bytes() as f64 / 1e6,
        started.elapsed().as_secs_f64(),
        out.join(output::INDEX).display()
    );
    Ok(())
}

/// The page's opening: what the session is, and the headline in plain
/// words (the product's mean error against the generic shapes').
fn intro(session: &Session, summary: &EvaluationReport) -> String {
    let mut out = String::new();
    let _ = write!(
        out,
        "<p>Recorded on {} ({}), {} frames at {} fps, {} of 52 prompts captured, {} test expressions{}.</p>",
        html::escape(&session.device.model),
        html::escape(&session.device.app_version),
        session.frames.len(),
        session.frame_rate,
        session.captures.len(),
        session.tests.len(),
        if session.truth.is_some() {
            "; simulated, so the true face is known"
        } else {
            ""
        }
    );
    let rmse = |m: Method| summary.method(m).map(|r| r.rmse_mm);
    if let (Some(product), Some(generic)) = (rmse(Method::DEFAULT), rmse(Method::Dt)) {
        let _ = write!(
            out,
            "<p><b>In short:</b> your personalized shapes reproduce your held-out expressions to \
             {product:.2} mm on average (RMSE); the generic shapes, carried onto your face unchanged, to \
             {generic:.2} mm.</p>"
        );
    }
    out
}
