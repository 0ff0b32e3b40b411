//! The wanted changes the skin can take: no two points close together on
//! the skin may ask for changes further apart than the points are.
//!
//! A mask that differs in shape from the avatar's face can lie folded on
//! it. ARKit's own mesh curls into the mouth far more than most avatars'
//! lips do, so its registration lays the inner lip over the outer one:
//! two mask vertices 0.2 mm apart on the avatar's skin then ask for the
//! scanned positions of a lip's outside and inside, 7–8 mm apart. The skin
//! passing through both bends by that much over 0.2 mm, and the
//! bi-Laplacian overshoots round them into spikes (up to 230 mm on the
//! default avatar).
//!
//! For two points `a`, `b` within [`NEIGHBOUR_MM`] of each other on the
//! skin, with wanted changes `d_a`, `d_b`, the skin between them is
//! stretched or compressed by about `‖d_a − d_b‖ / ‖p_a − p_b‖`. Past
//! [`MAX_CHANGE_SLOPE`] the pair conflicts: the skin would tear (stretch
//! past twice its length, the torn-edge limit the avatar stage checks) or
//! fold over itself. The points with the most conflicts are dropped one at
//! a time until no conflict is left; a dropped point asks nothing of the
//! skin, and the field passes smoothly through the points round it. A
//! point of one lip whose skin is the other lip's (the map `M` says which
//! lip each avatar vertex is, `FaceRegistration::vertex_lips`) is folded
//! across the slit, and dropped before ([`across_the_slit`]).

use glam::DVec3;
use std::collections::HashMap;

/// Whether a mask vertex of one lip only (`mask_lips`) has its point on
/// skin of the other lip only (`skin_lips`: every corner of the skin's
/// triangle of that lip): folded across the slit.
pub fn across_the_slit(mask_lips: u8, skin_lips: u8) -> bool {
    matches!((mask_lips, skin_lips), (1, 2) | (2, 1))
}

/// Points closer than this on the skin (mm at the mask's scale) are
/// compared: about the mask's densest spacing at the lips and eyes
/// (ARKit's and the simulator's, 2–3.3 mm), so each point is compared with
/// its neighbours, and folds (points fractions of a millimetre apart) are
/// found.
pub const NEIGHBOUR_MM: f64 = 3.0;

/// The largest difference of two wanted changes per unit distance between
/// their points on the skin: at 1 the skin between them may double its
/// length (the limit at which the avatar stage counts an edge as torn) or
/// shrink to nothing. The person's face differs from an avatar's over
/// centimetres, not millimetres: on the simulator's mask the steepest pair
/// of the committed subjects is well under this.
pub const MAX_CHANGE_SLOPE: f64 = 1.0;

/// A point of the skin that asks for a change: where (avatar units), the
/// change, and its mask vertex's lips
/// ([`crate::avatar::registration::lip_sides::LipSides::lips_of_vertex`]:
/// bits, 0 off the lips).
pub type AskedChange = (DVec3, DVec3, u8);

/// The indices of `points` to keep, increasing; `mm` is a millimetre at
/// the mask's scale in avatar units (module docs).
pub fn consistent_points(points: &[AskedChange], mm: f64) -> Vec<usize> {
    let reach = NEIGHBOUR_MM * mm;
    let key = |p: DVec3| (p / reach).floor().as_ivec3().to_array();
    let mut cells: HashMap<[i32; 3], Vec<usize>> = HashMap::new();
    for (i, (p, _, _)) in points.iter().enumerate() {
        cells.entry(key(*p)).or_default().push(i);
    }
    let mut conflicts: Vec<Vec<usize>> = vec![Vec::new(); points.len()];
    for (a, (p, d, lips)) in points.iter().enumerate() {
        let [x, y, z] = key(*p);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    for &b in cells.get(&[x + dx, y + dy, z + dz]).into_iter().flatten() {
                        let (q, e, other_lips) = points[b];
                        let apart = (q - *p).length();
                        let one_surface = *lips == 0 || other_lips == 0 || lips & other_lips != 0;
                        if b > a
                            && one_surface
                            && apart < reach
                            && (e - *d).length() > MAX_CHANGE_SLOPE * apart
                        {
                            conflicts[a].push(b);
                            conflicts[b].push(a);
                        }
                    }
                }
            }
        }
    }
    let mut dropped = vec![false; points.len()];
    let mut count: Vec<usize> = conflicts.iter().map(Vec::len).collect();
    // The point in most conflicts first, the lowest index among equals,
    // so the outcome does not depend on hashing.
    while let Some((worst, _)) = count
        .iter()
        .enumerate()
        .filter(|(_, c)| **c > 0)
        .max_by(|a, b| a.1.cmp(b.1).then(b.0.cmp(&a.0)))
    {
        dropped[worst] = true;
        count[worst] = 0;
        for &other in &conflicts[worst] {
            if !dropped[other] {
                count[other] -= 1;
            }
        }
    }
    (0..points.len()).filter(|i| !dropped[*i]).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_folded_onto_its_neighbour_is_dropped_and_smooth_ones_kept() {
        let mm = 1e-3;
        // A row of points 2 mm apart whose changes vary gently (0.1 per
        // unit distance), and one more 0.2 mm from the third asking for a
        // change 7 mm different: the fold.
        let mut points: Vec<AskedChange> = (0..6)
            .map(|k| {
                let x = 2.0 * k as f64 * mm;
                (DVec3::new(x, 0.0, 0.0), DVec3::new(0.0, 0.0, 0.1 * x), 0)
            })
            .collect();
        points.push((
            DVec3::new(4.2 * mm, 0.0, 0.0),
            DVec3::new(0.0, 0.0, 7.0 * mm),
            0,
        ));
        assert_eq!(consistent_points(&points, mm), vec![0, 1, 2, 3, 4, 5]);
    }

    #[test]
    fn far_points_never_conflict() {
        let mm = 1e-3;
        let points = vec![
            (DVec3::ZERO, DVec3::ZERO, 0),
            (
                DVec3::new(10.0 * mm, 0.0, 0.0),
                DVec3::new(0.0, 0.0, 9.0 * mm),
                0,
            ),
        ];
        assert_eq!(consistent_points(&points, mm), vec![0, 1]);
    }

    #[test]
    fn the_two_lips_part_as_they_please() {
        let mm = 1e-3;
        // The upper lip's edge 0.2 mm above the lower's, the person's
        // parted by 3 mm more than the avatar's: two surfaces, no fold.
        let points = vec![
            (DVec3::ZERO, DVec3::new(0.0, 1.5 * mm, 0.0), 1),
            (
                DVec3::new(0.0, -0.2 * mm, 0.0),
                DVec3::new(0.0, -1.5 * mm, 0.0),
                2,
            ),
        ];
        assert_eq!(consistent_points(&points, mm), vec![0, 1]);
        let one_lip: Vec<AskedChange> = points.iter().map(|(p, d, _)| (*p, *d, 1)).collect();
        assert_eq!(consistent_points(&one_lip, mm).len(), 1);
    }
}
