//! The person's face at rest, checked before the shapes are implanted on
//! it (beyond the paper; the shapes themselves: [`super::implant_check`]):
//!
//! | what | rule | limit |
//! |---|---|---|
//! | the change at rest ([`rest_spike`]) | a vertex moving much further than the scan asks of the face at any point | [`REST_OVERSHOOT`] × the largest change asked |
//! | creases at rest ([`rest_creases`]) | a head edge whose dihedral angle taking the face changes by more than [`REST_CREASE_ANGLE`], and by more than [`OWN_CREASE_ANGLE`] beyond how the scan itself bends there ([`scan_bend`]) | [`REST_CREASE_SHARE`] of the head's edges |
//!
//! Past either limit the face is not taken: the avatar keeps its own,
//! with a warning (`AvatarWarning::RestCreased`, `RestSpiked` of
//! [`super::personal_avatar`]), and still carries the person's motion.
//! The creases are the skin's alone, so they are checked first, before
//! what the skin holds follows it ([`super::person_face::SkinChange`]);
//! a face taken is then checked for spikes. A spike was once an error;
//! but the avatar's own face is always there to keep, and a smooth
//! overshoot is no broken file (the low-poly avatar's coarse temples,
//! 12 mm apart, bulged 13.7 mm where a simulated person's face asked 8.7
//! mm, 1.6 times).

use super::implant_check::{head_edges, head_triangles};
use super::model::Avatar;
use super::registration::FaceRegistration;
use crate::geometry::dihedral_angle::Hinges;
use glam::DVec3;
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

/// A head edge whose dihedral angle (between the normals of its two
/// triangles) taking the person's face changes by more than this
/// (radians, 45°) is creased. A face of another shape turns the skin
/// smoothly, a little at every edge: the taken faces of five simulated
/// people, up to 13 mm from the stock one, crease 0–2 of the default
/// avatar's edges. A crease turns one row of edges sharply: on ARKit's
/// mesh the mask's outline, the lid margins and the nostrils crease
/// 118–166 (five people, as `likeness simulate` and the mask study
/// simulate them). The rule before, a triangle turned past 45°,
/// counted 950–1,260 for them, mostly where the person's deep-set eyes
/// reshape the sockets smoothly: a turned triangle cannot tell a new
/// shape from a crease. An edge the scan itself bends as much (less
/// [`OWN_CREASE_ANGLE`]) is the person's, not a crease: the rule the
/// shapes' crease smoothing uses
/// ([`super::partial_transfer::crease_smoothing`]).
pub const REST_CREASE_ANGLE: f64 = std::f64::consts::FRAC_PI_4;

/// How much more than the scan bends the mask there an edge must turn to
/// be creased (radians, 22.5°), as the shapes' crease smoothing allows
/// ([`super::partial_transfer::crease_smoothing::OWN_CREASE_ANGLE`]).
pub use super::partial_transfer::crease_smoothing::OWN_CREASE_ANGLE;

/// Most creased edges at rest, as a share of the head's edges: a quarter
/// of the share of triangles one shape may fold
/// ([`super::implant_check::FOLDED_SHARE`]), since a crease at rest shows
/// in every frame (19 of the default avatar's 38,273 head edges).
pub const REST_CREASE_SHARE: f64 = 0.0005;

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

/// Head edges that taking the person's face would crease
/// ([`REST_CREASE_ANGLE`]): creases and crumples the scan would put into
/// the skin. The avatar then keeps its own face
/// ([`super::personal_avatar`]).
#[derive(Clone, Debug, PartialEq)]
pub struct RestCreases {
    /// Edges creased.
    pub edges: usize,
    /// The limit ([`REST_CREASE_SHARE`] of the head's edges).
    pub limit: usize,
    /// An end of the most changed one (avatar vertex).
    pub vertex: u32,
}

impl fmt::Display for RestCreases {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "taking the person's face would crease {} edges of the head at rest (limit {}), the worst at vertex {}: the avatar keeps its own face",
            self.edges, self.limit, self.vertex
        )
    }
}

/// For each avatar vertex, how much the scanned neutral (`neutral`, on the
/// mask, ARKit's face coordinates) bends the registered mask at the mask
/// triangle the map takes the vertex to: the largest change of a dihedral
/// angle at that triangle's edges (radians; 0 off the face). Where the
/// person's face bends unlike the avatar's (a nostril's rim, the lips'
/// edge), the new rest bends there too.
pub fn scan_bend(avatar: &Avatar, found: &FaceRegistration, neutral: &[DVec3]) -> Vec<f64> {
    let on_avatar = &found.mask_on_avatar;
    let change: Vec<DVec3> = on_avatar
        .iter()
        .enumerate()
        .map(|(i, m)| {
            neutral
                .get(i)
                .map_or(DVec3::ZERO, |p| found.similarity.apply(*p) - *m)
        })
        .collect();
    let hinges = Hinges::new(on_avatar, &found.map.mask_triangles);
    let at_triangle = hinges.largest_at_triangles(&hinges.changes(on_avatar, &change));
    let mut bend = vec![0.0; avatar.vertex_count()];
    for f in &found.map.face {
        if let (Some(b), Some(t)) = (
            bend.get_mut(f.vertex as usize),
            at_triangle.get(f.triangle as usize),
        ) {
            *b = *t;
        }
    }
    bend
}

/// The head edges of `avatar` (found by `found`, before its face was
/// taken) whose dihedral angle the rest change `moved` (one per vertex,
/// avatar units) changes by more than [`REST_CREASE_ANGLE`] and by more
/// than [`OWN_CREASE_ANGLE`] beyond the scan's own bend at any corner of
/// its two triangles (`bend`, [`scan_bend`]; all zero, the first rule
/// alone), each with its change (radians): the most changed first, the
/// first of equals first. An edge counts where exactly two head triangles
/// share it.
pub fn creased_edges(
    avatar: &Avatar,
    found: &FaceRegistration,
    moved: &[DVec3],
    bend: &[f64],
) -> Vec<(f64, (u32, u32))> {
    let triangles = head_triangles(avatar, found);
    let rest: Vec<DVec3> = avatar.positions().iter().map(|p| p.as_dvec3()).collect();
    let hinges = Hinges::new(&rest, &triangles);
    let changes = hinges.changes(&rest, moved);
    let scan_bends = |k: usize| {
        hinges.pairs()[k]
            .iter()
            .flat_map(|&t| hinges.triangles()[t])
            .map(|v| bend.get(v as usize).copied().unwrap_or(0.0))
            .fold(0.0, f64::max)
    };
    let mut creased: Vec<(f64, (u32, u32))> = hinges
        .edges()
        .iter()
        .zip(&changes)
        .enumerate()
        .filter(|(k, (_, change))| {
            **change > REST_CREASE_ANGLE && **change > scan_bends(*k) + OWN_CREASE_ANGLE
        })
        .map(|(_, (edge, change))| (*change, *edge))
        .collect();
    creased.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    creased
}

/// The edges taking the face creases ([`creased_edges`]), if more than
/// [`REST_CREASE_SHARE`] of the head's.
pub fn rest_creases(
    avatar: &Avatar,
    found: &FaceRegistration,
    moved: &[DVec3],
    bend: &[f64],
) -> Option<RestCreases> {
    let creased = creased_edges(avatar, found, moved, bend);
    let limit = (REST_CREASE_SHARE * head_edges(avatar, found).len() as f64).floor() as usize;
    let worst = creased.first()?;
    (creased.len() > limit).then_some(RestCreases {
        edges: creased.len(),
        limit,
        vertex: worst.1.0,
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
