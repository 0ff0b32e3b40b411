//! §3.3, the seamless partial deformation transfer (Fig. 3): the person's
//! shapes implanted into the avatar. Step 1 carries the personalized mask's
//! deformation onto the avatar's face region in the gradient domain; step 2
//! deforms the region next to it from the automatic retargeting `A_j`
//! with the face fixed; a lid that ends inside an eyeball is put back on
//! it; everything else (eyeballs, teeth, tongue, the back
//! of the head) follows `A_j`, which is zero where the avatar's own shapes
//! do not move it, except what lies just behind the skin, which follows
//! the skin ([`inside_follows`]).
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
//! | (beyond the paper) creases finer than the mask, which the transfer carries onto finer skin, smoothed out of the person's motion | [`crease_smoothing`] |
//! | (beyond the paper) what neither the person nor the avatar's rig moves stays put | [`stay_put`] |
//! | (beyond the paper) what lies just behind the skin (a lining, the teeth's edges) takes the skin's deviation from `A_j`, and what still comes out in front of the skin is put back behind it | [`inside_follows`] |
//! | §3.3 "eye balls and teeth … to their desired position" | rigid pieces (connected components any own target moves rigidly, in any mesh) kept rigid | [`rigid_parts`] |
//! | §3.3 "moving the eyelid vertices to their closest point on the eyeball surface \[2\]" | no lid inside an eyeball (eyeballs found by their shape, [`crate::avatar::registration::eyeballs`]) | [`eyelid_repair`] |

pub mod adjacent_step;
pub mod closed_lids;
pub mod crease_smoothing;
pub mod eyelid_repair;
pub mod face_step;
pub mod inside_follows;
pub mod lid_contacts;
pub mod rigid_parts;
pub mod stay_put;

use super::head_skin::{eyeball_flags, skin_flags};
use super::implant_check::open_blinks;
use super::model::Avatar;
use super::own_shapes::{MaskOnSkin, face_part_triangles};
use super::registration::FaceRegistration;
use super::registration::find_face::arkit_displacement;
use super::retargeting::{NegligibleLength, RetargetError, Retargeting, mapped_shapes};
use crate::arkit::{Blendshape, Blendshapes};
use crate::avatar::showing_through::InsideProbe;
use crate::geometry::dihedral_angle::Hinges;
use crate::geometry::mesh_boundary::{EyeHole, boundary_edges};
use crate::geometry::sparse_cholesky::FactorError;
use crate::personalize::blendshape_fit::{in_parallel_chunks, in_parallel_map, in_parallel_ranges};
use adjacent_step::AdjacentStep;
use closed_lids::ClosedLids;
use crease_smoothing::{CreaseSmoothing, ShapeToSmooth};
use eyelid_repair::{Eyeball, LID_OFFSET_MM, NEAR_MM, repair_eyelids};
use face_step::{FaceStep, FaceStepError};
use glam::{DVec3, Vec3};
use inside_follows::InsideFollows;
use lid_contacts::{ClosingEyes, LidClosingError, mask_eye_holes};
use rigid_parts::hold_rigid;
use stay_put::{FADE_MM, STILL_MM, StillFade};

/// Skin within this distance of the face region (mm at the mask's scale,
/// along the surface) is the adjacent region of step 2: the difference
/// between the person's motion and `A_j` at the mask's rim (a brow raise
/// moves the top of the forehead) fades out over it instead of stopping
/// at one edge, and beyond it the avatar follows `A_j` alone
/// ([`adjacent_step`]).
pub const BLEND_MARGIN_MM: f64 = 30.0;

