//! Where a triangle mesh passes through itself: the pairs of triangles
//! that share no corner and of which one has an edge crossing the other
//! (Möller & Trumbore 1997 for each edge against each triangle). The
//! triangles are binned by their bounding boxes in a grid of cells twice
//! the mean edge long, so only triangles that share a cell are compared.

use crate::geometry::ray_cover::PARALLEL;
use glam::DVec3;
use std::collections::{HashMap, HashSet};

/// The pairs `(i, j)`, `i < j`, of `triangles` (indices into it) that
/// share no corner and cut through each other at `positions`, sorted;
/// triangles naming a vertex past `positions` are skipped.
pub fn intersecting_pairs(positions: &[DVec3], triangles: &[[u32; 3]]) -> Vec<(usize, usize)> {
    let valid = |t: &[u32; 3]| t.iter().all(|&v| (v as usize) < positions.len());
    let corners = |t: &[u32; 3]| t.map(|v| positions[v as usize]);
    let mean_edge = triangles
        .iter()
        .filter(|t| valid(t))
        .map(|t| {
            let [a, b, c] = corners(t);
            ((b - a).length() + (c - b).length() + (a - c).length()) / 3.0
        })
        .sum::<f64>()
        / triangles.iter().filter(|t| valid(t)).count().max(1) as f64;
    let cell = 2.0 * mean_edge.max(f64::MIN_POSITIVE);
    let key = |p: DVec3| (p / cell).floor().as_ivec3().to_array();
    let mut cells: HashMap<[i32; 3], Vec<usize>> = HashMap::new();
    for (i, t) in triangles.iter().enumerate().filter(|(_, t)| valid(t)) {
        let [a, b, c] = corners(t);
        let (lo, hi) = (key(a.min(b).min(c)), key(a.max(b).max(c)));
        for x in lo[0]..=hi[0] {
            for y in lo[1]..=hi[1] {
                for z in lo[2]..=hi[2] {
                    cells.entry([x, y, z]).or_default().push(i);
                }
            }
        }
    }
    let crosses = |edge_of: &[u32; 3], other: &[u32; 3]| {
        let p = corners(edge_of);
        let q = corners(other);
        (0..3).any(|k| segment_crosses(p[k], p[(k + 1) % 3], q))
    };
    let mut pairs = HashSet::new();
    for list in cells.values() {
        for (x, &i) in list.iter().enumerate() {
            for &j in &list[..x] {
                let (a, b) = (&triangles[i], &triangles[j]);
                if a.iter().any(|v| b.contains(v)) {
                    continue;
                }
                if crosses(a, b) || crosses(b, a) {
                    pairs.insert((i.min(j), i.max(j)));
                }
            }
        }
    }
    let mut pairs: Vec<(usize, usize)> = pairs.into_iter().collect();
    pairs.sort_unstable();
    pairs
}

/// Whether the segment `ab` crosses triangle `q` (Möller–Trumbore, both
/// ends excluded).
fn segment_crosses(a: DVec3, b: DVec3, q: [DVec3; 3]) -> bool {
    let d = b - a;
    let (e1, e2) = (q[1] - q[0], q[2] - q[0]);
    let h = d.cross(e2);
    let det = e1.dot(h);
    if det.abs() <= PARALLEL * d.length() * e1.length() * e2.length() {
        return false;
    }
    let s = a - q[0];
    let u = s.dot(h) / det;
    let qv = s.cross(e1);
    let v = d.dot(qv) / det;
    let t = e2.dot(qv) / det;
    u > 0.0 && v > 0.0 && u + v < 1.0 && t > 0.0 && t < 1.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_crossing_triangles_are_found_and_neighbours_are_not() {
        let positions = [
            // A triangle in the plane z = 0 …
            DVec3::new(-1.0, -1.0, 0.0),
            DVec3::new(1.0, -1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
            // … one through it, upright …
            DVec3::new(0.0, 0.0, -1.0),
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::new(0.0, 0.5, 1.0),
            // … and one beside the first, sharing an edge.
            DVec3::new(2.0, 1.0, 0.0),
        ];
        let triangles = [[0, 1, 2], [3, 4, 5], [1, 6, 2]];
        assert_eq!(intersecting_pairs(&positions, &triangles), vec![(0, 1)]);
        let mut apart = positions;
        for p in &mut apart[3..6] {
            p.x += 5.0;
        }
        assert!(intersecting_pairs(&apart, &triangles).is_empty());
    }
}
