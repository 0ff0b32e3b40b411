//! The correspondence map `M` of §3.3: for every avatar vertex of the face
//! region, the point of the registered ARKit mask it corresponds to, as a
//! mask triangle and barycentric coordinates. Applied to a field on the
//! mask (a blendshape's displacements), it gives that field on the avatar's
//! face: `(M B_j)_v = Σ_k λ_vk B_j[t_vk]`.
//!
//! The face region is the part of the avatar that the registered mask
//! covers: a vertex belongs to it when its closest compatible point on the
//! mask (on a triangle facing within 60° of the vertex's normal, as the
//! registration pairs them) is within the tolerance and does not lie on
//! the mask's boundary (the outline, the eye holes, the mouth slit), where
//! a closest point only means that the vertex lies beyond the mask.
//!
//! Nor on a triangle at the rim of a hole: at the mouth's slit and the
//! lids' margins the mask's rim triangles lie against the other side's
//! (the upper lip's against the lower's), and an avatar vertex there takes
//! a mix of both sides' motion that tore the lips of ICT-FaceKit in
//! `jawOpen`. The region stops one mask triangle (1–2 mm) short of the
//! holes' rims (the outline has no other side and keeps its triangles),
//! and step 2 of the transfer carries the avatar's own rig across
//! the band ([`crate::avatar::partial_transfer::adjacent_step`]). The
//! normals keep the lining of the lips, the inside of the nostrils and
//! of the lids out of the region: they face away from the mask's skin,
//! and a lining vertex of the upper lip would otherwise take the lower
//! lip's motion, which lies as near at the mouth's slit.

use super::nonrigid::MIN_NORMAL_DOT;
use crate::geometry::closest_point::TriangleGrid;
use glam::DVec3;
use serde::{Deserialize, Serialize};
use std::collections::{HashMap, HashSet};

/// One avatar vertex of the face region and its point on the mask.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct FaceVertex {
    /// The avatar vertex (index into `Avatar::positions`).
    pub vertex: u32,
    /// The mask triangle its point lies on.
    pub triangle: u32,
    /// The point's barycentric coordinates in that triangle.
    pub barycentric: [f64; 3],
}

/// `M`: the face region's vertices and their points on the mask.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CorrespondenceMap {
    /// The mask's triangles (the map's barycentrics refer to them).
    pub mask_triangles: Vec<[u32; 3]>,
    /// The face region, in increasing vertex order.
    pub face: Vec<FaceVertex>,
}

impl CorrespondenceMap {
    /// `M f`: the mask field `field` (one value per mask vertex) at each
    /// face vertex, in the order of [`CorrespondenceMap::face`]. Entries
    /// whose triangle is out of range of the mask give zero.
    pub fn apply(&self, field: &[DVec3]) -> Vec<DVec3> {
        self.face
            .iter()
            .map(|f| {
                let Some(t) = self.mask_triangles.get(f.triangle as usize) else {
                    return DVec3::ZERO;
                };
                t.iter()
                    .zip(f.barycentric)
                    .map(|(&i, b)| field.get(i as usize).copied().unwrap_or(DVec3::ZERO) * b)
                    .sum()
            })
            .collect()
    }
}

/// Builds `M` for the avatar vertices `candidates` (index, position,
/// normal) against the registered mask `mask` (positions, triangles): a
/// vertex is in the face region when its closest compatible mask point is
/// within `tolerance` and not on the mask's boundary (module docs). A
/// vertex without a normal (no triangle) takes the plain closest point.
pub fn correspondence_map(
    candidates: impl Iterator<Item = (usize, DVec3, DVec3)>,
    mask: &[DVec3],
    triangles: &[[u32; 3]],
    tolerance: f64,
) -> CorrespondenceMap {
    let grid = TriangleGrid::new(mask, triangles);
    let boundary = boundary_edges(triangles);
    let on_outline: HashSet<u32> = boundary.iter().flat_map(|(a, b)| [*a, *b]).collect();
    let rims = hole_rims(mask, &boundary);
    let face = candidates
        .filter_map(|(v, p, normal)| {
            let c = if normal == DVec3::ZERO {
                grid.closest_within(p, tolerance)?
            } else {
                grid.closest_facing(p, normal, MIN_NORMAL_DOT, tolerance)?
            };
            let t = grid.triangles()[c.triangle];
            let b = c.barycentric;
            // On a triangle at a hole's rim: the mask's slit and lid
            // margins carry both sides' motion there, so the region stops
            // one mask triangle short of them (module docs).
            if t.iter().any(|v| rims.contains(v)) {
                return None;
            }
            // On the outline itself, the closest point only means that the
            // vertex lies beyond the mask.
            if on_boundary(t, b, &boundary, &on_outline) {
                return None;
            }
            Some(FaceVertex {
                vertex: v as u32,
                triangle: c.triangle as u32,
                barycentric: b,
            })
        })
        .collect();
    CorrespondenceMap {
        mask_triangles: grid.triangles().to_vec(),
        face,
    }
}

/// Whether barycentric point `b` of triangle `t` lies on a vertex or an
/// edge of the mask's `boundary` (edges, and their `vertices`).
fn on_boundary(
    t: [u32; 3],
    b: [f64; 3],
    boundary: &HashSet<(u32, u32)>,
    vertices: &HashSet<u32>,
) -> bool {
    const ON: f64 = 1e-9;
    (0..3).any(|k| {
        let (i, j) = (t[(k + 1) % 3], t[(k + 2) % 3]);
        (b[k] >= 1.0 - ON && vertices.contains(&t[k]))
            || (b[k] <= ON && boundary.contains(&(i.min(j), i.max(j))))
    })
}

/// The vertices on the rims of the mask's holes (the eyes, the mouth): the
/// boundary's connected pieces but the one of the largest extent, the
/// outline.
pub fn hole_rims(mask: &[DVec3], boundary: &HashSet<(u32, u32)>) -> HashSet<u32> {
    let mut next: HashMap<u32, Vec<u32>> = HashMap::new();
    for &(a, b) in boundary {
        next.entry(a).or_default().push(b);
        next.entry(b).or_default().push(a);
    }
    let mut seen: HashSet<u32> = HashSet::new();
    let mut pieces: Vec<Vec<u32>> = Vec::new();
    for &start in next.keys() {
        if !seen.insert(start) {
            continue;
        }
        let mut piece = vec![start];
        let mut k = 0;
        while k < piece.len() {
            for &n in &next[&piece[k]] {
                if seen.insert(n) {
                    piece.push(n);
                }
            }
            k += 1;
        }
        pieces.push(piece);
    }
    let extent = |piece: &[u32]| {
        let at = |v: u32| mask.get(v as usize).copied().unwrap_or_default();
        let (lo, hi) = piece.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), &v| (lo.min(at(v)), hi.max(at(v))),
        );
        (hi - lo).length()
    };
    pieces.sort_by(|a, b| extent(a).total_cmp(&extent(b)));
    pieces.pop();
    pieces.into_iter().flatten().collect()
}

/// The edges used by exactly one triangle, `(min, max)`.
pub fn boundary_edges(triangles: &[[u32; 3]]) -> HashSet<(u32, u32)> {
    let mut count: HashMap<(u32, u32), usize> = HashMap::new();
    for t in triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            *count.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    count
        .into_iter()
        .filter(|(_, c)| *c == 1)
        .map(|(e, _)| e)
        .collect()
}
