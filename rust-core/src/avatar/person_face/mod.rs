//! The person's own face on the avatar (beyond the paper): the avatar's
//! rest takes the person's scanned neutral `B₀` on the face region, the
//! rest of the head follows it seamlessly, and everything the skin holds
//! (eyeballs, teeth, ears, linings) follows the skin. The 52 shapes are
//! then implanted on that new rest ([`crate::avatar::partial_transfer`]),
//! so every shape is the person's motion on the person's face.
//!
//! **The skin.** The registration knows where each vertex `i` of the
//! mask lies on the avatar's skin, `p_i = Σ_k β_ik x_{v_ik}`
//! ([`crate::avatar::own_shapes::skin_points`]), and the scanned neutral
//! says where it should be, `q_i = σ(B₀_i)`, with `σ` the registration's
//! similarity (mask → avatar). The skin's change `u` is first drawn
//! through the wanted changes `d_i = q_i − p_i` at those points, held
//! softly, as smooth as can be between them (the thin-plate energy of the
//! change, bi-Laplacian like step 2's correction) and fading to zero
//! within [`REACH_MM`] of the face along the skin ([`mod@rest_field`]);
//! then laid on the scanned surface by rounds of closest points, which ask
//! how far the skin is off the face but not where along it a point should
//! go ([`surface_fit`]). A mask vertex off the skin (farther than the
//! registration's face tolerance), or lying folded on it so that its
//! change contradicts its neighbours' ([`mod@consistent_points`]), asks
//! nothing of the first change. Skin that touches itself at rest (the
//! lips along the mouth's line) stays together where the person's lips
//! stay together, and never passes through itself
//! ([`rest_field::keep_touching`]).
//!
//! **What the skin holds** ([`followers`]): the eyeballs take the
//! similarity that carries the lids around them (so they sit in the
//! person's eye openings, scaled to them), each rigid piece (teeth, gums)
//! the similarity that carries the skin around it (the mouth), and every
//! other vertex off the face parts (ears, sockets, the mouth's lining, a
//! tongue) the change of the skin point closest to it.
//!
//! | what | file |
//! |---|---|
//! | only the wanted changes the skin can take: none from a mask lying folded on it | [`mod@consistent_points`] |
//! | the skin through the wanted changes at points of it, the head following (thin-plate energy of the change, zero beyond the reach) | [`mod@rest_field`] |
//! | the skin laid on the scanned surface by rounds of closest points (non-rigid ICP, Amberg et al. 2007) | [`surface_fit`] |
//! | eyeballs into the person's eye openings, rigid pieces with the skin around them, the rest with the skin nearest | [`followers`] |

pub mod consistent_points;
pub mod followers;
pub mod rest_field;
pub mod surface_fit;

use super::model::Avatar;
use super::own_shapes::{face_part_triangles, skin_points};
use super::partial_transfer::adjacent_step::within;
use super::partial_transfer::stay_put::STILL_MM;
use super::registration::FaceRegistration;
use super::registration::find_face::FACE_TOLERANCE_MM;
use super::registration::nonrigid::vertex_normals;
use crate::avatar::partial_transfer::lid_contacts::mask_eye_holes;
use crate::geometry::closest_point::TriangleTree;
use crate::geometry::laplacian::laplace_beltrami_rows;
use crate::geometry::mesh_boundary::boundary_edges;
use crate::geometry::one_ring::one_rings;
use consistent_points::{AskedChange, across_the_slit, consistent_points};
use followers::{EyeFollowed, follow_skin};
use glam::DVec3;
use rest_field::{PointChange, RestSystem, TOUCH_MM, keep_touching, touching_pairs};
use std::collections::BTreeSet;
use std::time::Instant;
use surface_fit::{START_WEIGHT, Scan, Skin, fit_to_scan};

/// How far from the face region, along the skin, the change of the rest
/// fades out (mm at the mask's scale). A face that is 5 mm wider than the
/// stock one (between two adult faces, a common difference) then stretches
/// the skin beside it by about 5/80, 6%, over a band as wide as the face
/// is tall; the back of a head (the default avatar's crown is 120–150 mm
/// from the face's outline) stays as it was.
pub const REACH_MM: f64 = 80.0;

/// Why the person's face could not be taken.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum TakeFaceError {
    /// The neutral is not on the registered mask.
    #[error("the scanned neutral has {got} vertices, the registered mask {expected}")]
    NeutralSize {
        /// The registered mask's vertices.
        expected: usize,
        /// The neutral's.
        got: usize,
    },
    /// A neutral vertex is not finite.
    #[error("the scanned neutral is not finite at mask vertex {0}")]
    NotFinite(usize),
    /// The region around the face could not be solved.
    #[error("the head around the face could not be solved")]
    Unsolved,
}

