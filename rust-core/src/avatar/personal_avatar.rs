//! §3.3 end to end: a person's personalized shapes and an avatar in, the
//! person's avatar out as GLB bytes, with what each step found and every
//! step it had to skip said plainly. The command line and the phone (the
//! FFI) both call [`personal_avatar`]; neither repeats a decision.
//!
//! The steps, each in its own module: the face found ([`find_face()`], or a
//! registration cached from an earlier run), the person's own face taken
//! onto the avatar's rest if asked and the skin takes it without creasing
//! ([`skin_change`], [`super::rest_check`]), Eq. (4) ([`retarget`]), the
//! seamless partial deformation transfer ([`implant`]), and the GLB
//! written back ([`written_back_glb`]). Between steps the caller's
//! [`Progress`] hears how far the work has got and may cancel it.

use super::glb::{
    GlbAvatar, GlbError, MeshLook, NewGlbOptions, NewShapes, TargetEncoding, check_avatar,
    new_avatar_glb, written_back_glb,
};
use super::implant_check::{Fault, check_shapes};
use super::model::{Avatar, AvatarMesh, AvatarPart};
use super::partial_transfer::{ImplantError, Implanted, implant};
use super::person_face::{TakeFaceError, TakenFace, skin_change};
use super::registration::{FaceRegistration, RegistrationError, find_face};
use super::rest_check::{RestCreases, RestSpike, rest_creases, rest_spike, scan_bend};
use super::retargeting::{NEGLIGIBLE, RetargetError, Retargeting, retarget};
use super::target_names::{ArkitTargets, arkit_targets};
use crate::arkit::{Blendshape, Blendshapes};
use crate::geometry::Topology;
use glam::Vec3;
use serde::Serialize;
use std::fmt;
use std::path::Path;

/// A step of [`personal_avatar`], as reported to [`Progress`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AvatarStep {
    /// Checking the avatar's morph targets.
    Checking,
    /// Finding the face (skipped when a registration is given).
    FindingFace,
    /// Giving the avatar the person's face at rest (only for
    /// [`RestFace::Person`]).
    TakingFace,
    /// Eq. (4).
    Retargeting,
    /// Steps 1 and 2, rigid parts, eyelid repair.
    Implanting,
    /// Writing the GLB.
    Writing,
}

impl AvatarStep {
    /// The step in words.
    pub const fn name(self) -> &'static str {
        match self {
            AvatarStep::Checking => "checking the avatar",
            AvatarStep::FindingFace => "finding the face",
            AvatarStep::TakingFace => "taking the person's face",
            AvatarStep::Retargeting => "retargeting (Eq. 4)",
            AvatarStep::Implanting => "implanting the person's shapes",
            AvatarStep::Writing => "writing the GLB",
        }
    }

    /// The share of the whole work done when this step starts (measured
    /// on the default avatar: registration dominates).
    pub const fn done_before(self) -> f64 {
        match self {
            AvatarStep::Checking => 0.0,
            AvatarStep::FindingFace => 0.05,
            AvatarStep::TakingFace => 0.5,
            AvatarStep::Retargeting => 0.55,
            AvatarStep::Implanting => 0.6,
            AvatarStep::Writing => 0.9,
        }
    }
}

/// Hears which step starts and says whether to go on (`false` cancels).
pub trait Progress {
    /// `step` is about to start; return `false` to stop there.
    fn step(&mut self, step: AvatarStep) -> bool;
}

impl<F: FnMut(AvatarStep) -> bool> Progress for F {
    fn step(&mut self, step: AvatarStep) -> bool {
        self(step)
    }
}

/// Which shapes the written avatar carries.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum AvatarShapes {
    /// The person's shapes implanted (§3.3, the product).
    #[default]
    Personalized,
    /// The automatic retargeting `A_j` of Eq. (4): the avatar's own shapes
    /// combined (for comparison).
    Retargeted,
}

/// Whose face the avatar has at rest.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum RestFace {
    /// The avatar's own (the user chose that look).
    #[default]
    Stock,
    /// The person's, from the scanned neutral ([`crate::avatar::person_face`]):
    /// the default on the project's own default avatar.
    Person,
}

impl RestFace {
    /// Whose face an avatar gets at rest when the user asked for `asked`
    /// (or nothing): the person's on the project's default avatar, whose
    /// stock face nobody chose; the avatar's own on one the user brings,
    /// since they chose that look. What they asked for wins.
    pub fn chosen(on_default_avatar: bool, asked: Option<RestFace>) -> RestFace {
        asked.unwrap_or(if on_default_avatar {
            RestFace::Person
        } else {
            RestFace::Stock
        })
    }
}

