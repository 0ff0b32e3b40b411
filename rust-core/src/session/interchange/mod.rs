//! OBJ + CSV interchange of a capture [`Session`]: a folder of plain files
//! that other tools (Blender, Live Link Face, spreadsheets) read and write.
//!
//! # Layout
//!
//! ```text
//! DIR/template/neutral.obj     generic template, all weights 0
//! DIR/template/<name>.obj      one per ARKit name, that weight 1
//! DIR/neutral.obj              the person's neutral scan
//! DIR/expressions/<name>.obj   the captured mesh for that prompt
//! DIR/expressions/weights.csv  header: prompt,<the 52 ARKit names>; one row per capture
//! DIR/test/<id>.obj            optional held-out test expressions
//! DIR/test/weights.csv         header: id,<the 52 ARKit names>
//! DIR/frames.csv               optional weight stream (see below)
//! ```
//!
//! Every OBJ shares one topology, that of `template/neutral.obj` (same vertex
//! count and same face list, see [`crate::io::obj_reader`] for the OBJ dialect); units
//! are metres. Column names, `<name>` file stems and `prompt` cells may be
//! spelled any way [`Blendshape::parse`] accepts (`eyeBlinkLeft`,
//! `EyeBlinkLeft`, `eyeBlink_L`, …); on export ARKit's own spelling is used.
//! The CSV dialect is described in [`weights_csv`]. Weights must lie in
//! `[0, 1]` within [`WEIGHT_TOLERANCE`] (1e-3); accepted values are kept as
//! they are.
//!
//! A missing `template/<name>.obj` is imported as a zero delta (a copy of
//! the template neutral) with a warning; an OBJ in `expressions/` or `test/`
//! without a row in its `weights.csv` is ignored with a warning. A row
//! whose OBJ is missing is an error.
//!
//! `frames.csv` is either `timestamp,<52 names>` (seconds, non-decreasing)
//! or a Live Link Face recording: `Timecode`, `BlendshapeCount` (or
//! `BlendShapeCount`), the 52 names, and head and eye rotation columns,
//! which are ignored. A Live Link timecode `HH:MM:SS:FF.fff` is
//! `HH·3600 + MM·60 + SS + (FF + .fff) / r`, where the timecode rate `r` is
//! the smallest of 24, 25, 30, 48, 50, 60, 120 above every frame number
//! `FF` in the file; imported timestamps count from the first row. The
//! session's frame rate is one over the median spacing of the timestamps
//! (60 Hz with fewer than two distinct timestamps).
//!
//! # Limits
//!
//! Every file is opened only if it is a regular file (not a directory, a
//! FIFO or a device) and read one line at a time. An OBJ may hold
//! [`OBJ_LIMITS`] (a session's 16,384 vertices, and the file size, line
//! length and triangle count that follow); a CSV [`CSV_LIMITS`] (64 MiB,
//! lines of 16 KiB) and [`MAX_ROWS`] rows, each row turned into its weights
//! as it is read; a stream at most ten minutes
//! ([`MAX_DURATION_SECONDS`](crate::session::file::MAX_DURATION_SECONDS)).
//! A coordinate a session file cannot store (beyond ±100 m) is refused at
//! its OBJ line, and a bad cell is quoted by at most 40 characters.
//!
//! # What a round trip keeps
//!
//! [`export_folder`] followed by [`import_folder`] keeps the topology, the
//! template, the neutral scan, the captures (prompt, weights, meshes), the
//! tests and the stream's timestamps and weights. Weights and timestamps
//! are printed in Rust's shortest round-tripping notation, so they come back
//! bit for bit; coordinates are printed with 7 decimals, so they come back
//! within 0.06 µm (plus f32 rounding). It drops what the layout has no
//! place for: device information (imported as model `imported`), frame
//! meshes, the `tracked` flags (imported frames are tracked), the frame
//! indices of captures and tests, and simulator ground truth.
//!
//! # Files
//!
//! | what | file |
//! |---|---|
//! | folder → session, one part of the layout at a time | `import.rs` |
//! | session → folder | `export.rs` |
//! | the CSV dialect and weight tables | [`weights_csv`] |
//! | `frames.csv`: plain or Live Link Face timecodes | `frame_stream.rs` |
//! | errors naming file, line and column | `error.rs` |

