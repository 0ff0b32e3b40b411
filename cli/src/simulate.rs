//! `likeness simulate` and `likeness demo`.

use crate::CliResult;
use crate::info::{Summary, print_summary};
use crate::progress::bar;
use likeness::Session;
use likeness::session::file as session_file;
use likeness_sim::SimulationOptions;
use std::path::Path;

/// The sample session built into the binary: simulated subject 1, as
/// committed under `sim-data/sessions/`.
const EMBEDDED_SAMPLE: &[u8] = include_bytes!("../../sim-data/sessions/subject-1.likeness");

fn simulate_with_bar(seed: u64, options: SimulationOptions) -> Session {
    let progress = bar("simulating", 1);
    let session = likeness_sim::simulate_session_with(seed, options, &mut |done, total| {
        progress.set_length(total as u64);
        progress.set_position(done as u64);
    });
    progress.finish_and_clear();
    session
}

/// Simulates subject `seed` and writes the session to `out` atomically;
/// with `geometry_window`, meshes are kept only that many seconds around
/// captures and test expressions.
pub fn simulate(seed: u64, geometry_window: Option<f64>, out: &Path) -> CliResult {
    if let Some(w) = geometry_window.filter(|w| !(w.is_finite() && *w >= 0.0)) {
        return Err(
            format!("--geometry-window must be a non-negative number of seconds, not {w}").into(),
        );
    }
    let folder = out.parent().filter(|p| !p.as_os_str().is_empty());
    if let Some(folder) = folder.filter(|f| !f.is_dir()) {
        return Err(format!(
            "{}: the folder {} does not exist",
            out.display(),
            folder.display()
        )
        .into());
    }
    let session = simulate_with_bar(
        seed,
        SimulationOptions {
            geometry_window,
            ..SimulationOptions::default()
        },
    );
    session_file::write(out, &session)?;
    let size = std::fs::metadata(out)?.len();
    eprintln!(
        "wrote {} ({:.1} MB): {} frames, {} captures, {} test expressions",
        out.display(),
        size as f64 / 1e6,
        session.frames.len(),
        session.captures.len(),
        session.tests.len()
    );
    Ok(())
}

/// Runs the main job on the embedded sample, or on simulated subject `seed`.
pub fn demo(seed: Option<u64>) -> CliResult {
    let (session, bytes) = match seed {
        Some(seed) => {
            let session = simulate_with_bar(seed, SimulationOptions::default());
            let bytes = session_file::encode(&session)?.len();
            (session, bytes)
        }
        None => (
            session_file::decode(EMBEDDED_SAMPLE)?,
            EMBEDDED_SAMPLE.len(),
        ),
    };
    let source = match seed {
        Some(seed) => format!("simulated subject {seed}"),
        None => "embedded sample (simulated subject 1)".to_string(),
    };
    println!("Likeness demo: {source}\n");
    print_summary(&Summary::of(&session, bytes as u64));
    println!(
        "\nPersonalized blendshapes (§3.2), evaluated on the held-out test expressions (§4.1):\n"
    );
    let report = crate::evaluate::evaluation_report(&[source], &|_| Ok(session.clone()))?;
    crate::evaluate::print_table(&report);
    println!("\nThe avatar (§3.3):\n");
    // A second person, for the preview of two people's faces.
    let other_seed = seed.map_or(2, |s| s.wrapping_add(1));
    let other = simulate_with_bar(other_seed, SimulationOptions::default());
    let name = format!("subject {}", seed.unwrap_or(1));
    crate::avatar::demo_avatar(
        &session,
        &name,
        &other,
        &format!("subject {other_seed}"),
        likeness::personalize::Method::DEFAULT,
    )?;
    Ok(())
}
