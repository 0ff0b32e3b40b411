//! Eyelid repair (§3.3, after Achenbach et al. 2015): the mask has no
//! eyeballs, so a person's lid may pass through the avatar's eyeball in a
//! transferred shape. Every skin vertex that ends inside an eyeball is
//! moved to the eyeball's surface, [`LID_OFFSET_MM`] outside it along the
//! surface normal.
//!
//! Inside is judged against the eyeball's own triangles as displaced by the
//! same shape (an eyeLook turns the eyeball too): with `c` the closest
//! eyeball point to skin vertex `p` and `n` the outward normal of the
//! triangle it lies on, `p` is inside when `(p − c) · n < 0`. Eyeball parts
//! are closed and face outwards (the default avatar's are tested so); only
//! skin vertices within the eyeball's radius plus [`NEAR_MM`] of its centre
//! at rest, and within its bounding sphere in the shape, are looked at (an
//! eyeball turns about its centre, so the sphere holds it in every shape),
//! and each may stay as deep inside as the avatar's own shape of the same
//! name keeps it (as it rests where the avatar has no such shape): a
//! vertex the avatar keeps inside an eyeball's shell (a lid margin under a
//! cornea shell, or a lid an eyeLook target leaves behind a turned
//! eyeball) is the rig's own, and one the own shape keeps out is put out,
//! however it rests.

use crate::geometry::closest_point::TriangleGrid;
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
}

impl Eyeball {
    /// The eyeball made of `triangles` over `rest` (avatar positions).
    pub fn new(rest: &[DVec3], triangles: Vec<[u32; 3]>) -> Eyeball {
        let mut vertices: Vec<u32> = triangles.iter().flatten().copied().collect();
        vertices.sort_unstable();
        vertices.dedup();
        let n = vertices.len().max(1) as f64;
        let centre = vertices
            .iter()
            .filter_map(|&v| rest.get(v as usize))
            .sum::<DVec3>()
            / n;
        let radius = vertices
            .iter()
            .filter_map(|&v| rest.get(v as usize))
            .map(|p| (*p - centre).length())
            .fold(0.0, f64::max);
        Eyeball {
            triangles,
            centre,
            radius,
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
    let mut moved = 0;
    let posed: Vec<DVec3> = rest
        .iter()
        .zip(displacement.iter())
        .map(|(p, d)| *p + *d)
        .collect();
    let own_posed: Vec<DVec3> = rest
        .iter()
        .enumerate()
        .map(|(v, p)| *p + own.get(v).copied().unwrap_or(DVec3::ZERO))
        .collect();
    for eyeball in eyeballs {
        let grid = TriangleGrid::new(&posed, &eyeball.triangles);
        let at_rest = TriangleGrid::new(rest, &eyeball.triangles);
        let under_own = TriangleGrid::new(&own_posed, &eyeball.triangles);
        for &v in skin {
            let v = v as usize;
            let (Some(p0), Some(p)) = (rest.get(v), posed.get(v)) else {
                continue;
            };
            // Outside the sphere round the eyeball (which turns about its
            // centre) nothing can be inside it.
            if (*p0 - eyeball.centre).length() > eyeball.radius + near
                || (*p - eyeball.centre).length() > eyeball.radius
            {
                continue;
            }
            // How deep the avatar's own shape of this name keeps the
            // vertex (at rest where it has none): a lid margin tucked under
            // a rig's cornea shell, or left behind a turned eyeball, is the
            // rig's choice, not a lid passing through.
            let allowed = match own.is_empty() {
                true => depth(&at_rest, *p0),
                false => depth(&under_own, own_posed[v]),
            };
            if let Some((point, normal)) = inside(&grid, *p) {
                let deeper = (point - *p).dot(normal);
                if allowed == 0.0 {
                    displacement[v] = point + normal * offset - *p0;
                    moved += 1;
                } else if deeper > allowed + offset {
                    displacement[v] = point - normal * allowed - *p0;
                    moved += 1;
                }
            }
        }
    }
    moved
}

/// How far `p` lies inside the closed surface `grid` (zero outside):
/// along the normal of the closest point's triangle.
pub fn depth(grid: &TriangleGrid, p: DVec3) -> f64 {
    inside(grid, p).map_or(0.0, |(c, normal)| (c - p).dot(normal))
}

/// The closest point of `grid` to `p` and its triangle's normal, if `p`
/// is on the inner side of it.
fn inside(grid: &TriangleGrid, p: DVec3) -> Option<(DVec3, DVec3)> {
    let c = grid.closest(p)?;
    let normal = grid.triangle_normal(c.triangle);
    ((p - c.point).dot(normal) < 0.0).then_some((c.point, normal))
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
    }
}