/// The avatar with the person's face at rest, and what it took.
#[derive(Clone, Debug)]
pub struct TakenFace {
    /// The avatar with its rest moved (targets unchanged).
    pub avatar: Avatar,
    /// The registration moved with it: each mask vertex where the new
    /// skin has its point (the map `M` is unchanged).
    pub registration: FaceRegistration,
    /// The change of every vertex's rest (avatar units, as
    /// `Avatar::positions`).
    pub moved: Vec<DVec3>,
    /// How far the new rest passes from the scanned neutral at the mask's
    /// vertices: mean and largest (mm, mask scale).
    pub fit_mean_mm: f64,
    /// See `fit_mean_mm`.
    pub fit_max_mm: f64,
    /// How far the scanned neutral lies from the new skin (its closest
    /// point), over the mask's vertices on the skin: mean and 95th
    /// percentile (mm, mask scale).
    pub surface_mean_mm: f64,
    /// See `surface_mean_mm`.
    pub surface_p95_mm: f64,
    /// The mask vertices, increasing, that asked nothing of the skin and
    /// are not in the fit: off the skin, or lying folded on it
    /// ([`mod@consistent_points`]).
    pub points_left_out: Vec<u32>,
    /// The largest change of a vertex (mm, mask scale).
    pub largest_mm: f64,
    /// The largest change the scan asks of the skin at a point it holds
    /// (mm, mask scale): what the face itself moves by.
    pub asked_largest_mm: f64,
    /// Each eyeball as it followed its lids.
    pub eyeballs: Vec<EyeFollowed>,
    /// Time taken (s).
    pub seconds: f64,
}

/// Gives `avatar` (found by `registration`) the rest face `neutral`: the
/// person's scanned neutral on the mask, ARKit's face coordinates, metres
/// (module docs). The skin's change first ([`skin_change`]), then what the
/// skin holds ([`SkinChange::followed`]).
pub fn take_face(
    avatar: &Avatar,
    registration: &FaceRegistration,
    neutral: &[DVec3],
) -> Result<TakenFace, TakeFaceError> {
    skin_change(avatar, registration, neutral)?.followed(avatar, registration)
}

/// The change of the skin (the face parts) that takes the person's face,
/// before what the skin holds follows it: all a check of the skin's
/// creases needs (`crate::avatar::rest_check::rest_creases`), so a face
/// the skin cannot take costs no more.
#[derive(Clone, Debug)]
pub struct SkinChange {
    /// The change of every vertex's rest (avatar units): set on the face
    /// parts, zero elsewhere until [`SkinChange::followed`].
    pub moved: Vec<DVec3>,
    /// The largest change the scan asks of the skin at a point it holds
    /// (mm, mask scale).
    pub asked_largest_mm: f64,
    /// The avatar's stock rest.
    positions: Vec<DVec3>,
    /// The face parts' triangles.
    triangles: Vec<[u32; 3]>,
    /// Each mask vertex's point on the skin, if within the tolerance.
    points: Vec<Option<([u32; 3], [f64; 3])>>,
    /// Each mask vertex's scanned place (avatar frame).
    wanted: Vec<DVec3>,
    /// Each mask vertex's wanted change.
    change_at_mask: Vec<DVec3>,
    /// Whether each mask vertex asked its change of the skin.
    kept: Vec<bool>,
    /// Avatar units per mm at the mask's scale.
    to_avatar: f64,
    /// When the taking began.
    started: Instant,
}

