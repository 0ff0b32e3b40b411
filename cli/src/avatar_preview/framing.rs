//! Where each tile looks, found from the avatar itself: the avatar is
//! brought into the ARKit mask's frame by the face registration's
//! similarity (so "front" is the face's front whatever the file's axes and
//! units), the front view frames the face region, the eyes are where
//! eyeBlink moves the skin most, the mouth where jawOpen does.

use super::tiles::View;
use crate::report::rasterizer::FrontView;
use glam::{DVec2, DVec3, Vec3};
use likeness::avatar::registration::FaceRegistration;

/// A vertex "moves most" under a shape when it moves at least this share
/// of the most any vertex moves.
const MOVES_MOST: f64 = 0.4;

/// Empty room around the face in the front view (a share of the face's
/// larger extent on each side).
const FRONT_MARGIN: f64 = 0.14;

/// Empty room around each eye's lids in the eyes view (the brow and the
/// cheek below show).
const EYES_MARGIN: f64 = 0.3;

/// Empty room around the lips in the mouth view.
const MOUTH_MARGIN: f64 = 0.1;

/// The avatar's positions in the mask's frame (metres, +x to the face's
/// left, +y up, +z towards the viewer): the registration undone.
pub fn points_in_mask_frame(registration: &FaceRegistration, positions: &[Vec3]) -> Vec<DVec3> {
    let s = &registration.similarity;
    let back = s.rotation.transpose();
    positions
        .iter()
        .map(|p| back * (p.as_dvec3() - s.translation) / s.scale)
        .collect()
}

/// Displacements (avatar units and axes) in the mask's frame.
pub fn vectors_in_mask_frame(registration: &FaceRegistration, d: &[Vec3]) -> Vec<DVec3> {
    let s = &registration.similarity;
    let back = s.rotation.transpose();
    d.iter().map(|d| back * d.as_dvec3() / s.scale).collect()
}

/// The three views of every tile.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Framing {
    /// The whole face.
    pub front: FrontView,
    /// Each eye, close: the one on the picture's left (the face's right),
    /// then the other.
    pub eyes: [FrontView; 2],
    /// The mouth, close, with room for the jaw to open.
    pub mouth: FrontView,
}

impl Framing {
    /// The pictures of `view`, side by side in its tile.
    pub fn of(&self, view: View) -> &[FrontView] {
        match view {
            View::Front => std::slice::from_ref(&self.front),
            View::Eyes => &self.eyes,
            View::Mouth => std::slice::from_ref(&self.mouth),
        }
    }
}

/// What the framing is found from, all in the mask's frame.
pub struct FramingInput<'a> {
    /// Every avatar vertex at rest.
    pub rest: &'a [DVec3],
    /// The face region's vertices (the registration's map).
    pub face: &'a [u32],
    /// Which vertices are skin (not eyeballs, teeth or tongue).
    pub skin: &'a [bool],
    /// eyeBlinkLeft and eyeBlinkRight, as many versions as there are
    /// (the avatar's own, the written ones).
    pub blinks: &'a [&'a [DVec3]],
    /// jawOpen, likewise.
    pub jaw: &'a [&'a [DVec3]],
}

/// The smallest rectangle holding `points` seen from the front, or `None`
/// for no points.
fn bounds(points: impl IntoIterator<Item = DVec2>) -> Option<(DVec2, DVec2)> {
    points.into_iter().fold(None, |b, p| {
        Some(b.map_or((p, p), |(lo, hi): (DVec2, DVec2)| (lo.min(p), hi.max(p))))
    })
}

/// The skin vertices that some field of `fields` moves by at least
/// [`MOVES_MOST`] of the largest skin motion of that field.
fn moving_most(fields: &[&[DVec3]], skin: &[bool]) -> Vec<usize> {
    let mut chosen = vec![false; skin.len()];
    for field in fields {
        let most = field
            .iter()
            .zip(skin)
            .filter(|(_, s)| **s)
            .map(|(d, _)| d.length())
            .fold(0.0, f64::max);
        if most <= 0.0 {
            continue;
        }
        for (v, d) in field.iter().enumerate() {
            if skin.get(v) == Some(&true) && d.length() >= MOVES_MOST * most {
                chosen[v] = true;
            }
        }
    }
    (0..chosen.len()).filter(|&v| chosen[v]).collect()
}

