//! The inside of the head showing through its skin: a vertex of a piece
//! behind the face (the mouth's lining, the teeth, the tongue, a socket's
//! lining) that a shape puts in front of the face's outer skin, where the
//! avatar's own shape of the same name keeps it behind.
//!
//! A point shows through the skin when nothing of the skin lies ahead of
//! it (seen from straight ahead) and the first skin triangle a ray from
//! it meets going backwards (into the head, against the face's forward
//! direction) faces forward and is part of the outer skin, the skin a
//! camera in front of the face sees at rest (`front_visibility`): the
//! point then sits on the outer side of the face's surface. Teeth seen
//! through a mouth the person opens wider than the avatar does lie in
//! front of the mouth's inside (ICT-FaceKit's skin runs on into it, its
//! back wall facing forward), which the lips hide at rest, and do not
//! count; nor does the lining seen through an open mouth, whose ray
//! backwards meets the inside of the back of the head, or no skin.
//! Lashes and brows, which lie in front of the skin in the avatar's own
//! shapes too, do not count either: only a vertex the own shape keeps
//! behind the skin can show through.

use super::head_skin::{bounding_sphere, eyeball_flags, head_triangles, skin_flags};
use super::model::Avatar;
use super::registration::FaceRegistration;
use super::registration::find_face::VISIBILITY_PIXEL_MM;
use super::registration::part_roles::PartRole;
use crate::geometry::cube_grid::CubeGrid;
use crate::geometry::front_visibility::visible_from;
use crate::geometry::ray_cover::RayCover;
use glam::{DVec3, Vec3};

/// The pieces behind the face, and the head's skin round them, prepared
/// once for [`InsideProbe::showing`] over every shape.
pub struct InsideProbe {
    /// The avatar's rest positions.
    rest: Vec<DVec3>,
    /// Where what lies behind the skin is looked at: each vertex within
    /// the face's bounding sphere (the registered mask's) of parts neither
    /// skin nor eyeball that the skin hides at least half of from the
    /// front at rest (not an ear or a lash, which are meant to be seen),
    /// as `[v, v, v]`, and each triangle of three of them on a lining (a
    /// part of no other role), at its centre: teeth, gums and tongue are
    /// small convex pieces, looked at by their vertices.
    /// (The lining at the corners of the mouth, seen through the slit at
    /// rest, is in: stretched out over the cheek, it showed. A lining
    /// triangle whose corners lie 0.2 mm behind a folded corner of the
    /// mouth bulged through it at its centre.)
    places: Vec<[u32; 3]>,
    /// The head's skin triangles with a corner within about [`REACH_MM`]
    /// of a place's vertex at rest.
    skin: Vec<[u32; 3]>,
    /// The face's forward direction (avatar coordinates, unit).
    forward: DVec3,
    /// For each of `skin`, whether it is part of the outer skin (module
    /// docs).
    outer: Vec<bool>,
    /// The cells at rest ([`CELL_MM`] cubes) of the places' and the skin's
    /// vertices.
    grid: CubeGrid,
}

/// Skin farther than this from every vertex that can show through it
/// (mm at the mask's scale, at rest) is left out of the rays' way: no
/// shape moves the skin or what lies behind it this far from the other
/// (the default avatar's jawOpen moves the chin 21 mm, its lower teeth
/// 12 mm). The back of the head, which a ray from inside the mouth meets
/// from within, is left out with it: no hit behind counts the same.
pub const REACH_MM: f64 = 30.0;

/// The side of the cubes (mm at the mask's scale) by which a shape's
/// region is found ([`InsideProbe::region`]).
pub const CELL_MM: f64 = 10.0;

/// The triangles of `skin` (over `rest`) with a corner within about
/// `reach` of one of `points` (cubes of side `reach`, those holding a
/// point and the cubes round them).
fn near_points(rest: &[DVec3], skin: &[[u32; 3]], points: &[u32], reach: f64) -> Vec<[u32; 3]> {
    let grid = CubeGrid::new(rest, points.iter().chain(skin.iter().flatten()), reach);
    let mut near = vec![false; grid.cells()];
    for &k in points {
        if let Some(c) = grid.cell(k) {
            near[c] = true;
        }
    }
    grid.grow(&mut near, 1);
    skin.iter()
        .copied()
        .filter(|t| t.iter().any(|&k| grid.cell(k).is_some_and(|c| near[c])))
        .collect()
}

