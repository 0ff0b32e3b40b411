//! Finding the face on an avatar, fully automatically (§3.3): features
//! from both rigs' blendshapes place the mask roughly ([`super::features`]),
//! ICP with scale refines the placement ([`super::rigid_icp`]), non-rigid
//! registration lays the mask onto the avatar's skin
//! ([`super::nonrigid`]), and the correspondence map `M` is read off
//! ([`super::correspondence`]). Done once per avatar topology; the result
//! is cached by the caller under [`cache_key`].
//!
//! The avatar's eyeballs are left out of the surface the mask is fitted
//! to (the mask's lids would otherwise find the eyeball behind them): a
//! part is an eyeball when some eyeLook shape moves at least
//! [`EYEBALL_SHARE`] of its vertices. The face region is then taken only
//! from the parts the registered mask lies on (at least [`FACE_PART_SHARE`]
//! of its vertices closest to them): teeth and gums a millimetre behind
//! the lips are within reach of the mask but are not the face.

use super::correspondence::{CorrespondenceMap, correspondence_map};
use super::features::{REQUIRED, rig_features};
use super::nonrigid::register_nonrigid;
use super::rigid_icp::icp_with_scale;
use super::similarity::{Similarity, fit_similarity};
use crate::arkit::{Blendshape, Blendshapes};
use crate::avatar::model::Avatar;
use crate::avatar::target_names::arkit_targets;
use crate::geometry::Topology;
use crate::geometry::closest_point::TriangleGrid;
use glam::DVec3;
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// Share of a part's vertices an eyeLook shape must move for the part to
/// count as an eyeball.
pub const EYEBALL_SHARE: f64 = 0.9;

/// Share of the registered mask's vertices that must lie closest to a part
/// for the part to hold face region.
pub const FACE_PART_SHARE: f64 = 0.05;

/// A vertex of the avatar belongs to the face region when the registered
/// mask passes within this distance of it (mm of the mask's scale, so the
/// same on any avatar units).
pub const FACE_TOLERANCE_MM: f64 = 2.0;

/// The largest mean distance (mm, mask scale) of the registered mask from
/// the avatar's skin that still counts as a face found.
pub const MAX_MEAN_RESIDUAL_MM: f64 = 2.0;

/// The largest RMS disagreement of the features after their similarity
/// fit, as a share of the distance between the eyes, for them to be where
/// a face has them.
pub const MAX_FEATURE_MISFIT: f64 = 0.35;

/// Why no face was found.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum RegistrationError {
    /// The avatar lacks shapes the search starts from.
    #[error(
        "the avatar has no {0:?} target to find its face by (eyeBlinkLeft, eyeBlinkRight and jawOpen are needed)"
    )]
    MissingFeatureShapes(Vec<Blendshape>),
    /// The shapes exist but do not move where a face moves.
    #[error("the avatar's eyeBlink and jawOpen targets are not where a face has them (features disagree by {misfit:.0}% of the eye distance, at most {max:.0}%)", misfit = 100.0 * .0, max = 100.0 * MAX_FEATURE_MISFIT)]
    FeaturesNotFaceLike(f64),
    /// The mask could not be laid onto the avatar closely enough.
    #[error("no face found: the registered mask stays {mean_mm:.2} mm from the avatar's skin on average (at most {max:.1} mm)", max = MAX_MEAN_RESIDUAL_MM)]
    ResidualTooLarge {
        /// The mean distance reached (mm, mask scale).
        mean_mm: f64,
    },
    /// A registration system could not be solved.
    #[error(
        "the non-rigid registration could not be solved (no part of the mask matched the avatar)"
    )]
    Unsolvable,
}

