//! Features that both rigs define by their blendshapes: where a shape moves
//! its mesh the most. They place the ARKit mask on any avatar roughly,
//! whatever its units, orientation and origin, before ICP refines it.
//!
//! For a shape with displacement `d_v` at rest position `p_v`, the feature
//! is the motion-weighted centroid of the vertices that move at least
//! [`FEATURE_SHARE`] of the most any vertex moves:
//!
//! ```text
//! f = Σ_{v: ‖d_v‖ ≥ κ max‖d‖} ‖d_v‖ p_v / Σ ‖d_v‖.
//! ```
//!
//! eyeBlinkLeft/Right find the upper lids, jawOpen the chin, the smiles
//! the mouth corners, browInnerUp the inner brows. The first three are
//! required (three points fix a similarity); the others are used when the
//! avatar has them.

use crate::arkit::Blendshape;
use glam::DVec3;

/// κ: share of the largest motion from which a vertex counts for a feature.
pub const FEATURE_SHARE: f64 = 0.8;

/// The shapes whose features must exist on both rigs.
pub const REQUIRED: [Blendshape; 3] = [
    Blendshape::EyeBlinkLeft,
    Blendshape::EyeBlinkRight,
    Blendshape::JawOpen,
];

/// Further shapes whose features are used when both rigs have them.
pub const OPTIONAL: [Blendshape; 5] = [
    Blendshape::MouthSmileLeft,
    Blendshape::MouthSmileRight,
    Blendshape::BrowInnerUp,
    Blendshape::NoseSneerLeft,
    Blendshape::NoseSneerRight,
];

/// The features every rig places alike, held through the whole non-rigid
/// fit ([`super::nonrigid::Landmark::held`]). The blink's is the middle of
/// the upper lid's margin, which is where any blink moves most: on our own
/// variants (other proportions, low-poly, bones for eyes) the registered
/// mask's blink feature lies within 1.5 mm of the avatar's. The others
/// depend on how the rig's artist made the shape: `jawOpen` moves the
/// chin most on one rig and the lower lip on another (20 mm apart on
/// ICT-FaceKit), `noseSneer` the nostril's wing or the crease above it
/// (17 mm); they only bring the mask near and then fade.
pub const HELD: [Blendshape; 2] = [Blendshape::EyeBlinkLeft, Blendshape::EyeBlinkRight];

/// The feature of one shape (module docs): `None` when it moves nothing.
pub fn feature_point(rest: &[DVec3], displacement: &[DVec3]) -> Option<DVec3> {
    let weights = feature_weights(displacement)?;
    Some(
        weights
            .iter()
            .map(|&(v, w)| rest.get(v).copied().unwrap_or(DVec3::ZERO) * w)
            .sum(),
    )
}

/// The feature of one shape as a combination of vertices: each vertex
/// that moves at least κ of the most, weighted by its motion, the weights
/// summing to one (module docs); `None` when the shape moves nothing.
pub fn feature_weights(displacement: &[DVec3]) -> Option<Vec<(usize, f64)>> {
    let motion: Vec<f64> = displacement.iter().map(|d| d.length()).collect();
    let largest = motion.iter().copied().fold(0.0, f64::max);
    if !(largest > 0.0 && largest.is_finite()) {
        return None;
    }
    let chosen: Vec<(usize, f64)> = motion
        .iter()
        .enumerate()
        .filter(|(_, m)| **m >= FEATURE_SHARE * largest)
        .map(|(v, m)| (v, *m))
        .collect();
    let total: f64 = chosen.iter().map(|c| c.1).sum();
    (total > 0.0).then(|| chosen.into_iter().map(|(v, m)| (v, m / total)).collect())
}

/// Features of a rig with rest positions `rest` and per-shape displacements
/// from `shape` (`None` where the rig lacks the shape), for the
/// [`REQUIRED`] and [`OPTIONAL`] shapes it has.
pub fn rig_features(
    rest: &[DVec3],
    mut shape: impl FnMut(Blendshape) -> Option<Vec<DVec3>>,
) -> Vec<(Blendshape, DVec3)> {
    REQUIRED
        .into_iter()
        .chain(OPTIONAL)
        .filter_map(|b| Some((b, feature_point(rest, &shape(b)?)?)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_feature_is_where_the_shape_moves_most() {
        let rest: Vec<DVec3> = (0..10).map(|i| DVec3::new(i as f64, 0.0, 0.0)).collect();
        let mut d = vec![DVec3::ZERO; 10];
        d[3] = DVec3::Y;
        d[4] = DVec3::Y * 0.9;
        d[8] = DVec3::Y * 0.1;
        let f = feature_point(&rest, &d).expect("moves");
        assert!((f.x - (3.0 + 0.9 * 4.0) / 1.9).abs() < 1e-12);
        assert_eq!(feature_point(&rest, &[DVec3::ZERO; 10]), None);
    }
}
