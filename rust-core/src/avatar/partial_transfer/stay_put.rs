//! What nothing moves stays put (beyond the paper). The face step solves
//! for the whole face patch at once and step 2 interpolates across the
//! head, so a shape the person makes with the eyes alone leaves a small,
//! smooth drift everywhere else (a blink moved most of the default head by
//! up to 0.9 mm). Such motion is wrong twice: the avatar's cheek does not
//! move when the person's does not, and every moved vertex is stored in
//! the GLB's target.
//!
//! A vertex of the face parts *moves* in shape `j` when the person's mask
//! moves its face point by more than [`STILL_MM`], or the avatar's own
//! target `Ã_j` moves it at all, or the retargeted `A_j` moves it by more
//! than [`STILL_MM`]. Every other vertex's displacement is faded out with
//! its distance `d` along the surface from the nearest moving vertex:
//!
//! ```text
//! w(d) = ½ (1 + cos(π d / F))  for d < F,   0 beyond,
//! ```
//!
//! with `F` = [`FADE_MM`]: smooth (no crease where the fade starts or
//! ends), and a drift of `δ` faded over `F` strains the skin by at most
//! `π δ / 2F`, 14% for the 0.9 mm drift: no edge tears.

use crate::geometry::edge_distance::EdgeGraph;
use glam::DVec3;
use std::f64::consts::PI;

/// Motion below this (mm, mask scale) is not a motion the person or the
/// retargeting makes: a tenth of a millimetre, well below the TrueDepth
/// camera's depth noise (about 1 mm at arm's length) and so below anything
/// a capture can tell.
pub const STILL_MM: f64 = 0.1;

/// `F`: the band (mm along the skin, mask scale) over which a drift fades
/// to zero next to what moves (module docs): about the width of an eyelid,
/// so a blink's fade stays on the lids' surroundings.
pub const FADE_MM: f64 = 10.0;

/// `w(d)` of the module docs.
pub fn fade_weight(d: f64, fade: f64) -> f64 {
    if d >= fade {
        0.0
    } else {
        0.5 * (1.0 + (PI * d / fade).cos())
    }
}

/// The fade of the module docs, prepared once for every shape: the face
/// parts' edge graph and which vertices are on them.
pub struct StillFade {
    graph: EdgeGraph,
    on_parts: Vec<bool>,
    fade: f64,
}

impl StillFade {
    /// The fade over the face parts' `triangles` (avatar indices) with
    /// `positions` the avatar at rest and `fade` the band `F` in avatar
    /// units.
    pub fn new(positions: &[DVec3], triangles: &[[u32; 3]], fade: f64) -> StillFade {
        let mut on_parts = vec![false; positions.len()];
        for &v in triangles.iter().flatten() {
            if let Some(x) = on_parts.get_mut(v as usize) {
                *x = true;
            }
        }
        StillFade {
            graph: EdgeGraph::new(positions, triangles),
            on_parts,
            fade,
        }
    }

    /// Fades one shape's `displacement` (every avatar vertex) out on the
    /// face parts' vertices away from `moving` ones (module docs).
    /// Vertices outside the face parts are left alone. Returns how many
    /// vertices were changed.
    pub fn apply(&self, displacement: &mut [DVec3], moving: &[bool]) -> usize {
        let distance = self.graph.distances(moving, self.fade);
        let mut changed = 0;
        for (v, d) in displacement.iter_mut().enumerate() {
            let (Some(true), Some(&dist)) = (self.on_parts.get(v), distance.get(v)) else {
                continue;
            };
            let w = fade_weight(dist, self.fade);
            if w < 1.0 && *d != DVec3::ZERO {
                *d *= w;
                changed += 1;
            }
        }
        changed
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_weight_is_one_at_what_moves_and_zero_from_the_band_on() {
        assert_eq!(fade_weight(0.0, 10.0), 1.0);
        assert!((fade_weight(5.0, 10.0) - 0.5).abs() < 1e-12);
        assert_eq!(fade_weight(10.0, 10.0), 0.0);
        assert_eq!(fade_weight(30.0, 10.0), 0.0);
    }

    #[test]
    fn a_drift_fades_along_a_strip_and_vertices_off_the_parts_are_left() {
        // A strip of unit squares along x: vertices 2i at (i, 0), 2i+1 at
        // (i, 1); vertex 0 moves, everything drifts by 1; vertex 20 is not
        // on the strip.
        let mut p: Vec<DVec3> = (0..10)
            .flat_map(|i| {
                [
                    DVec3::new(i as f64, 0.0, 0.0),
                    DVec3::new(i as f64, 1.0, 0.0),
                ]
            })
            .collect();
        p.push(DVec3::splat(50.0));
        let t: Vec<[u32; 3]> = (0..9u32)
            .flat_map(|i| {
                [
                    [2 * i, 2 * i + 2, 2 * i + 1],
                    [2 * i + 1, 2 * i + 2, 2 * i + 3],
                ]
            })
            .collect();
        let mut d = vec![DVec3::X; p.len()];
        let mut moving = vec![false; p.len()];
        moving[0] = true;
        StillFade::new(&p, &t, 4.0).apply(&mut d, &moving);
        assert_eq!(d[0], DVec3::X);
        assert!((d[4].x - 0.5).abs() < 1e-12, "2 from the mover: half");
        assert_eq!(d[8], DVec3::ZERO, "4 away: faded out");
        assert_eq!(d[18], DVec3::ZERO);
        assert_eq!(d[20], DVec3::X, "not on the parts: left alone");
    }
}
