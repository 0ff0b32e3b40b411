//! A Wavefront OBJ reader for meshes of one topology: `v` and `f` lines.
//!
//! * `v x y z` (extra components, e.g. `w` or vertex colours, are ignored);
//!   every coordinate must be a finite number.
//! * `f` corners may be `a`, `a/b`, `a/b/c` or `a//c`; only the position
//!   index is kept. Indices are 1-based; negative indices count back from the
//!   last vertex defined so far, as the OBJ specification says.
//! * A polygon with more than three corners is split into a fan
//!   `(a b c) (a c d) …`, the same way for every file, so quad meshes of one
//!   topology still compare equal.
//! * Every other line (`vt`, `vn`, `o`, `g`, `s`, `usemtl`, comments …) is
//!   ignored.
//!
//! # Limits
//!
//! The caller states how many vertices a mesh may have ([`ObjLimits`]);
//! the rest follows from it and is checked while reading, before anything
//! is allocated for it: at most 4 triangles per vertex (a closed triangle
//! mesh has about 2), at most 512 bytes of file per vertex plus 64 KiB (a
//! `v` line is about 35 bytes; with `vt` and `vn` lines and two faces of
//! `a/b/c` corners per vertex about 170), and lines of at most
//! [`MAX_OBJ_LINE`] bytes. The file is read one line at a time.

use super::excerpt::Excerpt;
use super::file_error::FileError;
use super::text_lines::{TextLimits, TextLines, open_text};
use glam::Vec3;
use std::io::BufRead;
use std::path::{Path, PathBuf};

/// Longest OBJ line, in bytes: a `v` line is under 100, and a face of a
/// hundred `a/b/c` corners under 2,000.
pub const MAX_OBJ_LINE: usize = 4096;

/// What one OBJ file may hold.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ObjLimits {
    /// Largest vertex count.
    pub max_vertices: usize,
}

impl ObjLimits {
    /// Largest triangle count: four per vertex.
    pub fn max_triangles(self) -> usize {
        self.max_vertices.saturating_mul(4)
    }

    /// The file size and line length accepted.
    pub fn text(self) -> TextLimits {
        TextLimits {
            max_bytes: (self.max_vertices as u64).saturating_mul(512) + (64 << 10),
            max_line: MAX_OBJ_LINE,
            what: "an OBJ file",
        }
    }
}

/// Why an OBJ file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum ObjError {
    /// The file is missing, unreadable, too large, or not text.
    #[error(transparent)]
    File(#[from] FileError),
    /// A line could not be understood, or holds more than the limits allow.
    #[error("{}:{line}: {message}", path.display())]
    Syntax {
        /// The OBJ file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// What is wrong.
        message: String,
    },
}

/// The geometry and connectivity of one OBJ file.
#[derive(Clone, Debug, PartialEq)]
pub struct ObjMesh {
    /// Vertex positions in file order.
    pub positions: Vec<Vec3>,
    /// For each vertex, the 1-based line of its `v` line.
    pub vertex_lines: Vec<usize>,
    /// Triangles (0-based), polygons split into fans.
    pub triangles: Vec<[u32; 3]>,
    /// For each triangle, the 1-based line of the `f` line it came from.
    pub triangle_lines: Vec<usize>,
}

/// Reads and parses the OBJ file at `path` within `limits`; a missing file
/// is [`FileError::Missing`].
pub fn read_obj(path: &Path, limits: ObjLimits) -> Result<ObjMesh, ObjError> {
    parse_lines(open_text(path, limits.text())?, limits)
}

/// Parses OBJ text within `limits`; `path` only names the file in errors.
pub fn parse_obj(path: &Path, text: &str, limits: ObjLimits) -> Result<ObjMesh, ObjError> {
    parse_lines(TextLines::new(text.as_bytes(), path, limits.text()), limits)
}

