//! An avatar field seen by the registered mask, `S f`, and the avatar's
//! own shapes seen that way, `S_j = S Ã_j` (its morph target named `j`,
//! halves summed).
//!
//! `S f` is the field on the mask's vertices that the correspondence map
//! `M` carries back onto the avatar's face closest to `f`, each vertex
//! pulled weakly towards `f`'s value at the point where it lies on the
//! skin, `f(p_i)`:
//!
//! ```text
//! S f = argmin_s Σ_{v ∈ F} ‖(M s)_v − f_v‖² + ε Σ_i ‖s_i − f(p_i)‖²,
//! (MᵀM + εI) S f = Mᵀ f + ε f(p),      f(p_i) = Σ_k β_ik f(v_ik),
//! ```
//!
//! with `v_ik`, `β_ik` the corners and barycentrics of the avatar point
//! closest to registered mask vertex `i` among those facing the same way
//! (normals within 60°; for a mask vertex on one lip's edge, away from the
//! other lip's skin, [`crate::avatar::registration::lip_sides`]), and `ε`
//! [`POINT_PULL`] times the mean diagonal of
//! `MᵀM`. A vertex the map does not see (the rims of the eye and mouth
//! holes, beyond the face region) takes `f(p_i)`. `MᵀM + εI` depends only
//! on the registration: factored once, each field is one solve.
//!
//! **Why a fit, not the point values alone.** Where the avatar's field is
//! linear across each mask triangle (our default avatar's targets are the
//! template interpolated so), the fit gives back the mask's values
//! exactly, while the point values come out lower at every vertex where
//! the field bends (an avatar triangle spans the bend); on a smooth
//! artist's field both agree. `S_j` in the mask's frame is
//! `Rᵀ (S Ã_j) / s` with `s R` the registration's similarity
//! (mask → avatar).
//!
//! `S` serves the pipeline twice, so that what the mask
//! cannot resolve never reaches the transfer as if it were motion: Eq. (4)
//! compares the person's shapes with the avatar's targets seen through it
//! ([`crate::avatar::retargeting`]), and step 1 carries only the person's
//! deviation from `A_j` as the mask sees it, `B_j − S(A_j)`, adding `A_j`
//! itself at the avatar's own resolution
//! ([`crate::avatar::partial_transfer`]).
//!
//! Given `S_j` as the person ([`avatar_as_person`]), the implanted avatar
//! gives back its own targets (the round trip), checked on
//! every avatar the project generates (`tests/tests/avatar_round_trip.rs`).

use super::model::Avatar;
use super::registration::FaceRegistration;
use super::registration::find_face::arkit_displacement;
use super::registration::nonrigid::vertex_normals;
use super::registration::rigid_icp::MIN_NORMAL_DOT;
use crate::arkit::{Blendshape, Blendshapes, BlendshapesError};
use crate::geometry::closest_point::TriangleTree;
use crate::geometry::laplacian::normal_lower;
use crate::geometry::sparse_cholesky;
use faer::Mat;
use faer::linalg::solvers::Solve;
use faer::sparse::Triplet;
use faer::sparse::linalg::solvers::Llt;
use glam::DVec3;

/// `ε`, the pull of each mask vertex towards the avatar's value at its
/// point, relative to the mean diagonal of `MᵀM` (module docs). Small
/// enough that a vertex the map sees fully is fitted to within a per cent
/// of its rows' weight; large enough that one the map barely sees (a
/// corner of a triangle at the region's edge, weight `β² ≪ 1`) stays at
/// its point's value instead of swinging to fit a single row.
pub const POINT_PULL: f64 = 1e-2;

/// `S`: an avatar field seen by the registered mask (module docs), ready
/// to apply: where each mask vertex lies on the skin, and the normal
/// equations of the fit, factored once.
pub struct MaskOnSkin {
    /// Per mask vertex, the corners and barycentrics of its point on the
    /// avatar's skin.
    points: Vec<Option<([u32; 3], [f64; 3])>>,
    /// `M`: per face vertex, its avatar index, mask triangle and
    /// barycentrics.
    rows: Vec<(u32, [u32; 3], [f64; 3])>,
    /// `ε` (absolute).
    pull: f64,
    /// `MᵀM + εI`, factored (`None`: the points' values stand alone).
    llt: Option<Llt<usize, f64>>,
}

