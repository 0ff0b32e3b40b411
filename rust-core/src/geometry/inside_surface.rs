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

/// `triangles` over `positions`, turned to face outwards: all reversed
/// where the volume they enclose about the centroid of their corners,
/// `⅙ Σ (a − c) · ((b − c) × (d − c))`, is negative (a shell wound inside
/// out). Every rule here reads the inner side from a triangle's normal,
/// and an eyeball wound inside out (the low-poly avatar's generated ones
/// are) put lids 20 mm from its centre 8 mm "inside" it. On a shell open
/// at the back the sum is still dominated by the front's winding.
pub fn facing_outwards(positions: &[DVec3], triangles: &[[u32; 3]]) -> Vec<[u32; 3]> {
    let corners = || {
        triangles
            .iter()
            .flatten()
            .filter_map(|&v| positions.get(v as usize))
    };
    let count = corners().count().max(1) as f64;
    let c = corners().sum::<DVec3>() / count;
    let volume: f64 = triangles
        .iter()
        .filter_map(|t| {
            let [a, b, d] = [t[0], t[1], t[2]].map(|v| positions.get(v as usize).copied());
            Some((a? - c).dot((b? - c).cross(d? - c)))
        })
        .sum();
    if volume < 0.0 {
        triangles.iter().map(|&[a, b, d]| [a, d, b]).collect()
    } else {
        triangles.to_vec()
    }
}

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

#[cfg(test)]
mod tests {
    use super::*;

    /// A tetrahedron about the origin, wound outwards.
    fn tetrahedron() -> (Vec<DVec3>, Vec<[u32; 3]>) {
        let p = vec![
            DVec3::new(1.0, 1.0, 1.0),
            DVec3::new(1.0, -1.0, -1.0),
            DVec3::new(-1.0, 1.0, -1.0),
            DVec3::new(-1.0, -1.0, 1.0),
        ];
        (p, vec![[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]])
    }

    #[test]
    fn a_shell_wound_inside_out_is_turned_and_its_inside_found() {
        let (p, outwards) = tetrahedron();
        assert_eq!(facing_outwards(&p, &outwards), outwards);
        let inside_out: Vec<[u32; 3]> = outwards.iter().map(|&[a, b, c]| [a, c, b]).collect();
        let turned = facing_outwards(&p, &inside_out);
        assert_eq!(turned, outwards);
        // Read from its own normals, the inside-out shell has its inside
        // outside: the centre is not in it, a point beyond a face is.
        let beyond = DVec3::new(-1.0, -1.0, -1.0) * 0.6;
        let wrong = TriangleTree::new(&p, &inside_out);
        assert_eq!(depth(&wrong, DVec3::ZERO, false), 0.0);
        assert!(depth(&wrong, beyond, false) > 0.0);
        let right = TriangleTree::new(&p, &turned);
        assert!(depth(&right, DVec3::ZERO, false) > 0.0);
        assert_eq!(depth(&right, beyond, false), 0.0);
    }
}
