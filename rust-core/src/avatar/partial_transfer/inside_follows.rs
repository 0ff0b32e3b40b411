//! What lies just behind the skin follows the person's motion of the
//! skin it lies behind (beyond the paper). Off the face parts §3.3 moves
//! every vertex by `A_j`, the avatar's own shapes combined; the skin
//! itself takes the person's motion, `D_j = A_j + T(B_j − S(A_j))`. Where
//! the two differ, a piece that sits a few millimetres behind the skin
//! (the mouth's lining behind the lips and chin, the lower teeth behind
//! the lower lip, a socket's lining behind the lids) keeps the avatar's
//! motion while the skin in front of it takes the person's, and comes
//! out through it: a person whose corner of the mouth stretches less
//! than the avatar's left the lining's fold in front of the cheek, and a
//! jaw that opens less than the avatar's put the lower teeth through the
//! lower lip ([`crate::avatar::showing_through`] measures it).
//!
//! So each vertex off the face parts and off the eyeballs within
//! [`FREE_MM`] of the skin at rest takes the skin's deviation from `A_j`
//! at its closest point, `D_j − A_j` interpolated over that skin
//! triangle, wholly within [`HOLD_MM`] and fading linearly to nothing at
//! [`FREE_MM`]: the same blend, with the same distances, by which the
//! linings follow the person's face at rest
//! ([`crate::avatar::person_face::followers`]). Teeth, which take this
//! at their edges nearest the lips, are made rigid again afterwards with
//! every rigid piece ([`super::rigid_parts`]).
//!
//! What still lies in front of the skin after every step, where the
//! avatar's own shape keeps it behind (a tongue's tip through a puckered
//! lip, the lining's fold at a corner of the mouth that stretches less
//! than the avatar's), is put back behind it along the face's backward
//! direction, [`BEHIND_MM`] clear ([`put_back`]): a rigid piece wholly,
//! by the farthest of its points, so teeth stay whole; a lining vertex by
//! vertex, which dents it only where the skin hides the dent.

use crate::avatar::showing_through::InsideProbe;
use crate::geometry::closest_point::TriangleTree;
use glam::DVec3;

/// How far behind the skin a vertex put back is left (mm at the mask's
/// scale), as a lid put back on an eyeball
/// ([`super::eyelid_repair::LID_OFFSET_MM`]): enough that a renderer's
/// depth test tells the two apart.
pub const BEHIND_MM: f64 = 0.2;

/// A vertex of a piece off the skin within this distance of it (mm at
/// the mask's scale) takes the skin's motion at its closest point wholly,
/// one beyond [`FREE_MM`] its own; in between the two blend linearly:
/// here the skin's deviation from `A_j` (module docs), at rest the change
/// of the face taken ([`crate::avatar::person_face::followers`]). So the
/// lining of a socket stays behind the lids it lines (the default
/// avatar's socket rims lie 2.2 mm behind its lids) and an ear's root in
/// the head: on the default avatar, the sockets following their eyeballs
/// alone opened a see-through gap at the corners of the eyes.
pub const HOLD_MM: f64 = 2.5;

/// See [`HOLD_MM`]. Lips are 11–15 mm thick at the vermilion (Holdaway
/// 1983), so the lining behind their middle is beyond it, and the lining
/// at their corners, where they thin, within it.
pub const FREE_MM: f64 = 8.0;

/// One vertex behind the skin and the skin point it follows.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Anchor {
    /// The vertex.
    vertex: u32,
    /// Its closest skin triangle at rest.
    triangle: [u32; 3],
    /// The closest point's barycentric coordinates in it.
    weights: [f64; 3],
    /// Its share of the skin's deviation, 0–1.
    share: f64,
}

/// Every vertex behind the skin that follows it (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct InsideFollows {
    anchors: Vec<Anchor>,
}

