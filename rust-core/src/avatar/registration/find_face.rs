//! Finding the face on an avatar, fully automatically (§3.3): features
//! from both rigs' blendshapes place the mask roughly ([`super::features`]),
//! ICP with scale refines the placement ([`super::rigid_icp`]), optimal-step
//! non-rigid ICP lays the mask onto the avatar's skin, the features held as
//! landmarks while it is stiff ([`super::nonrigid`]), and the
//! correspondence map `M` is read off ([`super::correspondence`]). Done
//! once per avatar topology; the result is cached by the caller under
//! [`cache_key`].
//!
//! Only the avatar's triangles near the placed mask take part (within
//! [`REACH`] of the mask's radius of its centre): on a full-body avatar
//! the hands and feet are never the face, and leaving them out keeps the
//! closest-point search small. Of those, only the triangles seen from in
//! front of the placed mask take part
//! ([`crate::geometry::front_visibility`]): the ARKit mask is the surface
//! a depth camera sees, so teeth behind closed lips, the mouth's lining
//! and the inside of the nostrils are never its place. The eyeballs
//! ([`super::eyeballs`]) are left out too (the mask's lids would
//! otherwise find the eyeball behind them). The face region is then taken only from the parts the
//! registered mask lies on (at least [`FACE_PART_SHARE`] of its vertices
//! closest to them): teeth and gums a millimetre behind the lips are
//! within reach of the mask but are not the face.
//!
//! Whether a face was found does not depend on how closely the mask's
//! face and the avatar's agree in shape (the non-rigid step absorbs
//! that), only on whether the mask could be laid onto the avatar: at
//! least [`MIN_COVERAGE`] of the mask's vertices must end on the avatar
//! (close, facing the same way), and there lie within
//! [`MAX_MEAN_RESIDUAL_MM`] of it on average, in millimetres of the
//! mask's scale, i.e. relative to the face's size.

use super::correspondence::correspondence_map;
use super::eyeballs::find_eyeballs;
use super::face_registration::{FaceRegistration, FoundFace, InvalidRegistration};
use super::feature_fit::{FeatureFitError, FeaturePair, fit_features};
use super::features::{HELD, REQUIRED, feature_weights, rig_features};
use super::jaw_agreement::{MouthNeighbourhood, leave_out_other_lip};
use super::lips_parting::{STILL, WITH_JAW, lips_parting};
use super::mask_holes::mouth_rim;
use super::nonrigid::{Landmark, MIN_NORMAL_DOT, SEARCH_RADIUS, register_nonrigid, vertex_normals};
use super::part_roles::{MouthPlace, part_roles};
use super::rigid_icp::icp_with_scale;
use crate::arkit::{Blendshape, Blendshapes};
use crate::avatar::model::Avatar;
use crate::avatar::target_names::arkit_targets;
use crate::geometry::Topology;
use crate::geometry::closest_point::TriangleTree;
use crate::geometry::front_visibility::visible_from;
use crate::geometry::mesh_boundary::boundary_edges;
use glam::DVec3;
use std::time::Instant;

/// Share of the registered mask's vertices that must lie closest to a part
/// for the part to hold face region.
pub const FACE_PART_SHARE: f64 = 0.05;

/// A vertex of the avatar belongs to the face region when the registered
/// mask passes within this distance of it (mm of the mask's scale, so the
/// same on any avatar units).
pub const FACE_TOLERANCE_MM: f64 = 2.0;

/// The largest mean distance (mm, mask scale) of the registered mask's
/// kept vertices from the avatar's skin that still counts as a face found.
pub const MAX_MEAN_RESIDUAL_MM: f64 = 0.5;

/// The smallest share of the mask's vertices that must end on the avatar.
pub const MIN_COVERAGE: f64 = 0.7;

/// Avatar triangles with a corner within this many mask radii (largest
/// distance of a placed mask vertex from its centre) of the mask's centre
/// take part in the registration.
pub const REACH: f64 = 1.5;

/// Landmarks leave feature disagreements below this alone (mm, mask
/// scale; [`super::nonrigid::Landmark::slack`]): a blink's or the jaw's
/// feature, a motion-weighted mean over a few dozen vertices, moves by
/// about this much between two samplings of one rig.
pub const LANDMARK_SLACK_MM: f64 = 0.5;

/// The slack of a held landmark ([`super::features::HELD`]), which pulls
/// through the whole fit (mm at the mask's scale): two samplings of one
/// rig place the blink's feature up to 1.5 mm apart (our low-poly
/// variant; 0.7 mm on a remeshed mask), and a held landmark with less
/// slack would drag a lid that already lies right.
pub const HELD_SLACK_MM: f64 = 2.0;