/// Why the shapes could not be implanted, by the step that failed.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ImplantError {
    /// The personalized shapes do not fit the registration.
    #[error(transparent)]
    Mask(#[from] RetargetError),
    /// Step 1, the face patch, failed.
    #[error("face step: {0}")]
    Face(#[from] FaceStepError),
    /// A closed eye's lids could not be made to meet on the face patch.
    #[error("closing the lids on the face: {0}")]
    FaceLids(LidClosingError),
    /// Step 2's system, the region next to the face, could not be factored.
    #[error("the region next to the face: {0}")]
    Adjacent(FactorError),
    /// A closed eye's lids could not be made to meet in the region next to
    /// the face.
    #[error("closing the lids next to the face: {0}")]
    AdjacentLids(LidClosingError),
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
    /// Skin edges creased by a shape where the avatar's own shape keeps
    /// them smooth, over all 52 shapes, before and after smoothing
    /// ([`crease_smoothing`]).
    pub creases_found: usize,
    /// See `creases_found`.
    pub creases_left: usize,
    /// Vertices behind the skin that follow its deviation from `A_j`
    /// ([`inside_follows`]).
    pub behind_skin: usize,
    /// Vertices behind the skin put back behind it, over all 52 shapes
    /// ([`inside_follows::put_back`]).
    pub put_back_behind_skin: usize,
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
/// cover (module docs): the steps below, in order, each on what the one
/// before left. `template_neutral` is the template's neutral: the mask's
/// eye holes are split into lids at its corners, as the personalization
/// split them to close the person's blinks ([`mask_eye_holes`]).
pub fn implant(
    avatar: &Avatar,
    registration: &FaceRegistration,
    retargeting: &Retargeting,
    personalized: &Blendshapes,
    (mask_triangles, template_neutral): (&[[u32; 3]], &[DVec3]),
) -> Result<Implanted, ImplantError> {
    let scene = Scene::new(avatar, registration, retargeting);
    let mapped = mapped_shapes(registration, personalized)?;
    let on_skin = MaskOnSkin::new(registration, &scene.positions, &scene.skin_triangles);
    let holes = mask_eye_holes(mask_triangles, template_neutral);
    let closing = ClosingEyes::new(
        &scene.positions,
        &scene.skin_triangles,
        registration,
        personalized,
        &holes,
    );
    let person = Person {
        shapes: personalized,
        mask_triangles,
        mapped: &mapped,
    };
    let face = FaceStep::new(&scene.positions, &scene.skin_triangles, &registration.map)?;
    let mut on_face = face_step(&scene, &face, &on_skin, &person)?;
    close_lids_on_face(&scene, &face, &closing, &mut on_face).map_err(ImplantError::FaceLids)?;
    let mut full = beyond_the_face(&scene, &face, on_face);
    let adjacent = adjacent_step(&scene, &face, &mut full).map_err(ImplantError::Adjacent)?;
    close_lids_next_to_face(&scene, &adjacent, &closing, &mut full)
        .map_err(ImplantError::AdjacentLids)?;
    let closed_by_contacts = still_closed(&scene, &closing, (&holes, template_neutral), &full);
    let closed_lids = ClosedLids::new(
        &scene.own_shapes,
        (&scene.positions, &scene.in_face_parts, scene.to_avatar),
        &on_skin,
        personalized,
        (&holes, &closed_by_contacts),
    );
    closed_lids.apply(&mut full);
    let still_faded = stay_put_step(&scene, &mapped, &mut full);
    let (creases_found, creases_left) =
        smooth_creases(&scene, (&closing, &closed_lids), personalized, &mut full);
    let behind_skin = follow_the_skin(&scene, &mut full);
    let (rigid_pieces, rigid_deviation_removed) = hold_rigid_pieces(&scene, &mut full);
    let lids_repaired = repair_lids(&scene, &mut full);
    let put_back_behind_skin = put_back_inside(&scene, &rigid_pieces, &mut full);
    // Invisible displacements written as zero, as for `A_j`.
    let cut = NegligibleLength::of(scene.positions.iter().copied());
    Ok(Implanted {
        shapes: full
            .into_iter()
            .map(|d| d.into_iter().map(|x| cut.written(x)).collect())
            .collect(),
        face_vertices: face.vertices().len(),
        adjacent_vertices: adjacent.region().len(),
        still_faded,
        creases_found,
        creases_left,
        behind_skin,
        put_back_behind_skin,
        lids_repaired,
        lids_closed: closing.count(),
        own_lids: closed_lids.count(),
        rigid_parts: rigid_parts::wholly_rigid_parts(avatar, &rigid_pieces),
        rigid_pieces,
        rigid_deviation_removed,
    })
}

/// The mask's eye holes whose opening the lid contacts found and closed
/// ([`ClosingEyes::found`]) and whose blink (`eyeBlinkLeft` for the hole on
/// the mask's +x side) then leaves no more of the eyeball seen than the
/// avatar's own blink does, within the check's slack
/// ([`crate::avatar::implant_check::open_blinks`]). The others take the
/// avatar's own closed lids ([`ClosedLids`]): where the opening found is
/// not the lids' visible edge (MakeHuman's lids fold 4 mm inwards from
/// their margins to the loop the contacts close), the margins stayed a
/// slit apart and 2.2–2.9% of the eyeball stayed seen, where MakeHuman's
/// own blink shows none.
fn still_closed(
    scene: &Scene,
    closing: &ClosingEyes,
    (holes, template_neutral): (&[EyeHole], &[DVec3]),
    full: &[Vec<DVec3>],
) -> Vec<usize> {
    closing
        .found()
        .iter()
        .copied()
        .filter(|&h| {
            let Some(hole) = holes.get(h) else {
                return false;
            };
            let x: f64 = hole
                .upper
                .iter()
                .filter_map(|&v| template_neutral.get(v as usize))
                .map(|p| p.x)
                .sum();
            let blink = match x > 0.0 {
                true => Blendshape::EyeBlinkLeft,
                false => Blendshape::EyeBlinkRight,
            };
            let (Some(Some(own)), Some(got)) =
                (scene.own_shapes.get(blink.index()), full.get(blink.index()))
            else {
                return true;
            };
            let single = |d: &[DVec3]| d.iter().map(|x| x.as_vec3()).collect::<Vec<Vec3>>();
            open_blinks(
                scene.avatar,
                scene.registration,
                blink,
                (&single(own), &single(got)),
            )
            .is_empty()
        })
        .collect()
}

/// What every step reads of the avatar: its rest positions in double
/// precision, the triangles of the parts that hold the face, `A_j`, and
/// its own ARKit shapes.
struct Scene<'a> {
    avatar: &'a Avatar,
    registration: &'a FaceRegistration,
    /// Every vertex at rest ([`Avatar::positions`]).
    positions: Vec<DVec3>,
    /// The triangles of the parts the face was found on, avatar indices.
    skin_triangles: Vec<[u32; 3]>,
    /// Whether each vertex lies in a part the face was found on.
    in_face_parts: Vec<bool>,
    /// `A_j` for each ARKit shape (Apple's order), every vertex.
    retargeted: Vec<Vec<DVec3>>,
    /// The avatar's own ARKit shapes, Apple's order; `None` where it lacks
    /// one.
    own_shapes: Vec<Option<Vec<DVec3>>>,
    /// Avatar units per metre of the mask: a length in mm at the mask's
    /// scale times this / 1000 is one in the avatar's units.
    to_avatar: f64,
}

impl<'a> Scene<'a> {
    fn new(
        avatar: &'a Avatar,
        registration: &'a FaceRegistration,
        retargeting: &Retargeting,
    ) -> Scene<'a> {
        let positions: Vec<DVec3> = avatar.positions().iter().map(|p| p.as_dvec3()).collect();
        let in_face_parts = skin_flags(avatar, registration);
        Scene {
            avatar,
            registration,
            skin_triangles: face_part_triangles(avatar, registration),
            in_face_parts,
            retargeted: retargeting
                .displacements(avatar)
                .into_iter()
                .map(|d| d.into_iter().map(|x| x.as_dvec3()).collect())
                .collect(),
            own_shapes: in_parallel_map(Blendshape::ALL.len(), |j| {
                arkit_displacement(avatar, Blendshape::ALL[j])
            }),
            to_avatar: registration.similarity.scale / 1000.0,
            positions,
        }
    }
}