/// Parses OBJ lines as they are read.
fn parse_lines<R: BufRead>(
    mut lines: TextLines<R>,
    limits: ObjLimits,
) -> Result<ObjMesh, ObjError> {
    let path = lines.path().to_path_buf();
    let mut mesh = ObjMesh {
        positions: Vec::new(),
        vertex_lines: Vec::new(),
        triangles: Vec::new(),
        triangle_lines: Vec::new(),
    };
    let error = |line: usize, message: String| ObjError::Syntax {
        path: path.clone(),
        line,
        message,
    };
    let mut corners = Vec::with_capacity(4);
    while let Some((line, raw)) = lines.next_line()? {
        let content = raw.split('#').next().unwrap_or("");
        let mut fields = content.split_whitespace();
        match fields.next() {
            Some("v") => {
                if mesh.positions.len() == limits.max_vertices {
                    let message =
                        format!("more than the limit of {} vertices", limits.max_vertices);
                    return Err(error(line, message));
                }
                let mut xyz = [0.0f32; 3];
                for (k, slot) in xyz.iter_mut().enumerate() {
                    let field = fields.next().ok_or_else(|| {
                        error(line, format!("vertex has {k} coordinates, expected 3"))
                    })?;
                    *slot = field
                        .parse::<f32>()
                        .ok()
                        .filter(|x| x.is_finite())
                        .ok_or_else(|| {
                            error(
                                line,
                                format!(
                                    "vertex coordinate {} is {}, not a finite number",
                                    k + 1,
                                    Excerpt::of(field)
                                ),
                            )
                        })?;
                }
                mesh.positions.push(Vec3::from_array(xyz));
                mesh.vertex_lines.push(line);
            }
            Some("f") => {
                corners.clear();
                for field in fields {
                    let index_text = field.split('/').next().unwrap_or("");
                    let index: i64 = index_text.parse().map_err(|_| {
                        let message =
                            format!("face corner {} is not a vertex index", Excerpt::of(field));
                        error(line, message)
                    })?;
                    let defined = mesh.positions.len() as i64;
                    let zero_based = match index {
                        i if i > 0 => i - 1,
                        i if i < 0 => defined + i,
                        _ => -1,
                    };
                    if zero_based < 0 || zero_based >= defined {
                        return Err(error(
                            line,
                            format!(
                                "face refers to vertex {index}, but {defined} vertices are defined so far"
                            ),
                        ));
                    }
                    corners.push(zero_based as u32);
                }
                if corners.len() < 3 {
                    return Err(error(
                        line,
                        format!("face has {} corners, expected at least 3", corners.len()),
                    ));
                }
                if mesh.triangles.len() + corners.len() - 2 > limits.max_triangles() {
                    let message = format!(
                        "more than the limit of {} triangles",
                        limits.max_triangles()
                    );
                    return Err(error(line, message));
                }
                // Indexing: at least three corners, so `k + 1 < len`.
                for k in 1..corners.len() - 1 {
                    mesh.triangles
                        .push([corners[0], corners[k], corners[k + 1]]);
                    mesh.triangle_lines.push(line);
                }
            }
            _ => {}
        }
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;

    const LIMITS: ObjLimits = ObjLimits { max_vertices: 4 };

    #[test]
    fn reads_every_face_spelling_and_splits_quads_into_fans() {
        let text = "\u{feff}# cube corner\r\nv 0 0 0\r\nv 1 0 0\nv 1 1 0 1.0\nv 0 1 0\nvn 0 0 1\n\
                    f 1 2 3\nf 1/1/1 2/2/1 3/3/1\nf 1//1 3//1 4//1\nf -4 -3 -2 -1\n";
        let mesh = parse_obj(Path::new("a.obj"), text, LIMITS).unwrap();
        assert_eq!(mesh.positions.len(), 4);
        assert_eq!(mesh.positions[2], Vec3::new(1.0, 1.0, 0.0));
        assert_eq!(
            mesh.triangles,
            vec![[0, 1, 2], [0, 1, 2], [0, 2, 3], [0, 1, 2], [0, 2, 3]]
        );
        assert_eq!(mesh.triangle_lines, vec![7, 8, 9, 10, 10]);
        assert_eq!(mesh.vertex_lines, vec![2, 3, 4, 5]);
    }

    #[test]
    fn errors_name_the_file_and_line() {
        let cases = [
            ("v 0 0 0\nv 1 x 0\n", 2, "not a finite number"),
            ("v 0 0 0\nv nan 0 0\n", 2, "not a finite number"),
            ("v 0 0\n", 1, "2 coordinates"),
            ("v 0 0 0\nv 1 0 0\nf 1 2 3\n", 3, "vertex 3"),
            ("v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2\n", 4, "2 corners"),
            (
                "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 a 3\n",
                4,
                "not a vertex index",
            ),
        ];
        for (text, line, what) in cases {
            let err = parse_obj(Path::new("dir/m.obj"), text, LIMITS).unwrap_err();
            let message = err.to_string();
            assert!(
                message.starts_with(&format!("dir/m.obj:{line}: ")) && message.contains(what),
                "{message}"
            );
        }
    }

    #[test]
    fn counts_past_the_limits_are_refused_at_their_line() {
        let five = "v 0 0 0\n".repeat(5);
        let err = parse_obj(Path::new("m.obj"), &five, LIMITS).unwrap_err();
        assert_eq!(
            err.to_string(),
            "m.obj:5: more than the limit of 4 vertices"
        );
        let faces = format!("{}{}", "v 0 0 0\n".repeat(3), "f 1 2 3\n".repeat(17));
        let err = parse_obj(Path::new("m.obj"), &faces, LIMITS).unwrap_err();
        assert_eq!(
            err.to_string(),
            "m.obj:20: more than the limit of 16 triangles"
        );
        let long = format!("v 0 0 0\nv 1 {} 0\n", "9".repeat(2_000));
        let err = parse_obj(Path::new("m.obj"), &long, LIMITS).unwrap_err();
        let message = err.to_string();
        assert!(
            message.starts_with("m.obj:2: vertex coordinate 2 is \"999"),
            "{message}"
        );
        assert!(message.len() < 120, "{message}");
        let nul = format!("v 0 0 0\n{}", "\0".repeat(5_000));
        let err = parse_obj(Path::new("m.obj"), &nul, LIMITS).unwrap_err();
        assert!(
            matches!(err, ObjError::File(FileError::LineTooLong { line: 2, .. })),
            "{err}"
        );
    }
}