/// The rigid fit's features pull only beyond this distance (mm at the
/// mask's scale): two discretizations of one rig already place them up to
/// 3.5 mm apart (the jaw's, on the low-poly variant of our own avatar).
pub const FEATURE_SLACK_MM: f64 = 4.0;

/// How far from the placed mask's slit the avatar's lips may part for a
/// slit vertex to be held on the parting (mm at the mask's scale): the
/// rigid fit leaves the slit within a few millimetres of the lips'
/// parting (5 mm on ICT-FaceKit), and the lips are about 10 mm high.
pub const PARTING_REACH_MM: f64 = 8.0;

/// Pixel side of the depth buffer that decides which skin the mask may
/// lie on (mm, mask scale): finer than the few millimetres between lips
/// and teeth.
pub const VISIBILITY_PIXEL_MM: f64 = 0.5;

pub use super::feature_fit::MAX_FEATURE_MISFIT;

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
    #[error("no face found: where the registered mask lies on the avatar it stays {mean_mm:.2} mm from the skin on average (at most {max:.1} mm, in millimetres of a human face's size)", max = MAX_MEAN_RESIDUAL_MM)]
    ResidualTooLarge {
        /// The mean distance reached (mm, mask scale).
        mean_mm: f64,
    },
    /// Too little of the mask could be laid onto the avatar.
    #[error("no face found: only {share:.0}% of the registered mask lies on the avatar's skin (at least {min:.0}%); the rest found no surface facing the same way, mostly around the {region}", share = 100.0 * .share, min = 100.0 * MIN_COVERAGE)]
    TooLittleCovered {
        /// The share of mask vertices that ended on the avatar.
        share: f64,
        /// Where most of the uncovered vertices are (`forehead`, `chin`,
        /// `left cheek`, …), for the message.
        region: String,
    },
    /// A registration system could not be solved.
    #[error(
        "the non-rigid registration could not be solved (no part of the mask matched the avatar)"
    )]
    Unsolvable,
    /// What the search found does not fit the avatar (a mistake in the
    /// search itself).
    #[error("the face found does not fit the avatar: {0}")]
    Invalid(InvalidRegistration),
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
    let pairs: Vec<FeaturePair> = mask_features
        .iter()
        .filter_map(|(b, f)| {
            Some(FeaturePair {
                shape: *b,
                mask: *f,
                avatar: avatar_features.iter().find(|a| a.0 == *b)?.1,
            })
        })
        .collect();
    let fitted = fit_features(&pairs).map_err(|e| match e {
        FeatureFitError::Degenerate => RegistrationError::FeaturesNotFaceLike(f64::INFINITY),
        FeatureFitError::NotFaceLike(misfit) => RegistrationError::FeaturesNotFaceLike(misfit),
    })?;
    let initial = fitted.similarity;
    let p: Vec<DVec3> = fitted.kept.iter().map(|k| k.mask).collect();
    let q: Vec<DVec3> = fitted.kept.iter().map(|k| k.avatar).collect();

    // The eyeballs, then the skin near the placed mask.
    let looks: Vec<Vec<DVec3>> = [
        Blendshape::EyeLookOutLeft,
        Blendshape::EyeLookOutRight,
        Blendshape::EyeLookUpLeft,
        Blendshape::EyeLookUpRight,
    ]
    .iter()
    .filter_map(|b| arkit_displacement(avatar, *b))
    .collect();
    let mm = initial.scale / 1000.0;
    let eyeballs: Vec<Vec<u32>> = find_eyeballs(avatar, &positions, &[q[0], q[1]], mm, &looks)
        .into_iter()
        .map(|e| e.vertices)
        .collect();
    let mut is_eyeball = vec![false; positions.len()];
    for &v in eyeballs.iter().flatten() {
        is_eyeball[v as usize] = true;
    }
    let placed_initial: Vec<DVec3> = rig.neutral().iter().map(|p| initial.apply(*p)).collect();
    let centre = placed_initial.iter().sum::<DVec3>() / placed_initial.len().max(1) as f64;
    let reach = REACH
        * placed_initial
            .iter()
            .map(|p| (*p - centre).length())
            .fold(0.0, f64::max);
    let mut near_triangles: Vec<([u32; 3], usize)> = Vec::new();
    for i in 0..avatar.parts().len() {
        for t in avatar.part_triangles(&[i]) {
            if t.iter()
                .any(|&v| (positions[v as usize] - centre).length() <= reach)
            {
                near_triangles.push((t, i));
            }
        }
    }
    // Only the skin a depth camera in front of the face would see: the
    // ARKit mask is that surface (`front_visibility`).
    let towards_viewer = initial.rotation * DVec3::Z;
    let seen = visible_from(
        &positions,
        &near_triangles.iter().map(|t| t.0).collect::<Vec<_>>(),
        towards_viewer,
        VISIBILITY_PIXEL_MM * mm,
    );
    let (skin_triangles, part_of_triangle): (Vec<[u32; 3]>, Vec<usize>) = near_triangles
        .into_iter()
        .zip(seen)
        .filter(|((t, _), seen)| *seen && !t.iter().any(|&v| is_eyeball[v as usize]))
        .map(|(t, _)| t)
        .unzip();
    let skin = TriangleTree::new(&positions, &skin_triangles);

    // ICP with scale, then non-rigid, the features as landmarks.
    let mask_normals = vertex_normals(rig.neutral(), mask.triangles());
    let feature_pairs: Vec<(DVec3, DVec3)> = p.iter().copied().zip(q.iter().copied()).collect();
    let icp = icp_with_scale(
        rig.neutral(),
        &mask_normals,
        &skin,
        initial,
        &feature_pairs,
        FEATURE_SLACK_MM / 1000.0,
    );
    let placed: Vec<DVec3> = rig
        .neutral()
        .iter()
        .map(|p| icp.similarity.apply(*p))
        .collect();
    let mut landmarks: Vec<Landmark> = fitted
        .kept
        .iter()
        .map(|k| (k.shape, k.avatar))
        .filter_map(|(b, target)| {
            Some(Landmark {
                mask: feature_weights(rig.delta(b))?,
                target,
                slack: match HELD.contains(&b) {
                    true => HELD_SLACK_MM * mm,
                    false => LANDMARK_SLACK_MM * mm,
                },
                held: HELD.contains(&b),
            })
        })
        .collect();
    let mask_jaw = rig.delta(Blendshape::JawOpen);
    landmarks.extend(slit_landmarks(
        avatar,
        &positions,
        &skin_triangles,
        (mask.triangles(), mask_jaw),
        &placed,
        mm,
    ));
    let registered = register_nonrigid(&placed, mask.triangles(), &skin, &landmarks)
        .ok_or(RegistrationError::Unsolvable)?;
    let to_mm = 1000.0 / icp.similarity.scale;
    let kept: Vec<f64> = registered
        .distances
        .iter()
        .zip(&registered.kept)
        .filter(|(d, k)| **k && d.is_finite())
        .map(|(d, _)| *d)
        .collect();
    let coverage = kept.len() as f64 / registered.positions.len().max(1) as f64;
    let residual_mean_mm = kept.iter().sum::<f64>() / kept.len().max(1) as f64 * to_mm;
    let residual_max_mm = kept.iter().copied().fold(0.0, f64::max) * to_mm;
    if coverage.is_nan() || coverage < MIN_COVERAGE {
        return Err(RegistrationError::TooLittleCovered {
            share: coverage,
            region: uncovered_region(rig.neutral(), &registered.kept),
        });
    }
    if residual_mean_mm.is_nan() || residual_mean_mm > MAX_MEAN_RESIDUAL_MM {
        return Err(RegistrationError::ResidualTooLarge {
            mean_mm: residual_mean_mm,
        });
    }

    // Each kept vertex votes for the part of its compatible closest point
    // (the lips' vertices for the lips, not the gums behind them).
    let mut hits = vec![0usize; avatar.parts().len()];
    let normals = vertex_normals(&registered.positions, mask.triangles());
    let search = SEARCH_RADIUS * reach / REACH;
    for ((p, normal), _) in registered
        .positions
        .iter()
        .zip(&normals)
        .zip(&registered.kept)
        .filter(|(_, kept)| **kept)
    {
        if let Some(c) = skin.closest_facing(*p, *normal, MIN_NORMAL_DOT, search)
            && let Some(&part) = part_of_triangle.get(c.triangle)
        {
            hits[part] += 1;
        }
    }
    let needed = FACE_PART_SHARE * registered.positions.len() as f64;
    let face_parts: Vec<usize> = (0..avatar.parts().len())
        .filter(|&i| hits[i] as f64 >= needed)
        .collect();
    let face_triangles = avatar.part_triangles(&face_parts);
    let avatar_normals = vertex_normals(&positions, &face_triangles);
    let candidates = face_parts
        .iter()
        .flat_map(|&i| offsets[i]..offsets[i + 1])
        .filter(|&v| !is_eyeball[v])
        .map(|v| (v, positions[v], avatar_normals[v]));
    let mut map = correspondence_map(
        candidates,
        &registered.positions,
        mask.triangles(),
        FACE_TOLERANCE_MM / to_mm,
        &face_triangles,
    );
    let slit = mouth_rim(&registered.positions, &boundary_edges(mask.triangles()));
    let slit_middle = slit
        .iter()
        .map(|&v| registered.positions[v as usize])
        .sum::<DVec3>()
        / slit.len().max(1) as f64;
    if let Some(avatar_jaw) = arkit_displacement(avatar, Blendshape::JawOpen) {
        let radius = slit
            .iter()
            .map(|&v| registered.positions[v as usize].distance(slit_middle))
            .fold(0.0, f64::max);
        let mouth = MouthNeighbourhood {
            centre: slit_middle,
            radius,
        };
        leave_out_other_lip(&mut map, &positions, &avatar_jaw, mask_jaw, mouth);
    }
    let eyeball_parts: Vec<usize> = (0..avatar.parts().len())
        .filter(|&i| offsets[i] < offsets[i + 1])
        .filter(|&i| (offsets[i]..offsets[i + 1]).all(|v| is_eyeball[v]))
        .collect();
    let mouth = MouthPlace {
        centre: slit_middle,
        forward: (icp.similarity.rotation * DVec3::Z).normalize_or_zero(),
        per_mm: icp.similarity.scale / 1000.0,
    };
    let roles = part_roles(avatar, &face_parts, &eyeball_parts, mouth);
    let found = FoundFace {
        similarity: icp.similarity,
        mask_on_avatar: registered.positions,
        map,
        residual_mean_mm,
        residual_max_mm,
        icp_iterations: icp.iterations,
        features_left_out: fitted.left_out,
        roles,
        eyeballs,
        coverage,
        nonrigid_steps: (registered.stages, registered.steps),
        seconds: started.elapsed().as_secs_f64(),
    };
    FaceRegistration::new(found, avatar, mask.vertex_count()).map_err(RegistrationError::Invalid)
}

