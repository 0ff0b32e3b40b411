//! The avatar's own shapes seen through the registration, `S_j`: each
//! registered mask vertex takes the avatar's own displacement (its morph
//! target named `j`, halves summed) at the point where it lies on the
//! avatar's skin, carried back into the mask's frame,
//!
//! ```text
//! S_j(i) = Rᵀ (Σ_k β_ik Ã_j(v_ik)) / s,
//! ```
//!
//! with `v_ik`, `β_ik` the corners and barycentrics of the avatar point
//! closest to registered mask vertex `i` among those facing the same way
//! (normals within 60°), and `s R` the registration's
//! similarity (mask → avatar).
//!
//! This is the round trip of issue 21: given `S_j` as the person
//! ([`avatar_as_person`]), the implanted avatar should give back its own
//! targets. Measured by `likeness-tests`' `avatar_study` example; the
//! pipeline does not use `S_j` yet (issue 21: carrying
//! the person's deviation `B_j − k_j S_j` and adding `k_j Ã_j` made the
//! round trip exact but pulled the personalized avatar away from the
//! person's mask at the lips).

use super::model::Avatar;
use super::registration::FaceRegistration;
use super::registration::find_face::arkit_displacement;
use super::registration::nonrigid::vertex_normals;
use super::registration::rigid_icp::MIN_NORMAL_DOT;
use crate::arkit::{Blendshape, Blendshapes, BlendshapesError};
use crate::geometry::closest_point::{ClosestPoint, TriangleGrid};
use glam::DVec3;

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
    let grid = TriangleGrid::new(positions, face_triangles);
    // The compatible closest point (normals within 60°, as the
    // registration pairs them): a mask vertex on the lip's edge takes the
    // lip's outer skin, not the lining of the mouth behind it, which the
    // avatar's own mouthRollLower moves quite differently.
    let normals = vertex_normals(
        &registration.mask_on_avatar,
        &registration.map.mask_triangles,
    );
    let found: Vec<Option<ClosestPoint>> = registration
        .mask_on_avatar
        .iter()
        .zip(&normals)
        .map(|(p, n)| {
            grid.closest_facing(*p, *n, MIN_NORMAL_DOT, f64::INFINITY)
                .or_else(|| grid.closest(*p))
        })
        .collect();
    let points: Vec<Option<([u32; 3], [f64; 3])>> = found
        .iter()
        .map(|c| c.map(|c| (grid.triangles()[c.triangle], c.barycentric)))
        .collect();
    let back = registration.similarity;
    Blendshape::ALL
        .iter()
        .map(|b| {
            let own = arkit_displacement(avatar, *b)?;
            let at = |v: u32| own.get(v as usize).copied().unwrap_or(DVec3::ZERO);
            Some(
                points
                    .iter()
                    .map(|p| match p {
                        Some((t, w)) => {
                            let d: DVec3 = t.iter().zip(w).map(|(&v, w)| at(v) * *w).sum();
                            back.rotation.transpose() * d / back.scale
                        }
                        None => DVec3::ZERO,
                    })
                    .collect(),
            )
        })
        .collect()
}

/// The avatar's own shapes as a person (the round trip of issue 21): the
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
    avatar.triangles_of(&registration.face_parts)
}
