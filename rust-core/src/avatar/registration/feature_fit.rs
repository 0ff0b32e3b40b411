//! The similarity that both rigs' features imply ([`super::features`]),
//! with the optional features that disagree left out.
//!
//! Artists place some shapes where ARKit does not: MPFB's `noseSneer`
//! wrinkles the skin between the brows, 17 mm above the lid, where ARKit's
//! lifts the nostril's wing. One such feature skews the fit of all of them
//! (MPFB/MakeHuman: RMS misfit 39% of the eye distance with both sneers,
//! 6% without). So the fit is robust: starting from every matched
//! feature, the optional one farthest from its partner after the fit is
//! left out while it lies more than [`OUTLIER_SHARE`] of the eye distance
//! away, and the fit is made again; but never more of them than are kept,
//! so that the fit stays decided by features that agree (three points
//! alone fit almost any triangle, a face upside down among them). The
//! [`super::features::REQUIRED`] features are never left out: a rig whose
//! blinks and jaw disagree with a face is not a face, and
//! [`MAX_FEATURE_MISFIT`] decides that over what remains.

use super::features::REQUIRED;
use super::similarity::{Similarity, fit_similarity};
use crate::arkit::Blendshape;
use glam::DVec3;

/// An optional feature farther than this share of the eye distance from
/// its partner after the fit is left out. Two rigs that place a shape on
/// the same part of the face disagree by less: ICT-FaceKit's `noseSneer`
/// lifts the crease above the nostril's wing, ARKit's the wing itself,
/// 14% of the eye distance apart; our own variants stay within 10%. A
/// quarter of the eye distance (about 16 mm on a face) is another part of
/// the face.
pub const OUTLIER_SHARE: f64 = 0.25;

/// The largest RMS disagreement of the kept features after their
/// similarity fit, as a share of the distance between the eyes, for them
/// to be where a face has them.
pub const MAX_FEATURE_MISFIT: f64 = 0.35;

/// One shape's feature on the mask's rig (`mask`) and on the avatar's
/// (`avatar`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FeaturePair {
    /// The shape.
    pub shape: Blendshape,
    /// Its feature on the mask's rig.
    pub mask: DVec3,
    /// Its feature on the avatar.
    pub avatar: DVec3,
}

/// The features' fit (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct FeatureFit {
    /// The similarity taking the mask's features onto the avatar's.
    pub similarity: Similarity,
    /// The features it was fitted to, the required ones first.
    pub kept: Vec<FeaturePair>,
    /// The optional features left out, with how far each lay from its
    /// partner when it was left out (share of the eye distance).
    pub left_out: Vec<(Blendshape, f64)>,
    /// The RMS disagreement of the kept features after the fit, as a share
    /// of the distance between the avatar's eyes (the blinks' features).
    pub misfit: f64,
}

/// Why the features imply no placement.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FeatureFitError {
    /// Fewer than three features, or the mask's all in one point.
    Degenerate,
    /// The kept features disagree by this share of the eye distance
    /// (more than [`MAX_FEATURE_MISFIT`]).
    NotFaceLike(f64),
}

/// Fits the similarity to `pairs` (the [`REQUIRED`] shapes among them),
/// leaving out optional features that disagree (module docs).
pub fn fit_features(pairs: &[FeaturePair]) -> Result<FeatureFit, FeatureFitError> {
    let mut kept: Vec<FeaturePair> = REQUIRED
        .iter()
        .filter_map(|b| pairs.iter().find(|p| p.shape == *b).copied())
        .collect();
    let required = kept.len();
    kept.extend(pairs.iter().filter(|p| !REQUIRED.contains(&p.shape)));
    let mut left_out = Vec::new();
    loop {
        let fit = fit_kept(&kept)?;
        let worst = (required..kept.len())
            .map(|i| (i, fit.1[i]))
            .max_by(|a, b| a.1.total_cmp(&b.1));
        match worst {
            Some((i, off)) if off > OUTLIER_SHARE && left_out.len() + 1 < kept.len() - required => {
                left_out.push((kept.remove(i).shape, off));
            }
            _ => {
                let misfit = (fit.1.iter().map(|r| r * r).sum::<f64>() / kept.len() as f64).sqrt();
                if misfit.is_nan() || misfit > MAX_FEATURE_MISFIT {
                    return Err(FeatureFitError::NotFaceLike(misfit));
                }
                return Ok(FeatureFit {
                    similarity: fit.0,
                    kept,
                    left_out,
                    misfit,
                });
            }
        }
    }
}

