//! §3.3, the seamless partial deformation transfer (Fig. 3): the person's
//! shapes implanted into the avatar. Step 1 carries the personalized mask's
//! deformation onto the avatar's face region in the gradient domain; step 2
//! deforms the region next to it from the automatic retargeting `A_j`
//! with the face fixed; a lid that ends inside an eyeball is put back on
//! it; everything else (eyeballs, teeth, tongue, the back
//! of the head) follows `A_j`, which is zero where the avatar's own shapes
//! do not move it.
//!
//! **What step 1 carries.** Beyond the paper, step 1 carries the person's
//! deviation from the automatic retargeting as the mask sees it,
//! `B_j − S(A_j)` ([`crate::avatar::own_shapes`]), and adds `A_j` itself
//! at every face vertex:
//!
//! ```text
//! D_j = A_j + T(B_j − S(A_j)),
//! ```
//!
//! with `T` the face step's transfer (linear in the shape). The mask has
//! about 1,200 vertices; the avatar's face often ten times more, and its
//! artist's shapes have detail the mask cannot hold (a lip that rolls
//! in, a crease). `T` alone would smooth that detail to the mask's
//! triangles for every person, and for a person who moves exactly as the
//! avatar does it would give back up to 40% of a shape's motion wrong at
//! single vertices (ICT-FaceKit's `mouthRollUpper`). With `A_j` added the
//! avatar keeps its own detail wherever the person moves as its rig
//! does, and the person's own motion, at the mask's resolution, is what
//! `T` adds.
//!
//! | paper | what | file |
//! |---|---|---|
//! | §3.3 "deformation transfer to only the avatar's face using the precomputed correspondence mapping" | step 1 | [`face_step`] |
//! | §3.3 "the vertices in the adjacent area … are non-rigidly deformed from `A_j`" | step 2 | [`adjacent_step`] |
//! | (beyond the paper) closed eyes stay closed: the lid margins `M` leaves out made to meet | [`lid_contacts`], [`adjacent_step::AdjacentStep::close`] |
//! | (beyond the paper) a closed eye whose opening the contacts cannot find (lids folding into the sockets) closes the avatar's way: its own blink on the lids where the person's eye closes | [`closed_lids`] |
//! | (beyond the paper) what neither the person nor the avatar's rig moves stays put | [`stay_put`] |
//! | §3.3 "eye balls and teeth … to their desired position" | rigid pieces (connected components any own target moves rigidly, in any mesh) kept rigid | [`rigid_parts`] |
//! | §3.3 "moving the eyelid vertices to their closest point on the eyeball surface \[2\]" | no lid inside an eyeball (eyeballs found by their shape, [`crate::avatar::registration::eyeballs`]) | [`eyelid_repair`] |

pub mod adjacent_step;
pub mod closed_lids;
pub mod eyelid_repair;
pub mod face_step;
pub mod lid_contacts;
pub mod rigid_parts;
pub mod stay_put;

use super::model::Avatar;
use super::own_shapes::{MaskOnSkin, face_part_triangles};
use super::registration::FaceRegistration;
use super::registration::find_face::arkit_displacement;
use super::retargeting::{NegligibleLength, RetargetError, Retargeting, mapped_shapes};
use crate::arkit::{Blendshape, Blendshapes};
use crate::personalize::blendshape_fit::{in_parallel_chunks, in_parallel_ranges};
use adjacent_step::AdjacentStep;
use closed_lids::ClosedLids;
use eyelid_repair::{Eyeball, LID_OFFSET_MM, NEAR_MM, repair_eyelids};
use face_step::{FaceStep, FaceStepError};
use glam::{DVec3, Vec3};
use lid_contacts::ClosingEyes;
use rigid_parts::make_rigid;
use stay_put::{FADE_MM, STILL_MM, StillFade};

/// Skin within this distance of the face region (mm at the mask's scale,
/// along the surface) is the adjacent region of step 2: the difference
/// between the person's motion and `A_j` at the mask's rim (a brow raise
/// moves the top of the forehead) fades out over it instead of stopping
/// at one edge, and beyond it the avatar follows `A_j` alone
/// ([`adjacent_step`]).
pub const BLEND_MARGIN_MM: f64 = 30.0;

