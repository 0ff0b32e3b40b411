//! Rigid parts stay rigid (§3.3: "the approximations `A_j` also bring
//! facial details not included in the ARKit mesh (eye balls and teeth) to
//! their desired position"). A piece (a connected component of a part
//! outside the face) is rigid when every one of the avatar's own targets
//! moves it rigidly (within [`RIGID_TOLERANCE`] of its size): eyeballs,
//! teeth, the gums, whether each is a mesh of its own or both jaws share
//! one ([`rigid_pieces`]). Pieces that every target moves as one body and
//! that overlap are one body, even across parts: an eye's sclera, iris and
//! pupil, often separate primitives, turn together, or the iris would
//! sink into the sclera where their fits differ. `A_j` mixes several targets, and
//! a sum of rotations is not a rotation: a rigid part's displacement in a
//! shape is replaced by the rigid motion closest to it (least squares,
//! [`fit_rigid`]), unless it is already as near a rigid motion as the
//! rig's own targets keep the piece ([`hold_rigid`]). The largest
//! deviation from a rigid motion, before and after, is reported per shape.

use crate::avatar::model::Avatar;
use crate::avatar::registration::similarity::fit_rigid;
use crate::geometry::connected_components::component_vertices;
use glam::DVec3;

/// A connected piece of the avatar that every own target moves rigidly.
#[derive(Clone, Debug, PartialEq)]
pub struct RigidPiece {
    /// The part (index into `Avatar::parts`) it was first found in (a
    /// piece joined across parts, an eye's sclera and iris, lies in
    /// several).
    pub part: usize,
    /// Its avatar vertices (global indices), increasing.
    pub vertices: Vec<u32>,
    /// The most any own target deviates from a rigid motion on it
    /// ([`rigid_deviation`], avatar units): how rigid the rig itself keeps
    /// it. A rig's eyeLook targets are often sculpted, not turned
    /// (MakeHuman's deviate by 0.4 mm on a 29 mm eyeball).
    pub own_deviation: f64,
}

/// The rigid pieces of `avatar` (rest `positions`, own target
/// displacements `own`): the connected components that hold no vertex of
/// the skin the mask lies on (`on_mask`, flags over the avatar's
/// vertices; a head whose eyeballs and teeth are loose pieces of the
/// skin's own primitive, as Rocketbox's, has them found here too) and
/// that each target moves rigidly within [`RIGID_TOLERANCE`] of their
/// size, gathered greedily into groups that move as one rigid
/// body (the teeth of one jaw, whether one mesh or one component each):
/// within a part, any such; across parts, those whose boxes at rest
/// overlap (an eye's sclera, iris and pupil; not a static accessory that
/// merely never moves either). Pieces, not parts: many rigs keep both
/// jaws' teeth and the gums in one mesh, where only the lower arch follows
/// `jawOpen`.
pub fn rigid_pieces(
    avatar: &Avatar,
    positions: &[DVec3],
    own: &[Vec<DVec3>],
    on_mask: &[bool],
) -> Vec<RigidPiece> {
    let offsets = avatar.vertex_offsets();
    let rigid = |vertices: &[u32]| {
        let tolerance = RIGID_TOLERANCE * size(positions, vertices);
        vertices.len() >= 3
            && own
                .iter()
                .all(|d| rigid_deviation(positions, d, vertices) <= tolerance)
    };
    let mut pieces: Vec<RigidPiece> = Vec::new();
    for (i, part) in avatar.parts().iter().enumerate() {
        let o = offsets[i] as u32;
        for component in component_vertices(part.positions.len(), &part.triangles) {
            let vertices: Vec<u32> = component.into_iter().map(|v| v + o).collect();
            let skin = vertices
                .iter()
                .any(|&v| on_mask.get(v as usize).copied().unwrap_or(false));
            if skin || !rigid(&vertices) {
                continue;
            }
            let reach = bounds(positions, &vertices);
            let near = |piece: &RigidPiece| {
                piece.part == i || overlap(bounds(positions, &piece.vertices), reach)
            };
            let joined = pieces.iter_mut().filter(|p| near(p)).find_map(|piece| {
                let mut union = piece.vertices.clone();
                union.extend(&vertices);
                rigid(&union).then(|| {
                    union.sort_unstable();
                    piece.vertices = union;
                })
            });
            if joined.is_none() {
                pieces.push(RigidPiece {
                    part: i,
                    vertices,
                    own_deviation: 0.0,
                });
            }
        }
    }
    for piece in &mut pieces {
        piece.own_deviation = own
            .iter()
            .map(|d| rigid_deviation(positions, d, &piece.vertices))
            .fold(0.0, f64::max);
    }
    pieces
}

