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
//! At the mouth's slit and the lids' margins the mask's rim triangles lie
//! against the other side's (the upper lip's against the lower's), and an
//! avatar vertex there can find the other side's triangle closest: taking
//! its motion tore the lips of ICT-FaceKit in `jawOpen`. So at the lids
//! the region stops one mask triangle (1–2 mm) short of the margins, and
//! step 2 of the transfer carries the avatar's own rig across the band
//! ([`crate::avatar::partial_transfer::adjacent_step`]; the lids' contacts
//! close it). At the mouth each lip grows from the region to the slit, a
//! ring of the avatar's mesh at a time: a vertex whose taken neighbours
//! lie on one lip only takes its closest point among that lip's triangles
//! ([`super::lip_sides`]), so the lips' edges move as the person's do.
//! Beside the corners, where the lips meet, the band remains, and so it
//! does wherever a vertex's own closest point lies on the other lip than
//! its neighbours': there the registered mask's slit and the avatar's
//! disagree (a face of other proportions), and taking either lip tore the
//! lips into a saw-tooth in jawOpen. The
//! normals keep the lining of the lips, the inside of the nostrils and
//! of the lids out of the region: they face away from the mask's skin,
//! and a lining vertex of the upper lip would otherwise take the lower
//! lip's motion, which lies as near at the mouth's slit.

use super::lip_sides::LipSides;
use super::mask_holes::{hole_rims, mouth_rim};
use super::nonrigid::MIN_NORMAL_DOT;
use crate::geometry::closest_point::TriangleTree;
use crate::geometry::mesh_boundary::{boundary_edges, on_boundary};
use crate::geometry::one_ring::one_rings;
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
/// `avatar_triangles` (the face parts') tell which lip a vertex at the
/// mouth's slit belongs to.
pub fn correspondence_map(
    candidates: impl Iterator<Item = (usize, DVec3, DVec3)>,
    mask: &[DVec3],
    triangles: &[[u32; 3]],
    tolerance: f64,
    avatar_triangles: &[[u32; 3]],
) -> CorrespondenceMap {
    let grid = TriangleTree::new(mask, triangles);
    let boundary = boundary_edges(triangles);
    let on_outline: HashSet<u32> = boundary.iter().flat_map(|(a, b)| [*a, *b]).collect();
    let rims = hole_rims(mask, &boundary);
    let mouth = mouth_rim(mask, &boundary);
    let lips = LipSides::new(mask, grid.triangles(), &boundary, &mouth);
    // The mouth's rim edges are no edge of the mask's surface to a vertex
    // lying on them: they are the lips' own edges.
    let beyond: HashSet<(u32, u32)> = boundary
        .iter()
        .filter(|(a, b)| !(mouth.contains(a) && mouth.contains(b)))
        .copied()
        .collect();
    let mut face = Vec::new();
    // Vertices whose closest point lies on a lip's triangle at the slit:
    // taken once their neighbours tell their lip.
    let mut at_slit: Vec<(usize, DVec3, DVec3, u8)> = Vec::new();
    for (v, p, normal) in candidates {
        let closest = if normal == DVec3::ZERO {
            grid.closest_within(p, tolerance)
        } else {
            grid.closest_facing(p, normal, MIN_NORMAL_DOT, tolerance)
        };
        let Some(c) = closest else { continue };
        let t = grid.triangles()[c.triangle];
        let b = c.barycentric;
        // On the outline itself, the closest point only means that the
        // vertex lies beyond the mask.
        if on_boundary(t, b, &beyond, &on_outline) {
            continue;
        }
        // On a triangle at a hole's rim: the region stops one mask
        // triangle short of the lids' margins (module docs); at the
        // mouth's slit it takes a triangle of the vertex's own lip.
        if t.iter().any(|v| rims.contains(v)) {
            if let Some(lip) = lips.slit_triangle(t) {
                at_slit.push((v, p, normal, lip));
            }
            continue;
        }
        face.push(FaceVertex {
            vertex: v as u32,
            triangle: c.triangle as u32,
            barycentric: b,
        });
    }
    // Each lip grows from the region inwards to the slit, a ring at a
    // time: a vertex whose taken neighbours lie on one lip only (beside
    // the corners they lie on both) takes its closest point among that
    // lip's triangles and those off the rims.
    let mut lip_of: HashMap<u32, u8> = face
        .iter()
        .map(|f| {
            (
                f.vertex,
                lips.lips_of(grid.triangles()[f.triangle as usize]),
            )
        })
        .collect();
    let neighbours = one_rings(usize::MAX, avatar_triangles);
    let on_lip = |v: usize, p: DVec3, normal: DVec3, lip: u8| {
        let t = grid.closest_where(p, tolerance, |k| {
            let t = grid.triangles()[k];
            let compatible =
                normal == DVec3::ZERO || grid.triangle_normal(k).dot(normal) >= MIN_NORMAL_DOT;
            let own = lips.slit_triangle(t) == Some(lip) || !t.iter().any(|v| rims.contains(v));
            compatible && own
        })?;
        let tri = grid.triangles()[t.triangle];
        (!on_boundary(tri, t.barycentric, &beyond, &on_outline)).then_some(FaceVertex {
            vertex: v as u32,
            triangle: t.triangle as u32,
            barycentric: t.barycentric,
        })
    };
    loop {
        let mut taken = Vec::new();
        at_slit.retain(|&(v, p, normal, closest_lip)| {
            let lip = neighbours
                .get(&(v as u32))
                .into_iter()
                .flatten()
                .filter_map(|n| lip_of.get(n))
                .fold(0u8, |acc, b| acc | b);
            if lip != 1 && lip != 2 {
                return true;
            }
            // A vertex whose own closest point lies on the other lip is
            // where the registered mask's slit and the avatar's disagree
            // (a face of other proportions): it stays in the band, for
            // step 2, rather than take either lip's motion.
            if lip != closest_lip {
                return false;
            }
            if let Some(f) = on_lip(v, p, normal, lip) {
                taken.push((f, lip));
            }
            false
        });
        if taken.is_empty() {
            break;
        }
        for (f, lip) in taken {
            lip_of.insert(f.vertex, lip);
            face.push(f);
        }
    }
    face.sort_by_key(|f| f.vertex);
    CorrespondenceMap {
        mask_triangles: grid.triangles().to_vec(),
        face,
    }
}