impl MaskOnSkin {
    /// Finds the points for `registration` on the avatar with rest
    /// `positions` and face-part triangles `face_triangles` (avatar vertex
    /// indices), and factors the fit.
    pub fn new(
        registration: &FaceRegistration,
        positions: &[DVec3],
        face_triangles: &[[u32; 3]],
    ) -> MaskOnSkin {
        let points = skin_points(registration, positions, face_triangles, f64::INFINITY);
        let n = points.len();
        let triangles = &registration.map.mask_triangles;
        let rows: Vec<(u32, [u32; 3], [f64; 3])> = registration
            .map
            .face
            .iter()
            .filter_map(|f| {
                let t = *triangles.get(f.triangle as usize)?;
                t.iter()
                    .all(|&i| (i as usize) < n)
                    .then_some((f.vertex, t, f.barycentric))
            })
            .collect();
        // `Bᵀ B`, `B` the points' barycentric rows.
        let point_rows: Vec<[(usize, f64); 3]> = rows
            .iter()
            .map(|(_, t, b)| std::array::from_fn(|k| (t[k] as usize, b[k])))
            .collect();
        let mut entries = normal_lower(point_rows.iter().map(|r| r.as_slice()));
        let mut diagonal = vec![0.0; n];
        for e in entries.iter().filter(|e| e.row == e.col) {
            diagonal[e.row] += e.val;
        }
        let seen = diagonal.iter().filter(|d| **d > 0.0).count();
        let mean = diagonal.iter().sum::<f64>() / seen.max(1) as f64;
        let pull = POINT_PULL * if mean > 0.0 { mean } else { 1.0 };
        entries.extend((0..n).map(|i| Triplet::new(i, i, pull)));
        let llt = sparse_cholesky::factor(n, &entries).ok();
        MaskOnSkin {
            points,
            rows,
            pull,
            llt,
        }
    }

    /// `S f`: the avatar displacement `field` (one per avatar vertex,
    /// avatar frame) as a field on the mask's vertices, still in the
    /// avatar's frame (module docs); a missing point or vertex counts as
    /// zero.
    pub fn see(&self, field: &[DVec3]) -> Vec<DVec3> {
        let at = |v: u32| field.get(v as usize).copied().unwrap_or(DVec3::ZERO);
        let sampled: Vec<DVec3> = self
            .points
            .iter()
            .map(|p| match p {
                Some((t, w)) => t.iter().zip(w).map(|(&v, w)| at(v) * *w).sum(),
                None => DVec3::ZERO,
            })
            .collect();
        let Some(llt) = &self.llt else {
            return sampled;
        };
        // Mᵀ f + ε f(p).
        let n = sampled.len();
        let mut rhs = Mat::<f64>::zeros(n, 3);
        for (i, x) in sampled.iter().enumerate() {
            for axis in 0..3 {
                rhs[(i, axis)] = self.pull * x[axis];
            }
        }
        for (v, t, b) in &self.rows {
            let value = at(*v);
            for k in 0..3 {
                for axis in 0..3 {
                    rhs[(t[k] as usize, axis)] += b[k] * value[axis];
                }
            }
        }
        llt.solve_in_place(&mut rhs);
        (0..n)
            .map(|i| DVec3::new(rhs[(i, 0)], rhs[(i, 1)], rhs[(i, 2)]))
            .collect()
    }
}