/// The parts every vertex of which lies in some piece of `pieces`.
pub fn wholly_rigid_parts(avatar: &Avatar, pieces: &[RigidPiece]) -> Vec<usize> {
    let offsets = avatar.vertex_offsets();
    let mut in_piece = vec![false; offsets.last().copied().unwrap_or(0)];
    for &v in pieces.iter().flat_map(|p| &p.vertices) {
        if let Some(slot) = in_piece.get_mut(v as usize) {
            *slot = true;
        }
    }
    (0..avatar.parts().len())
        .filter(|&i| {
            offsets[i] < offsets[i + 1] && in_piece[offsets[i]..offsets[i + 1]].iter().all(|&x| x)
        })
        .collect()
}

/// The box (least and greatest corner) of `vertices` at rest.
fn bounds(rest: &[DVec3], vertices: &[u32]) -> (DVec3, DVec3) {
    vertices
        .iter()
        .filter_map(|&v| rest.get(v as usize))
        .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(*p), hi.max(*p))
        })
}

/// Whether two boxes share a point.
fn overlap(a: (DVec3, DVec3), b: (DVec3, DVec3)) -> bool {
    a.0.cmple(b.1).all() && b.0.cmple(a.1).all()
}

/// Largest deviation from a rigid motion, relative to the piece's size
/// (RMS radius), for a target to count as moving it rigidly. Rigs sculpt
/// their jaw shapes, so teeth that a bone would turn rigidly come out a
/// little deformed (a few per cent of a tooth's size; ICT-FaceKit's lower
/// teeth up to 2%), while parts that really bend are far off (a tongue
/// under tongueOut, the gums under jawOpen: 30% and more): the bound sits
/// between the two.
pub const RIGID_TOLERANCE: f64 = 0.05;

/// The largest distance between `rest + displacement` and the rigid motion
/// closest to it, over `vertices`; 0 for fewer than three, and for a
/// displacement that moves none of them (most targets leave the teeth and
/// eyeballs alone, and need no fit).
pub fn rigid_deviation(rest: &[DVec3], displacement: &[DVec3], vertices: &[u32]) -> f64 {
    let still = |v: &u32| {
        displacement
            .get(*v as usize)
            .is_none_or(|d| *d == DVec3::ZERO)
    };
    if vertices.iter().all(still) {
        return 0.0;
    }
    let (p, q) = pairs(rest, displacement, vertices);
    match fit_rigid(&p, &q, &vec![1.0; p.len()]) {
        Some(m) => p
            .iter()
            .zip(&q)
            .map(|(a, b)| (m.apply(*a) - *b).length())
            .fold(0.0, f64::max),
        None => 0.0,
    }
}

/// Relative slack on [`RigidPiece::own_deviation`] within which a shape
/// counts as as rigid as the rig's own ([`hold_rigid`]).
pub const OWN_DEVIATION_SLACK: f64 = 1e-6;

