//! What the skin holds follows the skin when the avatar takes the
//! person's face ([`super`]): given the change `u` of the face parts' rest,
//! every other vertex gets one. Nothing off the skin bends: each piece
//! takes one uniform scaling and shift, `x ↦ c' + s (x − c)`
//! ([`ScaleShift`]), fitted to the skin that holds it, so teeth keep their
//! shape and pieces that touch stay together.
//!
//! - **Eyeballs** ([`crate::avatar::registration::eyeballs`]) take the
//!   scaling and shift that carries the skin within [`NEAR_MM`] of the
//!   eyeball's sphere (its lids and the rim of its opening) closest to
//!   where `u` puts it: the eyeball moves into the person's eye opening,
//!   scaled to it. It does not turn: a turned eyeball is a gaze, and at
//!   rest the eyes look ahead. Every other piece within that sphere (the
//!   socket's lining) goes with its eyeball. A lid in front of the
//!   eyeball that then lies deeper inside it than it did on the stock
//!   avatar pushes the eye back, along the face's backward direction,
//!   until every such lid is at most as deep as it was ([`LID_OFFSET_MM`]
//!   more clear), so the eye never shows through a lid at rest
//!   (`push_back`).
//! - **Near the skin** a piece that bends (a lining, an ear; not an
//!   eyeball, nor teeth, which the avatar's own targets move only
//!   rigidly) blends from its group's motion into the skin's
//!   ([`HOLD_MM`], [`FREE_MM`]), so it stays on the skin it touches.
//! - **Every other piece** (a connected component off the face parts)
//!   joins the pieces within [`TOUCH_MM`] of it into one group (teeth,
//!   gums, tongue and the mouth's lining; an ear), and each group takes
//!   the scaling and shift that carries the skin within [`ANCHOR_MM`] of
//!   it (the lips and chin round the mouth, the side of the head round an
//!   ear), each skin vertex weighed by how near it is,
//!   `1 − dist / ANCHOR_MM`. A rotation fitted to that one-sided shell of
//!   skin swung the default avatar's teeth by up to 15 mm where the skin
//!   moved 8, and teeth and gums fitted apart parted by 5 mm, hence one
//!   scaling and shift per group. A group no skin is near stays.

use crate::avatar::head_skin::skin_flags;
use crate::avatar::model::Avatar;
use crate::avatar::partial_transfer::eyelid_repair::{Eyeball, LID_OFFSET_MM, NEAR_MM};
use crate::avatar::partial_transfer::inside_follows::{FREE_MM, HOLD_MM};
use crate::avatar::partial_transfer::rigid_parts::{RIGID_TOLERANCE, rigid_deviation, size};
use crate::avatar::registration::FaceRegistration;
use crate::geometry::closest_point::TriangleTree;
use crate::geometry::connected_components::component_vertices;
use crate::geometry::inside_surface::depth;
use crate::personalize::blendshape_fit::in_parallel_map;
use glam::DVec3;
use std::collections::HashSet;

/// The skin within this distance of a group of pieces (mm at the mask's
/// scale) carries it: the lips, the corners of the mouth and the chin for
/// the teeth, whose incisors sit 10–15 mm behind the lips' surface (upper
/// lip thickness at the vermilion 11–15 mm in adults, Holdaway 1983).
pub const ANCHOR_MM: f64 = 15.0;

/// Pieces closer than this (mm at the mask's scale) are one group: teeth
/// set in their gums, a tongue resting on the lower teeth, the lining
/// round them. The default avatar's pieces that belong together are
/// within 1 mm of each other; its ear and its mouth are 60 mm apart.
pub const TOUCH_MM: f64 = 2.0;

/// Whether every own target (`own`, per avatar vertex) that moves the
/// piece `vertices` moves it rigidly ([`RIGID_TOLERANCE`] of its size),
/// and one does.
fn moves_rigidly(positions: &[DVec3], own: &[Vec<DVec3>], vertices: &[u32]) -> bool {
    let tolerance = RIGID_TOLERANCE * size(positions, vertices);
    let moved = |d: &Vec<DVec3>| vertices.iter().any(|&v| d[v as usize] != DVec3::ZERO);
    let moving: Vec<&Vec<DVec3>> = own.iter().filter(|d| moved(d)).collect();
    !moving.is_empty()
        && moving
            .iter()
            .all(|d| rigid_deviation(positions, d, vertices) <= tolerance)
}

/// Pushing an eyeball back stops after this many rounds (each moves it by
/// the deepest lid's depth; one is enough unless the lid is curved
/// across the eyeball's path).
const PUSH_ROUNDS: usize = 4;

