//! Which lip a point of the mask lies on, so that an avatar vertex of one
//! lip never takes the other lip's motion.
//!
//! The mask's mouth is a slit: a boundary loop whose two chains between
//! the corners (the loop's two vertices farthest apart) are the upper and
//! the lower lip's edges, lying against each other. Each chain's inner
//! vertices are that lip's (bit `1` or `2`), the corners both lips'. A
//! mask vertex within [`LIP_RINGS`] rings of the slit takes the lip whose
//! chain is fewer rings away (both at a tie: beside the corners); a
//! triangle lies on the lips of its vertices.
//!
//! [`super::correspondence`] takes a triangle at the slit for an avatar
//! vertex only when the vertex's own neighbours in the avatar's mesh lie
//! on that lip: the lips' slit triangles lie against each other, so the
//! plain closest point can be the other lip's, while the avatar's surface
//! says which lip a vertex belongs to.

use super::mask_holes::mouth_rim;
use crate::geometry::mesh_boundary::boundary_edges;
use glam::DVec3;
use std::collections::{BTreeSet, HashMap, HashSet};

/// How many rings of mask vertices around the slit carry a lip: the
/// vermilion's height (about 8–10 mm) in the mask's 2–3 mm rings.
pub const LIP_RINGS: usize = 3;

/// The lips of a mask, as bit sets: `1` the first chain, `2` the second.
pub struct LipSides {
    /// For each slit vertex, the chain bits it belongs to (both for a
    /// corner).
    on_slit: HashMap<u32, u8>,
    /// For each mask vertex within [`LIP_RINGS`] of the slit, its lips.
    label: HashMap<u32, u8>,
}

impl LipSides {
    /// The lips of the mask `positions`, `triangles`: its slit is the
    /// boundary loop of its holes with the largest extent
    /// ([`mouth_rim`]).
    pub fn of_mask(positions: &[DVec3], triangles: &[[u32; 3]]) -> LipSides {
        let boundary = boundary_edges(triangles);
        let slit = mouth_rim(positions, &boundary);
        LipSides::new(positions, triangles, &boundary, &slit)
    }

    /// The lips of the mask `positions`, `triangles`, whose mouth's slit is
    /// the boundary loop through `slit` (its vertices, any order) made of
    /// `boundary` edges.
    pub fn new(
        positions: &[DVec3],
        triangles: &[[u32; 3]],
        boundary: &HashSet<(u32, u32)>,
        slit: &BTreeSet<u32>,
    ) -> LipSides {
        let on_slit = chains(positions, boundary, slit);
        let mut neighbours: HashMap<u32, Vec<u32>> = HashMap::new();
        for t in triangles {
            for k in 0..3 {
                neighbours.entry(t[k]).or_default().push(t[(k + 1) % 3]);
                neighbours.entry(t[(k + 1) % 3]).or_default().push(t[k]);
            }
        }
        // Rings out from each chain's inner vertices, level by level; a
        // vertex reached by both chains at the same level takes both.
        let mut label: HashMap<u32, u8> = on_slit.clone();
        let mut front: Vec<u32> = on_slit.keys().copied().collect();
        for _ in 0..LIP_RINGS {
            let mut reached: HashMap<u32, u8> = HashMap::new();
            for v in &front {
                let bits = label[v];
                for n in neighbours.get(v).into_iter().flatten() {
                    if !label.contains_key(n) {
                        *reached.entry(*n).or_default() |= bits;
                    }
                }
            }
            front = reached.keys().copied().collect();
            label.extend(reached);
        }
        LipSides { on_slit, label }
    }

    /// The lip (`1` or `2`) of a triangle touching the slit only at inner
    /// vertices of one chain; `None` for any other triangle.
    pub fn slit_triangle(&self, t: [u32; 3]) -> Option<u8> {
        let bits = t
            .iter()
            .filter_map(|v| self.on_slit.get(v))
            .fold(0u8, |acc, b| acc | b);
        (bits == 1 || bits == 2).then_some(bits)
    }

    /// The lips a mask triangle lies on (bits; 0 away from the mouth).
    pub fn lips_of(&self, t: [u32; 3]) -> u8 {
        t.iter()
            .filter_map(|v| self.label.get(v))
            .fold(0u8, |acc, b| acc | b)
    }

    /// The lips of a mask vertex (bits; 0 farther than [`LIP_RINGS`] from
    /// the slit).
    pub fn lips_of_vertex(&self, v: u32) -> u8 {
        self.label.get(&v).copied().unwrap_or(0)
    }