/// The person's side: their shapes on the mask, its triangles, and the
/// shapes mapped onto the avatar's face vertices through `M`.
struct Person<'a> {
    shapes: &'a Blendshapes,
    mask_triangles: &'a [[u32; 3]],
    mapped: &'a [Vec<DVec3>],
}

/// Step 1: each shape's displacement of the face patch,
/// `D_j = A_j + T(B_j − S(A_j))` (module docs), in the patch's vertex
/// order ([`FaceStep::vertices`]).
fn face_step(
    scene: &Scene,
    face: &FaceStep,
    on_skin: &MaskOnSkin,
    person: &Person,
) -> Result<Vec<Vec<DVec3>>, FaceStepError> {
    let s = scene.registration.similarity;
    let seen: Vec<Vec<DVec3>> = scene.retargeted.iter().map(|a| on_skin.see(a)).collect();
    let deviation: Vec<Vec<DVec3>> = Blendshape::ALL
        .iter()
        .zip(&seen)
        .map(|(b, seen)| {
            person
                .shapes
                .delta(*b)
                .iter()
                .zip(seen)
                .map(|(d, a)| *d - s.rotation.transpose() * *a / s.scale)
                .collect()
        })
        .collect();
    let deviation_mapped: Vec<Vec<DVec3>> = person
        .mapped
        .iter()
        .zip(&seen)
        .map(|(m, seen)| {
            m.iter()
                .zip(scene.registration.map.apply(seen))
                .map(|(m, a)| *m - a)
                .collect()
        })
        .collect();
    let deltas: Vec<&[DVec3]> = deviation.iter().map(|d| d.as_slice()).collect();
    let mut on_face = face.transfer(
        person.shapes.neutral(),
        &deltas,
        person.mask_triangles,
        s.rotation,
        &deviation_mapped,
    )?;
    for (shape, a) in on_face.iter_mut().zip(&scene.retargeted) {
        for (d, &v) in shape.iter_mut().zip(face.vertices()) {
            *d += a.get(v as usize).copied().unwrap_or(DVec3::ZERO);
        }
    }
    Ok(on_face)
}