/// `vertices` at rest and moved by each field, seen from the front.
fn rest_and_moved<'a>(
    rest: &'a [DVec3],
    vertices: &'a [usize],
    fields: &'a [&'a [DVec3]],
) -> impl Iterator<Item = DVec2> + 'a {
    vertices.iter().flat_map(move |&v| {
        std::iter::once(rest[v].truncate()).chain(
            fields
                .iter()
                .filter_map(move |f| f.get(v).map(|d| (rest[v] + *d).truncate())),
        )
    })
}

/// The view of `size` pixels showing the rectangle `lo … hi` with
/// `margin` (a share of its larger extent) on every side.
fn view_of((lo, hi): (DVec2, DVec2), size: (u32, u32), margin: f64) -> FrontView {
    let corners = [lo.extend(0.0), hi.extend(0.0)];
    FrontView::framing(&corners, size.0, size.1, margin)
}

/// The three views (module docs). Without a face region the whole avatar
/// is framed; without eyeBlink motion the eyes are taken as the band a
/// third of the way down the face; without jawOpen motion the mouth as the
/// band a fifth of the way up.
pub fn framing(input: &FramingInput<'_>) -> Framing {
    let face_bounds = bounds(
        input
            .face
            .iter()
            .filter_map(|&v| input.rest.get(v as usize).map(|p| p.truncate())),
    )
    .or_else(|| bounds(input.rest.iter().map(|p| p.truncate())))
    .unwrap_or((DVec2::splat(-0.1), DVec2::splat(0.1)));
    let (flo, fhi) = face_bounds;
    let size = fhi - flo;
    let front = view_of(face_bounds, View::Front.size(), FRONT_MARGIN);

    let lids = moving_most(input.blinks, input.skin);
    let eyes = bounds(rest_and_moved(input.rest, &lids, input.blinks)).unwrap_or_else(|| {
        let y = fhi.y - size.y / 3.0;
        (
            DVec2::new(flo.x + 0.15 * size.x, y - 0.08 * size.y),
            DVec2::new(fhi.x - 0.15 * size.x, y + 0.08 * size.y),
        )
    });
    // Each eye on its own: the lids left and right of their middle.
    let middle = (eyes.0.x + eyes.1.x) / 2.0;
    let side = |left: bool| {
        let chosen: Vec<usize> = lids
            .iter()
            .copied()
            .filter(|&v| (input.rest[v].x < middle) == left)
            .collect();
        bounds(rest_and_moved(input.rest, &chosen, input.blinks)).unwrap_or(if left {
            (eyes.0, DVec2::new(middle, eyes.1.y))
        } else {
            (DVec2::new(middle, eyes.0.y), eyes.1)
        })
    };
    let eye_size = View::Eyes.half_size();

    let mouth = mouth_bounds(input, &eyes).unwrap_or_else(|| {
        let y = flo.y + size.y / 5.0;
        (
            DVec2::new(flo.x + 0.3 * size.x, y - 0.08 * size.y),
            DVec2::new(fhi.x - 0.3 * size.x, y + 0.08 * size.y),
        )
    });
    Framing {
        front,
        eyes: [
            view_of(side(true), eye_size, EYES_MARGIN),
            view_of(side(false), eye_size, EYES_MARGIN),
        ],
        mouth: view_of(mouth, View::Mouth.size(), MOUTH_MARGIN),
    }
}

