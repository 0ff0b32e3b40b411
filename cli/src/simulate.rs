//! `likeness simulate` and `likeness demo`.

use crate::CliResult;
use crate::info::{Summary, print_summary};
use crate::progress::bar;
use likeness::Session;
use likeness::session::file as session_file;
use likeness_sim::SimulationOptions;
use likeness_sim::arkit_face::read_arkit_face;
use likeness_sim::face_basis::FaceBasis;
use std::path::{Path, PathBuf};

/// Which face mesh a simulated person wears.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Topology {
    /// The simulator's own mask (the committed sessions).
    Simulator,
    /// ARKit's own mesh, the one a real iPhone sends (read from
    /// --arkit-face, never committed).
    Arkit,
}

/// The face a simulated person is made on.
#[derive(Clone, Debug, clap::Args)]
pub struct FaceArgs {
    /// The face mesh: the simulator's mask or ARKit's own.
    #[arg(long, value_enum, default_value_t = Topology::Simulator)]
    topology: Topology,
    /// With --topology arkit: the folder of ARKit's generic face
    /// (Neutral.obj and one OBJ per ARKit name).
    #[arg(long, value_name = "DIR", default_value = "../shared/arkit-face")]
    arkit_face: PathBuf,
}

impl FaceArgs {
    /// The basis these arguments name; ARKit's face is read (and kept for
    /// the process) only when asked for.
    fn basis(&self) -> Result<FaceBasis, Box<dyn std::error::Error>> {
        match self.topology {
            Topology::Simulator => Ok(FaceBasis::Simulator),
            Topology::Arkit => {
                let face = read_arkit_face(&self.arkit_face)
                    .map_err(|e| format!("--topology arkit needs ARKit's generic face: {e}"))?;
                Ok(FaceBasis::Arkit(Box::leak(Box::new(face))))
            }
        }
    }
}

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
pub fn simulate(seed: u64, geometry_window: Option<f64>, face: &FaceArgs, out: &Path) -> CliResult {
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
            face: face.basis()?,
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

/// Runs the main job on the embedded sample, or on simulated subject `seed`
/// (subject 1 when only ARKit's mesh is asked for).
pub fn demo(seed: Option<u64>, face: &FaceArgs) -> CliResult {
    let basis = face.basis()?;
    let on_arkit = matches!(basis, FaceBasis::Arkit(_));
    let seed = seed.or(on_arkit.then_some(1));
    let options = SimulationOptions {
        face: basis,
        ..SimulationOptions::default()
    };
    let (session, bytes) = match seed {
        Some(seed) => {
            let session = simulate_with_bar(seed, options);
            let bytes = session_file::encode(&session)?.len();
            (session, bytes)
        }
        None => (
            session_file::decode(EMBEDDED_SAMPLE)?,
            EMBEDDED_SAMPLE.len(),
        ),
    };
    let source = match seed {
        Some(seed) => format!("simulated subject {seed} ({} mesh)", basis.name()),
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
    let other = simulate_with_bar(other_seed, options);
    let name = format!("subject {}", seed.unwrap_or(1));
    crate::demo_avatar::demo_avatar(
        &session,
        &name,
        &other,
        &format!("subject {other_seed}"),
        likeness::personalize::Method::DEFAULT,
    )?;
    Ok(())
}
