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
//! count and same face list, see [`obj_reader`] for the OBJ dialect); units
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

pub mod obj_reader;
pub mod weights_csv;

pub use obj_reader::{ObjMesh, read_obj};
pub use weights_csv::{WEIGHT_TOLERANCE, WeightTable, read_weight_table};

use crate::arkit_names::Blendshape;
use crate::atomic_write::write_atomically;
use crate::obj_export::write_obj;
use crate::session::{
    CapturedExpression, DeviceInfo, Frame, Session, SessionError, Template, TestExpression,
};
use crate::topology::Topology;
use glam::{DVec3, Vec3};
use std::io;
use std::path::{Path, PathBuf};

/// Frame rate of an imported session whose stream does not say otherwise.
pub const DEFAULT_FRAME_RATE: f32 = 60.0;

/// Device model of an imported session.
pub const IMPORTED_MODEL: &str = "imported";

/// What can go wrong reading or writing an interchange folder. Every error
/// names the file, and the 1-based line and column where there is one.
#[derive(Debug, thiserror::Error)]
pub enum InterchangeError {
    /// A required file is missing.
    #[error("{}: missing", path.display())]
    Missing {
        /// The missing file.
        path: PathBuf,
    },
    /// Reading or writing failed.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// What the system reported.
        source: io::Error,
    },
    /// A line of an OBJ file could not be understood.
    #[error("{}:{line}: {message}", path.display())]
    Obj {
        /// The OBJ file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// `template/neutral.obj` does not describe a valid triangle mesh.
    #[error("{}: {message}", path.display())]
    Topology {
        /// The template file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// An OBJ's vertex count differs from `template/neutral.obj`'s.
    #[error("{}: {found} vertices, but template/neutral.obj has {expected}", path.display())]
    VertexCount {
        /// The OBJ file.
        path: PathBuf,
        /// Vertex count of the template.
        expected: usize,
        /// Vertex count of this file.
        found: usize,
    },
    /// An OBJ's face list differs from `template/neutral.obj`'s.
    #[error("{}{}: {message}", path.display(), line.map(|l| format!(":{l}")).unwrap_or_default())]
    Faces {
        /// The OBJ file.
        path: PathBuf,
        /// 1-based line of the first differing face, if it has one.
        line: Option<usize>,
        /// How it differs.
        message: String,
    },
    /// A CSV row has a different number of fields than the header.
    #[error("{}:{line}: {found} fields, but the header has {expected}", path.display())]
    FieldCount {
        /// The CSV file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// Number of header fields.
        expected: usize,
        /// Number of fields on this line.
        found: usize,
    },
    /// A cell that must be a finite number is not (includes NaN and ±inf).
    #[error("{}:{line}: column {column} ({name}): {value:?} is not a finite number", path.display())]
    NotANumber {
        /// The CSV file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// The column's header.
        name: String,
        /// The cell.
        value: String,
    },
    /// A weight lies outside `[0, 1]` by more than [`WEIGHT_TOLERANCE`].
    #[error(
        "{}:{line}: column {column} ({name}): weight {value} is outside [0, 1] (tolerance {WEIGHT_TOLERANCE})",
        path.display()
    )]
    WeightRange {
        /// The CSV file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// The column's header.
        name: String,
        /// The weight.
        value: f32,
    },
    /// A header names the same column twice.
    #[error("{}:{line}: column {column}: duplicate column {name:?} (first at column {first})", path.display())]
    DuplicateColumn {
        /// The CSV file.
        path: PathBuf,
        /// 1-based line of the header.
        line: usize,
        /// 1-based column of the repeat.
        column: usize,
        /// The header cell.
        name: String,
        /// 1-based column of the first occurrence.
        first: usize,
    },
    /// A header cell is neither the key column nor an ARKit name.
    #[error("{}:{line}: column {column}: unknown column {name:?}", path.display())]
    UnknownColumn {
        /// The CSV file.
        path: PathBuf,
        /// 1-based line of the header.
        line: usize,
        /// 1-based column.
        column: usize,
        /// The header cell.
        name: String,
    },
    /// A required column is absent (or the file has no header at all).
    #[error("{}: missing column {name}", path.display())]
    MissingColumn {
        /// The CSV file.
        path: PathBuf,
        /// The missing column.
        name: String,
    },
    /// A key cell is wrong: an unknown prompt, a repeated key, a timestamp
    /// that is not a number or goes backwards, a bad timecode.
    #[error("{}:{line}: column {column}: {message}", path.display())]
    Key {
        /// The CSV file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What is wrong.
        message: String,
    },
    /// A row names an expression whose OBJ file does not exist.
    #[error("{}:{line}: {key:?} has no mesh: {} is missing", path.display(), mesh.display())]
    NoMesh {
        /// The CSV file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// The prompt or id.
        key: String,
        /// The expected OBJ file.
        mesh: PathBuf,
    },
    /// A test id cannot be written as a file name or CSV cell.
    #[error(
        "test expression id {0:?} cannot be a file name (empty, `.`, `..`, or contains `/`, `\\`, `,` or a line break)"
    )]
    BadId(String),
    /// The imported session, or the one to export, is not valid.
    #[error("{}: {source}", path.display())]
    Session {
        /// The folder.
        path: PathBuf,
        /// What is inconsistent.
        source: SessionError,
    },
}