/// Replaces the displacement of `piece`'s vertices by the rigid motion
/// closest to it, unless it already lies as close to a rigid motion as
/// the rig's own targets do ([`RigidPiece::own_deviation`]: the rig's own
/// shape given back is the rig's own). Returns the largest deviation that
/// was removed.
pub fn hold_rigid(rest: &[DVec3], displacement: &mut [DVec3], piece: &RigidPiece) -> f64 {
    // The rig's own shape comes back through Eq. (4) with weights a few
    // ulps from one and the other targets' a few ulps from zero: within
    // [`OWN_DEVIATION_SLACK`] of the own deviation is the own.
    let allowed = piece.own_deviation * (1.0 + OWN_DEVIATION_SLACK);
    if rigid_deviation(rest, displacement, &piece.vertices) <= allowed {
        return 0.0;
    }
    make_rigid(rest, displacement, &piece.vertices)
}

/// Replaces the displacement of `vertices` by the rigid motion closest to
/// it. Returns the largest deviation that was removed.
pub fn make_rigid(rest: &[DVec3], displacement: &mut [DVec3], vertices: &[u32]) -> f64 {
    let (p, q) = pairs(rest, displacement, vertices);
    let Some(m) = fit_rigid(&p, &q, &vec![1.0; p.len()]) else {
        return 0.0;
    };
    let mut removed = 0.0f64;
    for &v in vertices {
        let v = v as usize;
        if let (Some(r), Some(d)) = (rest.get(v), displacement.get_mut(v)) {
            let rigid = m.apply(*r) - *r;
            removed = removed.max((rigid - *d).length());
            *d = rigid;
        }
    }
    removed
}

/// RMS distance of `vertices` from their centroid at rest.
pub fn size(rest: &[DVec3], vertices: &[u32]) -> f64 {
    let points: Vec<DVec3> = vertices
        .iter()
        .filter_map(|&v| rest.get(v as usize).copied())
        .collect();
    let n = points.len().max(1) as f64;
    let c = points.iter().sum::<DVec3>() / n;
    (points
        .iter()
        .map(|p| (*p - c).length_squared())
        .sum::<f64>()
        / n)
        .sqrt()
}

