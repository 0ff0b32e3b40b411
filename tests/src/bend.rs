//! How sharply a shape bends the skin: the change, under the shape, of the
//! dihedral angle between two triangles sharing an edge. A smooth surface
//! moved smoothly changes it little from edge to edge; a crease shows as
//! one row of edges turning by tens of degrees.

use glam::Vec3;
use std::collections::HashMap;

/// The sharpest bend a shape makes at an edge, and where.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bend {
    /// Change of the dihedral angle at the edge (degrees).
    pub degrees: f64,
    /// The edge's midpoint at rest.
    pub at: Vec3,
}

/// The change of dihedral angle (degrees) under displacement `shape` (per
/// vertex of `positions`) at every interior edge of `triangles` (an edge
/// with exactly two triangles) whose two ends pass `counts`, with the
/// edge's ends.
pub fn bends(
    positions: &[Vec3],
    triangles: &[[u32; 3]],
    shape: &[Vec3],
    counts: impl Fn(u32, u32) -> bool,
) -> Vec<((u32, u32), f64)> {
    let mut sides: HashMap<(u32, u32), Vec<usize>> = HashMap::new();
    for (i, t) in triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            sides.entry((a.min(b), a.max(b))).or_default().push(i);
        }
    }
    let normal = |t: [u32; 3], moved: bool| {
        let p = |v: u32| positions[v as usize] + if moved { shape[v as usize] } else { Vec3::ZERO };
        (p(t[1]) - p(t[0]))
            .cross(p(t[2]) - p(t[0]))
            .normalize_or_zero()
    };
    sides
        .into_iter()
        .filter(|((a, b), ts)| ts.len() == 2 && counts(*a, *b))
        .map(|(edge, ts)| {
            let [s, t] = [triangles[ts[0]], triangles[ts[1]]];
            let before = normal(s, false).angle_between(normal(t, false));
            let after = normal(s, true).angle_between(normal(t, true));
            (edge, (after - before).abs().to_degrees() as f64)
        })
        .filter(|(_, d)| d.is_finite())
        .collect()
}

/// The largest change of dihedral angle, under displacement `shape` (per
/// vertex of `positions`), over the interior edges of `triangles` whose
/// two ends pass `counts`; `None` when no edge does.
pub fn largest_bend(
    positions: &[Vec3],
    triangles: &[[u32; 3]],
    shape: &[Vec3],
    counts: impl Fn(u32, u32) -> bool,
) -> Option<Bend> {
    bends(positions, triangles, shape, counts)
        .into_iter()
        .map(|((a, b), degrees)| Bend {
            degrees,
            at: 0.5 * (positions[a as usize] + positions[b as usize]),
        })
        .max_by(|x, y| x.degrees.total_cmp(&y.degrees))
}