/// The mask's slit held where the avatar's lips part
/// ([`super::lips_parting`]), through the whole fit. A slit vertex that
/// the template's `jawOpen` moves with the jaw (at least
/// [`super::lips_parting::WITH_JAW`] of the most it moves any slit vertex)
/// is on the lower lip, one it leaves (at most
/// [`super::lips_parting::STILL`]) on the upper; the corners are neither.
/// Each lip's slit vertices are pulled by one common offset: the mean, over
/// them, of the way from each to the nearest edge vertex of the avatar's
/// same lip (within [`PARTING_REACH_MM`]). A mean cancels the along-the-lip
/// part of the ways, which only says how the two meshes sample the lip,
/// and keeps the part across it: how far the slit lies from the parting.
/// Offsets within [`HELD_SLACK_MM`] pull nothing (two meshes of one face
/// place the lips' edges a millimetre or so apart: with half a millimetre
/// of slack, the other-proportions variant's blink round trip left 0.5% of
/// its eyeball seen, with 2 mm as before). None without a `jawOpen` or a
/// parting.
fn slit_landmarks(
    avatar: &Avatar,
    positions: &[DVec3],
    skin_triangles: &[[u32; 3]],
    mask: (&[[u32; 3]], &[DVec3]),
    placed: &[DVec3],
    mm: f64,
) -> Vec<Landmark> {
    let (mask_triangles, mask_jaw) = mask;
    let Some(jaw) = arkit_displacement(avatar, Blendshape::JawOpen) else {
        return Vec::new();
    };
    let slit: Vec<u32> = mouth_rim(placed, &boundary_edges(mask_triangles))
        .into_iter()
        .collect();
    let middle = slit.iter().map(|&v| placed[v as usize]).sum::<DVec3>() / slit.len().max(1) as f64;
    let half_width = slit
        .iter()
        .map(|&v| placed[v as usize].distance(middle))
        .fold(0.0, f64::max);
    let pairs = lips_parting(positions, skin_triangles, &jaw, middle, half_width, mm);
    let motion = |v: u32| mask_jaw.get(v as usize).map_or(0.0, |d| d.length());
    let largest = slit.iter().map(|&v| motion(v)).fold(0.0, f64::max);
    if largest.is_nan() || largest <= 0.0 {
        return Vec::new();
    }
    let mut landmarks = Vec::new();
    for lower in [true, false] {
        let edge: Vec<DVec3> = pairs
            .iter()
            .map(|(moving, still)| if lower { *moving } else { *still })
            .collect();
        let on_lip: Vec<u32> = slit
            .iter()
            .copied()
            .filter(|&v| match lower {
                true => motion(v) >= WITH_JAW * largest,
                false => motion(v) <= STILL * largest,
            })
            .collect();
        let ways: Vec<DVec3> = on_lip
            .iter()
            .filter_map(|&v| {
                let p = placed[v as usize];
                let q = edge
                    .iter()
                    .min_by(|a, b| a.distance_squared(p).total_cmp(&b.distance_squared(p)))?;
                (q.distance(p) <= PARTING_REACH_MM * mm).then_some(*q - p)
            })
            .collect();
        if ways.is_empty() {
            continue;
        }
        let offset = ways.iter().sum::<DVec3>() / ways.len() as f64;
        landmarks.extend(on_lip.iter().map(|&v| Landmark {
            mask: vec![(v as usize, 1.0)],
            target: placed[v as usize] + offset,
            slack: HELD_SLACK_MM * mm,
            held: true,
        }));
    }
    landmarks
}

