//! What each part of an avatar is: the skin the face was found on, an
//! eyeball, a row of teeth, the tongue, or something else (ears, linings,
//! hair, a body, glasses). Skin and eyeballs come from the search itself
//! ([`super::find_face()`], [`super::eyeballs`]); the mouth's parts are told
//! by which of the avatar's own ARKit shapes move them, as a rig moves
//! them:
//!
//! - **tongue**: `tongueOut` moves most of its vertices;
//! - **lower teeth** (the lower row, its gums): only the jaw's shapes
//!   (`jawOpen`, `jawForward`, `jawLeft`, `jawRight`, `mouthClose`) move
//!   it, and `jawOpen` moves every vertex of it;
//!
//!   and, for either, `jawOpen` moves them as a body: every vertex it moves
//!   by at least [`JAW_BODY_SHARE`] of its largest motion there (bar
//!   [`JAW_SEAM_SHARE`] of them), where a lining of the mouth fades out;
//! - **teeth** (both rows in one part, as ICT-FaceKit's `TeethGums`): only
//!   the jaw's shapes move it, and `jawOpen` some of its vertices;
//! - **upper teeth** (the upper row, its gums): no shape moves it, and it
//!   lies behind the mouth's slit, within [`MOUTH_REACH_MM`] of it;
//! - **other**: the rest (a lining of the mouth, a moustache in front of
//!   the lips, glasses, hair).
//!
//! A shape "moves" a vertex beyond [`MOVE_SHARE`] of the part's largest
//! motion.

use crate::arkit::Blendshape;
use crate::avatar::model::Avatar;
use crate::avatar::target_names::arkit_targets;
use glam::DVec3;
use serde::{Deserialize, Serialize};

/// What a part of the avatar is (module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum PartRole {
    /// The skin the face was found on.
    Skin,
    /// Wholly an eyeball (sclera, iris, cornea).
    Eyeball,
    /// The upper row of teeth, or its gums.
    UpperTeeth,
    /// The lower row of teeth, or its gums.
    LowerTeeth,
    /// Both rows of teeth in one part.
    Teeth,
    /// The tongue.
    Tongue,
    /// Anything else.
    Other,
}

impl PartRole {
    /// The role's name in reports: `skin`, `eyeball`, `upper teeth`, ….
    pub fn name(self) -> &'static str {
        match self {
            PartRole::Skin => "skin",
            PartRole::Eyeball => "eyeball",
            PartRole::UpperTeeth => "upper teeth",
            PartRole::LowerTeeth => "lower teeth",
            PartRole::Teeth => "teeth",
            PartRole::Tongue => "tongue",
            PartRole::Other => "other",
        }
    }

    /// Whether the part is teeth (or their gums): upper, lower or both.
    pub fn is_teeth(self) -> bool {
        matches!(
            self,
            PartRole::UpperTeeth | PartRole::LowerTeeth | PartRole::Teeth
        )
    }
}

/// How far from the mouth's slit (mm at the mask's scale) a part that no
/// shape moves may have its centre, behind the slit, and be upper teeth:
/// the upper dental arch reaches a few centimetres back from the incisors,
/// which sit 10–15 mm behind the lips' surface, so its centre lies well
/// within this; glasses, hair or a body lie farther, or in front.
pub const MOUTH_REACH_MM: f64 = 45.0;

/// The shapes a rig moves the jaw with: teeth follow these and no others.
const JAW_SHAPES: [Blendshape; 5] = [
    Blendshape::JawOpen,
    Blendshape::JawForward,
    Blendshape::JawLeft,
    Blendshape::JawRight,
    Blendshape::MouthClose,
];

/// The mouth as placed on the avatar: the centre of the registered mask's
/// slit, the direction out of the face, and avatar units per millimetre
/// of the mask.
#[derive(Clone, Copy, Debug)]
pub struct MouthPlace {
    /// Centre of the mouth's slit.
    pub centre: DVec3,
    /// Unit direction out of the face.
    pub forward: DVec3,
    /// Avatar units per mm at the mask's scale.
    pub per_mm: f64,
}

/// A shape moves a vertex when it displaces it by more than this share of
/// the largest displacement any ARKit shape gives the part: rigs leave
/// sculpting noise on parts a shape does not mean to move
/// (ICT-FaceKit's `TeethGums` moves under its eye and brow shapes by under
/// 1% of what `jawOpen` moves it).
pub const MOVE_SHARE: f64 = 0.05;

