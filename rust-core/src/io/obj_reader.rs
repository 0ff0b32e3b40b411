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

use super::text_file::{FileError, read_text};
use glam::Vec3;
use std::path::{Path, PathBuf};

/// Why an OBJ file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum ObjError {
    /// The file is missing or unreadable.
    #[error(transparent)]
    File(#[from] FileError),
    /// A line could not be understood.
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
    /// Triangles (0-based), polygons split into fans.
    pub triangles: Vec<[u32; 3]>,
    /// For each triangle, the 1-based line of the `f` line it came from.
    pub triangle_lines: Vec<usize>,
}

/// Reads and parses the OBJ file at `path`; a missing file is
/// [`FileError::Missing`].
pub fn read_obj(path: &Path) -> Result<ObjMesh, ObjError> {
    let text = read_text(path)?;
    parse_obj(path, &text)
}

/// Parses OBJ text; `path` only names the file in errors.
pub fn parse_obj(path: &Path, text: &str) -> Result<ObjMesh, ObjError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut mesh = ObjMesh {
        positions: Vec::new(),
        triangles: Vec::new(),
        triangle_lines: Vec::new(),
    };
    let error = |line: usize, message: String| ObjError::Syntax {
        path: path.to_path_buf(),
        line,
        message,
    };
    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let content = raw.split('#').next().unwrap_or("");
        let mut fields = content.split_whitespace();
        match fields.next() {
            Some("v") => {
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
                                    "vertex coordinate {} is {field:?}, not a finite number",
                                    k + 1
                                ),
                            )
                        })?;
                }
                mesh.positions.push(Vec3::from_array(xyz));
            }
            Some("f") => {
                let mut corners = Vec::with_capacity(4);
                for field in fields {
                    let index_text = field.split('/').next().unwrap_or("");
                    let index: i64 = index_text.parse().map_err(|_| {
                        error(line, format!("face corner {field:?} is not a vertex index"))
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

    #[test]
    fn reads_every_face_spelling_and_splits_quads_into_fans() {
        let text = "\u{feff}# cube corner\r\nv 0 0 0\r\nv 1 0 0\nv 1 1 0 1.0\nv 0 1 0\nvn 0 0 1\n\
                    f 1 2 3\nf 1/1/1 2/2/1 3/3/1\nf 1//1 3//1 4//1\nf -4 -3 -2 -1\n";
        let mesh = parse_obj(Path::new("a.obj"), text).unwrap();
        assert_eq!(mesh.positions.len(), 4);
        assert_eq!(mesh.positions[2], Vec3::new(1.0, 1.0, 0.0));
        assert_eq!(
            mesh.triangles,
            vec![[0, 1, 2], [0, 1, 2], [0, 2, 3], [0, 1, 2], [0, 2, 3]]
        );
        assert_eq!(mesh.triangle_lines, vec![7, 8, 9, 10, 10]);
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
            let err = parse_obj(Path::new("dir/m.obj"), text).unwrap_err();
            let message = err.to_string();
            assert!(
                message.starts_with(&format!("dir/m.obj:{line}: ")) && message.contains(what),
                "{message}"
            );
        }
    }
}
