//! Eyelid repair (§3.3, after Achenbach et al. 2015): the mask has no
//! eyeballs, so a person's lid may pass through the avatar's eyeball in a
//! transferred shape. Every skin vertex that ends inside an eyeball is
//! moved to the eyeball's surface, [`LID_OFFSET_MM`] outside it along the
//! surface normal.
//!
//! Inside is judged against the eyeball's own triangles as displaced by the
//! same shape (an eyeLook turns the eyeball too): with `c` the closest
//! eyeball point to skin vertex `p` and `n` the outward normal of the
//! triangle it lies on, `p` is inside when `(p − c) · n < 0` and the
//! eyeball winds round `p` ([`crate::geometry::inside_surface`]). Eyeball
//! parts face outwards (the default avatar's are tested so; MakeHuman's
//! shells are open at the back, which the winding number tells); only
//! skin vertices within the eyeball's radius plus [`NEAR_MM`] of its centre
//! at rest, and within its bounding sphere in the shape, are looked at (an
//! eyeball turns about its centre, so the sphere holds it in every shape),
//! and each may stay as deep inside as the avatar's own shape of the same
//! name keeps it (as it rests where the avatar has no such shape): a
//! vertex the avatar keeps inside an eyeball's shell (a lid margin under a
//! cornea shell, or a lid an eyeLook target leaves behind a turned
//! eyeball) is the rig's own, and one the own shape keeps out is put out,
//! however it rests.

use crate::geometry::closest_point::TriangleTree;
use crate::geometry::inside_surface::{depth, facing_outwards, inside, is_open};
use glam::DVec3;

/// How far outside the eyeball a repaired lid vertex is put (mm at the
/// mask's scale: the registration's scale turns it into avatar units).
pub const LID_OFFSET_MM: f64 = 0.2;

/// Skin vertices farther than this from the eyeball's sphere at rest (mm,
/// mask scale) are not looked at.
pub const NEAR_MM: f64 = 8.0;

/// One eyeball: its triangles (avatar vertex indices) and, at rest, its
/// centre and radius (largest distance of a vertex from the centre).
#[derive(Clone, Debug)]
pub struct Eyeball {
    /// Triangles, avatar vertex indices.
    pub triangles: Vec<[u32; 3]>,
    /// Centre at rest (mean of its vertices).
    pub centre: DVec3,
    /// Largest distance of a vertex from the centre at rest.
    pub radius: f64,
    /// The vertices of its triangles that lie within the rest positions
    /// it was made over, increasing.
    pub vertices: Vec<u32>,
    /// Those of its triangles, in order, over `vertices` (indices into
    /// it; [`TriangleTree::triangles`]), at its rest positions: moved to a
    /// shape's ([`TriangleTree::moved_to`]), it finds the eyeball's
    /// closest points in that shape.
    pub tree: TriangleTree,
    /// Whether its triangles leave a boundary (a shell open at the back;
    /// [`crate::geometry::inside_surface::is_open`]).
    pub open: bool,
}

impl Eyeball {
    /// The eyeball made of `triangles` over `rest` (avatar positions).
    pub fn new(rest: &[DVec3], triangles: Vec<[u32; 3]>) -> Eyeball {
        let mut all: Vec<u32> = triangles.iter().flatten().copied().collect();
        all.sort_unstable();
        all.dedup();
        let n = all.len().max(1) as f64;
        let centre = all
            .iter()
            .filter_map(|&v| rest.get(v as usize))
            .sum::<DVec3>()
            / n;
        let radius = all
            .iter()
            .filter_map(|&v| rest.get(v as usize))
            .map(|p| (*p - centre).length())
            .fold(0.0, f64::max);
        let within: Vec<[u32; 3]> = triangles
            .iter()
            .filter(|t| t.iter().all(|&v| (v as usize) < rest.len()))
            .copied()
            .collect();
        let mut vertices: Vec<u32> = within.iter().flatten().copied().collect();
        vertices.sort_unstable();
        vertices.dedup();
        let local: Vec<[u32; 3]> = within
            .iter()
            .map(|t| t.map(|v| vertices.binary_search(&v).unwrap_or(0) as u32))
            .collect();
        let at_rest: Vec<DVec3> = vertices.iter().map(|&v| rest[v as usize]).collect();
        // Its inner side is read from its normals: wound inside out, turned.
        let local = facing_outwards(&at_rest, &local);
        let tree = TriangleTree::new(&at_rest, &local);
        Eyeball {
            open: is_open(&local),
            triangles,
            centre,
            radius,
            vertices,
            tree,
        }
    }
}

