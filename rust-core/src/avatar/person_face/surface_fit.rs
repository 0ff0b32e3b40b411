//! The skin laid on the scanned face by closest points (beyond the paper):
//! rounds of a non-rigid ICP (Amberg, Romdhani & Vetter 2007, *Optimal
//! step nonrigid ICP*), each solving the skin's change again
//! ([`super::rest_field::RestSystem::rest_field`]) with the wanted changes its closest points
//! give.
//!
//! **Why not the registration's points alone.** The registration says
//! where each mask vertex lies on the avatar's skin, and the first change
//! carries those points onto the scan. Where the avatar's face and the
//! person's differ in shape, neighbouring points slide by different
//! amounts along the skin: on ARKit's mesh, whose face wraps further round
//! the cheeks than the default avatar's, its rim asks 9 mm along the skin
//! as well as 9 mm off it. Held exactly, those slides crumple the skin
//! between the points (137–166 creased edges for five people), so the
//! first change holds them softly ([`START_WEIGHT`]) and the rounds then
//! ask only where the skin is off the surface, not where along it a point
//! should go:
//!
//! - **Skin to scan.** Every face vertex of the skin (the map's) asks to
//!   go to its closest point on the scanned neutral, raised along the
//!   scan's normal there by its own height over the registered mask (along
//!   the normal of the mask's triangle under it at rest): the avatar's
//!   detail finer than the mask, which the mask's flat triangles cut
//!   through. Without it the skin was pulled flat onto them, and the
//!   avatar's own face, taken, moved its rest by 0.33 mm; with it, by 0.26
//!   mm at most, where a vertex lies over an edge of the mask and only its
//!   height is kept. (Its whole offset kept, turned as the mask's normal
//!   interpolated from its vertices turns to the scan's, moved the own face
//!   by under 0.1 mm but creased 9–22 edges past the scan's own bend on
//!   ARKit's mesh, against 8–14.) It asks where the scan's closest point
//!   lies within [`FIT_REACH_MM`], on a triangle facing the same way
//!   (normals within 60°), and not on the scan's rim, nor the mask's under
//!   the vertex at rest, nor farther from the registered mask than the
//!   registration's face tolerance: skin beyond the scan's holes and
//!   outline (the lids' margins, the lips' insides, the head past the
//!   face) has no surface to go to there and follows smoothly.
//! - **Scan to skin, at the rims.** Each mask vertex on the outline or the
//!   mouth's rim pulls the skin's point closest to it onto itself, raised
//!   along the scan's normal by the stock skin's height over the
//!   registered mask there (as the first rule keeps each vertex's): no
//!   skin vertex reaches a rim by the first rule, and without this the
//!   lips' edges stay up to 3.8 mm from the scan's. (Pulled onto the scan
//!   itself, the skin was pressed flat where the registered mask lies off
//!   it, up to the registration's residual. With the height kept, and the
//!   eyeballs pushed back only from the lids in front of them
//!   ([`super::followers`]), the mask study's avatars keep their own face
//!   for 14 of its 120 person–avatar pairs, against 22, and take it for
//!   every pair they took it for before.) The eye holes are left out:
//!   the avatar's eye openings are its own (its lids close on its own
//!   eyeballs, as [`crate::avatar::retargeting`] keeps their blinks), and
//!   ARKit's eye holes are wider than the default avatar's openings;
//!   pulled onto them, the lids crumpled (33–49 creased edges against
//!   15–21, for the first three people).

use super::rest_field::{PointChange, RestSystem};
use crate::avatar::registration::find_face::FACE_TOLERANCE_MM;
use crate::avatar::registration::nonrigid::vertex_normals;
use crate::geometry::closest_point::TriangleTree;
use crate::geometry::mesh_boundary::{boundary_edges, on_boundary};
use crate::personalize::blendshape_fit::in_parallel_map;
use glam::DVec3;
use std::collections::HashSet;

/// How strongly the registration's points hold in the first change,
/// against one row of the skin's Laplace–Beltrami operator squared: a
/// point's wanted change is met where its neighbours agree, and averaged
/// with theirs where they slide apart. At 10³ (met exactly) the rounds
/// could not undo the crumples: five people on ARKit's mesh kept 47–70
/// creased edges with the uniform Laplacian, 19–33 at 1.
pub const START_WEIGHT: f64 = 1.0;

/// How strongly a closest point holds in the rounds (as [`START_WEIGHT`]):
/// ten times the first change's, so the skin lies on the scan while the
/// bending energy still spreads each change over several of the avatar's
/// triangles. Thirty times brought the scan's 95th percentile distance
/// from the skin down by 0.02–0.03 mm on ARKit's mesh and creased up to
/// 9 more edges (the simulator's first person 19 against 8).
pub const FIT_WEIGHT: f64 = 10.0;

/// Rounds of closest points: five instead of three moved the scan's mean
/// distance from the skin by under 0.01 mm on five people on ARKit's
/// mesh.
pub const ROUNDS: usize = 3;

