//! `likeness`: the desktop command. Simulates capture sessions, inspects
//! session files, and runs the pipeline on them.
//!
//! Errors go to stderr with a non-zero exit status and never as a panic.

mod avatar;
mod avatar_preview;
mod avatar_summary;
mod demo_avatar;
mod evaluate;
mod info;
mod interchange;
mod personalize;
mod progress;
mod replay;
mod report;
mod simulate;
mod view;

use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;

/// Personalized ARKit blendshapes from a two-minute iPhone capture.
#[derive(Parser)]
#[command(name = "likeness", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run the main job on the embedded sample session (or on a freshly
    /// simulated subject with --seed) and summarize it.
    Demo {
        /// Simulate this subject instead of using the embedded sample.
        #[arg(long)]
        seed: Option<u64>,
        #[command(flatten)]
        face: simulate::FaceArgs,
    },
    /// Simulate a subject's full capture session and write it to a file.
    Simulate {
        /// Seed of the simulated subject and session.
        #[arg(long)]
        seed: u64,
        /// Where to write the session file.
        #[arg(long)]
        out: PathBuf,
        /// Keep meshes only this many seconds around each capture and test
        /// expression (as the committed samples do); default: every frame.
        #[arg(long, value_name = "SECONDS")]
        geometry_window: Option<f64>,
        #[command(flatten)]
        face: simulate::FaceArgs,
    },
    /// Personalize a session's blendshapes and write them as OBJ files
    /// (neutral.obj and one file per ARKit name).
    Personalize {
        /// The session file.
        file: PathBuf,
        /// dt, ebfr, paper, paper-cv or multi.
        #[arg(long, default_value_t = likeness::personalize::Method::DEFAULT)]
        method: likeness::personalize::Method,
        /// Folder for the OBJ files (created if missing).
        #[arg(long)]
        out: PathBuf,
    },
    /// Evaluate every method on the sessions' held-out test expressions
    /// (the paper's §4.1) and print the table.
    Evaluate {
        /// Session files.
        #[arg(required = true)]
        files: Vec<PathBuf>,
        /// Print a JSON object instead of the table.
        #[arg(long)]
        json: bool,
    },
    /// Build a session file from a folder of OBJ meshes and CSV weights
    /// (layout in the README).
    Import {
        /// The folder.
        dir: PathBuf,
        /// The session file to write.
        #[arg(long)]
        out: PathBuf,
    },
    /// Write a session as a folder of OBJ meshes and CSV weights.
    Export {
        /// The session file.
        file: PathBuf,
        /// The folder to write (created if missing).
        #[arg(long)]
        out: PathBuf,
    },
    /// Run a recorded frame stream through the guided capture, as the app
    /// would live, and report each capture (and its distance from the true
    /// peak on simulated sessions).
    Replay {
        /// A session file, or a Live Link Face CSV of weights.
        file: PathBuf,
        /// Print a JSON object instead of the table.
        #[arg(long)]
        json: bool,
    },
    /// Put a session's personalized shapes onto an avatar (§3.3: seamless
    /// partial deformation transfer, eyelid repair) and write it as GLB.
    Avatar {
        /// The session file.
        session: PathBuf,
        /// The avatar (.glb or .gltf with ARKit-named morph targets);
        /// default: the project's own default avatar.
        #[arg(long)]
        avatar: Option<PathBuf>,
        /// The GLB to write.
        #[arg(long)]
        out: PathBuf,
        /// dt, ebfr, paper, paper-cv or multi.
        #[arg(long, default_value_t = likeness::personalize::Method::DEFAULT)]
        method: likeness::personalize::Method,
        /// Also write the 52 × k weights that map ARKit's weights to the
        /// avatar's own targets, as JSON (format in the README).
        #[arg(long, value_name = "FILE")]
        retarget_map: Option<PathBuf>,
        /// Where registrations are cached (default: ~/.cache/likeness).
        #[arg(long, value_name = "DIR")]
        cache_dir: Option<PathBuf>,
        /// Write the automatic retargeting of Eq. (4) instead: the avatar's
        /// own blendshapes combined to approximate the person's.
        #[arg(long)]
        retargeted: bool,
        /// Keep the default avatar's stock face (by default it takes the
        /// person's scanned face at rest).
        #[arg(long, conflicts_with_all = ["take_face", "mask_only"])]
        keep_face: bool,
        /// Give the avatar the person's scanned face at rest (the default
        /// on the default avatar; on one you bring, only when asked).
        #[arg(long, conflicts_with = "mask_only")]
        take_face: bool,
        /// Write the person's personalized face mask alone (ARKit's mesh,
        /// their neutral and 52 shapes) instead of an avatar.
        #[arg(long, conflicts_with_all = ["avatar", "retargeted", "retarget_map", "preview"])]
        mask_only: bool,
        /// Also write a contact sheet into this folder (created if missing):
        /// neutral and eleven shapes, the avatar's own beside the written
        /// ones, each as the face, the eyes and the mouth (PNG tiles,
        /// contact-sheet.png, its legend, index.html).
        #[arg(long, value_name = "DIR")]
        preview: Option<PathBuf>,
        /// Print a JSON object instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Write the project's own default avatar (head, eyes, teeth, tongue;
    /// its 52 generic ARKit shapes) as GLB.
    DefaultAvatar {
        /// The GLB to write.
        #[arg(long)]
        out: PathBuf,
    },
    /// Show an avatar in the browser (the page in viewer/, built with npm):
    /// 52 sliders by ARKit name, a take played back, the generic avatar
    /// beside it. Serves on 127.0.0.1 only and prints the address.
    View {
        /// The avatar GLB (e.g. what `likeness avatar` wrote).
        avatar: PathBuf,
        /// The avatar before implanting, shown on the left with the same weights.
        #[arg(long, value_name = "GLB")]
        generic: Option<PathBuf>,
        /// A weight stream to play: a Live Link Face CSV, or frames.csv from
        /// `likeness export`.
        #[arg(long, value_name = "CSV")]
        take: Option<PathBuf>,
        /// The port (default: a free one).
        #[arg(long, default_value_t = 0)]
        port: u16,
        /// The built page (default: viewer/dist in this repository).
        #[arg(long, value_name = "DIR")]
        viewer_dir: Option<PathBuf>,
    },
    /// Write a session's report: a folder with index.html, renderings and
    /// charts (the capture, §4.1's accuracy, Fig. 2 and 4–8).
    Report {
        /// The session file.
        session: PathBuf,
        /// The avatar (.glb or .gltf); default: the project's own.
        #[arg(long)]
        avatar: Option<PathBuf>,
        /// The folder to write (a previous report there is replaced).
        #[arg(long)]
        out: PathBuf,
    },
    /// Print a summary of a session file.
    Info {
        /// The session file.
        file: PathBuf,
        /// Print a JSON object instead of text.
        #[arg(long)]
        json: bool,
    },
}