/// The places of `inner` (`InsideProbe::places`' docs): each vertex, and
/// each triangle of three of them on a lining (a part of role
/// [`PartRole::Other`]).
fn places_of(avatar: &Avatar, found: &FaceRegistration, inner: &[u32]) -> Vec<[u32; 3]> {
    let offsets = avatar.vertex_offsets();
    let mut lining = vec![false; avatar.vertex_count()];
    for (k, role) in found.roles.iter().enumerate() {
        if let (PartRole::Other, Some((&a, &b))) = (role, offsets.get(k).zip(offsets.get(k + 1))) {
            lining[a..b].fill(true);
        }
    }
    let mut is_inner = vec![false; avatar.vertex_count()];
    for &v in inner {
        is_inner[v as usize] = true;
    }
    let on_lining = |t: &&[u32; 3]| {
        t.iter()
            .all(|&v| is_inner[v as usize] && lining[v as usize])
    };
    inner
        .iter()
        .map(|&v| [v; 3])
        .chain(avatar.triangles().iter().filter(on_lining).copied())
        .collect()
}

/// How far the inside shows through the skin in one shape.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Showing {
    /// Places (vertices and triangles' centres) in front of the skin
    /// where the own shape keeps them behind.
    pub points: usize,
    /// The farthest of them in front of the skin (avatar units).
    pub depth: f64,
    /// A corner of that place (avatar vertex).
    pub vertex: u32,
}

impl InsideProbe {
    /// Prepares `avatar` found as `found`.
    pub fn new(avatar: &Avatar, found: &FaceRegistration) -> InsideProbe {
        let rest: Vec<DVec3> = avatar.positions().iter().map(|p| p.as_dvec3()).collect();
        let all: Vec<u32> = (0..found.mask_on_avatar.len() as u32).collect();
        let (centre, radius) = bounding_sphere(&found.mask_on_avatar, &all);
        let in_eyeball = eyeball_flags(avatar, found);
        let offsets = avatar.vertex_offsets();
        let on_skin = skin_flags(avatar, found);
        let skin: Vec<[u32; 3]> = head_triangles(avatar, found)
            .into_iter()
            .filter(|t| {
                t.iter()
                    .any(|&v| (rest[v as usize] - centre).length() < 1.5 * radius)
            })
            .collect();
        let forward = found.similarity.rotation * DVec3::Z;
        let at_rest = RayCover::new(
            skin.iter().map(|t| t.map(|v| rest[v as usize])).collect(),
            forward,
        );
        let covered: Vec<bool> = (0..rest.len())
            .map(|v| !on_skin[v] && !in_eyeball[v] && at_rest.covers(rest[v]))
            .collect();
        // Parts the skin hides at rest: at least half their vertices.
        let mut hidden = vec![false; rest.len()];
        for (&a, &b) in offsets.iter().zip(offsets.iter().skip(1)) {
            let count = covered[a..b].iter().filter(|c| **c).count();
            if 2 * count >= b - a {
                hidden[a..b].fill(true);
            }
        }
        let inner: Vec<u32> = (0..rest.len())
            .filter(|&v| hidden[v] && (rest[v] - centre).length() < radius)
            .map(|v| v as u32)
            .collect();
        let mm = found.similarity.scale / 1000.0;
        let skin = near_points(&rest, &skin, &inner, REACH_MM * mm);
        // The outer skin: what of it is seen from the front among every
        // triangle near the face (teeth through parted lips hide what
        // lies behind them).
        let others = avatar.triangles().iter().filter(|t| {
            !t.iter().all(|&v| on_skin[v as usize])
                && t.iter()
                    .any(|&v| (rest[v as usize] - centre).length() < 1.5 * radius)
        });
        let all: Vec<[u32; 3]> = skin.iter().chain(others).copied().collect();
        let mut outer = visible_from(&rest, &all, forward, VISIBILITY_PIXEL_MM * mm);
        outer.truncate(skin.len());
        let places = places_of(avatar, found, &inner);
        InsideProbe::from_parts(rest, places, (skin, outer), forward, mm)
    }