impl InsideFollows {
    /// The vertices `follows(v)` allows (off the face parts and the
    /// eyeballs) within [`FREE_MM`] of `skin_triangles` at `positions`;
    /// `to_avatar` is avatar units per mm at the mask's scale.
    pub fn new(
        positions: &[DVec3],
        skin_triangles: &[[u32; 3]],
        follows: impl Fn(usize) -> bool,
        to_avatar: f64,
    ) -> InsideFollows {
        let tree = TriangleTree::new(positions, skin_triangles);
        let (hold, free) = (HOLD_MM * to_avatar, FREE_MM * to_avatar);
        let anchors = (0..positions.len())
            .filter(|&v| follows(v))
            .filter_map(|v| {
                let c = tree.closest_within(positions[v], free)?;
                let distance = (c.point - positions[v]).length();
                let share = ((free - distance) / (free - hold)).clamp(0.0, 1.0);
                Some(Anchor {
                    vertex: v as u32,
                    triangle: *tree.triangles().get(c.triangle)?,
                    weights: c.barycentric,
                    share,
                })
            })
            .filter(|a| a.share > 0.0)
            .collect();
        InsideFollows { anchors }
    }

    /// How many vertices follow the skin.
    pub fn len(&self) -> usize {
        self.anchors.len()
    }

    /// Whether none does.
    pub fn is_empty(&self) -> bool {
        self.anchors.is_empty()
    }

    /// Adds to each following vertex of `made` (one shape's displacement
    /// of every vertex) its share of the skin's deviation from
    /// `retargeted` (`A_j`) at its anchor.
    pub fn apply(&self, retargeted: &[DVec3], made: &mut [DVec3]) {
        let deviation = |v: u32| -> DVec3 {
            let v = v as usize;
            match (made.get(v), retargeted.get(v)) {
                (Some(d), Some(a)) => *d - *a,
                _ => DVec3::ZERO,
            }
        };
        let moves: Vec<(u32, DVec3)> = self
            .anchors
            .iter()
            .map(|a| {
                let at: DVec3 = (0..3)
                    .map(|k| a.weights[k] * deviation(a.triangle[k]))
                    .sum();
                (a.vertex, a.share * at)
            })
            .collect();
        for (v, m) in moves {
            if let Some(d) = made.get_mut(v as usize) {
                *d += m;
            }
        }
    }
}

/// Rounds of [`put_back`] at most: a round that puts a triangle's
/// corners back can leave a neighbour's centre out where the skin folds.
pub const PUT_BACK_ROUNDS: usize = 3;