/// Repairs one shape's `displacement` (all avatar vertices, `rest` their
/// positions; `own` the avatar's own shape of that name, empty if it has
/// none): every vertex of `skin` that ends inside an eyeball where `own`
/// keeps it outside is moved onto it, `offset` (avatar units) outside;
/// one that `own` keeps inside too, but ends deeper by more than `offset`,
/// is moved back to `own`'s depth (module docs). Returns how many were
/// moved.
pub fn repair_eyelids(
    rest: &[DVec3],
    own: &[DVec3],
    displacement: &mut [DVec3],
    skin: &[u32],
    eyeballs: &[Eyeball],
    offset: f64,
    near: f64,
) -> usize {
    // Every eyeball is judged on the shape as given: the changes are
    // worked out first, then made.
    let shape: &[DVec3] = displacement;
    let posed = |v: usize| rest[v] + shape.get(v).copied().unwrap_or(DVec3::ZERO);
    let own_posed = |v: usize| rest[v] + own.get(v).copied().unwrap_or(DVec3::ZERO);
    let mut changes: Vec<(usize, DVec3)> = Vec::new();
    for eyeball in eyeballs {
        let (vertices, tree) = (&eyeball.vertices, &eyeball.tree);
        // Where the shape leaves the eyeball and a vertex as the avatar's
        // own shape (or its rest) has them, the vertex is exactly as deep
        // as it may be: nothing to look at.
        let as_own = |v: usize| posed(v) == own_posed(v);
        let eyeball_as_own = vertices.iter().all(|&v| as_own(v as usize));
        // Outside the sphere round the eyeball (which turns about its
        // centre) nothing can be inside it.
        let looked_at: Vec<usize> = skin
            .iter()
            .map(|&v| v as usize)
            .filter(|&v| {
                v < rest.len()
                    && (rest[v] - eyeball.centre).length() <= eyeball.radius + near
                    && (posed(v) - eyeball.centre).length() <= eyeball.radius
                    && !(eyeball_as_own && as_own(v))
            })
            .collect();
        if looked_at.is_empty() {
            continue;
        }
        // The eyeball's own vertices, in the shape and as the avatar's own
        // shape (or its rest) has them.
        let on = |place: &dyn Fn(usize) -> DVec3| -> Vec<DVec3> {
            vertices.iter().map(|&v| place(v as usize)).collect()
        };
        let grid = tree.moved_to(&on(&posed));
        let own_tree;
        let allowed_by = match own.is_empty() {
            true => tree,
            false => {
                own_tree = tree.moved_to(&on(&own_posed));
                &own_tree
            }
        };
        for v in looked_at {
            let (p0, p) = (rest[v], posed(v));
            // How deep the avatar's own shape of this name keeps the
            // vertex (at rest where it has none): a lid margin tucked under
            // a rig's cornea shell, or left behind a turned eyeball, is the
            // rig's choice, not a lid passing through.
            let allowed = match own.is_empty() {
                true => depth(allowed_by, p0, eyeball.open),
                false => depth(allowed_by, own_posed(v), eyeball.open),
            };
            if let Some((point, normal)) = inside(&grid, p, eyeball.open) {
                let deeper = (point - p).dot(normal);
                if allowed == 0.0 {
                    changes.push((v, point + normal * offset - p0));
                } else if deeper > allowed + offset {
                    changes.push((v, point - normal * allowed - p0));
                }
            }
        }
    }
    for &(v, d) in &changes {
        displacement[v] = d;
    }
    changes.len()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube centred at the origin, faces outwards.
    fn cube() -> (Vec<DVec3>, Vec<[u32; 3]>) {
        let p: Vec<DVec3> = (0..8)
            .map(|i| DVec3::new((i & 1) as f64, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64) - 0.5)
            .collect();
        let quads = [
            [0, 2, 3, 1], // z = −½
            [4, 5, 7, 6], // z = +½
            [0, 1, 5, 4], // y = −½
            [2, 6, 7, 3], // y = +½
            [0, 4, 6, 2], // x = −½
            [1, 3, 7, 5], // x = +½
        ];
        let t = quads
            .iter()
            .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
            .collect();
        (p, t)
    }

    #[test]
    fn a_lid_inside_is_put_back_outside_and_one_outside_is_left() {
        let (mut rest, triangles) = cube();
        // Vertex 8 rests outside above the top face and is moved inside by
        // the shape; vertex 9 stays outside.
        rest.push(DVec3::new(0.1, 0.1, 0.7));
        rest.push(DVec3::new(0.0, 0.0, 0.9));
        let eyeball = Eyeball::new(&rest, triangles);
        // Vertices 8 and 9 as skin, 0.01 offset, 1 near.
        let repair = |rest: &[DVec3], own: &[DVec3], d: &mut [DVec3]| {
            repair_eyelids(
                rest,
                own,
                d,
                &[8, 9],
                std::slice::from_ref(&eyeball),
                0.01,
                1.0,
            )
        };
        let mut d = vec![DVec3::ZERO; rest.len()];
        d[8] = DVec3::new(0.0, 0.0, -0.4);
        let moved = repair(&rest, &[], &mut d);
        assert_eq!(moved, 1);
        let at = rest[8] + d[8];
        assert!((at - DVec3::new(0.1, 0.1, 0.51)).length() < 1e-12, "{at}");
        assert_eq!(d[9], DVec3::ZERO);
        // Where the avatar's own shape moves the vertex inside too (0.1
        // deep), that depth is the rig's choice: kept within it (and the
        // offset) it is left alone, deeper it goes back to it.
        let mut own = vec![DVec3::ZERO; rest.len()];
        own[8] = DVec3::new(0.0, 0.0, -0.3);
        let mut d = vec![DVec3::ZERO; rest.len()];
        d[8] = DVec3::new(0.0, 0.0, -0.305);
        let moved = repair(&rest, &own, &mut d);
        assert_eq!(moved, 0);
        assert_eq!(d[8], DVec3::new(0.0, 0.0, -0.305));
        d[8] = DVec3::new(0.0, 0.0, -0.4);
        let moved = repair(&rest, &own, &mut d);
        assert_eq!(moved, 1);
        assert!((rest[8] + d[8] - DVec3::new(0.1, 0.1, 0.4)).length() < 1e-12);
        // A vertex resting inside (a margin under a cornea shell) that the
        // own shape brings out is put out with it.
        let mut rest_in = rest.clone();
        rest_in[8] = DVec3::new(0.1, 0.1, 0.45);
        let mut own = vec![DVec3::ZERO; rest.len()];
        own[8] = DVec3::new(0.0, 0.0, 0.2);
        let mut d = vec![DVec3::ZERO; rest.len()];
        let moved = repair(&rest_in, &own, &mut d);
        assert_eq!(moved, 1);
        assert!((rest_in[8] + d[8] - DVec3::new(0.1, 0.1, 0.51)).length() < 1e-12);
        // A shape that is the avatar's own there, eyeball and lid alike,
        // keeps the lid as deep as its own does.
        let mut own = vec![DVec3::ZERO; rest.len()];
        own[8] = DVec3::new(0.0, 0.0, -0.4);
        let mut d = own.clone();
        assert_eq!(repair(&rest, &own, &mut d), 0);
        assert_eq!(d, own);
    }

    #[test]
    fn an_eyeballs_own_triangles_are_numbered_over_its_own_vertices() {
        let (rest, triangles) = cube();
        let shifted: Vec<[u32; 3]> = triangles.iter().map(|t| t.map(|v| v + 10)).collect();
        let mut padded = vec![DVec3::ZERO; 10];
        padded.extend(&rest);
        let eyeball = Eyeball::new(&padded, shifted.clone());
        assert_eq!(eyeball.vertices, (10..18).collect::<Vec<u32>>());
        assert_eq!(eyeball.tree.triangles(), &triangles[..]);
        // A triangle past the positions given is left out.
        assert_eq!(
            Eyeball::new(&padded[..17], shifted).tree.triangles().len(),
            6
        );
    }

    #[test]
    fn beside_an_open_shells_opening_is_not_inside() {
        // The cube without its back (z = −½), as an eyeball shell open
        // behind (MakeHuman's): a point behind the opening, beside the
        // rim, lies on the inner side of the rim's closest triangle but in
        // no eyeball; one just under the front face is inside.
        let (rest, triangles) = cube();
        let open: Vec<[u32; 3]> = triangles[2..].to_vec();
        let tree = TriangleTree::new(&rest, &open);
        let behind = DVec3::new(0.45, 0.0, -0.6);
        let c = tree.closest(behind).expect("a mesh");
        assert!((behind - c.point).dot(tree.triangle_normal(c.triangle)) < 0.0);
        assert!(is_open(&open));
        assert_eq!(inside(&tree, behind, true), None);
        assert_eq!(depth(&tree, behind, true), 0.0);
        let under_front = DVec3::new(0.1, 0.1, 0.4);
        assert!((depth(&tree, under_front, true) - 0.1).abs() < 1e-12);
        // Closed, the same points as before.
        let closed = TriangleTree::new(&rest, &triangles);
        assert!(!is_open(&triangles));
        assert_eq!(depth(&closed, behind, false), 0.0);
        assert!((depth(&closed, under_front, false) - 0.1).abs() < 1e-12);
        // Without the winding number, the open shell's rim takes the point.
        assert!(inside(&tree, behind, false).is_some());
    }
}