/// Something the avatar lacked, so a step was skipped or limited; the
/// avatar is still written.
#[derive(Clone, Debug, PartialEq)]
pub enum AvatarWarning {
    /// ARKit shapes the avatar has no target for: Eq. (4) has less to
    /// combine (they are written anyway, from the person's mask).
    MissingShapes(Vec<Blendshape>),
    /// Targets with ARKit names that move nothing.
    StillTargets(Vec<String>),
    /// No eyeball found, by shape or by eyeLook
    /// ([`crate::avatar::registration::eyeballs`]): eyelid repair is
    /// skipped.
    NoEyeballs,
    /// No rigid piece (teeth, gums) follows the jaw: the mouth's inside
    /// is not held rigid.
    NoTeeth,
    /// A shape of the person's avatar is past a limit of the check
    /// ([`super::implant_check`]): it is written, and still animates.
    Fault(Fault),
    /// Taking the person's face would have creased the skin at rest
    /// ([`super::rest_check::rest_creases`]): the avatar kept its own
    /// face.
    RestCreased(RestCreases),
    /// Taking the person's face would have moved something much further
    /// than the scan asks of the face ([`super::rest_check::rest_spike`]):
    /// the avatar kept its own face.
    RestSpiked(RestSpike),
}

impl fmt::Display for AvatarWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            AvatarWarning::MissingShapes(shapes) => write!(
                f,
                "the avatar has no target for {} ARKit shape(s) ({}): retargeting combines the others",
                shapes.len(),
                shapes.iter().map(|b| b.name()).collect::<Vec<_>>().join(", ")
            ),
            AvatarWarning::StillTargets(names) => write!(
                f,
                "{} target(s) move nothing ({})",
                names.len(),
                names.join(", ")
            ),
            AvatarWarning::NoEyeballs => f.write_str(
                "no eyeballs found (no eye-sized sphere behind the lids, and no part that eyeLook moves): eyelid repair skipped",
            ),
            AvatarWarning::NoTeeth => f.write_str(
                "no teeth found (no piece of a mesh that jawOpen moves rigidly): the mouth's inside follows the retargeted shapes as they are",
            ),
            AvatarWarning::Fault(fault) => fault.fmt(f),
            AvatarWarning::RestCreased(creases) => creases.fmt(f),
            AvatarWarning::RestSpiked(spike) => {
                write!(f, "{spike}: the avatar keeps its own face")
            }
        }
    }
}

/// Why no avatar was made.
#[derive(Debug, thiserror::Error)]
pub enum AvatarError {
    /// The GLB could not be read, checked or written.
    #[error(transparent)]
    Glb(#[from] GlbError),
    /// Every morph target of the avatar is still.
    #[error("{file}: none of the avatar's {targets} morph targets moves a vertex")]
    StillAvatar {
        /// The avatar's file.
        file: String,
        /// Its morph targets.
        targets: usize,
    },
    /// No face was found.
    #[error("{file}: {source}")]
    Registration {
        /// The avatar's file.
        file: String,
        /// Why.
        #[source]
        source: RegistrationError,
    },
    /// Eq. (4) failed.
    #[error("{file}: {source}")]
    Retargeting {
        /// The avatar's file.
        file: String,
        /// Why.
        #[source]
        source: RetargetError,
    },
    /// The person's face could not be taken.
    #[error("{file}: taking the person's face: {source}")]
    TakeFace {
        /// The avatar's file.
        file: String,
        /// Why.
        #[source]
        source: TakeFaceError,
    },
    /// The transfer failed.
    #[error("{file}: {source}")]
    Implant {
        /// The avatar's file.
        file: String,
        /// Why.
        #[source]
        source: ImplantError,
    },
    /// The caller's [`Progress`] asked to stop before `step`.
    #[error("cancelled before {}", .0.name())]
    Cancelled(AvatarStep),
}

/// What [`personal_avatar`] needs besides the avatar.
pub struct PersonInput<'a> {
    /// The mask's topology (the session's).
    pub mask: &'a Topology,
    /// The generic template shapes on the mask (the session's template),
    /// which the face search starts from.
    pub rig: &'a Blendshapes,
    /// The person's personalized shapes on the mask.
    pub personalized: &'a Blendshapes,
}