/// How one eyeball followed its lids.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EyeFollowed {
    /// The scale its lids took.
    pub scale: f64,
    /// How far it was pushed back so no lid is inside (mm, mask scale).
    pub pushed_back_mm: f64,
}

/// Fills `field` (the change of every avatar vertex; set on the face
/// parts) for every vertex off the face parts (module docs). `positions`
/// is the avatar's stock rest; `to_avatar` avatar units per mm at the
/// mask's scale. Returns how each eyeball followed.
pub fn follow_skin(
    avatar: &Avatar,
    positions: &[DVec3],
    registration: &FaceRegistration,
    field: &mut [DVec3],
    to_avatar: f64,
) -> Vec<EyeFollowed> {
    let n = positions.len();
    let on_skin = skin_flags(avatar, registration);
    let skin: Vec<u32> = (0..n as u32).filter(|&v| on_skin[v as usize]).collect();

    // Pieces off the skin: connected components of the other triangles.
    let off_skin: Vec<[u32; 3]> = avatar
        .triangles()
        .iter()
        .copied()
        .filter(|t| t.iter().all(|&v| !on_skin[v as usize]))
        .collect();
    let all_pieces: Vec<Vec<u32>> = component_vertices(n, &off_skin)
        .into_iter()
        .filter(|c| !on_skin[c[0] as usize])
        .collect();
    let pieces = &all_pieces;
    let in_eyeball: HashSet<u32> = registration.eyeballs.iter().flatten().copied().collect();
    let mut done = on_skin.clone();

    // Eyeballs, and what lies within their spheres.
    let backward = -(registration.similarity.rotation * DVec3::Z).normalize_or_zero();
    let mut eyes = Vec::new();
    for vertices in &registration.eyeballs {
        let eyeball = Eyeball::new(positions, avatar.triangles_within(vertices));
        let reach = eyeball.radius + NEAR_MM * to_avatar;
        let near = |v: &u32| (positions[*v as usize] - eyeball.centre).length() <= reach;
        let lids: Vec<u32> = skin.iter().copied().filter(near).collect();
        let Some(mut fit) = carried(positions, field, &lids, |_| 1.0) else {
            continue;
        };
        let pushed = push_back(
            positions,
            field,
            &eyeball,
            &mut fit,
            &lids,
            backward,
            LID_OFFSET_MM * to_avatar,
        );
        let held: Vec<u32> = pieces
            .iter()
            .filter(|c| !done[c[0] as usize] && (c.iter().any(near) || vertices.contains(&c[0])))
            .flatten()
            .copied()
            .collect();
        for &v in vertices.iter().chain(&held) {
            let p = positions[v as usize];
            field[v as usize] = fit.apply(p) - p;
            done[v as usize] = true;
        }
        eyes.push(EyeFollowed {
            scale: fit.scale,
            pushed_back_mm: pushed / to_avatar,
        });
    }

    // The other pieces, in groups of those that touch.
    let pieces: Vec<&Vec<u32>> = pieces.iter().filter(|c| !done[c[0] as usize]).collect();
    // The searches below are independent: over the cores.
    let grids: Vec<TriangleTree> = in_parallel_map(pieces.len(), |i| {
        TriangleTree::new(positions, &avatar.triangles_within(pieces[i]))
    });
    let touch = TOUCH_MM * to_avatar;
    let mut group: Vec<usize> = (0..pieces.len()).collect();
    for a in 0..pieces.len() {
        for b in 0..a {
            let touching = pieces[a].iter().any(|&v| {
                grids[b]
                    .closest_within(positions[v as usize], touch)
                    .is_some()
            });
            if touching {
                let (ga, gb) = (group[a], group[b]);
                group.iter_mut().filter(|g| **g == ga).for_each(|g| *g = gb);
            }
        }
    }
    let reach = ANCHOR_MM * to_avatar;
    let mut groups: Vec<usize> = group.clone();
    groups.sort_unstable();
    groups.dedup();
    for g in groups {
        let members: Vec<usize> = (0..pieces.len()).filter(|&i| group[i] == g).collect();
        let near: Vec<(u32, f64)> = in_parallel_map(skin.len(), |k| {
            let v = skin[k];
            let distance = members
                .iter()
                .filter_map(|&i| grids[i].closest_within(positions[v as usize], reach))
                .map(|c| c.distance)
                .fold(f64::INFINITY, f64::min);
            (distance <= reach).then_some((v, 1.0 - distance / reach))
        })
        .into_iter()
        .flatten()
        .collect();
        let anchors: Vec<u32> = near.iter().map(|(v, _)| *v).collect();
        let Some(fit) = carried(positions, field, &anchors, |i| near[i].1) else {
            continue;
        };
        for &v in members.iter().flat_map(|&i| pieces[i].iter()) {
            let p = positions[v as usize];
            field[v as usize] = fit.apply(p) - p;
        }
    }

    // Near the skin, a piece that bends stays on it.
    let skin_triangles = avatar.part_triangles(&registration.face_parts());
    let grid = TriangleTree::new(positions, &skin_triangles);
    let (hold, free) = (HOLD_MM * to_avatar, FREE_MM * to_avatar);
    let own = avatar.moving_target_displacements();
    // Each vertex reads only the skin's field, which none of them is.
    let bending: Vec<u32> = all_pieces
        .iter()
        .filter(|piece| {
            !piece.iter().any(|v| in_eyeball.contains(v)) && !moves_rigidly(positions, &own, piece)
        })
        .flatten()
        .copied()
        .collect();
    let followed = in_parallel_map(bending.len(), |k| {
        let v = bending[k] as usize;
        let c = grid.closest_within(positions[v], free)?;
        let t = grid.triangles()[c.triangle];
        let on: DVec3 = (0..3)
            .map(|k| field[t[k] as usize] * c.barycentric[k])
            .sum();
        let own = ((c.distance - hold) / (free - hold)).clamp(0.0, 1.0);
        Some(field[v] * own + on * (1.0 - own))
    });
    for (&v, moved) in bending.iter().zip(followed) {
        if let Some(moved) = moved {
            field[v as usize] = moved;
        }
    }
    eyes
}

