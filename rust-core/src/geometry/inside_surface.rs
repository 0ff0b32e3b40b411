//! Whether a point lies inside a surface kept for closest-point queries,
//! and how deep: on the inner side of the closest triangle (its normal
//! facing outwards), and within the surface by its generalized winding
//! number ([`super::winding_number`]), which tells a point beside an open
//! shell's rim from one inside it. The winding number sums over every
//! triangle, so it is summed only for a surface that has a boundary
//! ([`is_open`]): on a closed one the closest triangle's side decides
//! alone, as the two agree there.

use super::closest_point::TriangleTree;
use super::mesh_boundary::boundary_edges;
use super::winding_number::winding_number;
use glam::DVec3;

/// Whether `triangles` leave an edge with only one triangle on it.
pub fn is_open(triangles: &[[u32; 3]]) -> bool {
    !boundary_edges(triangles).is_empty()
}

/// How far `p` lies inside the surface `tree` (zero outside, [`inside`]):
/// along the normal of the closest point's triangle.
pub fn depth(tree: &TriangleTree, p: DVec3, open: bool) -> f64 {
    inside(tree, p, open).map_or(0.0, |(c, normal)| (c - p).dot(normal))
}

/// The closest point of `tree` to `p` and its triangle's normal, if `p`
/// is on the inner side of it and, where the surface is `open`
/// ([`is_open`]), the surface winds round it (generalized
/// winding number at least ½, [`super::winding_number`]): on a closed
/// surface the two agree; on a shell open at the back (MakeHuman's
/// eyeballs) a point beside the opening may lie on the inner side of the
/// rim's closest triangle without being in the shell at all.
pub fn inside(tree: &TriangleTree, p: DVec3, open: bool) -> Option<(DVec3, DVec3)> {
    let c = tree.closest(p)?;
    let normal = tree.triangle_normal(c.triangle);
    ((p - c.point).dot(normal) < 0.0 && (!open || winding_number(tree.corners(), p) >= 0.5))
        .then_some((c.point, normal))
}
