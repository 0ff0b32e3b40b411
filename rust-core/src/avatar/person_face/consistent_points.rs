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
//!
//! Which surface a point asks of is the skin's to say first. Points on
//! nearby skin (their triangles within two rings of each other) are one
//! surface; otherwise points on the skin of one lip are one surface and
//! points on the skin of the two are two; where the skin is of neither (or
//! of both, at a mouth's corner), the mask's lips decide. At a mouth's
//! corner both lips of ARKit's mask lie on the same few avatar triangles,
//! and told apart by the mask's lips alone, an upper-lip and a lower-lip
//! point on one triangle, asking changes a millimetre apart, were never
//! compared: the skin through both levered the corner vertex 18–27 mm away
//! from its neighbours (five people on ARKit's mesh, the default avatar;
//! now no skin vertex moves more than 6.3 mm from its neighbours' mean,
//! the lips' edges held together where the scan pulls them apart). Told
//! apart by the skin's lips alone, the points where a simulated person's
//! lips meet conflicted, and the face missed its scan there by up to
//! 1.85 mm; now 0–2 of them are left out and the face lies on its scan.

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

/// A point of the skin that asks for a change.
#[derive(Clone, Debug, PartialEq)]
pub struct AskedChange {
    /// Where it is (avatar units).
    pub at: DVec3,
    /// The change it asks for.
    pub change: DVec3,
    /// Its mask vertex's lips
    /// ([`crate::avatar::registration::lip_sides::LipSides::lips_of_vertex`]:
    /// bits, 0 off the lips).
    pub lips: u8,
    /// The lip of the skin it lies on, where all three corners of its
    /// triangle are of one lip (as `lips`; 0 off the lips, where the lips
    /// meet, or unknown).
    pub skin_lips: u8,
    /// The corners of its skin triangle and their neighbours (avatar
    /// vertices, increasing): the skin round it.
    pub patch: Vec<u32>,
}

impl AskedChange {
    /// Whether `self` and `other` ask of one surface (module docs): their
    /// patches share a vertex, or else the skin's lips, or else the
    /// mask's, say so.
    fn one_surface(&self, other: &AskedChange) -> bool {
        let touching = self
            .patch
            .iter()
            .any(|v| other.patch.binary_search(v).is_ok());
        if touching {
            return true;
        }
        if self.skin_lips != 0 && other.skin_lips != 0 {
            return self.skin_lips & other.skin_lips != 0;
        }
        self.lips == 0 || other.lips == 0 || self.lips & other.lips != 0
    }
}

/// The indices of `points` to keep, increasing; `mm` is a millimetre at
/// the mask's scale in avatar units (module docs).
pub fn consistent_points(points: &[AskedChange], mm: f64) -> Vec<usize> {
    let reach = NEIGHBOUR_MM * mm;
    let key = |p: DVec3| (p / reach).floor().as_ivec3().to_array();
    let mut cells: HashMap<[i32; 3], Vec<usize>> = HashMap::new();
    for (i, point) in points.iter().enumerate() {
        cells.entry(key(point.at)).or_default().push(i);
    }
    let mut conflicts: Vec<Vec<usize>> = vec![Vec::new(); points.len()];
    for (a, point) in points.iter().enumerate() {
        let [x, y, z] = key(point.at);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    for &b in cells.get(&[x + dx, y + dy, z + dz]).into_iter().flatten() {
                        let other = &points[b];
                        let apart = (other.at - point.at).length();
                        if b > a
                            && point.one_surface(other)
                            && apart < reach
                            && (other.change - point.change).length() > MAX_CHANGE_SLOPE * apart
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

    /// A point at `at` asking `change` (both in mm), of mask lips `lips`,
    /// on skin triangle `triangle`.
    fn point(at: [f64; 3], change: [f64; 3], lips: u8, triangle: [u32; 3]) -> AskedChange {
        let mm = 1e-3;
        AskedChange {
            at: DVec3::from(at) * mm,
            change: DVec3::from(change) * mm,
            lips,
            skin_lips: 0,
            patch: {
                let mut patch = triangle.to_vec();
                patch.sort_unstable();
                patch
            },
        }
    }

    /// `points`, each changed by `f`.
    fn each(points: &[AskedChange], f: impl Fn(&mut AskedChange)) -> Vec<AskedChange> {
        points
            .iter()
            .map(|p| {
                let mut p = p.clone();
                f(&mut p);
                p
            })
            .collect()
    }

    #[test]
    fn a_point_folded_onto_its_neighbour_is_dropped_and_smooth_ones_kept() {
        // A row of points 2 mm apart whose changes vary gently (0.1 per
        // unit distance), and one more 0.2 mm from the third asking for a
        // change 7 mm different: the fold.
        let mut points: Vec<AskedChange> = (0..6)
            .map(|k| {
                let x = 2.0 * k as f64;
                point([x, 0.0, 0.0], [0.0, 0.0, 0.1 * x], 0, [k, k + 10, k + 20])
            })
            .collect();
        points.push(point([4.2, 0.0, 0.0], [0.0, 0.0, 7.0], 0, [30, 31, 32]));
        assert_eq!(consistent_points(&points, 1e-3), vec![0, 1, 2, 3, 4, 5]);
    }

    #[test]
    fn far_points_never_conflict() {
        let points = vec![
            point([0.0; 3], [0.0; 3], 0, [0, 1, 2]),
            point([10.0, 0.0, 0.0], [0.0, 0.0, 9.0], 0, [0, 1, 2]),
        ];
        assert_eq!(consistent_points(&points, 1e-3), vec![0, 1]);
    }

    #[test]
    fn the_two_lips_part_as_they_please() {
        // The upper lip's edge 0.2 mm above the lower's, the person's
        // parted by 3 mm more than the avatar's: two surfaces, no fold.
        let points = vec![
            point([0.0; 3], [0.0, 1.5, 0.0], 1, [0, 1, 2]),
            point([0.0, -0.2, 0.0], [0.0, -1.5, 0.0], 2, [3, 4, 5]),
        ];
        assert_eq!(consistent_points(&points, 1e-3), vec![0, 1]);
        let one_lip = each(&points, |p| p.lips = 1);
        assert_eq!(consistent_points(&one_lip, 1e-3).len(), 1);
    }

    #[test]
    fn two_lips_on_one_piece_of_skin_are_one_surface() {
        // At a mouth's corner: an upper-lip and a lower-lip point 0.2 mm
        // apart on triangles that share a corner, asking changes 1 mm
        // apart. The skin through both would be levered out: one goes.
        let corner = vec![
            point([0.0; 3], [0.0, 3.4, 0.0], 1, [536, 1986, 168]),
            point([0.2, 0.0, 0.0], [0.0, 2.4, 0.0], 2, [535, 536, 168]),
        ];
        assert_eq!(consistent_points(&corner, 1e-3).len(), 1);
        // Without knowing the skin, the lips part.
        let unknown = each(&corner, |p| p.patch.clear());
        assert_eq!(consistent_points(&unknown, 1e-3).len(), 2);
        // Both on the lower lip's skin, though the mask says one is of
        // the upper: one surface, wherever the triangles are.
        let lower = each(&unknown, |p| p.skin_lips = 2);
        assert_eq!(consistent_points(&lower, 1e-3).len(), 1);
        // On the skin of the two lips, apart, they part, whatever the mask
        // says.
        let mut apart = each(&unknown, |p| p.lips = 1);
        apart[0].skin_lips = 1;
        apart[1].skin_lips = 2;
        assert_eq!(consistent_points(&apart, 1e-3).len(), 2);
    }
}