/// Puts back behind the skin whatever of `probe`'s places the shape
/// `made` (displacements of every vertex from `positions`) leaves in
/// front of it where `own` (the avatar's own shape; empty for none)
/// does not (module docs), in up to [`PUT_BACK_ROUNDS`] rounds; `piece_of`
/// names each vertex's rigid piece, whose vertices `pieces` lists, and
/// `clear` is [`BEHIND_MM`] in avatar units. A place's corners go back by
/// its depth and `clear`. Returns the places found in front over the
/// rounds.
pub fn put_back(
    probe: &InsideProbe,
    positions: &[DVec3],
    (piece_of, pieces): (&[Option<usize>], &[&[u32]]),
    own: &[DVec3],
    made: &mut [DVec3],
    clear: f64,
) -> usize {
    let at = |d: &[DVec3], v: u32| {
        positions[v as usize] + d.get(v as usize).copied().unwrap_or_default()
    };
    let back = -probe.forward();
    let still = |v: u32| own.get(v as usize).copied().unwrap_or_default();
    let region = probe.region(|v| (made[v as usize] - still(v)).length() > 0.5 * clear);
    let mut count = 0;
    for _ in 0..PUT_BACK_ROUNDS {
        let (ahead, depth): (Vec<[u32; 3]>, Vec<f64>) = region
            .places
            .iter()
            .zip(probe.depths(|v| at(made, v), &region.skin, &region.places))
            .filter(|(_, g)| *g > 0.0)
            .map(|(p, g)| (*p, g))
            .unzip();
        if ahead.is_empty() {
            break;
        }
        let own_depth = probe.depths_near(|v| at(own, v), &ahead);
        let mut piece_push = vec![0.0f64; pieces.len()];
        let mut vertex_push: Vec<(u32, f64)> = Vec::new();
        let mut found = 0;
        for ((place, &g), &o) in ahead.iter().zip(&depth).zip(&own_depth) {
            if o > 0.0 {
                continue;
            }
            found += 1;
            for &v in place {
                match piece_of.get(v as usize).copied().flatten() {
                    Some(p) => piece_push[p] = piece_push[p].max(g),
                    None => vertex_push.push((v, g)),
                }
            }
        }
        if found == 0 {
            break;
        }
        count += found;
        // Each vertex back by the most any of its places asks.
        vertex_push.sort_by(|a, b| a.0.cmp(&b.0).then(b.1.total_cmp(&a.1)));
        vertex_push.dedup_by_key(|x| x.0);
        for (v, g) in vertex_push {
            made[v as usize] += back * (g + clear);
        }
        for (piece, push) in pieces.iter().zip(piece_push) {
            if push > 0.0 {
                for &v in *piece {
                    made[v as usize] += back * (push + clear);
                }
            }
        }
    }
    count
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A skin of two triangles in the plane z = 0 and three vertices
    /// behind it at 1, 5 and 20 units (a unit per mm).
    #[test]
    fn a_vertex_behind_the_skin_takes_its_deviation_by_distance() {
        let mut positions = vec![
            DVec3::new(-10.0, -10.0, 0.0),
            DVec3::new(10.0, -10.0, 0.0),
            DVec3::new(10.0, 10.0, 0.0),
            DVec3::new(-10.0, 10.0, 0.0),
        ];
        positions.extend([1.0, 5.0, 20.0].map(|z| DVec3::new(0.0, 0.0, -z)));
        let skin = [[0, 1, 2], [0, 2, 3]];
        let follows = InsideFollows::new(&positions, &skin, |v| v >= 4, 1.0);
        assert_eq!(follows.len(), 2);
        // A_j moves everything by x; the person's skin moves by x + y.
        let retargeted = vec![DVec3::X; 7];
        let mut made = retargeted.clone();
        for d in &mut made[..4] {
            *d += DVec3::Y;
        }
        follows.apply(&retargeted, &mut made);
        assert!((made[4] - (DVec3::X + DVec3::Y)).length() < 1e-12);
        let share = (FREE_MM - 5.0) / (FREE_MM - HOLD_MM);
        assert!((made[5] - (DVec3::X + share * DVec3::Y)).length() < 1e-12);
        assert_eq!(made[6], DVec3::X);
    }

    /// The skin of [`a_vertex_behind_the_skin_takes_its_deviation_by_distance`]
    /// facing +z, a lining vertex and a two-vertex rigid piece behind it.
    #[test]
    fn what_comes_out_in_front_of_the_skin_is_put_back_behind_it() {
        let positions = vec![
            DVec3::new(-10.0, -10.0, 0.0),
            DVec3::new(10.0, -10.0, 0.0),
            DVec3::new(10.0, 10.0, 0.0),
            DVec3::new(-10.0, 10.0, 0.0),
            DVec3::new(0.0, 0.0, -1.0),
            DVec3::new(3.0, 0.0, -2.0),
            DVec3::new(3.0, 1.0, -5.0),
        ];
        let probe = InsideProbe::from_parts(
            positions.clone(),
            vec![[4; 3], [5; 3], [6; 3]],
            (vec![[0, 1, 2], [0, 2, 3]], vec![true, true]),
            DVec3::Z,
            1.0,
        );
        let piece: &[u32] = &[5, 6];
        let piece_of = [None, None, None, None, None, Some(0), Some(0)];
        // The lining 0.5 out, the piece's front vertex 1 out, its back
        // one still behind.
        let mut made = vec![DVec3::ZERO; 7];
        made[4] = DVec3::new(0.0, 0.0, 1.5);
        made[5] = DVec3::new(0.0, 0.0, 3.0);
        made[6] = DVec3::new(0.0, 0.0, 3.0);
        let put = put_back(
            &probe,
            &positions,
            (&piece_of, &[piece]),
            &[],
            &mut made,
            0.2,
        );
        assert_eq!(put, 2);
        assert!((made[4].z - (1.5 - 0.7)).abs() < 1e-12, "{}", made[4]);
        // The piece moved wholly, by its front vertex's 1 and the
        // clearance: rigid still.
        assert!((made[5].z - (3.0 - 1.2)).abs() < 1e-12, "{}", made[5]);
        assert_eq!(made[5], made[6]);
        let posed: Vec<DVec3> = positions.iter().zip(&made).map(|(p, d)| *p + *d).collect();
        assert!(posed[4].z < 0.0 && posed[5].z < 0.0);
        // Nothing left to put back.
        let again = made.clone();
        assert_eq!(
            put_back(
                &probe,
                &positions,
                (&piece_of, &[piece]),
                &[],
                &mut made,
                0.2
            ),
            0
        );
        assert_eq!(made, again);
    }
}