    /// The lip (`1` or `2`) of a slit vertex between the corners; `None`
    /// for a corner or a vertex off the slit.
    pub fn lip_of_vertex(&self, v: u32) -> Option<u8> {
        self.on_slit.get(&v).copied().filter(|b| *b != 3)
    }
}

/// The chain bits of each slit vertex: the loop split at its two vertices
/// farthest apart (the corners, both bits).
fn chains(
    positions: &[DVec3],
    boundary: &HashSet<(u32, u32)>,
    slit: &BTreeSet<u32>,
) -> HashMap<u32, u8> {
    let at = |v: u32| positions.get(v as usize).copied().unwrap_or_default();
    let mut next: HashMap<u32, Vec<u32>> = HashMap::new();
    for &(a, b) in boundary {
        if slit.contains(&a) && slit.contains(&b) {
            next.entry(a).or_default().push(b);
            next.entry(b).or_default().push(a);
        }
    }
    let mut sorted: Vec<u32> = slit.iter().copied().collect();
    sorted.sort_unstable();
    let mut corners = (0, 0);
    let mut widest = -1.0;
    for (k, &a) in sorted.iter().enumerate() {
        for &b in &sorted[k + 1..] {
            let d = at(a).distance_squared(at(b));
            if d > widest {
                widest = d;
                corners = (a, b);
            }
        }
    }
    let mut bits: HashMap<u32, u8> = HashMap::from([(corners.0, 3), (corners.1, 3)]);
    // Walk from the first corner along each of its two edges to the other,
    // the edge to the lower-numbered vertex first: which chain is `1` is
    // then the same every time the lips of one mask are found.
    let mut starts = next.get(&corners.0).cloned().unwrap_or_default();
    starts.sort_unstable();
    for (chain, &first) in starts.iter().take(2).enumerate() {
        let (mut previous, mut here) = (corners.0, first);
        while here != corners.1 && !bits.contains_key(&here) {
            bits.insert(here, 1 << chain);
            let Some(&step) = next
                .get(&here)
                .and_then(|n| n.iter().find(|&&n| n != previous))
            else {
                break;
            };
            (previous, here) = (here, step);
        }
    }
    bits
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A slit between two strips of triangles: upper vertices 0..=4 on
    /// y = 0 (corners 0 and 4 shared), lower lip edge 5..=7 under them at
    /// the same height, and rows above (8..=12) and below (13..=17).
    fn slit() -> (Vec<DVec3>, Vec<[u32; 3]>) {
        let mut p: Vec<DVec3> = (0..5).map(|i| DVec3::new(i as f64, 0.0, 0.0)).collect();
        p.extend((1..4).map(|i| DVec3::new(i as f64, -0.001, 0.0)));
        p.extend((0..5).map(|i| DVec3::new(i as f64, 1.0, 0.0)));
        p.extend((0..5).map(|i| DVec3::new(i as f64, -1.0, 0.0)));
        let upper = [0, 1, 2, 3, 4];
        let lower = [0, 5, 6, 7, 4];
        let mut t = Vec::new();
        for k in 0..4 {
            let (a, b) = (upper[k], upper[k + 1]);
            let (c, d) = (8 + k as u32, 9 + k as u32);
            t.push([a, b, d]);
            t.push([a, d, c]);
            let (a, b) = (lower[k], lower[k + 1]);
            let (c, d) = (13 + k as u32, 14 + k as u32);
            t.push([a, c, d]);
            t.push([a, d, b]);
        }
        (p, t)
    }

    #[test]
    fn a_slit_triangle_and_the_rows_beyond_it_are_on_their_own_lip() {
        let (p, t) = slit();
        // The fixture's slit touches its outline at the corners, so it is
        // named rather than found.
        let slit: BTreeSet<u32> = [0, 1, 2, 3, 4, 5, 6, 7].into();
        let sides = LipSides::new(&p, &t, &boundary_edges(&t), &slit);
        let (upper, lower) = ([1, 2, 10], [5, 14, 15]);
        let (u, l) = (sides.slit_triangle(upper), sides.slit_triangle(lower));
        assert!(u.is_some() && l.is_some() && u != l);
        // A corner's triangle belongs to neither lip alone.
        assert_eq!(sides.slit_triangle([0, 1, 9]), None);
        // The rows beyond each lip's edge lie on that lip only.
        assert_eq!(Some(sides.lips_of([10, 11, 2])), u);
        assert_eq!(Some(sides.lips_of([15, 16, 6])), l);
        // Beside a corner, both.
        assert_eq!(sides.lips_of([0, 8, 13]), 3);
        assert_eq!(sides.lip_of_vertex(0), None);
        assert_eq!(sides.lip_of_vertex(2), u);
    }
}