fn pairs(rest: &[DVec3], displacement: &[DVec3], vertices: &[u32]) -> (Vec<DVec3>, Vec<DVec3>) {
    vertices
        .iter()
        .filter_map(|&v| {
            let (r, d) = (rest.get(v as usize)?, displacement.get(v as usize)?);
            Some((*r, *r + *d))
        })
        .unzip()
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DMat3;

    /// Twenty points spread in 3D, no three in a line.
    fn cloud() -> Vec<DVec3> {
        (0..20)
            .map(|i| {
                let f = i as f64;
                DVec3::new((f * 0.9).sin(), (f * 0.4).cos(), (f * 1.7).sin() * 0.3)
            })
            .collect()
    }

    #[test]
    fn a_sum_of_rotations_is_made_rigid_and_a_rotation_is_left_alone() {
        let rest = cloud();
        let vertices: Vec<u32> = (0..20).collect();
        let turn = |a: f64| -> Vec<DVec3> {
            rest.iter()
                .map(|p| DMat3::from_rotation_x(a) * *p - *p)
                .collect()
        };
        let one = turn(0.35);
        assert!(rigid_deviation(&rest, &one, &vertices) < 1e-12);
        // Twice a rotation's displacement is not a rotation.
        let mut doubled: Vec<DVec3> = one.iter().map(|d| *d * 2.0).collect();
        assert!(rigid_deviation(&rest, &doubled, &vertices) > 0.05);
        make_rigid(&rest, &mut doubled, &vertices);
        assert!(rigid_deviation(&rest, &doubled, &vertices) < 1e-12);
    }

    #[test]
    fn a_shape_as_near_rigid_as_the_rigs_own_is_kept() {
        // A rig whose own target turns the piece and bends one vertex a
        // little (sculpted, not turned): the same shape given back is kept
        // as it is; twice the bend is made rigid.
        let rest = cloud();
        let mut sculpted: Vec<DVec3> = rest
            .iter()
            .map(|p| DMat3::from_rotation_y(0.2) * *p - *p)
            .collect();
        sculpted[3] += DVec3::new(0.0, 0.02, 0.0);
        let piece = RigidPiece {
            part: 0,
            vertices: (0..20).collect(),
            own_deviation: rigid_deviation(&rest, &sculpted, &(0..20).collect::<Vec<_>>()),
        };
        assert!(piece.own_deviation > 0.01);
        let mut same = sculpted.clone();
        assert_eq!(hold_rigid(&rest, &mut same, &piece), 0.0);
        assert_eq!(same, sculpted);
        let mut more = sculpted.clone();
        more[3] += DVec3::new(0.0, 0.02, 0.0);
        assert!(hold_rigid(&rest, &mut more, &piece) > 0.02);
        assert!(rigid_deviation(&rest, &more, &piece.vertices) < 1e-12);
    }

    #[test]
    fn an_eyes_parts_turn_as_one_body_and_a_still_far_part_stays_apart() {
        use crate::avatar::model::{AvatarMesh, AvatarPart};
        // A sclera (points on the unit sphere), an iris disc just inside
        // its front as a part of its own, and a far hat; the own targets
        // turn the eye's two parts about the centre and leave the hat.
        let fan = |n: u32| (1..n - 1).map(|i| [0, i, i + 1]).collect::<Vec<_>>();
        let sclera: Vec<DVec3> = (0..40)
            .map(|i| {
                let (t, p) = (0.3 + 2.5 * i as f64 / 40.0, 2.4 * i as f64);
                DVec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
            })
            .collect();
        let iris: Vec<DVec3> = (0..12)
            .map(|i| {
                let a = std::f64::consts::TAU * i as f64 / 12.0;
                DVec3::new(0.4 * a.cos(), 0.4 * a.sin(), 0.9)
            })
            .collect();
        let hat: Vec<DVec3> = (0..8)
            .map(|i| DVec3::new(5.0 + i as f64, 5.0, 5.0))
            .collect();
        let part = |name: &str, points: &[DVec3]| AvatarPart {
            name: name.into(),
            mesh: 0,
            primitive: 0,
            positions: points.iter().map(|p| p.as_vec3()).collect(),
            triangles: fan(points.len() as u32),
            targets: Vec::new(),
        };
        let avatar = Avatar::new(
            vec![AvatarMesh {
                name: None,
                target_names: Vec::new(),
            }],
            vec![
                part("sclera", &sclera),
                part("iris", &iris),
                part("hat", &hat),
            ],
        )
        .unwrap();
        let rest: Vec<DVec3> = [sclera, iris, hat].concat();
        let eye = 0..52;
        let turn = |m: DMat3| -> Vec<DVec3> {
            (rest.iter().enumerate())
                .map(|(v, p)| {
                    if eye.contains(&v) {
                        m * *p - *p
                    } else {
                        DVec3::ZERO
                    }
                })
                .collect()
        };
        let own = [
            turn(DMat3::from_rotation_x(0.3)),
            turn(DMat3::from_rotation_y(0.3)),
        ];
        let pieces = rigid_pieces(&avatar, &rest, &own, &[]);
        assert_eq!(pieces.len(), 2, "{pieces:?}");
        assert_eq!(pieces[0].vertices, (0..52).collect::<Vec<u32>>());
        assert_eq!(pieces[1].vertices, (52..60).collect::<Vec<u32>>());
        assert_eq!(wholly_rigid_parts(&avatar, &pieces), [0, 1, 2]);
        // A sum of both turns (what A_j mixes) made rigid keeps the iris
        // where it was on the sclera.
        let mut mixed: Vec<DVec3> = own[0].iter().zip(&own[1]).map(|(a, b)| *a + *b).collect();
        make_rigid(&rest, &mut mixed, &pieces[0].vertices);
        let posed = |v: usize| rest[v] + mixed[v];
        for (s, i) in [(0, 40), (7, 45), (39, 51)] {
            let before = rest[s].distance(rest[i]);
            assert!((posed(s).distance(posed(i)) - before).abs() < 1e-9);
        }
    }
}
