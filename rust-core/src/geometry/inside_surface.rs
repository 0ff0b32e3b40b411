//! Whether a point lies inside a surface kept for closest-point queries,
//! and how deep: on the inner side of the closest triangle (its normal
//! facing outwards), and within the surface by its generalized winding
//! number ([`super::winding_number`]), which tells a point beside an open
//! shell's rim from one inside it.

use super::closest_point::TriangleTree;
use super::winding_number::winding_number;
use glam::DVec3;

/// How far `p` lies inside the surface `tree` (zero outside, [`inside`]):
/// along the normal of the closest point's triangle.
pub fn depth(tree: &TriangleTree, p: DVec3) -> f64 {
    inside(tree, p).map_or(0.0, |(c, normal)| (c - p).dot(normal))
}

/// The closest point of `tree` to `p` and its triangle's normal, if `p`
/// is on the inner side of it and the surface winds round it (generalized
/// winding number at least ½, [`super::winding_number`]): on a closed
/// surface the two agree; on a shell open at the back (MakeHuman's
/// eyeballs) a point beside the opening may lie on the inner side of the
/// rim's closest triangle without being in the shell at all.
pub fn inside(tree: &TriangleTree, p: DVec3) -> Option<(DVec3, DVec3)> {
    let c = tree.closest(p)?;
    let normal = tree.triangle_normal(c.triangle);
    ((p - c.point).dot(normal) < 0.0 && winding_number(tree.corners(), p) >= 0.5)
        .then_some((c.point, normal))
}
