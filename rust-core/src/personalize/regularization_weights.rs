//! Eq. (3): per-vertex regularization weights of the personalized fit.
//!
//! `(D_j)_{i,i} = max_k ‖t_{k,j} − t_{k,0}‖ / ‖t_{i,j} − t_{i,0}‖`, where
//! `t_{i,j} − t_{i,0}` is the displacement of vertex `i` in the generic
//! (transferred) blendshape `T_j`. A vertex that moves little in the template
//! gets a large weight, so it stays put in the personalized shape too; the
//! vertex that moves most gets weight 1. Where the template does not move at
//! all (`‖·‖ < ε`) the weight is clamped to [`MAX_WEIGHT`] = 10⁵, as the paper
//! does, to avoid dividing by zero.

use crate::arkit::Blendshapes;
use glam::DVec3;

/// The clamp of Eq. (3): the weight of a vertex the template does not move.
pub const MAX_WEIGHT: f64 = 1e5;

/// ε of Eq. (3) (m): displacements below 1 µm count as "does not move".
/// One micrometre is a tenth of the session file's 10 µm precision, so
/// nothing the phone reports as motion is clamped, and it is well above the
/// round-off of a deformation-transfer solve on a 15 cm face (~1e-12 m).
pub const STATIC_EPSILON: f64 = 1e-6;

/// Eq. (3) for one generic blendshape: one weight per vertex, each in
/// `[1, MAX_WEIGHT]`. A shape that moves no vertex by `STATIC_EPSILON` gets
/// `MAX_WEIGHT` everywhere.
pub fn regularization_weights(delta: &[DVec3]) -> Vec<f64> {
    let largest = delta.iter().map(|d| d.length()).fold(0.0, f64::max);
    delta
        .iter()
        .map(|d| {
            let moved = d.length();
            if moved < STATIC_EPSILON {
                MAX_WEIGHT
            } else {
                (largest / moved).min(MAX_WEIGHT)
            }
        })
        .collect()
}

/// Eq. (3) for each of the 52 generic blendshapes `T_j` of `generic`: the
/// diagonals of `D_1 … D_52`, in Apple's order.
pub fn regularization_weights_per_shape(generic: &Blendshapes) -> Vec<Vec<f64>> {
    generic
        .deltas()
        .iter()
        .map(|t| regularization_weights(t))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hand_made_case() {
        let delta = [
            DVec3::new(0.004, 0.0, 0.0),  // moves most: weight 1
            DVec3::new(0.0, 0.002, 0.0),  // half as far: weight 2
            DVec3::new(0.0, 0.0, 0.0001), // 1/40: weight 40
            DVec3::new(0.0, 0.0, 0.0),    // does not move: clamped
            DVec3::new(0.0, 5e-7, 0.0),   // below ε: clamped
            DVec3::new(0.0, 0.0, 3e-6),   // just above ε: 4e-3 / 3e-6 ≈ 1333
        ];
        let d = regularization_weights(&delta);
        assert_eq!(d[0], 1.0);
        assert_eq!(d[1], 2.0);
        assert!((d[2] - 40.0).abs() < 1e-12);
        assert_eq!(d[3], MAX_WEIGHT);
        assert_eq!(d[4], MAX_WEIGHT);
        assert!((d[5] - 4e-3 / 3e-6).abs() < 1e-9);
        assert!(d.iter().all(|w| (1.0..=MAX_WEIGHT).contains(w)));
    }

    #[test]
    fn a_shape_that_moves_nothing_is_clamped_everywhere() {
        let d = regularization_weights(&[DVec3::ZERO; 4]);
        assert!(d.iter().all(|w| *w == MAX_WEIGHT));
    }
}