mod error;
mod export;
mod frame_stream;
mod import;
pub mod weights_csv;

pub use error::InterchangeError;
pub use export::export_folder;
use frame_stream::frame_rate;
#[cfg(test)]
use frame_stream::parse_timecode;
pub use frame_stream::read_frames;
pub use import::import_folder;

pub use crate::io::obj_reader::{ObjLimits, ObjMesh, read_obj};
pub use weights_csv::{
    CSV_LIMITS, MAX_ROWS, WEIGHT_TOLERANCE, WeightRow, WeightTable, read_weight_table,
};

use crate::arkit::Blendshape;
use crate::geometry::topology::Topology;
use crate::io::Excerpt;
pub use crate::io::FileError;
use crate::io::atomic_write::write_atomically;
use crate::io::obj_writer::write_obj;
use crate::session::file::{MAX_Q, QUANTUM, quantize};
use crate::session::{
    CapturedExpression, DeviceInfo, Session, SessionError, SessionParts, Template, TestExpression,
};
use glam::{DVec3, Vec3};
use std::io;
use std::path::{Path, PathBuf};

/// Frame rate of an imported session whose stream does not say otherwise.
pub const DEFAULT_FRAME_RATE: f32 = 60.0;

/// Device model of an imported session.
pub const IMPORTED_MODEL: &str = "imported";

/// What one OBJ of the folder may hold: as many vertices as a session
/// ([`MAX_VERTICES`](crate::session::file::MAX_VERTICES)); the file size,
/// line length and triangle count follow ([`ObjLimits`]).
pub const OBJ_LIMITS: ObjLimits = ObjLimits {
    max_vertices: crate::session::file::MAX_VERTICES,
};

pub(super) fn io_error(path: &Path) -> impl FnOnce(io::Error) -> InterchangeError + '_ {
    move |source| {
        InterchangeError::File(FileError::Io {
            path: path.to_path_buf(),
            source,
        })
    }
}

/// Reads an OBJ within [`OBJ_LIMITS`] whose every coordinate a session
/// file can store (±100 m); one that cannot is blamed on its line.
pub(super) fn read_storable_obj(path: &Path) -> Result<ObjMesh, InterchangeError> {
    let mesh = read_obj(path, OBJ_LIMITS)?;
    let unstorable = |p: &Vec3| p.to_array().into_iter().find(|&x| quantize(x).is_none());
    let first = mesh
        .positions
        .iter()
        .zip(&mesh.vertex_lines)
        .find_map(|(p, &line)| unstorable(p).map(|x| (x, line)));
    if let Some((x, line)) = first {
        return Err(InterchangeError::Obj {
            path: path.to_path_buf(),
            line,
            message: format!(
                "coordinate {x} m is outside the range ±{:.0} m a session file can store",
                MAX_Q as f64 * QUANTUM
            ),
        });
    }
    Ok(mesh)
}

/// Reads an OBJ and checks it against the template topology.
pub(super) fn read_mesh(path: &Path, topology: &Topology) -> Result<Vec<Vec3>, InterchangeError> {
    let mesh = read_storable_obj(path)?;
    if mesh.positions.len() != topology.vertex_count() {
        return Err(InterchangeError::VertexCount {
            path: path.to_path_buf(),
            expected: topology.vertex_count(),
            found: mesh.positions.len(),
        });
    }
    let expected = topology.triangles();
    let first_difference = mesh
        .triangles
        .iter()
        .zip(expected)
        .enumerate()
        .find(|(_, (found, wanted))| found != wanted);
    if let Some((k, (found, wanted))) = first_difference {
        let [a, b, c] = found.map(|i| i + 1);
        let [x, y, z] = wanted.map(|i| i + 1);
        return Err(InterchangeError::Faces {
            path: path.to_path_buf(),
            line: mesh.triangle_lines.get(k).copied(),
            message: format!(
                "triangle {} is ({a} {b} {c}), but in template/neutral.obj it is ({x} {y} {z})",
                k + 1
            ),
        });
    }
    if mesh.triangles.len() != expected.len() {
        return Err(InterchangeError::Faces {
            path: path.to_path_buf(),
            line: None,
            message: format!(
                "{} triangles, but template/neutral.obj has {}",
                mesh.triangles.len(),
                expected.len()
            ),
        });
    }
    Ok(mesh.positions)
}