/// Why the shapes could not be implanted.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ImplantError {
    /// Step 1 failed.
    #[error("face step: {0}")]
    Face(#[from] FaceStepError),
    /// The personalized shapes do not fit the registration.
    #[error(transparent)]
    Mask(#[from] RetargetError),
    /// Step 2's system could not be solved.
    #[error("the region next to the face could not be solved")]
    Adjacent,
}

/// The person's 52 shapes on the avatar, and what each step covered.
#[derive(Clone, Debug, PartialEq)]
pub struct Implanted {
    /// For each ARKit shape (Apple's order), the displacement of every
    /// avatar vertex (as `Avatar::positions`).
    pub shapes: Vec<Vec<Vec3>>,
    /// Avatar vertices set by step 1 (the face region).
    pub face_vertices: usize,
    /// Avatar vertices set by step 2 (next to the face).
    pub adjacent_vertices: usize,
    /// Vertex displacements faded out because nothing moves there, over
    /// all 52 shapes ([`stay_put`]).
    pub still_faded: usize,
    /// Lid vertices moved out of an eyeball, over all 52 shapes.
    pub lids_repaired: usize,
    /// Eyes closed on the avatar because the person's closed (shape, eye
    /// pairs; [`lid_contacts`]).
    pub lids_closed: usize,
    /// Eyes given the avatar's own closed lid because the person's closed
    /// (shape, eye pairs; [`closed_lids`]).
    pub own_lids: usize,
    /// The parts found wholly rigid (every avatar target moves each of
    /// their pieces rigidly).
    pub rigid_parts: Vec<usize>,
    /// The rigid pieces held rigid ([`rigid_parts::rigid_pieces`]).
    pub rigid_pieces: Vec<rigid_parts::RigidPiece>,
    /// For each rigid piece, the largest deviation from a rigid motion
    /// that `A_j` had in any shape, removed (avatar units).
    pub rigid_deviation_removed: Vec<f64>,
}

/// Implants `personalized` (the person's neutral `B₀` and 52 deltas, mask
/// topology `mask_triangles`) into `avatar` found by `registration`, with
/// `retargeting` (Eq. 4 of the same shapes) for what the mask does not
/// cover (module docs).
pub fn implant(
    avatar: &Avatar,
    registration: &FaceRegistration,
    retargeting: &Retargeting,
    personalized: &Blendshapes,
    mask_triangles: &[[u32; 3]],
) -> Result<Implanted, ImplantError> {
    let positions: Vec<DVec3> = avatar.positions().iter().map(|p| p.as_dvec3()).collect();
    let offsets = avatar.vertex_offsets();
    let face_part_triangles = face_part_triangles(avatar, registration);
    let retargeted: Vec<Vec<DVec3>> = retargeting
        .displacements(avatar)
        .into_iter()
        .map(|d| d.into_iter().map(|x| x.as_dvec3()).collect())
        .collect();
    // The avatar's own ARKit shapes, in Apple's order (`None` where it
    // lacks one), read once.
    let own_shapes: Vec<Option<Vec<DVec3>>> = Blendshape::ALL
        .iter()
        .map(|b| arkit_displacement(avatar, *b))
        .collect();

    // Step 1.
    let face = FaceStep::new(&positions, &face_part_triangles, &registration.map)?;
    let mapped = mapped_shapes(registration, personalized)?;
    // The person's deviation from `A_j` as the mask sees it, `B_j − S(A_j)`,
    // is what step 1 carries; `A_j` itself is added at the avatar's own
    // resolution (module docs).
    let on_skin = MaskOnSkin::new(registration, &positions, &face_part_triangles);
    let s = registration.similarity;
    let seen: Vec<Vec<DVec3>> = retargeted.iter().map(|a| on_skin.see(a)).collect();
    let deviation: Vec<Vec<DVec3>> = Blendshape::ALL
        .iter()
        .zip(&seen)
        .map(|(b, seen)| {
            personalized
                .delta(*b)
                .iter()
                .zip(seen)
                .map(|(d, a)| *d - s.rotation.transpose() * *a / s.scale)
                .collect()
        })
        .collect();
    let deviation_mapped: Vec<Vec<DVec3>> = mapped
        .iter()
        .zip(&seen)
        .map(|(m, seen)| {
            m.iter()
                .zip(registration.map.apply(seen))
                .map(|(m, a)| *m - a)
                .collect()
        })
        .collect();
    let deltas: Vec<&[DVec3]> = deviation.iter().map(|d| d.as_slice()).collect();
    let mut on_face = face.transfer(
        personalized.neutral(),
        &deltas,
        mask_triangles,
        s.rotation,
        &deviation_mapped,
    )?;
    for (shape, a) in on_face.iter_mut().zip(&retargeted) {
        for (d, &v) in shape.iter_mut().zip(face.vertices()) {
            *d += a.get(v as usize).copied().unwrap_or(DVec3::ZERO);
        }
    }
    // Eyes the person closes, closed on the face patch.
    let closing = ClosingEyes::new(
        &positions,
        &face_part_triangles,
        registration,
        personalized,
        mask_triangles,
    );
    // Beyond the patch, `A_j` stands in for what step 2 will make.
    let patch_at = |j: usize, d: &Vec<DVec3>, v: u32| {
        let moved = match face.index(v) {
            Some(i) => d.get(i)?,
            None => retargeted.get(j)?.get(v as usize)?,
        };
        Some(positions[v as usize] + *moved)
    };
    let patch_close = |j: usize, d: &mut Vec<DVec3>, c: &[lid_contacts::LidContact]| {
        retargeted
            .get(j)
            .is_some_and(|beyond| face.close(&positions, beyond, d, c))
    };
    if !closing.close_all(&mut on_face, patch_at, patch_close) {
        return Err(ImplantError::Adjacent);
    }
    let mut full = retargeted.clone();
    for (j, shape) in on_face.iter().enumerate() {
        for (&v, d) in face.vertices().iter().zip(shape) {
            if let Some(x) = full[j].get_mut(v as usize) {
                *x = *d;
            }
        }
    }

    // Step 2, on the parts that hold the face.
    let n = positions.len();
    let mut is_face = vec![false; n];
    for &v in face.vertices() {
        if let Some(f) = is_face.get_mut(v as usize) {
            *f = true;
        }
    }
    let mut in_face_parts = vec![false; n];
    for &i in &registration.face_parts {
        if i + 1 < offsets.len() {
            in_face_parts[offsets[i]..offsets[i + 1]]
                .iter_mut()
                .for_each(|x| *x = true);
        }
    }
    let margin = adjacent_step::within(
        &positions,
        &face_part_triangles,
        &is_face,
        BLEND_MARGIN_MM * registration.similarity.scale / 1000.0,
    );
    let near: Vec<bool> = (0..n).map(|v| in_face_parts[v] && margin[v]).collect();
    let adjacent = AdjacentStep::new(&face_part_triangles, &is_face, &near);
    if !adjacent.complete(&mut full, &retargeted) {
        return Err(ImplantError::Adjacent);
    }
    // And on the region next to it, for lid vertices there.
    let full_at =
        |_: usize, d: &Vec<DVec3>, v: u32| Some(positions[v as usize] + *d.get(v as usize)?);
    let full_close = |_: usize, d: &mut Vec<DVec3>, c: &[lid_contacts::LidContact]| {
        adjacent.close(&positions, d, c)
    };
    if !closing.close_all(&mut full, full_at, full_close) {
        return Err(ImplantError::Adjacent);
    }
    // A closed eye whose opening the contacts cannot find closes the
    // avatar's way.
    let closed_lids = ClosedLids::new(
        &own_shapes,
        (
            &positions,
            &in_face_parts,
            registration.similarity.scale / 1000.0,
        ),
        &on_skin,
        personalized,
        (mask_triangles, closing.found()),
    );
    closed_lids.apply(&mut full);
    // What neither the person, the avatar's own target nor `A_j` moves
    // stays put.
    let to_avatar = registration.similarity.scale / 1000.0;
    let person_moves = mapped;
    let still = STILL_MM * to_avatar;
    let fading = StillFade::new(&positions, &face_part_triangles, FADE_MM * to_avatar);
    // Shape `j` faded (module docs of `stay_put`); the shapes are
    // independent, so they are shared out between the cores.
    let fade = |j: usize| -> (Vec<DVec3>, usize) {
        let mut moving = vec![false; n];
        for (f, m) in registration.map.face.iter().zip(&person_moves[j]) {
            if m.length() > still {
                moving[f.vertex as usize] = true;
            }
        }
        if let Some(own) = &own_shapes[j] {
            for (x, o) in moving.iter_mut().zip(own) {
                *x |= *o != DVec3::ZERO;
            }
        }
        for (x, a) in moving.iter_mut().zip(&retargeted[j]) {
            *x |= a.length() > still;
        }
        let mut d = full[j].clone();
        let changed = fading.apply(&mut d, &moving);
        (d, changed)
    };
    let fade_range = |range: std::ops::Range<usize>| range.map(fade).collect::<Vec<_>>();
    let faded_shapes: Vec<(Vec<DVec3>, usize)> = match in_parallel_ranges(full.len(), fade_range)
        .into_iter()
        .collect::<Option<Vec<_>>>()
    {
        Some(parts) => parts.into_iter().flatten().collect(),
        // A thread panicked: again on this thread, where the panic
        // reaches the caller.
        None => fade_range(0..full.len()),
    };
    let faded = faded_shapes
        .iter()
        .map(|(_, changed)| changed)
        .sum::<usize>();
    full = faded_shapes.into_iter().map(|(d, _)| d).collect();
    // Rigid pieces: each connected component outside the face parts that
    // every own target moves rigidly (an eyeball; each tooth, or a
    // teeth-and-gums arch, in a mesh that holds both jaws), held rigid.
    let own = avatar.moving_target_displacements();
    let pieces = rigid_parts::rigid_pieces(avatar, &positions, &own, &registration.face_parts);
    let rigid_deviation_removed: Vec<f64> = pieces
        .iter()
        .map(|piece| {
            full.iter_mut()
                .map(|d| make_rigid(&positions, d, &piece.vertices))
                .fold(0.0, f64::max)
        })
        .collect();

    // Eyelid repair.
    let eyeballs: Vec<Eyeball> = registration
        .eyeballs
        .iter()
        .map(|vertices| Eyeball::new(&positions, avatar.triangles_within(vertices)))
        .collect();
    let skin: Vec<u32> = (0..n as u32)
        .filter(|&v| in_face_parts[v as usize])
        .collect();
    // Shape by shape, the shapes shared out between the cores.
    let repair = |first: usize, shapes: &mut [Vec<DVec3>]| -> usize {
        shapes
            .iter_mut()
            .enumerate()
            .map(|(k, d)| {
                repair_eyelids(
                    &positions,
                    own_shapes[first + k].as_deref().unwrap_or_default(),
                    d,
                    &skin,
                    &eyeballs,
                    LID_OFFSET_MM * to_avatar,
                    NEAR_MM * to_avatar,
                )
            })
            .sum()
    };
    let lids_repaired: usize = match in_parallel_chunks(&mut full, repair)
        .into_iter()
        .collect::<Option<Vec<usize>>>()
    {
        Some(counts) => counts.into_iter().sum(),
        // A thread panicked: again on this thread, where the panic
        // reaches the caller.
        None => repair(0, &mut full),
    };
    // Invisible displacements written as zero, as for `A_j`.
    let cut = NegligibleLength::of(positions.iter().copied());
    Ok(Implanted {
        shapes: full
            .into_iter()
            .map(|d| d.into_iter().map(|x| cut.written(x)).collect())
            .collect(),
        face_vertices: face.vertices().len(),
        adjacent_vertices: adjacent.region().len(),
        still_faded: faded,
        lids_repaired,
        lids_closed: closing.count(),
        own_lids: closed_lids.count(),
        rigid_parts: rigid_parts::wholly_rigid_parts(avatar, &pieces),
        rigid_pieces: pieces,
        rigid_deviation_removed,
    })
}