/// Reads a whole text file; a missing file is [`InterchangeError::Missing`].
pub(crate) fn read_text(path: &Path) -> Result<String, InterchangeError> {
    std::fs::read_to_string(path).map_err(|source| {
        if source.kind() == io::ErrorKind::NotFound {
            InterchangeError::Missing {
                path: path.to_path_buf(),
            }
        } else {
            InterchangeError::Io {
                path: path.to_path_buf(),
                source,
            }
        }
    })
}

fn io_error(path: &Path) -> impl FnOnce(io::Error) -> InterchangeError + '_ {
    move |source| InterchangeError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// Reads an OBJ and checks it against the template topology.
fn read_mesh(path: &Path, topology: &Topology) -> Result<Vec<Vec3>, InterchangeError> {
    let mesh = read_obj(path)?;
    if mesh.positions.len() != topology.vertex_count() {
        return Err(InterchangeError::VertexCount {
            path: path.to_path_buf(),
            expected: topology.vertex_count(),
            found: mesh.positions.len(),
        });
    }
    let expected = topology.triangles();
    if let Some(k) =
        (0..mesh.triangles.len().min(expected.len())).find(|&k| mesh.triangles[k] != expected[k])
    {
        let [a, b, c] = mesh.triangles[k].map(|i| i + 1);
        let [x, y, z] = expected[k].map(|i| i + 1);
        return Err(InterchangeError::Faces {
            path: path.to_path_buf(),
            line: Some(mesh.triangle_lines[k]),
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

/// The `*.obj` file stems in `dir` (empty if `dir` does not exist).
fn obj_stems(dir: &Path) -> Result<Vec<String>, InterchangeError> {
    let entries = match std::fs::read_dir(dir) {
        Ok(e) => e,
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(Vec::new()),
        Err(e) => return Err(io_error(dir)(e)),
    };
    let mut stems = Vec::new();
    for entry in entries {
        let path = entry.map_err(io_error(dir))?.path();
        if path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("obj"))
        {
            if let Some(stem) = path.file_stem().and_then(|s| s.to_str()) {
                stems.push(stem.to_string());
            }
        }
    }
    stems.sort();
    Ok(stems)
}

/// Finds the OBJ in `dir` for `shape` under any accepted spelling, ARKit's
/// own first.
fn shape_obj(dir: &Path, stems: &[String], shape: Blendshape) -> Option<PathBuf> {
    let own = dir.join(format!("{}.obj", shape.name()));
    if own.is_file() {
        return Some(own);
    }
    stems
        .iter()
        .find(|s| Blendshape::parse(s) == Ok(shape))
        .map(|s| dir.join(format!("{s}.obj")))
}

/// Reads an interchange folder (see the [module docs](self)) into a session
/// that passes [`Session::validate`]. Returns the session and warnings for
/// the person: missing template shapes, unused OBJ files.
pub fn import_folder(dir: &Path) -> Result<(Session, Vec<String>), InterchangeError> {
    let mut warnings = Vec::new();
    let template_dir = dir.join("template");
    let template_neutral_path = template_dir.join("neutral.obj");
    let template_mesh = read_obj(&template_neutral_path)?;
    let topology =
        Topology::new(template_mesh.positions.len(), template_mesh.triangles).map_err(|e| {
            InterchangeError::Topology {
                path: template_neutral_path.clone(),
                message: e.to_string(),
            }
        })?;
    let template_neutral = template_mesh.positions;

    let template_stems = obj_stems(&template_dir)?;
    let mut shapes = Vec::with_capacity(Blendshape::ALL.len());
    for shape in Blendshape::ALL {
        match shape_obj(&template_dir, &template_stems, shape) {
            Some(path) => shapes.push(read_mesh(&path, &topology)?),
            None => {
                warnings.push(format!(
                    "{}: missing; {shape} is taken as a zero delta",
                    template_dir.join(format!("{}.obj", shape.name())).display()
                ));
                shapes.push(template_neutral.clone());
            }
        }
    }
    let neutral = read_mesh(&dir.join("neutral.obj"), &topology)?;

    // Captures.
    let expr_dir = dir.join("expressions");
    let expr_csv = expr_dir.join("weights.csv");
    let table = read_weight_table(&expr_csv, &["prompt"])?;
    let expr_stems = obj_stems(&expr_dir)?;
    let mut captures: Vec<CapturedExpression> = Vec::with_capacity(table.rows.len());
    let mut capture_lines = Vec::with_capacity(table.rows.len());
    for row in &table.rows {
        let prompt = Blendshape::parse(&row.key).map_err(|e| InterchangeError::Key {
            path: expr_csv.clone(),
            line: row.line,
            column: row.key_column,
            message: e.to_string(),
        })?;
        if let Some(k) = captures.iter().position(|c| c.prompt == prompt) {
            return Err(InterchangeError::Key {
                path: expr_csv.clone(),
                line: row.line,
                column: row.key_column,
                message: format!(
                    "prompt {prompt} is captured twice (first on line {})",
                    capture_lines[k]
                ),
            });
        }
        let mesh =
            shape_obj(&expr_dir, &expr_stems, prompt).ok_or_else(|| InterchangeError::NoMesh {
                path: expr_csv.clone(),
                line: row.line,
                key: row.key.clone(),
                mesh: expr_dir.join(format!("{}.obj", prompt.name())),
            })?;
        captures.push(CapturedExpression {
            prompt,
            frame: None,
            weights: row.weights,
            vertices: read_mesh(&mesh, &topology)?,
        });
        capture_lines.push(row.line);
    }
    for stem in &expr_stems {
        if !Blendshape::parse(stem).is_ok_and(|s| captures.iter().any(|c| c.prompt == s)) {
            warnings.push(format!(
                "{}: no row in {}; ignored",
                expr_dir.join(format!("{stem}.obj")).display(),
                expr_csv.display()
            ));
        }
    }

    // Tests.
    let test_dir = dir.join("test");
    let test_csv = test_dir.join("weights.csv");
    let test_stems = obj_stems(&test_dir)?;
    let mut tests: Vec<TestExpression> = Vec::new();
    if test_csv.exists() || !test_stems.is_empty() {
        let table = read_weight_table(&test_csv, &["id"])?;
        let mut lines = Vec::new();
        for row in &table.rows {
            if let Some(k) = tests.iter().position(|t| t.id == row.key) {
                return Err(InterchangeError::Key {
                    path: test_csv.clone(),
                    line: row.line,
                    column: row.key_column,
                    message: format!(
                        "id {:?} appears twice (first on line {})",
                        row.key, lines[k]
                    ),
                });
            }
            check_id(&row.key).map_err(|e| InterchangeError::Key {
                path: test_csv.clone(),
                line: row.line,
                column: row.key_column,
                message: e.to_string(),
            })?;
            let mesh = test_dir.join(format!("{}.obj", row.key));
            if !mesh.is_file() {
                return Err(InterchangeError::NoMesh {
                    path: test_csv.clone(),
                    line: row.line,
                    key: row.key.clone(),
                    mesh,
                });
            }
            tests.push(TestExpression {
                id: row.key.clone(),
                frame: None,
                weights: row.weights,
                vertices: read_mesh(&mesh, &topology)?,
            });
            lines.push(row.line);
        }
        for stem in &test_stems {
            if !tests.iter().any(|t| &t.id == stem) {
                warnings.push(format!(
                    "{}: no row in {}; ignored",
                    test_dir.join(format!("{stem}.obj")).display(),
                    test_csv.display()
                ));
            }
        }
    }

    // Stream.
    let frames_csv = dir.join("frames.csv");
    let frames = if frames_csv.exists() {
        read_frames(&frames_csv)?
    } else {
        Vec::new()
    };
    let frame_rate = frame_rate(&frames);

    let session = Session {
        device: DeviceInfo {
            model: IMPORTED_MODEL.to_string(),
            ..DeviceInfo::default()
        },
        frame_rate,
        topology,
        template: Template {
            neutral: template_neutral,
            shapes,
        },
        neutral,
        frames,
        captures,
        tests,
        truth: None,
    };
    session
        .validate()
        .map_err(|source| InterchangeError::Session {
            path: dir.to_path_buf(),
            source,
        })?;
    Ok((session, warnings))
}

/// Reads `frames.csv` (plain or Live Link Face).
fn read_frames(path: &Path) -> Result<Vec<Frame>, InterchangeError> {
    let table = read_weight_table(path, &["timestamp", "timecode"])?;
    let live_link = table.key_name.eq_ignore_ascii_case("timecode");
    let key_error = |row: &weights_csv::WeightRow, message: String| InterchangeError::Key {
        path: path.to_path_buf(),
        line: row.line,
        column: row.key_column,
        message,
    };
    let mut times = Vec::with_capacity(table.rows.len());
    if live_link {
        let mut parsed = Vec::with_capacity(table.rows.len());
        for row in &table.rows {
            parsed.push(parse_timecode(&row.key).ok_or_else(|| {
                key_error(
                    row,
                    format!("{:?} is not a timecode HH:MM:SS:FF[.fff]", row.key),
                )
            })?);
        }
        let max_frame = parsed.iter().map(|t| t.1).fold(0.0, f64::max);
        let rate = [24.0, 25.0, 30.0, 48.0, 50.0, 60.0, 120.0]
            .into_iter()
            .find(|r| max_frame < *r)
            .unwrap_or(max_frame.floor() + 1.0);
        let start = parsed.first().map(|t| t.0 + t.1 / rate).unwrap_or(0.0);
        times.extend(parsed.iter().map(|t| t.0 + t.1 / rate - start));
    } else {
        for row in &table.rows {
            let t = row
                .key
                .parse::<f64>()
                .ok()
                .filter(|t| t.is_finite())
                .ok_or_else(|| {
                    key_error(
                        row,
                        format!("timestamp {:?} is not a finite number", row.key),
                    )
                })?;
            times.push(t);
        }
    }
    let mut frames = Vec::with_capacity(times.len());
    for (k, (row, t)) in table.rows.iter().zip(times).enumerate() {
        if k > 0 && t < frames.last().map(|f: &Frame| f.timestamp).unwrap_or(t) {
            return Err(key_error(
                row,
                format!("time {t} s is earlier than the row before"),
            ));
        }
        frames.push(Frame {
            timestamp: t,
            weights: row.weights,
            tracked: true,
            vertices: None,
        });
    }
    Ok(frames)
}

/// `HH:MM:SS:FF[.fff]` → (whole seconds, frames including the fraction).
fn parse_timecode(text: &str) -> Option<(f64, f64)> {
    let parts: Vec<&str> = text.split(':').collect();
    let [h, m, s, f] = parts.as_slice() else {
        return None;
    };
    let int = |x: &str| -> Option<f64> {
        (!x.is_empty() && x.bytes().all(|b| b.is_ascii_digit())).then(|| x.parse().ok())?
    };
    let (h, m, s) = (int(h)?, int(m)?, int(s)?);
    if m >= 60.0 || s >= 61.0 {
        return None;
    }
    let (whole, fraction) = f.split_once('.').unwrap_or((f, ""));
    let frames = int(whole)?
        + if fraction.is_empty() {
            0.0
        } else {
            int(fraction)? / 10f64.powi(fraction.len() as i32)
        };
    Some((h * 3600.0 + m * 60.0 + s, frames))
}

/// One over the median spacing of the timestamps, or [`DEFAULT_FRAME_RATE`].
fn frame_rate(frames: &[Frame]) -> f32 {
    let mut spacing: Vec<f64> = frames
        .windows(2)
        .map(|w| w[1].timestamp - w[0].timestamp)
        .filter(|d| *d > 0.0)
        .collect();
    if spacing.is_empty() {
        return DEFAULT_FRAME_RATE;
    }
    spacing.sort_by(f64::total_cmp);
    let n = spacing.len();
    let median = if n % 2 == 1 {
        spacing[n / 2]
    } else {
        0.5 * (spacing[n / 2 - 1] + spacing[n / 2])
    };
    let rate = (1.0 / median) as f32;
    if rate.is_finite() && rate > 0.0 {
        rate
    } else {
        DEFAULT_FRAME_RATE
    }
}

/// Whether a test id can be a file stem and a CSV cell.
fn check_id(id: &str) -> Result<(), InterchangeError> {
    let bad = id.is_empty()
        || id == "."
        || id == ".."
        || id != id.trim()
        || id.contains(['/', '\\', ',', '\n', '\r']);
    if bad {
        Err(InterchangeError::BadId(id.to_string()))
    } else {
        Ok(())
    }
}

/// Writes `session` as an interchange folder (see the [module docs](self)),
/// creating `dir` and its subfolders if needed. Every file is written
/// atomically. `frames.csv` is written only if the session has frames, and
/// `test/` only if it has test expressions.
pub fn export_folder(session: &Session, dir: &Path) -> Result<(), InterchangeError> {
    session
        .validate_expressions()
        .map_err(|source| InterchangeError::Session {
            path: dir.to_path_buf(),
            source,
        })?;
    for test in &session.tests {
        check_id(&test.id)?;
    }
    let topo = &session.topology;
    let obj = |path: PathBuf, mesh: &[Vec3], comment: &str| {
        let positions: Vec<DVec3> = mesh.iter().map(|p| p.as_dvec3()).collect();
        write_obj(&path, topo, &positions, comment).map_err(io_error(&path))
    };
    let text = |path: PathBuf, text: String| {
        write_atomically(&path, text.as_bytes()).map_err(io_error(&path))
    };
    let mkdir = |path: &Path| std::fs::create_dir_all(path).map_err(io_error(path));

    let template_dir = dir.join("template");
    mkdir(&template_dir)?;
    obj(
        template_dir.join("neutral.obj"),
        &session.template.neutral,
        "template neutral",
    )?;
    for (shape, mesh) in Blendshape::ALL.iter().zip(&session.template.shapes) {
        obj(
            template_dir.join(format!("{}.obj", shape.name())),
            mesh,
            &format!("template {shape}"),
        )?;
    }
    obj(dir.join("neutral.obj"), &session.neutral, "neutral scan")?;

    let expr_dir = dir.join("expressions");
    mkdir(&expr_dir)?;
    for c in &session.captures {
        obj(
            expr_dir.join(format!("{}.obj", c.prompt.name())),
            &c.vertices,
            &format!("captured expression {}", c.prompt),
        )?;
    }
    text(
        expr_dir.join("weights.csv"),
        weights_csv::weight_table_text(
            "prompt",
            session
                .captures
                .iter()
                .map(|c| (c.prompt.name().to_string(), &c.weights)),
        ),
    )?;

    if !session.tests.is_empty() {
        let test_dir = dir.join("test");
        mkdir(&test_dir)?;
        for t in &session.tests {
            obj(
                test_dir.join(format!("{}.obj", t.id)),
                &t.vertices,
                &format!("test expression {}", t.id),
            )?;
        }
        text(
            test_dir.join("weights.csv"),
            weights_csv::weight_table_text(
                "id",
                session.tests.iter().map(|t| (t.id.clone(), &t.weights)),
            ),
        )?;
    }

    if !session.frames.is_empty() {
        text(
            dir.join("frames.csv"),
            weights_csv::weight_table_text(
                "timestamp",
                session
                    .frames
                    .iter()
                    .map(|f| (format!("{:?}", f.timestamp), &f.weights)),
            ),
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

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
        let frames: Vec<_> = [0.0, 0.02, 0.04, 0.1, 0.12]
            .into_iter()
            .map(frame)
            .collect();
        assert!((frame_rate(&frames) - 50.0).abs() < 1e-3);
    }
}