/// The face found on an avatar.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FaceRegistration {
    /// Mask (metres, ARKit's face coordinates) → avatar (its units).
    pub similarity: Similarity,
    /// The mask's vertices registered onto the avatar (avatar units).
    pub mask_on_avatar: Vec<DVec3>,
    /// `M`.
    pub map: CorrespondenceMap,
    /// Mean and largest distance of the registered mask's vertices from
    /// the avatar's skin (mm, mask scale).
    pub residual_mean_mm: f64,
    /// See `residual_mean_mm`.
    pub residual_max_mm: f64,
    /// ICP iterations run.
    pub icp_iterations: usize,
    /// Parts taken for eyeballs (indices into `Avatar::parts`).
    pub eyeball_parts: Vec<usize>,
    /// Parts the face region was taken from.
    pub face_parts: Vec<usize>,
    /// Time the registration took (s).
    pub seconds: f64,
}

/// The displacement of every avatar vertex under ARKit shape `shape` (its
/// whole target or the sum of its halves); `None` if the avatar lacks it.
pub fn arkit_displacement(avatar: &Avatar, shape: Blendshape) -> Option<Vec<DVec3>> {
    let targets = arkit_targets(avatar);
    let ids = targets.of(shape);
    if ids.is_empty() {
        return None;
    }
    Some(
        avatar
            .summed_displacement(ids)
            .iter()
            .map(|d| d.as_dvec3())
            .collect(),
    )
}

/// Finds the face of `avatar` for the ARKit mask `mask` with generic shapes
/// `rig` (module docs).
pub fn find_face(
    avatar: &Avatar,
    mask: &Topology,
    rig: &Blendshapes,
) -> Result<FaceRegistration, RegistrationError> {
    let started = Instant::now();
    let positions: Vec<DVec3> = avatar.positions().iter().map(|p| p.as_dvec3()).collect();
    let offsets = avatar.vertex_offsets();
    let eyeball_parts = eyeball_parts(avatar, &offsets);
    let mut skin_triangles: Vec<[u32; 3]> = Vec::new();
    let mut part_of_triangle: Vec<usize> = Vec::new();
    for (i, part) in avatar.parts.iter().enumerate() {
        if eyeball_parts.contains(&i) {
            continue;
        }
        let o = offsets[i] as u32;
        for t in &part.triangles {
            if t.iter().all(|&v| (v as usize) < part.positions.len()) {
                skin_triangles.push(t.map(|v| v + o));
                part_of_triangle.push(i);
            }
        }
    }
    let skin = TriangleGrid::new(&positions, &skin_triangles);

    // Features, then the similarity they imply.
    let mask_features = rig_features(rig.neutral(), |b| Some(rig.delta(b).to_vec()));
    let avatar_features = rig_features(&positions, |b| arkit_displacement(avatar, b));
    let missing: Vec<Blendshape> = REQUIRED
        .into_iter()
        .filter(|b| !avatar_features.iter().any(|f| f.0 == *b))
        .collect();
    if !missing.is_empty() {
        return Err(RegistrationError::MissingFeatureShapes(missing));
    }
    let (p, q): (Vec<DVec3>, Vec<DVec3>) = mask_features
        .iter()
        .filter_map(|(b, f)| Some((*f, avatar_features.iter().find(|a| a.0 == *b)?.1)))
        .unzip();
    let initial = fit_similarity(&p, &q, &vec![1.0; p.len()])
        .ok_or(RegistrationError::FeaturesNotFaceLike(f64::INFINITY))?;
    let eye_distance = (p[0] - p[1]).length() * initial.scale;
    let misfit = (p
        .iter()
        .zip(&q)
        .map(|(a, b)| (initial.apply(*a) - *b).length_squared())
        .sum::<f64>()
        / p.len() as f64)
        .sqrt()
        / eye_distance.max(f64::MIN_POSITIVE);
    if misfit.is_nan() || misfit > MAX_FEATURE_MISFIT {
        return Err(RegistrationError::FeaturesNotFaceLike(misfit));
    }

    // ICP with scale, then non-rigid.
    let icp = icp_with_scale(rig.neutral(), &skin, initial);
    let placed: Vec<DVec3> = rig
        .neutral()
        .iter()
        .map(|p| icp.similarity.apply(*p))
        .collect();
    let registered =
        register_nonrigid(&placed, mask.triangles(), &skin).ok_or(RegistrationError::Unsolvable)?;
    let to_mm = 1000.0 / icp.similarity.scale;
    let finite: Vec<f64> = registered
        .distances
        .iter()
        .copied()
        .filter(|d| d.is_finite())
        .collect();
    let residual_mean_mm = finite.iter().sum::<f64>() / finite.len().max(1) as f64 * to_mm;
    let residual_max_mm = finite.iter().copied().fold(0.0, f64::max) * to_mm;
    if residual_mean_mm.is_nan() || residual_mean_mm > MAX_MEAN_RESIDUAL_MM {
        return Err(RegistrationError::ResidualTooLarge {
            mean_mm: residual_mean_mm,
        });
    }

    let mut hits = vec![0usize; avatar.parts.len()];
    for p in &registered.positions {
        if let Some(c) = skin.closest(*p)
            && let Some(&part) = part_of_triangle.get(c.triangle)
        {
            hits[part] += 1;
        }
    }
    let needed = FACE_PART_SHARE * registered.positions.len() as f64;
    let face_parts: Vec<usize> = (0..avatar.parts.len())
        .filter(|&i| hits[i] as f64 >= needed)
        .collect();
    let candidates = avatar
        .parts
        .iter()
        .enumerate()
        .filter(|(i, _)| face_parts.contains(i))
        .flat_map(|(i, part)| {
            (offsets[i]..offsets[i] + part.positions.len()).map(|v| (v, positions[v]))
        });
    let tolerance = FACE_TOLERANCE_MM / to_mm;
    let map = correspondence_map(
        candidates,
        &registered.positions,
        mask.triangles(),
        tolerance,
    );
    Ok(FaceRegistration {
        similarity: icp.similarity,
        mask_on_avatar: registered.positions,
        map,
        residual_mean_mm,
        residual_max_mm,
        icp_iterations: icp.iterations,
        eyeball_parts,
        face_parts,
        seconds: started.elapsed().as_secs_f64(),
    })
}

