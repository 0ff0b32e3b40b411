//! Where the avatar's lips part, by its own `jawOpen`: its artist made the
//! lower lip follow the mandible and the upper lip stay, so where a skin
//! vertex that moves with the jaw touches one that does not, the lips
//! part. The registered mask's slit is held there
//! ([`super::nonrigid::Landmark`], `find_face::slit_landmarks`): the
//! mask's surface alone can slide a
//! few millimetres along the lips' smooth fronts (on ICT-FaceKit it came
//! to rest 4–5 mm low, and the top of the lower lip took the upper lip's
//! motion).
//!
//! A vertex moves with the jaw when `jawOpen` moves it by at least
//! [`WITH_JAW`] of the most it moves any vertex near the mouth, and stays
//! when it moves by at most [`STILL`]. The lips part between a vertex that
//! moves with the jaw and the nearest that stays, where they lie within
//! [`TOUCHING_MM`] of each other: closed lips touch, whether the mesh
//! joins them or leaves a slit; over the cheeks the jaw's pull fades over
//! centimetres, and no such pair is that near. An avatar whose lips part
//! nowhere near the mask's slit gets no landmark.

use glam::DVec3;

/// Share of the largest `jawOpen` motion near the mouth from which a vertex
/// moves with the jaw (the lower lip moves 80–90% of the chin on
/// ICT-FaceKit and on the default avatar).
pub const WITH_JAW: f64 = 0.5;
/// Share up to which a vertex stays with the skull (the upper lip moves 6%
/// of the chin on ICT-FaceKit, none on the default avatar).
pub const STILL: f64 = 0.2;

/// How near a vertex that moves with the jaw and one that stays must lie
/// to be the two lips' (mm): relaxed closed lips touch or lie a fraction
/// of a millimetre apart; 3 mm allows for meshes whose lips' rows are
/// offset.
pub const TOUCHING_MM: f64 = 3.0;

/// The parting pairs (module docs) among the vertices of `triangles`
/// within `radius` of `around`, as (the vertex that moves with the jaw,
/// the nearest that stays): the two lips' edges where they part; `jaw` is
/// `jawOpen`'s displacement per vertex of `positions`, `mm` a millimetre
/// in the avatar's units. Empty without a parting there.
pub fn lips_parting(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    jaw: &[DVec3],
    around: DVec3,
    radius: f64,
    mm: f64,
) -> Vec<(DVec3, DVec3)> {
    let mut near: Vec<u32> = triangles
        .iter()
        .flatten()
        .copied()
        .filter(|&v| {
            positions
                .get(v as usize)
                .is_some_and(|p| p.distance(around) <= radius)
        })
        .collect();
    near.sort_unstable();
    near.dedup();
    let motion = |v: u32| jaw.get(v as usize).map_or(0.0, |d| d.length());
    let largest = near.iter().map(|&v| motion(v)).fold(0.0, f64::max);
    if largest.is_nan() || largest <= 0.0 {
        return Vec::new();
    }
    let moving: Vec<DVec3> = near
        .iter()
        .filter(|&&v| motion(v) >= WITH_JAW * largest)
        .map(|&v| positions[v as usize])
        .collect();
    let still: Vec<DVec3> = near
        .iter()
        .filter(|&&v| motion(v) <= STILL * largest)
        .map(|&v| positions[v as usize])
        .collect();
    moving
        .iter()
        .filter_map(|p| {
            let q = still
                .iter()
                .min_by(|a, b| a.distance_squared(*p).total_cmp(&b.distance_squared(*p)))?;
            (q.distance(*p) <= TOUCHING_MM * mm).then_some((*p, *q))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two rows of a strip 1 apart (a millimetre), the lower one moving with
    /// the jaw: each of its vertices pairs with the one above.
    #[test]
    fn the_lips_part_between_what_moves_and_what_stays() {
        let positions: Vec<DVec3> = (0..3)
            .flat_map(|x| {
                [
                    DVec3::new(x as f64, 1.0, 0.0),
                    DVec3::new(x as f64, 0.0, 0.0),
                ]
            })
            .collect();
        // Vertex 2i above, 2i + 1 below.
        let triangles = vec![[0, 1, 2], [2, 1, 3], [2, 3, 4], [4, 3, 5]];
        let jaw: Vec<DVec3> = (0..6)
            .map(|v| {
                if v % 2 == 1 {
                    DVec3::new(0.0, -1.0, 0.0)
                } else {
                    DVec3::ZERO
                }
            })
            .collect();
        let at = lips_parting(
            &positions,
            &triangles,
            &jaw,
            DVec3::new(1.0, 0.5, 0.0),
            5.0,
            1.0,
        );
        assert_eq!(at.len(), 3, "{at:?}");
        assert!(
            at.iter()
                .all(|(p, q)| p.y == 0.0 && q.y == 1.0 && p.x == q.x),
            "{at:?}"
        );
        // A jaw fading smoothly across the rows parts nothing.
        let smooth: Vec<DVec3> = jaw
            .iter()
            .map(|d| *d * 0.5 + DVec3::new(0.0, -0.4, 0.0))
            .collect();
        assert!(lips_parting(&positions, &triangles, &smooth, DVec3::ZERO, 5.0, 1.0).is_empty());
    }
}
