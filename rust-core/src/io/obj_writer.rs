//! Wavefront OBJ output of meshes that share a topology: the plain format
//! every tool reads, used to hand personalized blendshapes to people and to
//! look at them.
//!
//! One file per mesh: `v x y z` lines in metres, then `f a b c` lines with
//! 1-based indices. Each file is written atomically.

use crate::geometry::topology::Topology;
use crate::io::atomic_write::write_atomically;
use glam::DVec3;
use std::fmt::Write as _;
use std::io;
use std::path::Path;

/// The OBJ text of one mesh. Coordinates are printed with 7 decimals
/// (0.1 µm), far below the tracker's precision.
pub fn obj_text(topology: &Topology, positions: &[DVec3], comment: &str) -> String {
    let mut out = String::with_capacity(40 * positions.len() + 24 * topology.triangles().len());
    for line in comment.lines() {
        let _ = writeln!(out, "# {line}");
    }
    for p in positions {
        let _ = writeln!(out, "v {:.7} {:.7} {:.7}", p.x, p.y, p.z);
    }
    for t in topology.triangles() {
        let _ = writeln!(out, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
    }
    out
}

/// Writes one mesh as an OBJ file at `path`, atomically.
pub fn write_obj(
    path: &Path,
    topology: &Topology,
    positions: &[DVec3],
    comment: &str,
) -> io::Result<()> {
    write_atomically(path, obj_text(topology, positions, comment).as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_vertices_then_one_based_faces() {
        let topo = Topology::new(3, vec![[0, 1, 2]]).unwrap();
        let text = obj_text(
            &topo,
            &[DVec3::ZERO, DVec3::X, DVec3::new(0.0, 0.001, 0.0)],
            "neutral",
        );
        assert_eq!(
            text,
            "# neutral\nv 0.0000000 0.0000000 0.0000000\nv 1.0000000 0.0000000 0.0000000\n\
             v 0.0000000 0.0010000 0.0000000\nf 1 2 3\n"
        );
    }
}