/// The person's avatar, and what each step found.
#[derive(Debug)]
pub struct PersonalAvatar {
    /// The GLB: the avatar unchanged except its 52 ARKit targets.
    pub glb: Vec<u8>,
    /// Which targets carry ARKit's shapes in the avatar as read.
    pub found: ArkitTargets,
    /// The face found (or the one given), on the avatar as read.
    pub registration: FaceRegistration,
    /// The person's face taken onto the rest ([`RestFace::Person`]): the
    /// avatar the shapes were implanted into, and the registration moved
    /// with it.
    pub taken_face: Option<TakenFace>,
    /// Eq. (4).
    pub retargeting: Retargeting,
    /// What the transfer did (`None` for [`AvatarShapes::Retargeted`]).
    pub implanted: Option<Implanted>,
    /// What the avatar lacked.
    pub warnings: Vec<AvatarWarning>,
}

impl PersonalAvatar {
    /// The shapes past a limit of the check on the result
    /// ([`crate::avatar::implant_check`]), among the warnings.
    pub fn faults(&self) -> impl Iterator<Item = &Fault> {
        self.warnings.iter().filter_map(|w| match w {
            AvatarWarning::Fault(f) => Some(f),
            _ => None,
        })
    }

    /// The avatar the shapes were implanted into: `stock` (the avatar as
    /// read), or it with the person's face at rest.
    pub fn shaped<'a>(&'a self, stock: &'a Avatar) -> &'a Avatar {
        self.taken_face.as_ref().map_or(stock, |t| &t.avatar)
    }

    /// The registration on [`PersonalAvatar::shaped`].
    pub fn shaped_registration(&self) -> &FaceRegistration {
        self.taken_face
            .as_ref()
            .map_or(&self.registration, |t| &t.registration)
    }
}

/// Makes the person's avatar from `glb` (module docs): `registration` is a
/// face found earlier on this avatar for this mask (see
/// [`super::registration::cache`]), or `None` to find it now; `face` says
/// whose face it has at rest.
pub fn personal_avatar(
    glb: &GlbAvatar,
    person: &PersonInput<'_>,
    registration: Option<FaceRegistration>,
    shapes: AvatarShapes,
    face: RestFace,
    progress: &mut dyn Progress,
) -> Result<PersonalAvatar, AvatarError> {
    let file = glb.file.display().to_string();
    let mut go = |step: AvatarStep| {
        if progress.step(step) {
            Ok(())
        } else {
            Err(AvatarError::Cancelled(step))
        }
    };
    go(AvatarStep::Checking)?;
    let avatar = &glb.avatar;
    let found = check_avatar(glb)?;
    let mut warnings = still_targets(avatar, &found, &file)?;
    let missing = found.missing();
    if !missing.is_empty() {
        warnings.insert(0, AvatarWarning::MissingShapes(missing));
    }

    let registration = match registration {
        Some(r) => r,
        None => {
            go(AvatarStep::FindingFace)?;
            find_face(avatar, person.mask, person.rig).map_err(|source| {
                AvatarError::Registration {
                    file: file.clone(),
                    source,
                }
            })?
        }
    };
    if registration.eyeballs.is_empty() {
        warnings.push(AvatarWarning::NoEyeballs);
    }
    let taken_face = match face {
        RestFace::Stock => None,
        RestFace::Person => {
            go(AvatarStep::TakingFace)?;
            let taking = |source| AvatarError::TakeFace {
                file: file.clone(),
                source,
            };
            let skin = skin_change(avatar, &registration, person.personalized.neutral())
                .map_err(taking)?;
            // A face the skin cannot take without creasing is not taken:
            // the avatar keeps its own, and the person's motion. The skin
            // alone says (what it holds follows it after).
            let bend = scan_bend(avatar, &registration, person.personalized.neutral());
            match rest_creases(avatar, &registration, &skin.moved, &bend) {
                Some(creases) => {
                    warnings.push(AvatarWarning::RestCreased(creases));
                    None
                }
                None => {
                    let taken = skin.followed(avatar, &registration).map_err(taking)?;
                    // A face that would move anything far past what the
                    // scan asks is not taken either.
                    match rest_spike(avatar, &registration, &taken.moved, taken.asked_largest_mm) {
                        Some(spike) => {
                            warnings.push(AvatarWarning::RestSpiked(spike));
                            None
                        }
                        None => Some(taken),
                    }
                }
            }
        }
    };
    let (avatar, found_on) = match &taken_face {
        Some(t) => (&t.avatar, &t.registration),
        None => (avatar, &registration),
    };

    go(AvatarStep::Retargeting)?;
    let retargeting = retarget(avatar, found_on, person.personalized).map_err(|source| {
        AvatarError::Retargeting {
            file: file.clone(),
            source,
        }
    })?;

    go(AvatarStep::Implanting)?;
    let (displacements, implanted) = match shapes {
        AvatarShapes::Retargeted => (retargeting.displacements(avatar), None),
        AvatarShapes::Personalized => {
            let implanted = implant(
                avatar,
                found_on,
                &retargeting,
                person.personalized,
                (person.mask.triangles(), person.rig.neutral()),
            )
            .map_err(|source| AvatarError::Implant {
                file: file.clone(),
                source,
            })?;
            if !has_teeth(avatar, &implanted, found_on) {
                warnings.push(AvatarWarning::NoTeeth);
            }
            (implanted.shapes.clone(), Some(implanted))
        }
    };

    // The product checks its own output against the avatar's own rig.
    warnings.extend(
        check_shapes(
            avatar,
            found_on,
            &displacements,
            &retargeting.floored_residual,
        )
        .into_iter()
        .map(AvatarWarning::Fault),
    );

    go(AvatarStep::Writing)?;
    let mut new_shapes = per_part_shapes(avatar, &displacements);
    if taken_face.is_some() {
        new_shapes.set_rest(avatar.parts().iter().map(|p| p.positions.clone()).collect());
    }
    let bytes = written_back_glb(glb, &new_shapes, TargetEncoding::Smallest, &glb.file)?;
    Ok(PersonalAvatar {
        glb: bytes,
        found,
        registration,
        taken_face,
        retargeting,
        implanted,
        warnings,
    })
}

