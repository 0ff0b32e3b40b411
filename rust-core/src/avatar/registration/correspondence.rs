//! The correspondence map `M` of §3.3: for every avatar vertex of the face
//! region, the point of the registered ARKit mask it corresponds to, as a
//! mask triangle and barycentric coordinates. Applied to a field on the
//! mask (a blendshape's displacements), it gives that field on the avatar's
//! face: `(M B_j)_v = Σ_k λ_vk B_j[t_vk]`.
//!
//! The face region is the part of the avatar that the registered mask
//! covers: a vertex belongs to it when its closest point on the mask is
//! within the tolerance and does not lie on the mask's boundary (the
//! outline, the eye holes, the mouth slit), where a closest point only
//! means that the vertex lies beyond the mask.

use crate::geometry::closest_point::TriangleGrid;
use glam::DVec3;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;

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

/// Builds `M` for the avatar vertices `candidates` (index, position) against
/// the registered mask `mask` (positions, triangles): a vertex is in the
/// face region when its closest mask point is within `tolerance` and not on
/// the mask's boundary (module docs).
pub fn correspondence_map(
    candidates: impl Iterator<Item = (usize, DVec3)>,
    mask: &[DVec3],
    triangles: &[[u32; 3]],
    tolerance: f64,
) -> CorrespondenceMap {
    let grid = TriangleGrid::new(mask, triangles);
    let boundary = boundary_edges(triangles);
    let boundary_vertices: std::collections::HashSet<u32> =
        boundary.iter().flat_map(|(a, b)| [*a, *b]).collect();
    let face = candidates
        .filter_map(|(v, p)| {
            let c = grid.closest_within(p, tolerance)?;
            let t = grid.triangles()[c.triangle];
            let b = c.barycentric;
            const ON: f64 = 1e-9;
            // On a vertex of the boundary, or on a boundary edge.
            for k in 0..3 {
                if b[k] >= 1.0 - ON && boundary_vertices.contains(&t[k]) {
                    return None;
                }
                let (i, j) = (t[(k + 1) % 3], t[(k + 2) % 3]);
                if b[k] <= ON && boundary.contains(&(i.min(j), i.max(j))) {
                    return None;
                }
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

/// The edges used by exactly one triangle, `(min, max)`.
pub fn boundary_edges(triangles: &[[u32; 3]]) -> std::collections::HashSet<(u32, u32)> {
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