/// The eyes the person closes, closed on the face patch `on_face` (step
/// 1's result; [`lid_contacts`]): beyond the patch `A_j` stands in for
/// what step 2 will make.
fn close_lids_on_face(
    scene: &Scene,
    face: &FaceStep,
    closing: &ClosingEyes,
    on_face: &mut [Vec<DVec3>],
) -> Result<(), LidClosingError> {
    let (positions, retargeted) = (&scene.positions, &scene.retargeted);
    let at = |j: usize, d: &Vec<DVec3>, v: u32| {
        let moved = match face.index(v) {
            Some(i) => d.get(i)?,
            None => retargeted.get(j)?.get(v as usize)?,
        };
        Some(positions[v as usize] + *moved)
    };
    let close =
        |j: usize, d: &mut Vec<DVec3>, c: &[lid_contacts::LidContact]| match retargeted.get(j) {
            Some(beyond) => face.close(positions, beyond, d, c),
            None => Ok(()),
        };
    closing.close_all(on_face, at, close)
}

/// Every vertex's displacement for each shape: step 1's `on_face` on the
/// face patch, `A_j` everywhere else (until step 2).
fn beyond_the_face(scene: &Scene, face: &FaceStep, on_face: Vec<Vec<DVec3>>) -> Vec<Vec<DVec3>> {
    let mut full = scene.retargeted.clone();
    for (j, shape) in on_face.iter().enumerate() {
        for (&v, d) in face.vertices().iter().zip(shape) {
            if let Some(x) = full[j].get_mut(v as usize) {
                *x = *d;
            }
        }
    }
    full
}

