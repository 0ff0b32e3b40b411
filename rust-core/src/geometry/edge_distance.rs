//! Distances along a mesh's edges from a set of source vertices: Dijkstra's
//! shortest paths over the edge graph, each edge as long as it is at rest.
//! An upper bound on the geodesic distance (a path zig-zags along edges),
//! which is all the avatar stage needs to fade a motion out over a band.

use glam::DVec3;
use std::cmp::Reverse;
use std::collections::BinaryHeap;

/// A mesh's edge graph: each vertex's neighbours along the edges of its
/// triangles, each edge once, with its length at rest. Built once and
/// searched many times (one search per shape when fading 52 shapes).
#[derive(Clone, Debug)]
pub struct EdgeGraph {
    /// `neighbours[offsets[v]..offsets[v + 1]]` are `v`'s.
    offsets: Vec<usize>,
    /// Each neighbour and the edge's length.
    neighbours: Vec<(u32, f64)>,
}

impl EdgeGraph {
    /// The edges of `triangles` over the vertices of `positions`, with the
    /// lengths of `positions`; triangles naming a vertex past `positions`
    /// are skipped.
    pub fn new(positions: &[DVec3], triangles: &[[u32; 3]]) -> EdgeGraph {
        let n = positions.len();
        let mut lists: Vec<Vec<u32>> = vec![Vec::new(); n];
        for t in triangles {
            if t.iter().any(|&v| v as usize >= n) {
                continue;
            }
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                lists[a as usize].push(b);
                lists[b as usize].push(a);
            }
        }
        let mut offsets = Vec::with_capacity(n + 1);
        let mut neighbours = Vec::new();
        offsets.push(0);
        for (v, list) in lists.iter_mut().enumerate() {
            list.sort_unstable();
            list.dedup();
            neighbours.extend(
                list.iter()
                    .map(|&u| (u, positions[v].distance(positions[u as usize]))),
            );
            offsets.push(neighbours.len());
        }
        EdgeGraph {
            offsets,
            neighbours,
        }
    }

    /// For every vertex, the length of the shortest edge path from a
    /// vertex with `source[v]` (0 for those; vertices past `source` are
    /// not sources); `f64::INFINITY` beyond `reach` (the search stops
    /// there).
    pub fn distances(&self, source: &[bool], reach: f64) -> Vec<f64> {
        let n = self.offsets.len() - 1;
        let mut distance = vec![f64::INFINITY; n];
        let mut queue = BinaryHeap::new();
        for v in (0..n.min(source.len())).filter(|&v| source[v]) {
            distance[v] = 0.0;
            queue.push(Reverse((Key(0.0), v)));
        }
        while let Some(Reverse((Key(d), v))) = queue.pop() {
            if d > distance[v] {
                continue;
            }
            for &(u, length) in &self.neighbours[self.offsets[v]..self.offsets[v + 1]] {
                let u = u as usize;
                let next = d + length;
                if next < distance[u] && next <= reach {
                    distance[u] = next;
                    queue.push(Reverse((Key(next), u)));
                }
            }
        }
        distance
    }
}

/// For every vertex, the length of the shortest edge path from a vertex
/// with `source[v]` over the edges of `triangles` with the lengths of
/// `positions` ([`EdgeGraph::distances`] on a graph built for one search).
pub fn edge_distances(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    source: &[bool],
    reach: f64,
) -> Vec<f64> {
    EdgeGraph::new(positions, triangles).distances(source, reach)
}

/// A distance ordered totally (`f64::total_cmp`), for the queue.
#[derive(PartialEq)]
struct Key(f64);
impl Eq for Key {}
impl PartialOrd for Key {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Key {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&other.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_strip_measures_along_its_edges_and_stops_at_reach() {
        // Two triangles: 0-1-2 and 1-3-2, a unit square split on 1-2.
        let p = [
            DVec3::ZERO,
            DVec3::X,
            DVec3::Y,
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::splat(9.0),
        ];
        let t = [[0, 1, 2], [1, 3, 2]];
        let d = edge_distances(&p, &t, &[true, false, false, false, false], 1.5);
        assert_eq!(&d[..3], &[0.0, 1.0, 1.0]);
        assert!(d[3].is_infinite(), "2 along the edges, beyond reach 1.5");
        assert!(d[4].is_infinite(), "not connected");
        let d = edge_distances(&p, &t, &[true, false, false, false, false], 5.0);
        assert_eq!(d[3], 2.0);
    }
}