    /// The probe of `places` (`[v, v, v]` for a vertex, a triangle at its
    /// centre) behind `skin` (triangles over `rest`, each with whether it
    /// is outer skin, module docs), the face looking along `forward`; `mm`
    /// is a millimetre at the mask's scale in `rest`'s units.
    pub fn from_parts(
        rest: Vec<DVec3>,
        places: Vec<[u32; 3]>,
        (skin, outer): (Vec<[u32; 3]>, Vec<bool>),
        forward: DVec3,
        mm: f64,
    ) -> InsideProbe {
        let grid = CubeGrid::new(
            &rest,
            places.iter().flatten().chain(skin.iter().flatten()),
            CELL_MM * mm,
        );
        InsideProbe {
            rest,
            places,
            skin,
            forward: forward.normalize_or_zero(),
            outer,
            grid,
        }
    }

    /// The places, and the skin triangles (indices into `skin`), that a
    /// shape can change where it moves the vertices `moves(v)` says it
    /// moves otherwise than the own shape: the places within a cell of
    /// such a vertex ([`CELL_MM`], the cells round it), the skin within
    /// [`REACH_MM`] more. Elsewhere the shape leaves the places where the
    /// own shape does, in front of the skin or behind it.
    pub fn region(&self, moves: impl Fn(u32) -> bool) -> Region {
        let mut near = vec![false; self.grid.cells()];
        let corners = self
            .places
            .iter()
            .flatten()
            .chain(self.skin.iter().flatten());
        for &v in corners {
            if let Some(c) = self.grid.cell(v).filter(|_| moves(v)) {
                near[c] = true;
            }
        }
        self.grid.grow(&mut near, 1);
        let places = self
            .places
            .iter()
            .filter(|p| self.grid.cell(p[0]).is_some_and(|c| near[c]))
            .copied()
            .collect();
        self.grid
            .grow(&mut near, (REACH_MM / CELL_MM).ceil() as usize);
        let skin = (0..self.skin.len())
            .filter(|&i| {
                self.skin[i]
                    .iter()
                    .any(|&v| self.grid.cell(v).is_some_and(|c| near[c]))
            })
            .collect();
        Region { places, skin }
    }

    /// Where what lies behind the skin is looked at (`places`' docs).
    pub fn places(&self) -> &[[u32; 3]] {
        &self.places
    }

    /// The face's forward direction (avatar coordinates, unit).
    pub fn forward(&self) -> DVec3 {
        self.forward
    }

    /// How far each of `which` (places, at the mean of their corners)
    /// lies in front of the skin triangles `skin` (indices into the
    /// probe's) with every vertex `v` at `posed(v)`, where none of them
    /// covers it from the front (module docs; 0 otherwise), avatar units.
    pub fn depths(
        &self,
        posed: impl Fn(u32) -> DVec3,
        skin: &[usize],
        which: &[[u32; 3]],
    ) -> Vec<f64> {
        let cover = RayCover::new(
            skin.iter().map(|&i| self.skin[i].map(&posed)).collect(),
            self.forward,
        );
        which
            .iter()
            .map(|place| {
                let at = place.iter().map(|&v| posed(v)).sum::<DVec3>() / 3.0;
                // Covered from the front, or the nearest crossing behind.
                let behind =
                    cover
                        .line_crossings(at)
                        .try_fold(None, |near, c| match (c.1 > 0.0, near) {
                            (true, _) => Err(()),
                            (false, Some((_, s))) if s >= c.1 => Ok(near),
                            (false, _) => Ok(Some(c)),
                        });
                let Ok(behind) = behind else {
                    return 0.0;
                };
                behind.map_or(0.0, |(i, s)| {
                    let [a, b, c] = cover.triangle(i);
                    let outer = skin.get(i).and_then(|&k| self.outer.get(k));
                    let outer = outer.copied().unwrap_or(false);
                    match outer && (b - a).cross(c - a).dot(self.forward) > 0.0 {
                        true => -s,
                        false => 0.0,
                    }
                })
            })
            .collect()
    }