/// Whether some rigid piece other than the eyeballs moves with the jaw
/// (jawOpen moves it): teeth, gums or a tongue.
fn has_teeth(avatar: &Avatar, implanted: &Implanted, registration: &FaceRegistration) -> bool {
    let jaw = arkit_targets(avatar).displacement(avatar, Blendshape::JawOpen);
    let in_eyeball = |v: u32| {
        registration
            .eyeballs
            .iter()
            .any(|e| e.binary_search(&v).is_ok())
    };
    implanted
        .rigid_pieces
        .iter()
        .filter(|p| !p.vertices.iter().any(|&v| in_eyeball(v)))
        .any(|p| {
            p.vertices
                .iter()
                .any(|&v| jaw.get(v as usize).is_some_and(|x| *x != Vec3::ZERO))
        })
}

/// The ARKit shapes whose targets (on every mesh that has one, halves
/// summed) move no vertex by more than [`NEGLIGIBLE`] of the avatar's
/// size, as a warning; an error if every morph target of the avatar is
/// still. (A target that is zero on one mesh is normal: avatars give every
/// mesh all 52 names, and the mouth's do not move the eyes.)
fn still_targets(
    avatar: &Avatar,
    found: &ArkitTargets,
    file: &str,
) -> Result<Vec<AvatarWarning>, AvatarError> {
    let positions = avatar.positions();
    let size = positions
        .iter()
        .fold(None::<(Vec3, Vec3)>, |b, p| {
            Some(b.map_or((*p, *p), |(lo, hi)| (lo.min(*p), hi.max(*p))))
        })
        .map_or(0.0, |(lo, hi)| (hi - lo).length());
    let threshold = (NEGLIGIBLE * f64::from(size)) as f32;
    let still = |d: &[Vec3]| d.iter().all(|x| x.length() <= threshold);
    let ids = avatar.target_ids();
    if !ids.is_empty()
        && ids
            .iter()
            .all(|&(m, t)| still(&avatar.target_displacement(m, t)))
    {
        return Err(AvatarError::StillAvatar {
            file: file.to_string(),
            targets: ids.len(),
        });
    }
    let names: Vec<String> = Blendshape::ALL
        .iter()
        .filter(|b| {
            let ids = found.of(**b);
            !ids.is_empty() && still(&avatar.summed_displacement(ids))
        })
        .map(|b| b.name().to_string())
        .collect();
    Ok(if names.is_empty() {
        Vec::new()
    } else {
        vec![AvatarWarning::StillTargets(names)]
    })
}