/// The least share of its largest `jawOpen` motion the jaw gives every
/// vertex of teeth or gums it moves: the jaw turns about its hinge, and the
/// last molars lie about half as far from it as the incisors, so they
/// move about half as far; a lining that stretches from the moving lower
/// lip to the still palate moves its vertices anywhere from nothing up.
pub const JAW_BODY_SHARE: f64 = 0.25;

/// The share of the jaw's moved vertices allowed below
/// [`JAW_BODY_SHARE`]: where a part joins the lower gums to the upper, the
/// joint may stretch. ICT-FaceKit's `TeethGums` (both gums one connected
/// piece) needs none of it: all 1,690 vertices its jawOpen moves move by
/// over a quarter of the largest motion; the default avatar's lining, 16%
/// of them by less.
pub const JAW_SEAM_SHARE: f64 = 0.05;

/// Each part's role (module docs): `face_parts` are skin, `eyeball_parts`
/// eyeballs, the rest by the avatar's own shapes and `mouth`.
pub fn part_roles(
    avatar: &Avatar,
    face_parts: &[usize],
    eyeball_parts: &[usize],
    mouth: MouthPlace,
) -> Vec<PartRole> {
    let targets = arkit_targets(avatar);
    (0..avatar.parts().len())
        .map(|i| {
            if face_parts.contains(&i) {
                return PartRole::Skin;
            }
            if eyeball_parts.contains(&i) {
                return PartRole::Eyeball;
            }
            let part = &avatar.parts()[i];
            let n = part.positions.len();
            // How far each shape moves each vertex of the part.
            let lengths = |shape: Blendshape| -> Vec<f32> {
                let mut moved = vec![0.0f32; n];
                for &(m, t) in targets.of(shape) {
                    if m == part.mesh
                        && let Some(d) = part.targets.get(t)
                    {
                        for (x, d) in moved.iter_mut().zip(d) {
                            *x = x.max(d.length());
                        }
                    }
                }
                moved
            };
            let all: Vec<Vec<f32>> = Blendshape::ALL.iter().map(|&s| lengths(s)).collect();
            let largest = all.iter().flatten().copied().fold(0.0f32, f32::max);
            let floor = MOVE_SHARE as f32 * largest;
            let count = |s: Blendshape| all[s.index()].iter().filter(|&&x| x > floor).count();
            if n == 0 {
                return PartRole::Other;
            }
            if 2 * count(Blendshape::TongueOut) > n {
                return PartRole::Tongue;
            }
            let others_move = Blendshape::ALL
                .iter()
                .filter(|s| !JAW_SHAPES.contains(s))
                .any(|&s| count(s) > 0);
            if others_move {
                return PartRole::Other;
            }
            // Teeth and gums follow the jaw as a body: every vertex the
            // jaw moves, it moves far; a lining fades out.
            let jaw = &all[Blendshape::JawOpen.index()];
            let jaw_largest = jaw.iter().copied().fold(0.0f32, f32::max);
            let moved = jaw.iter().filter(|&&x| x > floor);
            let far = moved
                .clone()
                .filter(|&&x| f64::from(x) > JAW_BODY_SHARE * f64::from(jaw_largest))
                .count();
            let as_a_body = || far as f64 >= (1.0 - JAW_SEAM_SHARE) * moved.clone().count() as f64;
            match count(Blendshape::JawOpen) {
                j if j == n && as_a_body() => PartRole::LowerTeeth,
                j if j == n => PartRole::Other,
                j if j > 0 && as_a_body() => PartRole::Teeth,
                j if j > 0 => PartRole::Other,
                _ if largest > 0.0 => PartRole::Other,
                _ => {
                    let centre =
                        part.positions.iter().map(|p| p.as_dvec3()).sum::<DVec3>() / n as f64;
                    let to = centre - mouth.centre;
                    let behind = to.dot(mouth.forward) < 0.0;
                    if behind && to.length() <= MOUTH_REACH_MM * mouth.per_mm {
                        PartRole::UpperTeeth
                    } else {
                        PartRole::Other
                    }
                }
            }
        })
        .collect()
}