/// The skin's change that takes the rest face `neutral` onto `avatar`
/// (found by `registration`; module docs), the skin alone.
pub fn skin_change(
    avatar: &Avatar,
    registration: &FaceRegistration,
    neutral: &[DVec3],
) -> Result<SkinChange, TakeFaceError> {
    let started = Instant::now();
    let expected = registration.mask_on_avatar.len();
    if neutral.len() != expected {
        return Err(TakeFaceError::NeutralSize {
            expected,
            got: neutral.len(),
        });
    }
    if let Some(i) = neutral.iter().position(|p| !p.is_finite()) {
        return Err(TakeFaceError::NotFinite(i));
    }
    let positions: Vec<DVec3> = avatar.positions().iter().map(|p| p.as_dvec3()).collect();
    let n = positions.len();
    let triangles = face_part_triangles(avatar, registration);
    let s = registration.similarity;
    let to_avatar = s.scale * 1e-3;
    // A mask vertex off the skin (farther from it than the registration's
    // face tolerance) asks nothing of it.
    let points = skin_points(
        registration,
        &positions,
        &triangles,
        FACE_TOLERANCE_MM * to_avatar,
    );
    let wanted: Vec<DVec3> = neutral.iter().map(|p| s.apply(*p)).collect();
    let change_at_mask: Vec<DVec3> = points
        .iter()
        .zip(&wanted)
        .zip(&registration.mask_on_avatar)
        .map(|((point, q), registered)| *q - at(point, &positions).unwrap_or(*registered))
        .collect();

    // The skin: smooth through the points, zero beyond the reach.
    let mut face = vec![false; n];
    for f in &registration.map.face {
        if let Some(x) = face.get_mut(f.vertex as usize) {
            *x = true;
        }
    }
    let region = within(&positions, &triangles, &face, REACH_MM * to_avatar);
    // Only changes the skin can take: a mask lying folded on the skin asks
    // two points a hair apart for changes far apart.
    let on_skin: Vec<usize> = (0..points.len()).filter(|i| points[*i].is_some()).collect();
    let lips = registration.lip_sides();
    let skin_lips = registration.vertex_lips(&lips, n);
    // The lip of the skin a point lies on, where every corner of its
    // triangle is of that one lip (0 otherwise).
    let point_lip = |i: usize| {
        points[i].map_or(0, |(t, _)| {
            let corners = t.map(|v| skin_lips.get(v as usize).copied().unwrap_or(0));
            if corners.iter().all(|l| *l == corners[0]) {
                corners[0]
            } else {
                0
            }
        })
    };
    // A point of one lip lying on the other lip's skin is folded across
    // the slit: it asks for nothing.
    let on_skin: Vec<usize> = on_skin
        .into_iter()
        .filter(|&i| !across_the_slit(lips.lips_of_vertex(i as u32), point_lip(i)))
        .collect();
    let rings = one_rings(n, &triangles);
    let patch = |t: [u32; 3]| {
        let mut near: Vec<u32> = t
            .iter()
            .flat_map(|v| rings.get(v).into_iter().flatten().copied().chain([*v]))
            .collect();
        near.sort_unstable();
        near.dedup();
        near
    };
    let asked: Vec<AskedChange> = on_skin
        .iter()
        .map(|&i| AskedChange {
            at: at(&points[i], &positions).unwrap_or(registration.mask_on_avatar[i]),
            change: change_at_mask[i],
            lips: lips.lips_of_vertex(i as u32),
            skin_lips: point_lip(i),
            patch: points[i].map(|(t, _)| patch(t)).unwrap_or_default(),
        })
        .collect();
    let mut kept = vec![false; points.len()];
    for k in consistent_points(&asked, to_avatar) {
        kept[on_skin[k]] = true;
    }
    let wanted_changes: Vec<PointChange> = points
        .iter()
        .zip(&change_at_mask)
        .zip(&kept)
        .filter(|(_, keep)| **keep)
        .filter_map(|((point, d), _)| point.map(|(t, b)| (t, b, *d)))
        .collect();
    let asked_largest_mm = wanted_changes
        .iter()
        .map(|(_, _, d)| d.length())
        .fold(0.0, f64::max)
        / to_avatar;
    // Two independent passes over the skin, one on each core.
    let (ties, rows) = std::thread::scope(|scope| {
        let ties = scope.spawn(|| touching_pairs(&positions, &triangles, TOUCH_MM * to_avatar));
        let rows = laplace_beltrami_rows(&positions, &triangles);
        (
            ties.join().unwrap_or_else(|e| std::panic::resume_unwind(e)),
            rows,
        )
    });
    let system = RestSystem::new(n, &rows, &region, &ties).map_err(|_| TakeFaceError::Unsolved)?;
    let start = system
        .rest_field(&wanted_changes, START_WEIGHT)
        .ok_or(TakeFaceError::Unsolved)?;
    // Then on the scanned surface by closest points: the mouth's rim and
    // the outline pull the skin, the eye holes do not (surface_fit).
    let eye_rims: BTreeSet<u32> = mask_eye_holes(&registration.map.mask_triangles, neutral)
        .iter()
        .flat_map(|h| h.upper.iter().chain(&h.lower).copied())
        .collect();
    let registered_normals = vertex_normals(
        &registration.mask_on_avatar,
        &registration.map.mask_triangles,
    );
    let pulling: Vec<(u32, f64)> = boundary_edges(&registration.map.mask_triangles)
        .iter()
        .flat_map(|&(a, b)| [a, b])
        .collect::<BTreeSet<u32>>()
        .into_iter()
        .filter(|i| !eye_rims.contains(i))
        .filter_map(|i| {
            let r = registration.mask_on_avatar[i as usize];
            let on_skin = at(&points[i as usize], &positions)?;
            Some((i, (on_skin - r).dot(registered_normals[i as usize])))
        })
        .collect();
    let skin = Skin {
        positions: &positions,
        triangles: &triangles,
        system: &system,
        face: &face,
    };
    let scan = Scan {
        positions: &wanted,
        registered: &registration.mask_on_avatar,
        triangles: &registration.map.mask_triangles,
        pulling: &pulling,
    };
    let (mut field, fit_asked) =
        fit_to_scan(&skin, &scan, start, to_avatar).ok_or(TakeFaceError::Unsolved)?;
    let asked_largest_mm = asked_largest_mm.max(fit_asked / to_avatar);
    // Lips the person keeps closed stay exactly closed, and never pass
    // through each other: a slide below what a capture can tell is no
    // parting.
    keep_touching(
        &positions,
        &mut field,
        &triangles,
        &ties,
        STILL_MM * to_avatar,
    );
    Ok(SkinChange {
        moved: field,
        asked_largest_mm,
        positions,
        triangles,
        points,
        wanted,
        change_at_mask,
        kept,
        to_avatar,
        started,
    })
}