/// Farthest a skin vertex and its closest point on the scan may be apart
/// for it to ask anything (mm at the mask's scale): after the first
/// change, the skin is within a millimetre of the scan nearly everywhere;
/// farther is another surface (a lip's lining behind the other lip).
pub const FIT_REACH_MM: f64 = 5.0;

/// Least cosine between a skin vertex's normal and the scan's triangle
/// normal at its closest point (60°): the lower lip's top does not take
/// the upper lip's underside.
pub const FACING: f64 = 0.5;

/// The skin the rounds move: the avatar's face parts at rest.
pub struct Skin<'a> {
    /// The avatar's vertices at rest (avatar units).
    pub positions: &'a [DVec3],
    /// The face parts' triangles.
    pub triangles: &'a [[u32; 3]],
    /// Its bending and ties over the vertices that may move.
    pub system: &'a RestSystem,
    /// Which vertices are the map's face vertices.
    pub face: &'a [bool],
}

/// The person's scanned neutral in the avatar's frame, on the mask.
pub struct Scan<'a> {
    /// Each mask vertex's scanned place.
    pub positions: &'a [DVec3],
    /// Each mask vertex where the registration put it on the avatar's
    /// skin: the skin's height over this surface is the avatar's detail,
    /// finer than the mask, and is kept over the scan.
    pub registered: &'a [DVec3],
    /// The mask's triangles.
    pub triangles: &'a [[u32; 3]],
    /// Mask vertices on the outline or the mouth's rim that lie on the
    /// skin, those that pull the skin onto themselves, each with the stock
    /// skin's height over its registered place (along the registered
    /// mask's normal there): kept over the scan.
    pub pulling: &'a [(u32, f64)],
}

/// The change of the skin after [`ROUNDS`] rounds from `start` (module
/// docs), `to_avatar` avatar units per mm, and the largest change the
/// last round asked of a point (avatar units); `None` if a round cannot
/// be solved.
pub fn fit_to_scan(
    skin: &Skin,
    scan: &Scan,
    start: Vec<DVec3>,
    to_avatar: f64,
) -> Option<(Vec<DVec3>, f64)> {
    let n = skin.positions.len();
    let surface = TriangleTree::new(scan.positions, scan.triangles);
    let rim = boundary_edges(scan.triangles);
    let rim_vertices: HashSet<u32> = rim.iter().flat_map(|&(a, b)| [a, b]).collect();
    let scan_normals = vertex_normals(scan.positions, scan.triangles);
    let reach = FIT_REACH_MM * to_avatar;
    // Each face vertex's height over the registered mask, along the
    // normal of the triangle under it: none farther than the
    // registration's face tolerance (not over the mask) or over its rim.
    let registered = TriangleTree::new(scan.registered, scan.triangles);
    let on_mask = FACE_TOLERANCE_MM * to_avatar;
    // The searches are independent: over the cores, here and below.
    let height: Vec<Option<f64>> = in_parallel_map(n, |v| {
        if !skin.face[v] {
            return None;
        }
        let c = registered.closest_within(skin.positions[v], on_mask)?;
        let inside = !on_boundary(
            scan.triangles[c.triangle],
            c.barycentric,
            &rim,
            &rim_vertices,
        );
        inside.then(|| (skin.positions[v] - c.point).dot(registered.triangle_normal(c.triangle)))
    });
    let mut field = start;
    let mut asked = 0.0;
    for _ in 0..ROUNDS {
        let now: Vec<DVec3> = (skin.positions.iter().zip(&field))
            .map(|(p, u)| *p + *u)
            .collect();
        let normals = vertex_normals(&now, skin.triangles);
        let asks = |v: usize| -> Option<PointChange> {
            let h = height[v]?;
            let c = surface.closest_within(now[v], reach)?;
            let normal = surface.triangle_normal(c.triangle);
            if on_boundary(
                scan.triangles[c.triangle],
                c.barycentric,
                &rim,
                &rim_vertices,
            ) || normals[v].dot(normal) < FACING
            {
                return None;
            }
            let target = c.point + normal * h;
            Some(([v as u32; 3], [1.0, 0.0, 0.0], target - skin.positions[v]))
        };
        let mut wanted: Vec<PointChange> = in_parallel_map(n, asks).into_iter().flatten().collect();
        let on_skin = TriangleTree::new(&now, skin.triangles);
        for &(i, h) in scan.pulling {
            let q = scan.positions[i as usize] + scan_normals[i as usize] * h;
            let Some(c) = on_skin.closest_within(q, reach) else {
                continue;
            };
            if on_skin
                .triangle_normal(c.triangle)
                .dot(scan_normals[i as usize])
                < FACING
            {
                continue;
            }
            let t = skin.triangles[c.triangle];
            let b = c.barycentric;
            let at_rest: DVec3 = (0..3).map(|k| skin.positions[t[k] as usize] * b[k]).sum();
            wanted.push((t, b, q - at_rest));
        }
        asked = wanted.iter().map(|w| w.2.length()).fold(0.0, f64::max);
        field = skin.system.rest_field(&wanted, FIT_WEIGHT)?;
    }
    Some((field, asked))
}