/// What a command can fail with: a message for the person at the terminal.
pub type CliResult = Result<(), Box<dyn std::error::Error>>;

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Demo { seed, face } => simulate::demo(seed, &face),
        Command::Simulate {
            seed,
            out,
            geometry_window,
            face,
        } => simulate::simulate(seed, geometry_window, &face, &out),
        Command::Info { file, json } => info::info(&file, json),
        Command::DefaultAvatar { out } => avatar::default_avatar_command(&out),
        Command::Avatar {
            session,
            avatar,
            out,
            method,
            retarget_map,
            cache_dir,
            retargeted,
            keep_face,
            take_face,
            mask_only,
            preview,
            json,
        } => avatar::avatar_command(&avatar::AvatarArgs {
            session,
            avatar,
            out,
            method,
            retarget_map,
            cache_dir,
            retargeted,
            face: match (keep_face, take_face) {
                (true, _) => Some(likeness::avatar::personal_avatar::RestFace::Stock),
                (_, true) => Some(likeness::avatar::personal_avatar::RestFace::Person),
                _ => None,
            },
            mask_only,
            preview,
            json,
        }),
        Command::Replay { file, json } => replay::replay_command(&file, json),
        Command::Personalize { file, method, out } => {
            personalize::personalize_command(&file, method, &out)
        }
        Command::Evaluate { files, json } => evaluate::evaluate_command(&files, json),
        Command::Report {
            session,
            avatar,
            out,
        } => report::report_command(&session, avatar.as_deref(), &out),
        Command::Import { dir, out } => interchange::import_command(&dir, &out),
        Command::Export { file, out } => interchange::export_command(&file, &out),
        Command::View {
            avatar,
            generic,
            take,
            port,
            viewer_dir,
        } => view::view_command(&view::ViewArgs {
            avatar,
            generic,
            take,
            port,
            viewer_dir,
        }),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // Causes not already part of the message, outermost first.
            let mut message = e.to_string();
            let mut source = e.source();
            while let Some(s) = source {
                let cause = s.to_string();
                if !message.contains(&cause) {
                    message = format!("{message}: {cause}");
                }
                source = s.source();
            }
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}