/// A uniform scaling about a centre and a shift, `x ↦ c' + s (x − c)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ScaleShift {
    /// `c`.
    pub from: DVec3,
    /// `c'`.
    pub to: DVec3,
    /// `s` (> 0).
    pub scale: f64,
}

impl ScaleShift {
    /// Maps a point.
    pub fn apply(&self, p: DVec3) -> DVec3 {
        self.to + (p - self.from) * self.scale
    }
}

/// The [`ScaleShift`] minimizing `Σ_i w_i ‖c' + s (p_i − c) − q_i‖²`:
/// `c`, `c'` the weighted centroids of `p` and `q`, and
/// `s = Σ w (p − c)·(q − c') / Σ w ‖p − c‖²`. `None` for fewer than two
/// weighted points, all in one place, or a scale that is not positive.
pub fn fit_scale_shift(p: &[DVec3], q: &[DVec3], w: &[f64]) -> Option<ScaleShift> {
    let total: f64 = w.iter().filter(|w| **w > 0.0).sum();
    if w.iter().filter(|w| **w > 0.0).count() < 2 || total <= 0.0 {
        return None;
    }
    let weighted =
        |x: &[DVec3]| x.iter().zip(w).map(|(x, w)| *x * w.max(0.0)).sum::<DVec3>() / total;
    let (from, to) = (weighted(p), weighted(q));
    let (mut across, mut spread) = (0.0, 0.0);
    for ((p, q), w) in p.iter().zip(q).zip(w) {
        let w = w.max(0.0);
        across += w * (*p - from).dot(*q - to);
        spread += w * (*p - from).length_squared();
    }
    let scale = across / spread;
    (spread > 0.0 && scale.is_finite() && scale > 0.0).then_some(ScaleShift { from, to, scale })
}

/// The [`ScaleShift`] carrying `anchors` from `positions` to `positions +
/// field`, anchor `i` weighed by `weight(i)`.
fn carried(
    positions: &[DVec3],
    field: &[DVec3],
    anchors: &[u32],
    weight: impl Fn(usize) -> f64,
) -> Option<ScaleShift> {
    let from: Vec<DVec3> = anchors.iter().map(|&v| positions[v as usize]).collect();
    let to: Vec<DVec3> = anchors
        .iter()
        .map(|&v| positions[v as usize] + field[v as usize])
        .collect();
    let w: Vec<f64> = (0..anchors.len()).map(weight).collect();
    fit_scale_shift(&from, &to, &w)
}