/// An OBJ file found in a folder: its stem and its path as spelled on
/// disk (`.obj` in any case).
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) struct ObjFile {
    /// The file name without its extension.
    pub stem: String,
    /// The file.
    pub path: PathBuf,
}

/// The `*.obj` files in `dir`, the extension in any case, sorted by stem
/// (empty if `dir` does not exist).
pub(super) fn obj_files(dir: &Path) -> Result<Vec<ObjFile>, InterchangeError> {
    let entries = match std::fs::read_dir(dir) {
        Ok(e) => e,
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(io_error(dir)(e)),
    };
    let mut files = Vec::new();
    for entry in entries {
        let path = entry.map_err(io_error(dir))?.path();
        if path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("obj"))
        {
            if let Some(stem) = path.file_stem().and_then(|s| s.to_str()) {
                let stem = stem.to_string();
                files.push(ObjFile { stem, path });
            }
        }
    }
    files.sort_by(|a, b| a.stem.cmp(&b.stem));
    Ok(files)
}

/// Finds the OBJ in `dir` for `shape` under any accepted spelling, ARKit's
/// own first.
pub(super) fn shape_obj(dir: &Path, files: &[ObjFile], shape: Blendshape) -> Option<PathBuf> {
    let own = dir.join(format!("{}.obj", shape.name()));
    if own.is_file() {
        return Some(own);
    }
    files
        .iter()
        .find(|f| f.stem == shape.name())
        .or_else(|| {
            files
                .iter()
                .find(|f| Blendshape::parse(&f.stem) == Ok(shape))
        })
        .map(|f| f.path.clone())
}

/// Whether a test id can be a file stem and a CSV cell.
pub(super) fn check_id(id: &str) -> Result<(), InterchangeError> {
    let bad = id.is_empty()
        || id == "."
        || id == ".."
        || id != id.trim()
        || id.contains(['/', '\\', ',', '\n', '\r']);
    if bad {
        Err(InterchangeError::BadId(Excerpt::of(id)))
    } else {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::session::Frame;

    #[test]
    fn timecodes_parse_with_subframes() {
        assert_eq!(
            parse_timecode("10:42:31:12.456"),
            Some((10.0 * 3600.0 + 42.0 * 60.0 + 31.0, 12.456))
        );
        assert_eq!(parse_timecode("00:00:01:05"), Some((1.0, 5.0)));
        for bad in [
            "",
            "1:2:3",
            "10:42:31:x",
            "10:42:31:12.4a",
            "10:61:00:00",
            "a:b:c:d",
            ":::",
            "1:2:3:4:5",
            "00:00:00:.5",
            "٣:00:00:00",
            "+1:00:00:00",
        ] {
            assert_eq!(parse_timecode(bad), None, "{bad}");
        }
    }

    #[test]
    fn frame_rate_is_the_median_spacing() {
        let frame = |t| Frame {
            timestamp: t,
            weights: Default::default(),
            tracked: true,
            vertices: None,
        };
        assert_eq!(frame_rate(&[]), DEFAULT_FRAME_RATE);
        assert_eq!(frame_rate(&[frame(1.0), frame(1.0)]), DEFAULT_FRAME_RATE);
        assert_eq!(frame_rate(&[frame(0.0), frame(0.5)]), 2.0);
        let frames: Vec<_> = [0.0, 0.02, 0.04, 0.1, 0.12]
            .into_iter()
            .map(frame)
            .collect();
        assert!((frame_rate(&frames) - 50.0).abs() < 1e-3);
    }
}