/// The parts that some eyeLook shape moves almost entirely (module docs).
fn eyeball_parts(avatar: &Avatar, offsets: &[usize]) -> Vec<usize> {
    let looks = [
        Blendshape::EyeLookOutLeft,
        Blendshape::EyeLookOutRight,
        Blendshape::EyeLookUpLeft,
        Blendshape::EyeLookUpRight,
    ];
    let fields: Vec<Vec<DVec3>> = looks
        .iter()
        .filter_map(|b| arkit_displacement(avatar, *b))
        .collect();
    let largest = fields
        .iter()
        .flatten()
        .map(|d| d.length())
        .fold(0.0, f64::max);
    (0..avatar.parts.len())
        .filter(|&i| {
            let range = offsets[i]..offsets[i + 1];
            !range.is_empty()
                && fields.iter().any(|f| {
                    let moved = f[range.clone()]
                        .iter()
                        .filter(|d| d.length() > 1e-3 * largest)
                        .count();
                    moved as f64 >= EYEBALL_SHARE * range.len() as f64
                })
        })
        .collect()
}

/// Version of the registration's rules: part of the cache key, so a cached
/// result from older rules is never taken for a new one.
pub const REGISTRATION_VERSION: u32 = 1;

/// The key a registration is cached under: the rules' version, the
/// avatar's vertex count and a CRC-32 of its rest geometry and triangles
/// and of the mask's neutral.
pub fn cache_key(avatar: &Avatar, rig: &Blendshapes) -> String {
    let mut hasher = crc32fast::Hasher::new();
    for part in &avatar.parts {
        for p in &part.positions {
            hasher.update(&p.x.to_le_bytes());
            hasher.update(&p.y.to_le_bytes());
            hasher.update(&p.z.to_le_bytes());
        }
        for t in &part.triangles {
            for i in t {
                hasher.update(&i.to_le_bytes());
            }
        }
    }
    for p in rig.neutral() {
        hasher.update(&p.x.to_le_bytes());
        hasher.update(&p.y.to_le_bytes());
        hasher.update(&p.z.to_le_bytes());
    }
    format!(
        "v{REGISTRATION_VERSION}-{}-{:08x}",
        avatar.vertex_count(),
        hasher.finalize()
    )
}