/// Step 2: the skin of the face parts within [`BLEND_MARGIN_MM`] of the
/// face patch, completed in every shape of `full` as `A_j + C`
/// ([`adjacent_step`]).
fn adjacent_step(
    scene: &Scene,
    face: &FaceStep,
    full: &mut [Vec<DVec3>],
) -> Result<AdjacentStep, FactorError> {
    let n = scene.positions.len();
    let mut is_face = vec![false; n];
    for &v in face.vertices() {
        if let Some(f) = is_face.get_mut(v as usize) {
            *f = true;
        }
    }
    let margin = adjacent_step::within(
        &scene.positions,
        &scene.skin_triangles,
        &is_face,
        BLEND_MARGIN_MM * scene.registration.similarity.scale / 1000.0,
    );
    let near: Vec<bool> = (0..n)
        .map(|v| scene.in_face_parts[v] && margin[v])
        .collect();
    let adjacent = AdjacentStep::new(&scene.skin_triangles, &is_face, &near)?;
    adjacent.complete(full, &scene.retargeted);
    Ok(adjacent)
}

/// The eyes the person closes, closed again for lid vertices in step 2's
/// region ([`AdjacentStep::close`]).
fn close_lids_next_to_face(
    scene: &Scene,
    adjacent: &AdjacentStep,
    closing: &ClosingEyes,
    full: &mut [Vec<DVec3>],
) -> Result<(), LidClosingError> {
    let positions = &scene.positions;
    let at = |_: usize, d: &Vec<DVec3>, v: u32| Some(positions[v as usize] + *d.get(v as usize)?);
    let close = |_: usize, d: &mut Vec<DVec3>, c: &[lid_contacts::LidContact]| {
        adjacent.close(positions, d, c)
    };
    closing.close_all(full, at, close)
}