/// `displacements[j]` (every avatar vertex, ARKit shape `j`) split per
/// part, as the GLB writer takes them.
pub fn per_part_shapes(avatar: &Avatar, displacements: &[Vec<Vec3>]) -> NewShapes {
    let offsets = avatar.vertex_offsets();
    let mut shapes = NewShapes::new();
    for (shape, all) in Blendshape::ALL.into_iter().zip(displacements) {
        let per_part = (0..avatar.parts().len())
            .filter_map(|i| Some(all.get(offsets[i]..offsets[i + 1])?.to_vec()))
            .collect();
        shapes.set(shape, per_part);
    }
    shapes
}

/// The person's personalized face mask alone (their neutral and 52
/// shapes, ARKit's face coordinates, metres) as a GLB with 52 targets in
/// ARKit's names; `name` names it in messages.
pub fn mask_glb(mask: &Topology, shapes: &Blendshapes, name: &Path) -> Result<Vec<u8>, GlbError> {
    let avatar = Avatar::new(
        vec![AvatarMesh {
            name: Some("mask".into()),
            target_names: Blendshape::ALL
                .iter()
                .map(|b| b.name().to_string())
                .collect(),
        }],
        vec![AvatarPart {
            name: "mask".into(),
            mesh: 0,
            primitive: 0,
            positions: shapes.neutral().iter().map(|p| p.as_vec3()).collect(),
            triangles: mask.triangles().to_vec(),
            targets: Blendshape::ALL
                .iter()
                .map(|b| shapes.delta(*b).iter().map(|d| d.as_vec3()).collect())
                .collect(),
        }],
    )
    .map_err(|source| GlbError::Avatar {
        file: name.to_path_buf(),
        source,
    })?;
    let options = NewGlbOptions {
        looks: vec![MeshLook::SKIN],
        ..NewGlbOptions::default()
    };
    new_avatar_glb(&avatar, &options, name)
}

/// The retarget map's file format (docs/avatar.md, "The retarget map").
#[derive(Serialize)]
struct RetargetMapFile<'a> {
    format: &'static str,
    version: u32,
    avatar: String,
    usage: &'static str,
    relative_ridge: f64,
    arkit: Vec<&'static str>,
    targets: Vec<MapTarget<'a>>,
    weights: &'a [Vec<f64>],
}

/// One of the avatar's blendshapes in the map: its name and the morph
/// targets that carry it.
#[derive(Serialize)]
struct MapTarget<'a> {
    name: &'a str,
    morph_targets: Vec<MapMorphTarget<'a>>,
}

#[derive(Serialize)]
struct MapMorphTarget<'a> {
    mesh: usize,
    #[serde(skip_serializing_if = "Option::is_none")]
    mesh_name: Option<&'a str>,
    index: usize,
}

/// The 52 × k weights of Eq. (4) as the JSON of docs/avatar.md's "The
/// retarget map", for engines that drive the avatar's own shapes.
pub fn retarget_map_json(glb: &GlbAvatar, r: &Retargeting) -> String {
    let file = RetargetMapFile {
        format: "likeness-retarget-map",
        version: 1,
        avatar: glb.file.display().to_string(),
        usage: "weight of the avatar's blendshape targets[i] = sum over ARKit shapes j of weights[j][i] * ARKit weight j",
        relative_ridge: r.relative_ridge,
        arkit: Blendshape::ALL.iter().map(|b| b.name()).collect(),
        targets: r
            .targets
            .iter()
            .map(|t| MapTarget {
                name: &t.name,
                morph_targets: t
                    .targets
                    .iter()
                    .map(|&(mesh, index)| MapMorphTarget {
                        mesh,
                        mesh_name: glb
                            .avatar
                            .meshes()
                            .get(mesh)
                            .and_then(|m| m.name.as_deref()),
                        index,
                    })
                    .collect(),
            })
            .collect(),
        weights: &r.weights,
    };
    // Serializing strings, numbers and arrays cannot fail.
    serde_json::to_string_pretty(&file).unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_avatar_takes_the_persons_face_and_a_brought_one_keeps_its_own() {
        assert_eq!(RestFace::chosen(true, None), RestFace::Person);
        assert_eq!(RestFace::chosen(false, None), RestFace::Stock);
        for asked in [RestFace::Stock, RestFace::Person] {
            for on_default in [true, false] {
                assert_eq!(RestFace::chosen(on_default, Some(asked)), asked);
            }
        }
    }
}