/// Where on the mask (ARKit's face coordinates, metres: +x the person's
/// left, +y up) most of the vertices not `kept` are, in words.
fn uncovered_region(neutral: &[DVec3], kept: &[bool]) -> String {
    const NAMES: [&str; 6] = [
        "forehead",
        "left eye",
        "right eye",
        "left cheek",
        "right cheek",
        "mouth and chin",
    ];
    let centre = neutral.iter().sum::<DVec3>() / neutral.len().max(1) as f64;
    let mut counts = [0usize; 6];
    for (p, _) in neutral.iter().zip(kept).filter(|(_, k)| !**k) {
        let d = *p - centre;
        let side = usize::from(d.x <= 0.0);
        let region = match d.y {
            y if y > 0.035 => 0,
            y if y > 0.01 => 1 + side,
            y if y > -0.02 => 3 + side,
            _ => 5,
        };
        counts[region] += 1;
    }
    let most = (0..6).max_by_key(|&i| counts[i]).unwrap_or(0);
    NAMES[most].to_string()
}

/// Version of the registration's rules: part of the cache key, so a cached
/// result from older rules is never taken for a new one.
pub const REGISTRATION_VERSION: u32 = 10;

/// The key a registration is cached under: the rules' version, the
/// avatar's vertex count and a CRC-32 of everything the registration
/// reads: the avatar's rest geometry, triangles and targets (its features
/// are where its blinks and jaw move most) and the mask's neutral and
/// shapes. An avatar whose shapes change (a new export of the same head)
/// is found again.
pub fn cache_key(avatar: &Avatar, rig: &Blendshapes) -> String {
    // The bytes are gathered part by part and hashed in bulk (a call per
    // number is ten times slower).
    let mut hasher = crc32fast::Hasher::new();
    let mut bytes: Vec<u8> = Vec::new();
    let floats = |bytes: &mut Vec<u8>, p: glam::Vec3| {
        for x in p.to_array() {
            bytes.extend_from_slice(&x.to_le_bytes());
        }
    };
    for part in avatar.parts() {
        bytes.clear();
        bytes.extend_from_slice(&(part.positions.len() as u64).to_le_bytes());
        for p in &part.positions {
            floats(&mut bytes, *p);
        }
        for i in part.triangles.iter().flatten() {
            bytes.extend_from_slice(&i.to_le_bytes());
        }
        bytes.extend_from_slice(&(part.targets.len() as u64).to_le_bytes());
        for d in part.targets.iter().flatten() {
            floats(&mut bytes, *d);
        }
        hasher.update(&bytes);
    }
    for mesh in avatar.meshes() {
        for name in &mesh.target_names {
            hasher.update(name.as_bytes());
            hasher.update(&[0]);
        }
    }
    bytes.clear();
    for p in rig.neutral().iter().chain(rig.deltas().iter().flatten()) {
        for x in p.to_array() {
            bytes.extend_from_slice(&x.to_le_bytes());
        }
    }
    hasher.update(&bytes);
    format!(
        "v{REGISTRATION_VERSION}-{}-{:08x}",
        avatar.vertex_count(),
        hasher.finalize()
    )
}
