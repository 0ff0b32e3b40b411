//! The order in which a mesh's values are coded, and which neighbours
//! predict each value.
//!
//! Indexing: vertex indices come from a checked [`Topology`], so they index
//! the per-vertex arrays (`start` has `v + 1` entries); the adjacency holds
//! the `6 · triangles` entries `start` counts. [`Traversal::earlier`] and
//! [`Traversal::predict`] take a value index `j < len()` and one frame of
//! `len()` values, which is what every caller (`geometry_codec.rs`,
//! `series.rs`) passes: meshes quantized over the same topology.

use crate::geometry::topology::Topology;

/// Most neighbours a value is predicted from (bounds decoding time on
/// hostile topologies).
const MAX_NEIGHBOURS: usize = 8;

/// The order in which a mesh's values are coded and, for each value, the
/// values it is predicted from spatially: a breadth-first traversal of the
/// mesh's edges (from vertex 0, then from each vertex not yet reached, in
/// index order), repeated for the x, y and z planes. A value is predicted by
/// the rounded mean of its neighbours that come earlier in the order (the
/// first [`MAX_NEIGHBOURS`] by index). Encoder and decoder derive it from the
/// topology alone.
#[derive(Clone, Debug)]
pub struct Traversal {
    order: Vec<u32>,
    start: Vec<u32>,
    earlier: Vec<u32>,
}

impl Traversal {
    /// Index order and no spatial prediction, for `n` values.
    pub fn identity(n: usize) -> Self {
        Traversal {
            order: (0..n as u32).collect(),
            start: vec![0; n + 1],
            earlier: Vec::new(),
        }
    }

    /// The traversal of a mesh over `topology`, in planar value indices.
    pub fn for_mesh(topology: &Topology) -> Self {
        let v = topology.vertex_count();
        // Compressed adjacency: each triangle contributes its three edges
        // both ways.
        let mut start = vec![0u32; v + 1];
        for tri in topology.triangles() {
            for &a in tri {
                start[a as usize + 1] += 2;
            }
        }
        for i in 0..v {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut neighbours = vec![0u32; start[v] as usize];
        for tri in topology.triangles() {
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                for (x, y) in [(a, b), (b, a)] {
                    neighbours[fill[x as usize] as usize] = y;
                    fill[x as usize] += 1;
                }
            }
        }
        let adjacent = |a: usize| &neighbours[start[a] as usize..start[a + 1] as usize];
        let mut rank = vec![u32::MAX; v];
        let mut order: Vec<u32> = Vec::with_capacity(v);
        for root in 0..v {
            if rank[root] != u32::MAX {
                continue;
            }
            rank[root] = order.len() as u32;
            order.push(root as u32);
            let mut head = order.len() - 1;
            while head < order.len() {
                let a = order[head] as usize;
                head += 1;
                for &b in adjacent(a) {
                    if rank[b as usize] == u32::MAX {
                        rank[b as usize] = order.len() as u32;
                        order.push(b);
                    }
                }
            }
        }
        // Per vertex, its earlier neighbours, deduplicated, by index.
        let mut vertex_start = Vec::with_capacity(v + 1);
        let mut vertex_earlier = Vec::new();
        vertex_start.push(0u32);
        for i in 0..v {
            let mut e: Vec<u32> = adjacent(i)
                .iter()
                .copied()
                .filter(|&b| rank[b as usize] < rank[i])
                .collect();
            e.sort_unstable();
            e.dedup();
            e.truncate(MAX_NEIGHBOURS);
            vertex_earlier.extend_from_slice(&e);
            vertex_start.push(vertex_earlier.len() as u32);
        }
        let per_plane = vertex_earlier.len() as u32;
        let plane = |c: usize, i: u32| (c * v) as u32 + i;
        let mut start = Vec::with_capacity(3 * v + 1);
        for c in 0..3u32 {
            start.extend(vertex_start[..v].iter().map(|s| s + c * per_plane));
        }
        start.push(3 * per_plane);
        Traversal {
            order: (0..3)
                .flat_map(|c| order.iter().map(move |&i| plane(c, i)))
                .collect(),
            start,
            earlier: (0..3)
                .flat_map(|c| vertex_earlier.iter().map(move |&i| plane(c, i)))
                .collect(),
        }
    }

    /// Number of values.
    pub fn len(&self) -> usize {
        self.order.len()
    }

    /// Value indices in coding order.
    pub fn order(&self) -> &[u32] {
        &self.order
    }

    /// The values `j` is predicted from; each comes before `j` in the order.
    #[inline]
    pub fn earlier(&self, j: usize) -> &[u32] {
        &self.earlier[self.start[j] as usize..self.start[j + 1] as usize]
    }

    /// The spatial prediction of value `j` from one frame's `values`: the
    /// rounded mean of its earlier neighbours' values, or 0 if it has none.
    #[inline]
    pub fn predict(&self, j: usize, values: &[i64]) -> i64 {
        self.predict_from(j, |p| values[p])
    }

    /// [`Traversal::predict`] with value `p` of the frame read by `value`
    /// (the decoder keeps a block's values value by value).
    #[inline]
    pub fn predict_from(&self, j: usize, value: impl Fn(usize) -> i64) -> i64 {
        let earlier = self.earlier(j);
        match earlier.len() {
            0 => 0,
            1 => value(earlier[0] as usize),
            m => {
                let sum: i64 = earlier.iter().map(|&p| value(p as usize)).sum();
                let twice = 2 * sum + m as i64;
                // The usual counts spelled out, so that each division is by
                // a constant (a multiply and a shift, not a hardware
                // divide); the same result either way.
                match m {
                    2 => twice.div_euclid(4),
                    3 => twice.div_euclid(6),
                    4 => twice.div_euclid(8),
                    5 => twice.div_euclid(10),
                    6 => twice.div_euclid(12),
                    _ => twice.div_euclid(2 * m as i64),
                }
            }
        }
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    /// A 2 × 4 strip of triangles.
    pub fn strip() -> Topology {
        // 0-1-2-3 along the top, 4-5-6-7 below.
        let mut t = Vec::new();
        for a in 0..3u32 {
            t.push([a, a + 4, a + 1]);
            t.push([a + 1, a + 4, a + 5]);
        }
        Topology::new(8, t).unwrap()
    }

    #[test]
    fn traversal_predicts_from_earlier_neighbours_in_the_same_plane() {
        let traversal = Traversal::for_mesh(&strip());
        assert_eq!(traversal.len(), 24);
        let mut seen = [false; 24];
        for &j in traversal.order() {
            for &p in traversal.earlier(j as usize) {
                assert!(seen[p as usize], "{j} before its neighbour {p}");
                assert_eq!(p / 8, j / 8, "neighbour in another plane");
            }
            seen[j as usize] = true;
        }
        assert!(seen.iter().all(|s| *s));
        assert!(traversal.earlier(0).is_empty());
        assert!(traversal.earlier(8).is_empty());
        // BFS order 0, 4, 1, 5, 2, ...: vertex 5 touches 1 and 4 (earlier)
        // and 2 and 6 (later).
        assert_eq!(traversal.order()[..5], [0, 4, 1, 5, 2]);
        assert_eq!(traversal.earlier(5), [1, 4]);
        assert_eq!(traversal.earlier(13), [9, 12]);
        let values: Vec<i64> = (0..24).map(|j| j * 10 + 1).collect();
        assert_eq!(traversal.predict(5, &values), 26); // (11 + 41) / 2
        assert_eq!(traversal.predict(2, &values), 31); // (11 + 51) / 2
        assert_eq!(traversal.predict(0, &values), 0);
    }
}