/// What neither the person, the avatar's own target nor `A_j` moves stays
/// put ([`stay_put`]); returns how many displacements were faded. The
/// shapes are independent, so they are shared out between the cores.
fn stay_put_step(scene: &Scene, mapped: &[Vec<DVec3>], full: &mut Vec<Vec<DVec3>>) -> usize {
    let n = scene.positions.len();
    let still = STILL_MM * scene.to_avatar;
    let fading = StillFade::new(
        &scene.positions,
        &scene.skin_triangles,
        FADE_MM * scene.to_avatar,
    );
    let fade = |j: usize| -> (Vec<DVec3>, usize) {
        let mut moving = vec![false; n];
        for (f, m) in scene.registration.map.face.iter().zip(&mapped[j]) {
            if m.length() > still {
                moving[f.vertex as usize] = true;
            }
        }
        if let Some(own) = &scene.own_shapes[j] {
            for (x, o) in moving.iter_mut().zip(own) {
                *x |= *o != DVec3::ZERO;
            }
        }
        for (x, a) in moving.iter_mut().zip(&scene.retargeted[j]) {
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
    let faded = faded_shapes.iter().map(|(_, changed)| changed).sum();
    *full = faded_shapes.into_iter().map(|(d, _)| d).collect();
    faded
}

/// Creases finer than the mask smoothed out of every shape
/// ([`crease_smoothing`]), the lids a closing placed and the lips' edges
/// held (a smoothed corner of the mouth strayed 2.5 mm from the person's
/// mouthClose, `tests/tests/partial_transfer.rs`), the shapes
/// shared out between the cores; returns the creased edges found and
/// left over all shapes. A shape whose region cannot be solved is left
/// as it was (the shapes' check still counts its folds).
fn smooth_creases(
    scene: &Scene,
    (closing, closed_lids): (&ClosingEyes, &ClosedLids),
    personalized: &Blendshapes,
    full: &mut [Vec<DVec3>],
) -> (usize, usize) {
    let n = scene.positions.len();
    let smoothing = CreaseSmoothing::new(&scene.positions, &scene.skin_triangles, scene.to_avatar);
    let neutral = personalized.neutral();
    let map = &scene.registration.map;
    let mask_hinges = map
        .mask_triangles
        .iter()
        .flatten()
        .all(|&v| (v as usize) < neutral.len())
        .then(|| Hinges::new(neutral, &map.mask_triangles));
    // The lips' edges (the skin's border where it is lip): where the lips
    // meet, part and press, the line the person's mouth draws.
    let lips = scene.registration.lip_sides();
    let on_lip = scene.registration.vertex_lips(&lips, n);
    let mut lip_edges = vec![false; n];
    for (a, b) in boundary_edges(&scene.skin_triangles) {
        for v in [a, b] {
            if on_lip.get(v as usize).is_some_and(|l| *l != 0) {
                lip_edges[v as usize] = true;
            }
        }
    }
    let smooth = |first: usize, shapes: &mut [Vec<DVec3>]| -> (usize, usize) {
        let mut counts = (0, 0);
        for (k, made) in shapes.iter_mut().enumerate() {
            let j = first + k;
            let bend = mask_bend(scene, (personalized, mask_hinges.as_ref()), j);
            let mut held = lip_edges.clone();
            closing.hold(j, &mut held);
            closed_lids.hold(j, &mut held);
            let retargeted = &scene.retargeted[j];
            let own = scene.own_shapes[j].as_deref().unwrap_or(retargeted);
            let shape = ShapeToSmooth {
                made,
                own,
                retargeted,
                held: &held,
                mask_bend: &bend,
            };
            // A shape whose region cannot be solved is left as it was made.
            if let Ok((found, left)) = smoothing.smooth(&scene.positions, shape) {
                counts.0 += found;
                counts.1 += left;
            }
        }
        counts
    };
    match in_parallel_chunks(full, smooth)
        .into_iter()
        .collect::<Option<Vec<(usize, usize)>>>()
    {
        Some(counts) => counts
            .into_iter()
            .fold((0, 0), |a, b| (a.0 + b.0, a.1 + b.1)),
        // A thread panicked: again on this thread, where the panic
        // reaches the caller.
        None => smooth(0, full),
    }
}

/// For each avatar vertex, how much the person's shape `j` bends the mask
/// at the mask triangle `M` takes the vertex to: the largest change of the
/// dihedral angles at its three edges (radians; 0 off the face, or where
/// the mask's `hinges` could not be made: a map naming vertices the
/// neutral lacks).
fn mask_bend(
    scene: &Scene,
    (personalized, hinges): (&Blendshapes, Option<&Hinges>),
    j: usize,
) -> Vec<f64> {
    let mut bend = vec![0.0; scene.positions.len()];
    let (Some(shape), Some(hinges)) = (Blendshape::ALL.get(j), hinges) else {
        return bend;
    };
    let neutral = personalized.neutral();
    let at_triangles =
        hinges.largest_at_triangles(&hinges.changes(neutral, personalized.delta(*shape)));
    for f in &scene.registration.map.face {
        if let (Some(b), Some(x)) = (
            bend.get_mut(f.vertex as usize),
            at_triangles.get(f.triangle as usize),
        ) {
            *b = *x;
        }
    }
    bend
}

/// What lies just behind the skin takes the skin's deviation from `A_j`
/// in every shape ([`inside_follows`]); returns how many vertices follow.
fn follow_the_skin(scene: &Scene, full: &mut [Vec<DVec3>]) -> usize {
    let in_eyeball = eyeball_flags(scene.avatar, scene.registration);
    let follows = InsideFollows::new(
        &scene.positions,
        &scene.skin_triangles,
        |v| !scene.in_face_parts[v] && !in_eyeball[v],
        scene.to_avatar,
    );
    for (made, retargeted) in full.iter_mut().zip(&scene.retargeted) {
        follows.apply(retargeted, made);
    }
    follows.len()
}

/// Rigid pieces: each connected component off the skin the mask lies on
/// that every own target moves rigidly (an eyeball; each tooth, or a
/// teeth-and-gums arch, in a mesh that holds both jaws), held rigid in
/// every shape ([`rigid_parts`]). Returns the pieces and, for each, the
/// largest deviation from a rigid motion removed.
fn hold_rigid_pieces(
    scene: &Scene,
    full: &mut [Vec<DVec3>],
) -> (Vec<rigid_parts::RigidPiece>, Vec<f64>) {
    let own = scene.avatar.moving_target_displacements();
    let mut on_mask = vec![false; scene.positions.len()];
    for f in &scene.registration.map.face {
        if let Some(flag) = on_mask.get_mut(f.vertex as usize) {
            *flag = true;
        }
    }
    let pieces = rigid_parts::rigid_pieces(scene.avatar, &scene.positions, &own, &on_mask);
    let removed = pieces
        .iter()
        .map(|piece| {
            full.iter_mut()
                .map(|d| hold_rigid(&scene.positions, d, piece))
                .fold(0.0, f64::max)
        })
        .collect();
    (pieces, removed)
}

/// Nothing from behind the skin in front of it ([`inside_follows::put_back`]),
/// shape by shape, the shapes shared out between the cores; returns the
/// vertices put back.
fn put_back_inside(
    scene: &Scene,
    pieces: &[rigid_parts::RigidPiece],
    full: &mut [Vec<DVec3>],
) -> usize {
    let probe = InsideProbe::new(scene.avatar, scene.registration);
    let mut piece_of = vec![None; scene.positions.len()];
    for (k, piece) in pieces.iter().enumerate() {
        for &v in &piece.vertices {
            piece_of[v as usize] = Some(k);
        }
    }
    let vertices: Vec<&[u32]> = pieces.iter().map(|p| p.vertices.as_slice()).collect();
    let clear = inside_follows::BEHIND_MM * scene.to_avatar;
    count_over_shapes(full, |j, d| {
        let own = scene.own_shapes[j].as_deref().unwrap_or_default();
        inside_follows::put_back(
            &probe,
            &scene.positions,
            (&piece_of, &vertices),
            own,
            d,
            clear,
        )
    })
}

/// No lid inside an eyeball ([`eyelid_repair`]), shape by shape, the
/// shapes shared out between the cores; returns the lid vertices moved.
fn repair_lids(scene: &Scene, full: &mut [Vec<DVec3>]) -> usize {
    let positions = &scene.positions;
    let eyeballs: Vec<Eyeball> = scene
        .registration
        .eyeballs
        .iter()
        .map(|vertices| Eyeball::new(positions, scene.avatar.triangles_within(vertices)))
        .collect();
    let skin: Vec<u32> = (0..positions.len() as u32)
        .filter(|&v| scene.in_face_parts[v as usize])
        .collect();
    count_over_shapes(full, |j, d| {
        repair_eyelids(
            positions,
            scene.own_shapes[j].as_deref().unwrap_or_default(),
            d,
            &skin,
            &eyeballs,
            LID_OFFSET_MM * scene.to_avatar,
            NEAR_MM * scene.to_avatar,
        )
    })
}

/// The sum over the shapes of `full` of `per_shape(j, shape j)`, the
/// shapes shared out between the cores ([`in_parallel_chunks`]).
fn count_over_shapes(
    full: &mut [Vec<DVec3>],
    per_shape: impl Fn(usize, &mut Vec<DVec3>) -> usize + Sync,
) -> usize {
    let run = |first: usize, shapes: &mut [Vec<DVec3>]| -> usize {
        shapes
            .iter_mut()
            .enumerate()
            .map(|(k, d)| per_shape(first + k, d))
            .sum()
    };
    match in_parallel_chunks(full, run)
        .into_iter()
        .collect::<Option<Vec<usize>>>()
    {
        Some(counts) => counts.into_iter().sum(),
        // A thread panicked: again on this thread, where the panic
        // reaches the caller.
        None => run(0, full),
    }
}