/// The mouth from jawOpen: the skin that moves most is the lower lip and
/// the chin below it, so the mouth's line is the top of that region; the
/// rectangle runs from a little above that line (the upper lip) down to
/// where the lower lip goes with the jaw open, across the width of the
/// moving skin near the line (the lower lip), centred under the eyes.
fn mouth_bounds(input: &FramingInput<'_>, eyes: &(DVec2, DVec2)) -> Option<(DVec2, DVec2)> {
    let moving = moving_most(input.jaw, input.skin);
    let line = moving
        .iter()
        .map(|&v| input.rest[v].y)
        .fold(f64::NEG_INFINITY, f64::max);
    if !line.is_finite() {
        return None;
    }
    let eye_width = eyes.1.x - eyes.0.x;
    // The lower lip: the moving skin within a lip's height of the line.
    let lip: Vec<usize> = moving
        .iter()
        .copied()
        .filter(|&v| input.rest[v].y >= line - 0.12 * eye_width)
        .collect();
    let (lo, hi) = bounds(rest_and_moved(input.rest, &lip, input.jaw))?;
    let centre = (eyes.0.x + eyes.1.x) / 2.0;
    let half = (hi.x - centre).max(centre - lo.x);
    Some((
        DVec2::new(centre - half, lo.y),
        DVec2::new(centre + half, line + 0.1 * eye_width),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat face 14 cm square, vertices 5 mm apart.
    fn grid() -> Vec<DVec3> {
        (0..29)
            .flat_map(|i| (0..29).map(move |j| (i, j)))
            .map(|(i, j)| {
                DVec3::new(
                    -0.07 + 0.005 * f64::from(i),
                    -0.07 + 0.005 * f64::from(j),
                    0.0,
                )
            })
            .collect()
    }

    #[test]
    fn eyes_and_mouth_are_found_where_blink_and_jaw_move_the_skin() {
        let rest = grid();
        // The lids of two eyes at (±3 cm, 3 cm) close by 1 cm.
        let blink: Vec<DVec3> = rest
            .iter()
            .map(|p| {
                let lid = (p.x.abs() - 0.03).abs() <= 0.012 && (p.y - 0.03).abs() <= 0.0051;
                if lid {
                    DVec3::new(0.0, -0.01, 0.0)
                } else {
                    DVec3::ZERO
                }
            })
            .collect();
        // Everything below the mouth's line at y = −3 cm drops, more so lower.
        let jaw: Vec<DVec3> = rest
            .iter()
            .map(|p| {
                if p.y <= -0.0299 {
                    DVec3::new(0.0, -(0.01 + 0.1 * (-0.03 - p.y)), 0.0)
                } else {
                    DVec3::ZERO
                }
            })
            .collect();
        let face: Vec<u32> = (0..rest.len() as u32).collect();
        let skin = vec![true; rest.len()];
        let f = framing(&FramingInput {
            rest: &rest,
            face: &face,
            skin: &skin,
            blinks: &[&blink],
            jaw: &[&jaw],
        });
        assert!(f.front.centre.length() < 1e-9, "{:?}", f.front);
        let [right, left] = f.eyes;
        assert!((right.centre.x + 0.03).abs() < 0.002, "{right:?}");
        assert!((left.centre.x - 0.03).abs() < 0.002, "{left:?}");
        for eye in [right, left] {
            assert!((eye.centre.y - 0.025).abs() < 0.003, "{eye:?}");
            // The eye, not the face: a close-up.
            assert!(eye.metres_per_pixel < f.front.metres_per_pixel / 2.0);
        }
        // The mouth's line, and the open jaw below it, are in view.
        let m = f.mouth;
        let half_height = f64::from(m.height) / 2.0 * m.metres_per_pixel;
        assert!(m.centre.x.abs() < 1e-9, "{m:?}");
        assert!(m.centre.y < -0.03 && m.centre.y > -0.05, "{m:?}");
        assert!(m.centre.y + half_height > -0.025, "{m:?}");
        assert!(m.centre.y - half_height < -0.05, "{m:?}");
    }

    #[test]
    fn without_motion_the_eyes_sit_above_the_mouth() {
        let rest = grid();
        let face: Vec<u32> = (0..rest.len() as u32).collect();
        let skin = vec![true; rest.len()];
        let f = framing(&FramingInput {
            rest: &rest,
            face: &face,
            skin: &skin,
            blinks: &[],
            jaw: &[],
        });
        assert!(f.eyes[0].centre.y > f.mouth.centre.y + 0.03, "{f:?}");
        assert!(
            f.eyes[0].centre.x < 0.0 && f.eyes[1].centre.x > 0.0,
            "{f:?}"
        );
    }
}