/// Shifts the eyeball's `fit` along `backward` until no lid in front of
/// it lies deeper inside it than on the stock avatar (`eyeball` at
/// `positions`); returns how far (avatar units). A lid that went deeper
/// is cleared by `clear` more, so the eye never shows through it at rest.
///
/// Only lids in front of the eyeball's centre count: pushing the eyeball
/// back draws it away from them, but into the skin that wraps round its
/// sides and back (a socket's lining, a head whose skin runs behind the
/// eye), which each round then sank deeper. Counted, they pushed
/// ICT-FaceKit's eyes back 4.5 mm when the avatar took its own face on
/// ARKit's mesh. A round that leaves the deepest lid no shallower is
/// undone and the pushing stops: an eyeball open at the back (MakeHuman's)
/// took its lids in through the opening as it went back, 2.6 mm for its
/// own face.
fn push_back(
    positions: &[DVec3],
    field: &[DVec3],
    eyeball: &Eyeball,
    fit: &mut ScaleShift,
    lids: &[u32],
    backward: DVec3,
    clear: f64,
) -> f64 {
    let front: Vec<u32> = lids
        .iter()
        .copied()
        .filter(|&v| (positions[v as usize] - eyeball.centre).dot(backward) < 0.0)
        .collect();
    // The eyeball was made over `positions`: its tree is the stock one.
    let allowed: Vec<f64> = front
        .iter()
        .map(|&v| depth(&eyeball.tree, positions[v as usize], eyeball.open))
        .collect();
    // How much deeper than at rest the deepest lid lies, with `fit`.
    let deepest = |fit: &ScaleShift| {
        let placed: Vec<DVec3> = eyeball
            .vertices
            .iter()
            .map(|&v| fit.apply(positions[v as usize]))
            .collect();
        let grid = eyeball.tree.moved_to(&placed);
        front
            .iter()
            .zip(&allowed)
            .map(|(&v, a)| {
                let d = depth(
                    &grid,
                    positions[v as usize] + field[v as usize],
                    eyeball.open,
                );
                if d > 0.0 { d - a } else { 0.0 }
            })
            .fold(0.0, f64::max)
    };
    let mut total = 0.0;
    let mut worst = deepest(fit);
    for _ in 0..PUSH_ROUNDS {
        if worst <= 0.0 {
            break;
        }
        let step = worst + clear;
        fit.to += backward * step;
        let after = deepest(fit);
        if after >= worst {
            fit.to -= backward * step;
            break;
        }
        total += step;
        worst = after;
    }
    total
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::test_shapes::uv_sphere;

    /// An eyeball of radius 1 looking along +Z, a lid resting on its front
    /// pole that sinks 0.1 into it, and skin resting against its back pole
    /// that does not move: the eyeball goes back by the lid's 0.1 and the
    /// clearance, once, and the skin behind it does not drive it further
    /// (counted, it sank as the eyeball went back and was pushed again,
    /// round after round).
    #[test]
    fn an_eyeball_is_pushed_back_from_the_lids_in_front_only() {
        let (mut positions, triangles) = uv_sphere(24, 32);
        let eyeball = Eyeball::new(&positions, triangles);
        let lid = positions.len() as u32;
        positions.push(DVec3::new(0.0, 0.0, 1.0));
        let behind = lid + 1;
        positions.push(DVec3::new(0.0, 0.0, -1.01));
        let mut field = vec![DVec3::ZERO; positions.len()];
        field[lid as usize] = DVec3::new(0.0, 0.0, -0.1);
        let mut fit = ScaleShift {
            from: DVec3::ZERO,
            to: DVec3::ZERO,
            scale: 1.0,
        };
        let clear = 0.02;
        let pushed = push_back(
            &positions,
            &field,
            &eyeball,
            &mut fit,
            &[lid, behind],
            -DVec3::Z,
            clear,
        );
        assert!((pushed - (0.1 + clear)).abs() < 1e-3, "{pushed}");
        assert!((fit.to - DVec3::new(0.0, 0.0, -pushed)).length() < 1e-12);
    }

    #[test]
    fn a_scaled_and_shifted_ring_gives_back_its_scale_and_shift() {
        let ring: Vec<DVec3> = (0..12)
            .map(|k| {
                let a = k as f64 * std::f64::consts::TAU / 12.0;
                DVec3::new(a.cos(), a.sin(), 0.3 * (2.0 * a).cos())
            })
            .collect();
        let moved: Vec<DVec3> = ring
            .iter()
            .map(|p| DVec3::new(0.5, -1.0, 2.0) + *p * 1.1)
            .collect();
        let fit = fit_scale_shift(&ring, &moved, &[1.0; 12]).expect("fits");
        assert!((fit.scale - 1.1).abs() < 1e-12);
        for (p, q) in ring.iter().zip(&moved) {
            assert!((fit.apply(*p) - *q).length() < 1e-12);
        }
        assert!(fit_scale_shift(&ring[..1], &moved[..1], &[1.0]).is_none());
        assert!(fit_scale_shift(&[DVec3::ONE; 3], &moved[..3], &[1.0; 3]).is_none());
    }
}
