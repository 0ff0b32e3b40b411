//! The person's face at rest, checked before the shapes are implanted on
//! it (beyond the paper; the shapes themselves: [`super::implant_check`]):
//!
//! | what | rule | limit |
//! |---|---|---|
//! | the change at rest ([`rest_spike`]) | a vertex moving much further than the scan asks of the face at any point | [`REST_OVERSHOOT`] × the largest change asked |
//! | creases at rest ([`rest_folds`]) | a head triangle that taking the face turns past [`REST_FOLD_ANGLE`] | [`FOLDED_SHARE`] of the head's triangles |
//!
//! A spike makes the avatar unusable and is refused
//! (`AvatarError::RestSpike` of [`super::personal_avatar`]); past the
//! creases' limit the face is not taken: the avatar keeps its own, with a
//! warning.

use super::implant_check::{FOLDED_SHARE, OWN_FOLD_ANGLE, head_triangles, turn};
use super::model::Avatar;
use super::registration::FaceRegistration;
use glam::{DVec3, Vec3};
use std::fmt;

/// No vertex may move, at rest, more than this many times the largest
/// change the scan asks of the face at the points the skin holds: the
/// skin passes smoothly between those points, what it holds follows it,
/// and the skin beyond continues the face's change, overshooting it a
/// little where the change is steep at the face's border (ARKit's mesh,
/// seed 3, on the default avatar: the crown 25.1 mm beyond a face that
/// moved 22.1 mm, 1.14 times). The spikes this catches were four to eight
/// times what was asked (the mouth's lining 230 mm, a lip's corner 108 mm,
/// where the scan asked at most 27–30 mm).
pub const REST_OVERSHOOT: f64 = 1.5;

/// A head triangle that taking the person's face turns by more than this
/// at rest (radians, 45°, [`OWN_FOLD_ANGLE`]: the most the avatar's own
/// shapes may turn a triangle that a personalized shape then folds) is
/// creased. A face of another shape bends the skin gently: the taken face
/// of a simulated person turns 15 of the default avatar's 25,000 head
/// triangles past it (changes up to 8.6 mm); a person on ARKit's own mesh,
/// whose coarse lips curl inwards, turned 990–1,258 (crumpled lips, a
/// crease along the mask's outline).
pub const REST_FOLD_ANGLE: f64 = OWN_FOLD_ANGLE;

/// A vertex that moved at rest more than [`REST_OVERSHOOT`] times the
/// largest change the scan asks of the face.
#[derive(Clone, Debug, PartialEq)]
pub struct RestSpike {
    /// The part it is in.
    pub part: String,
    /// The avatar vertex.
    pub vertex: u32,
    /// How far it moved (mm at the mask's scale).
    pub moved_mm: f64,
    /// The largest change the scan asks of the face (mm at the mask's
    /// scale).
    pub asked_mm: f64,
}

impl fmt::Display for RestSpike {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "taking the person's face moved vertex {} of part '{}' by {:.1} mm, far more than the scan asks of the face ({:.1} mm at most)",
            self.vertex, self.part, self.moved_mm, self.asked_mm
        )
    }
}

/// Head triangles that taking the person's face would turn past
/// [`REST_FOLD_ANGLE`] at rest: creases and crumples the scan would put
/// into the skin. The avatar then keeps its own face
/// ([`super::personal_avatar`]).
#[derive(Clone, Debug, PartialEq)]
pub struct RestFolds {
    /// Triangles folded.
    pub triangles: usize,
    /// The limit ([`FOLDED_SHARE`] of the head's triangles).
    pub limit: usize,
    /// A corner of the most turned one (avatar vertex).
    pub vertex: u32,
}

impl fmt::Display for RestFolds {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "taking the person's face would crease {} triangles of the head at rest (limit {}), the worst at vertex {}: the avatar keeps its own face",
            self.triangles, self.limit, self.vertex
        )
    }
}

/// The head triangles of `avatar` (found by `found`, before its face was
/// taken) that the rest change `moved` (one per vertex, avatar units)
/// turns past [`REST_FOLD_ANGLE`], if more than [`FOLDED_SHARE`] of them
/// ([`super::implant_check::folded_triangles`]' rule with the stock rest as the avatar's own,
/// which turns nothing, and the rest's own angle).
pub fn rest_folds(avatar: &Avatar, found: &FaceRegistration, moved: &[DVec3]) -> Option<RestFolds> {
    let triangles = head_triangles(avatar, found);
    let rest = avatar.positions();
    let got: Vec<Vec3> = moved.iter().map(|d| d.as_vec3()).collect();
    let folded: Vec<(f64, [u32; 3])> = triangles
        .iter()
        .map(|t| (turn(&rest, &got, *t), *t))
        .filter(|(angle, _)| *angle > REST_FOLD_ANGLE)
        .collect();
    let limit = (FOLDED_SHARE * triangles.len() as f64).floor() as usize;
    // The most turned, the first of equals.
    let worst = folded.iter().reduce(|a, b| if b.0 > a.0 { b } else { a })?;
    (folded.len() > limit).then(|| RestFolds {
        triangles: folded.len(),
        limit,
        vertex: worst.1[0],
    })
}

/// The largest change at rest `moved` (one per avatar vertex, avatar units)
/// of any vertex, if it passes [`REST_OVERSHOOT`] times `asked_mm`, the
/// largest change the scan asks of the face (mm at the mask's scale;
/// module docs).
pub fn rest_spike(
    avatar: &Avatar,
    found: &FaceRegistration,
    moved: &[DVec3],
    asked_mm: f64,
) -> Option<RestSpike> {
    let to_mm = 1000.0 / found.similarity.scale;
    let (vertex, moved_mm) = moved
        .iter()
        .enumerate()
        .map(|(v, d)| (v, d.length() * to_mm))
        .fold((0, 0.0), |a, b| if b.1 > a.1 { b } else { a });
    if moved_mm <= REST_OVERSHOOT * asked_mm {
        return None;
    }
    let offsets = avatar.vertex_offsets();
    let part = (0..avatar.parts().len())
        .find(|&i| offsets[i] <= vertex && vertex < offsets[i + 1])
        .map(|i| avatar.parts()[i].name.clone())
        .unwrap_or_default();
    Some(RestSpike {
        part,
        vertex: vertex as u32,
        moved_mm,
        asked_mm,
    })
}