    /// [`InsideProbe::depths`] of a few places `which`, against only the
    /// skin within [`REACH_MM`] of them.
    pub fn depths_near(&self, posed: impl Fn(u32) -> DVec3, which: &[[u32; 3]]) -> Vec<f64> {
        let mut corner = vec![false; self.rest.len()];
        for &v in which.iter().flatten() {
            if let Some(c) = corner.get_mut(v as usize) {
                *c = true;
            }
        }
        let near = self.region(|v| corner.get(v as usize).copied().unwrap_or(false));
        self.depths(posed, &near.skin, which)
    }

    /// The places `got` puts in front of the skin by more than `least`
    /// (avatar units) where `own` keeps them behind it (module docs): in
    /// the region where the two differ by more than half `least`
    /// ([`InsideProbe::region`]). Elsewhere neither a place nor the skin
    /// round it moves half `least` from where `own` puts it, so a place
    /// comes out further only where `own` leaves it on the edge of what
    /// hides it (MPFB's tongueOut, for one simulated person: 0.38 mm, the
    /// tongue's tip under the lip's edge).
    pub fn showing(&self, own: &[Vec3], got: &[Vec3], least: f64) -> Showing {
        let moves = |v: u32| {
            let v = v as usize;
            f64::from((got[v] - own[v]).length()) > 0.5 * least
        };
        let region = self.region(moves);
        let posed = |d: &[Vec3], v: u32| self.rest[v as usize] + d[v as usize].as_dvec3();
        let (ahead, depth): (Vec<[u32; 3]>, Vec<f64>) = region
            .places
            .iter()
            .zip(self.depths(|v| posed(got, v), &region.skin, &region.places))
            .filter(|(_, g)| *g > least)
            .map(|(p, g)| (*p, g))
            .unzip();
        if ahead.is_empty() {
            return Showing::default();
        }
        ahead
            .iter()
            .zip(
                self.depths_near(|v| posed(own, v), &ahead)
                    .iter()
                    .zip(&depth),
            )
            .filter(|(_, (o, _))| **o == 0.0)
            .fold(Showing::default(), |s, (p, (_, &g))| Showing {
                points: s.points + 1,
                depth: s.depth.max(g),
                vertex: if g > s.depth { p[0] } else { s.vertex },
            })
    }
}