/// The similarity fitted to `kept` and each feature's distance from its
/// partner after it, as a share of the eye distance.
fn fit_kept(kept: &[FeaturePair]) -> Result<(Similarity, Vec<f64>), FeatureFitError> {
    let p: Vec<DVec3> = kept.iter().map(|k| k.mask).collect();
    let q: Vec<DVec3> = kept.iter().map(|k| k.avatar).collect();
    let similarity =
        fit_similarity(&p, &q, &vec![1.0; p.len()]).ok_or(FeatureFitError::Degenerate)?;
    let eye_distance = match (p.first(), p.get(1)) {
        (Some(a), Some(b)) => (*a - *b).length() * similarity.scale,
        _ => return Err(FeatureFitError::Degenerate),
    };
    if eye_distance.is_nan() || eye_distance <= 0.0 {
        return Err(FeatureFitError::Degenerate);
    }
    let off = p
        .iter()
        .zip(&q)
        .map(|(a, b)| (similarity.apply(*a) - *b).length() / eye_distance)
        .collect();
    Ok((similarity, off))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A face's features, in millimetres: blinks, jaw, smiles, inner brow,
    /// sneers.
    fn face() -> Vec<(Blendshape, DVec3)> {
        vec![
            (Blendshape::EyeBlinkLeft, DVec3::new(32.0, 35.0, 0.0)),
            (Blendshape::EyeBlinkRight, DVec3::new(-32.0, 35.0, 0.0)),
            (Blendshape::JawOpen, DVec3::new(0.0, -60.0, 5.0)),
            (Blendshape::MouthSmileLeft, DVec3::new(25.0, -30.0, 0.0)),
            (Blendshape::MouthSmileRight, DVec3::new(-25.0, -30.0, 0.0)),
            (Blendshape::BrowInnerUp, DVec3::new(0.0, 50.0, 5.0)),
            (Blendshape::NoseSneerLeft, DVec3::new(12.0, 0.0, 15.0)),
            (Blendshape::NoseSneerRight, DVec3::new(-12.0, 0.0, 15.0)),
        ]
    }

    /// The face placed by `x ↦ 0.01 x + (1, 2, 3)`, rotated a quarter turn
    /// about y (an avatar in other units and facing).
    fn placed(p: DVec3) -> DVec3 {
        DVec3::new(p.z, p.y, -p.x) * 0.01 + DVec3::new(1.0, 2.0, 3.0)
    }

    fn pairs(moved: &[(Blendshape, DVec3)]) -> Vec<FeaturePair> {
        face()
            .into_iter()
            .map(|(shape, mask)| {
                let shift = moved
                    .iter()
                    .find(|m| m.0 == shape)
                    .map_or(DVec3::ZERO, |m| m.1);
                FeaturePair {
                    shape,
                    mask,
                    avatar: placed(mask + shift),
                }
            })
            .collect()
    }

    #[test]
    fn features_that_agree_are_all_kept() {
        let fit = fit_features(&pairs(&[])).expect("a face");
        assert_eq!(fit.kept.len(), 8);
        assert!(fit.left_out.is_empty());
        assert!(fit.misfit < 1e-9, "{}", fit.misfit);
        assert!((fit.similarity.scale - 0.01).abs() < 1e-12);
    }

    #[test]
    fn sneers_between_the_brows_are_left_out_and_the_rest_placed_right() {
        // MPFB's sneers: up between the brows, not at the nostrils.
        let up = DVec3::new(0.0, 52.0, -10.0);
        let moved = [
            (Blendshape::NoseSneerLeft, up - DVec3::X * 4.0),
            (Blendshape::NoseSneerRight, up + DVec3::X * 4.0),
        ];
        let fit = fit_features(&pairs(&moved)).expect("still a face");
        let out: Vec<Blendshape> = fit.left_out.iter().map(|l| l.0).collect();
        assert_eq!(out.len(), 2, "{out:?}");
        assert!(
            out.contains(&Blendshape::NoseSneerLeft) && out.contains(&Blendshape::NoseSneerRight)
        );
        assert!(fit.left_out.iter().all(|l| l.1 > OUTLIER_SHARE));
        assert!(fit.misfit < 1e-9);
        let p = DVec3::new(10.0, 20.0, 30.0);
        assert!((fit.similarity.apply(p) - placed(p)).length() < 1e-9);
    }

    #[test]
    fn a_small_disagreement_is_kept() {
        // 8 mm, an eighth of the eye distance: another artist's sneer.
        let moved = [(Blendshape::NoseSneerLeft, DVec3::new(0.0, 8.0, 0.0))];
        let fit = fit_features(&pairs(&moved)).expect("a face");
        assert!(fit.left_out.is_empty());
        assert_eq!(fit.kept.len(), 8);
    }

    #[test]
    fn required_features_that_disagree_are_not_a_face() {
        // The jaw's feature up on the forehead: never left out, refused.
        let moved = [(Blendshape::JawOpen, DVec3::new(0.0, 160.0, 0.0))];
        match fit_features(&pairs(&moved)) {
            Err(FeatureFitError::NotFaceLike(m)) => assert!(m > MAX_FEATURE_MISFIT, "{m}"),
            other => panic!("{other:?}"),
        }
        assert_eq!(
            fit_features(&pairs(&[])[..2]),
            Err(FeatureFitError::Degenerate)
        );
    }
}