/// Where each registered mask vertex lies on the avatar's skin: the
/// corners and barycentrics of the closest point of `face_triangles`
/// (avatar vertex indices over rest `positions`) among those facing the
/// same way (normals within 60°, as the registration pairs them), else the
/// plain closest point; `None` when there are no triangles. With a finite
/// `reach` (avatar units) only points within it count, and a mask vertex
/// with no compatible point that near is off the skin (`None`): the mask
/// reaches past the avatar's skin there (ARKit's own mesh curls into the
/// mouth further than many avatars' lips), and the skin far from it is not
/// its point.
pub fn skin_points(
    registration: &FaceRegistration,
    positions: &[DVec3],
    face_triangles: &[[u32; 3]],
    reach: f64,
) -> Vec<Option<([u32; 3], [f64; 3])>> {
    let grid = TriangleTree::new(positions, face_triangles);
    // The compatible closest point: a mask vertex on the lip's edge takes
    // the lip's outer skin, not the lining of the mouth behind it, which
    // the avatar's own mouthRollLower moves quite differently.
    let normals = vertex_normals(
        &registration.mask_on_avatar,
        &registration.map.mask_triangles,
    );
    // A mask vertex on one lip's edge takes a point of that lip: the lips
    // lie against each other at the slit, and the other lip's skin can be
    // nearer (a coarse avatar's lip triangles reach across the gap).
    let lips = registration.lip_sides();
    let vertex_lips = registration.vertex_lips(&lips, positions.len());
    let other_lip = |t: usize, lip: Option<u8>| {
        let Some(lip) = lip else { return false };
        grid.triangles()[t]
            .iter()
            .any(|&v| vertex_lips.get(v as usize).is_some_and(|l| *l == 3 & !lip))
    };
    registration
        .mask_on_avatar
        .iter()
        .zip(&normals)
        .enumerate()
        .map(|(i, (p, n))| {
            let lip = lips.lip_of_vertex(i as u32);
            let compatible = grid.closest_where(*p, reach, |t| {
                grid.triangle_normal(t).dot(*n) >= MIN_NORMAL_DOT && !other_lip(t, lip)
            });
            if reach.is_finite() {
                compatible
            } else {
                compatible.or_else(|| grid.closest(*p))
            }
            .map(|c| (grid.triangles()[c.triangle], c.barycentric))
        })
        .collect()
}

/// For each ARKit shape (Apple's order), `S_j` at every registered mask
/// vertex in the mask's frame (module docs); `None` where the avatar has
/// no target of that name. `face_triangles` are the avatar's triangles of
/// the face parts (avatar vertex indices), `positions` its rest positions.
pub fn own_shapes_on_mask(
    avatar: &Avatar,
    registration: &FaceRegistration,
    positions: &[DVec3],
    face_triangles: &[[u32; 3]],
) -> Vec<Option<Vec<DVec3>>> {
    let on_skin = MaskOnSkin::new(registration, positions, face_triangles);
    let back = registration.similarity;
    Blendshape::ALL
        .iter()
        .map(|b| {
            let own = arkit_displacement(avatar, *b)?;
            Some(
                on_skin
                    .see(&own)
                    .into_iter()
                    .map(|d| back.rotation.transpose() * d / back.scale)
                    .collect(),
            )
        })
        .collect()
}

/// The avatar's own shapes as a person (the round trip): the
/// registered mask carried back into the mask's frame as the neutral, and
/// `S_j` as the 52 deltas (zero where the avatar lacks a shape).
pub fn avatar_as_person(
    avatar: &Avatar,
    registration: &FaceRegistration,
) -> Result<Blendshapes, BlendshapesError> {
    let positions: Vec<DVec3> = avatar.positions().iter().map(|p| p.as_dvec3()).collect();
    let triangles = face_part_triangles(avatar, registration);
    let s = registration.similarity;
    let neutral = registration
        .mask_on_avatar
        .iter()
        .map(|p| s.rotation.transpose() * (*p - s.translation) / s.scale)
        .collect::<Vec<_>>();
    let n = neutral.len();
    let deltas = own_shapes_on_mask(avatar, registration, &positions, &triangles)
        .into_iter()
        .map(|d| d.unwrap_or_else(|| vec![DVec3::ZERO; n]))
        .collect();
    Blendshapes::new(neutral, deltas)
}

/// The triangles of the parts the face was found on, in avatar vertex
/// indices.
pub fn face_part_triangles(avatar: &Avatar, registration: &FaceRegistration) -> Vec<[u32; 3]> {
    avatar.part_triangles(&registration.face_parts())
}