/// What one shape can change: places and skin triangles
/// ([`InsideProbe::region`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Region {
    /// The places.
    pub places: Vec<[u32; 3]>,
    /// The skin triangles, indices into the probe's.
    pub skin: Vec<usize>,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A skin of two triangles in the plane z = 0 facing +z (forward),
    /// 20 units square, with a lining vertex 1 behind it, a lash 1 in
    /// front of it and a vertex 1 behind a hole beside it (no skin).
    fn scene() -> InsideProbe {
        let rest = vec![
            DVec3::new(-10.0, -10.0, 0.0),
            DVec3::new(10.0, -10.0, 0.0),
            DVec3::new(10.0, 10.0, 0.0),
            DVec3::new(-10.0, 10.0, 0.0),
            DVec3::new(0.0, 0.0, -1.0),
            DVec3::new(2.0, 0.0, 1.0),
            DVec3::new(30.0, 0.0, -1.0),
        ];
        InsideProbe::from_parts(
            rest,
            vec![[4; 3], [5; 3], [6; 3]],
            (vec![[0, 1, 2], [0, 2, 3]], vec![true, true]),
            DVec3::Z,
            1.0,
        )
    }

    #[test]
    fn a_vertex_brought_out_in_front_of_the_skin_shows_and_one_in_front_already_does_not() {
        let probe = scene();
        let own = vec![Vec3::ZERO; 7];
        assert_eq!(probe.showing(&own, &own, 0.0), Showing::default());
        // The lining comes 1.5 in front; the lash moves too (it was in
        // front already); the vertex behind the hole comes forward 3,
        // with no skin behind it.
        let mut got = own.clone();
        got[4] = Vec3::new(0.0, 0.0, 2.5);
        got[5] = Vec3::new(0.0, 0.0, 0.5);
        got[6] = Vec3::new(0.0, 0.0, 3.0);
        let showing = probe.showing(&own, &got, 0.0);
        assert_eq!(showing.points, 1);
        assert_eq!(showing.vertex, 4);
        assert!((showing.depth - 1.5).abs() < 1e-6, "{showing:?}");
        // Past the least depth asked only.
        assert_eq!(probe.showing(&own, &got, 2.0).points, 0);
        // The skin moving forward with it hides it again.
        let mut both = got.clone();
        for d in &mut both[..4] {
            *d = Vec3::new(0.0, 0.0, 3.0);
        }
        assert_eq!(probe.showing(&own, &both, 0.0).points, 0);
    }

    /// The same skin as the mouth's inside (hidden at rest): teeth seen
    /// in front of its back wall through an opened mouth.
    #[test]
    fn a_vertex_in_front_of_skin_the_face_hides_at_rest_does_not_count() {
        let outer = scene();
        let probe = InsideProbe::from_parts(
            outer.rest.clone(),
            outer.places.clone(),
            (outer.skin.clone(), vec![false, false]),
            DVec3::Z,
            1.0,
        );
        let own = vec![Vec3::ZERO; 7];
        let mut got = own.clone();
        got[4] = Vec3::new(0.0, 0.0, 2.5);
        assert_eq!(outer.showing(&own, &got, 0.0).points, 1);
        assert_eq!(probe.showing(&own, &got, 0.0).points, 0);
    }

    /// A lining triangle whose corners lie just behind the skin, which a
    /// shape folds into a valley between them (along x = 0), bulges
    /// through it at its centre.
    #[test]
    fn a_triangle_through_a_fold_of_the_skin_shows_at_its_centre() {
        let rest = vec![
            DVec3::new(-10.0, -10.0, 1.0),
            DVec3::new(0.0, -10.0, 1.0),
            DVec3::new(0.0, 10.0, 1.0),
            DVec3::new(-10.0, 10.0, 1.0),
            DVec3::new(10.0, -10.0, 1.0),
            DVec3::new(10.0, 10.0, 1.0),
            DVec3::new(-6.0, -1.0, 0.5),
            DVec3::new(6.0, -1.0, 0.5),
            DVec3::new(6.0, 3.0, 0.5),
        ];
        let skin = vec![[0, 1, 2], [0, 2, 3], [1, 4, 5], [1, 5, 2]];
        let places = vec![[6; 3], [7; 3], [8; 3], [6, 7, 8]];
        let probe = InsideProbe::from_parts(rest, places, (skin, vec![true; 4]), DVec3::Z, 1.0);
        let own = vec![Vec3::ZERO; 9];
        assert_eq!(probe.showing(&own, &own, 0.0).points, 0);
        // The valley sinks to z = 0: the corners (under skin at 0.6) stay
        // 0.1 behind it, the centre (x = 2, skin at 0.2) comes 0.3 out.
        let mut got = own.clone();
        got[1] = Vec3::new(0.0, 0.0, -1.0);
        got[2] = Vec3::new(0.0, 0.0, -1.0);
        let showing = probe.showing(&own, &got, 0.0);
        assert_eq!(showing.points, 1, "{showing:?}");
        assert_eq!(showing.vertex, 6);
        assert!((showing.depth - 0.3).abs() < 1e-6, "{showing:?}");
    }

    #[test]
    fn a_vertex_the_own_shape_brings_out_as_well_does_not_count() {
        let probe = scene();
        let mut own = vec![Vec3::ZERO; 7];
        own[4] = Vec3::new(0.0, 0.0, 1.5);
        let mut got = own.clone();
        got[4] = Vec3::new(0.0, 0.0, 2.0);
        assert_eq!(probe.showing(&own, &got, 0.0).points, 0);
    }
}