/// The mean of `values` and their 95th percentile (the value 95% of the
/// way up the sorted list): the face match's two figures
/// ([`TakenFace::surface_mean_mm`]); zeros for none.
pub fn mean_and_p95(mut values: Vec<f64>) -> (f64, f64) {
    values.sort_by(f64::total_cmp);
    let mean = values.iter().sum::<f64>() / values.len().max(1) as f64;
    let p95 = values
        .get((values.len() * 95 / 100).min(values.len().saturating_sub(1)))
        .copied()
        .unwrap_or(0.0);
    (mean, p95)
}

/// `field` at a mask vertex's point on the skin (its triangle's corners
/// and barycentrics), if it has one.
fn at(point: &Option<([u32; 3], [f64; 3])>, field: &[DVec3]) -> Option<DVec3> {
    point.map(|(t, b)| (0..3).map(|k| field[t[k] as usize] * b[k]).sum::<DVec3>())
}

impl SkinChange {
    /// The person's face taken: what the skin holds follows it
    /// ([`follow_skin`]), and the new rest is measured against the scan.
    pub fn followed(
        self,
        avatar: &Avatar,
        registration: &FaceRegistration,
    ) -> Result<TakenFace, TakeFaceError> {
        let SkinChange {
            moved: mut field,
            asked_largest_mm,
            positions,
            triangles,
            points,
            wanted,
            change_at_mask,
            kept,
            to_avatar,
            started,
        } = self;
        let eyeballs = follow_skin(avatar, &positions, registration, &mut field, to_avatar);

        let taken = avatar
            .with_rest_moved(&field)
            .map_err(|_| TakeFaceError::Unsolved)?;
        let new_positions: Vec<DVec3> =
            positions.iter().zip(&field).map(|(p, u)| *p + *u).collect();
        let moved_registration = registration
            .with_mask_moved(&taken, |i| {
                at(&points[i], &field).unwrap_or(change_at_mask[i])
            })
            .map_err(|_| TakeFaceError::Unsolved)?;
        let fits: Vec<f64> = points
            .iter()
            .enumerate()
            .filter(|(i, _)| kept[*i])
            .filter_map(|(i, point)| {
                Some((at(point, &new_positions)? - wanted[i]).length() / to_avatar)
            })
            .collect();
        // How far the scanned face is from the new skin, wherever the mask
        // lies on the skin (left out or not): the face a user compares.
        let new_skin = TriangleTree::new(&new_positions, &triangles);
        let surface: Vec<f64> = (0..points.len())
            .filter(|i| points[*i].is_some())
            .filter_map(|i| Some(new_skin.closest(wanted[i])?.distance / to_avatar))
            .collect();
        let (surface_mean_mm, surface_p95_mm) = mean_and_p95(surface);
        let largest = field.iter().map(|u| u.length()).fold(0.0, f64::max) / to_avatar;
        Ok(TakenFace {
            asked_largest_mm,
            surface_mean_mm,
            surface_p95_mm,
            avatar: taken,
            registration: moved_registration,
            moved: field,
            fit_mean_mm: fits.iter().sum::<f64>() / fits.len().max(1) as f64,
            fit_max_mm: fits.iter().copied().fold(0.0, f64::max),
            points_left_out: (0..points.len() as u32)
                .filter(|i| !kept[*i as usize])
                .collect(),
            largest_mm: largest,
            eyeballs,
            seconds: started.elapsed().as_secs_f64(),
        })
    }
}
