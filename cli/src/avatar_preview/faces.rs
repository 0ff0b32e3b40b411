//! `likeness demo`'s faces picture: one avatar at rest wearing different
//! faces (its stock face, and each person's taken from their neutral scan,
//! [`likeness::avatar::person_face`]), side by side, each seen from the
//! front and from its side, all through the same framing, so that a
//! difference of shape between two people shows as one in the picture.

use super::font::{GLYPH, draw_text, text_size};
use super::sheet::{GAP, GROUND, INK, TEXT_SCALE};
use super::tiles::Scene;
use crate::report::image::Image;
use crate::report::rasterizer::FrontView;
use glam::{DQuat, DVec3};

/// One face's picture, in pixels (the face region is taller than wide).
const TILE: (u32, u32) = (300, 360);

/// The margin around the face region in each picture, as a share of its
/// larger extent.
const MARGIN: f64 = 0.08;

/// The height of the line of text above each column.
const LINE: u32 = GLYPH.1 * TEXT_SCALE + 8;

/// One column of the picture.
pub struct Face<'a> {
    /// Whose face it is, written above it.
    pub label: &'a str,
    /// Every vertex of the avatar at rest, in the mask's frame.
    pub rest: Vec<DVec3>,
}

/// The avatar's meshes as the faces share them.
pub struct Meshes<'a> {
    /// Every triangle.
    pub triangles: &'a [[u32; 3]],
    /// The eyeballs' vertex ranges.
    pub eyeballs: &'a [std::ops::Range<usize>],
    /// The teeth's, gums' and tongue's vertex ranges.
    pub mouth_parts: &'a [std::ops::Range<usize>],
    /// The face region's vertices.
    pub face: &'a [u32],
    /// Each vertex's own colour, where the file gives it.
    pub colours: &'a [Option<[u8; 3]>],
}

/// `p` turned a quarter turn about the vertical (y): the face's side
/// faces the viewer (+z), its nose points right.
fn side_on(p: DVec3) -> DVec3 {
    DQuat::from_rotation_y(std::f64::consts::FRAC_PI_2) * p
}

/// The view of [`TILE`] framing the face region of every face in `faces`
/// (as `turn` shows it), so that every column shares it.
fn shared_view(faces: &[Face<'_>], face: &[u32], turn: fn(DVec3) -> DVec3) -> FrontView {
    let points: Vec<DVec3> = faces
        .iter()
        .flat_map(|f| face.iter().filter_map(|&v| f.rest.get(v as usize)))
        .map(|p| turn(*p))
        .collect();
    FrontView::framing(&points, TILE.0, TILE.1, MARGIN)
}

/// The picture: a column per face of `faces` (its label above), from the
/// front on top and from the side below.
pub fn faces_picture(faces: &[Face<'_>], meshes: &Meshes<'_>) -> Image {
    let turns: [fn(DVec3) -> DVec3; 2] = [|p| p, side_on];
    let views = turns.map(|turn| shared_view(faces, meshes.face, turn));
    let columns = faces.len() as u32;
    let width = GAP + columns * (TILE.0 + GAP);
    let height = LINE + 2 * (TILE.1 + GAP) + GAP;
    let mut picture = Image::filled(width, height, GROUND);
    for (c, face) in faces.iter().enumerate() {
        let left = GAP + c as u32 * (TILE.0 + GAP);
        let (w, h) = text_size(face.label, TEXT_SCALE);
        let text_left = left + TILE.0.saturating_sub(w) / 2;
        draw_text(
            &mut picture,
            face.label,
            text_left,
            (LINE - h) / 2,
            TEXT_SCALE,
            INK,
        );
        for (r, (turn, view)) in turns.iter().zip(&views).enumerate() {
            let rest: Vec<DVec3> = face.rest.iter().map(|p| turn(*p)).collect();
            let scene = Scene::new(
                rest,
                meshes.triangles.to_vec(),
                meshes.eyeballs,
                meshes.mouth_parts,
                meshes.face,
            )
            .painted(meshes.colours);
            let tile = scene.render(&scene.rest, std::slice::from_ref(view), false);
            picture.place(&tile, left, LINE + GAP + r as u32 * (TILE.1 + GAP));
        }
    }
    picture
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat square "face" of two triangles at `z`, `wide` across.
    fn square(wide: f64) -> Vec<DVec3> {
        let h = wide / 2.0;
        vec![
            DVec3::new(-h, -h, 0.0),
            DVec3::new(h, -h, 0.0),
            DVec3::new(h, h, 0.01),
            DVec3::new(-h, h, 0.01),
        ]
    }

    #[test]
    fn faces_share_one_framing_so_a_larger_face_covers_more() {
        let triangles = [[0, 1, 2], [0, 2, 3]];
        let meshes = Meshes {
            triangles: &triangles,
            eyeballs: &[],
            mouth_parts: &[],
            face: &[0, 1, 2, 3],
            colours: &[],
        };
        let faces = [
            Face {
                label: "small",
                rest: square(0.05),
            },
            Face {
                label: "large",
                rest: square(0.1),
            },
        ];
        let picture = faces_picture(&faces, &meshes);
        assert_eq!(picture.width, GAP + 2 * (TILE.0 + GAP));
        assert_eq!(picture.height, LINE + 2 * (TILE.1 + GAP) + GAP);
        // Pixels of the front row that are not the background, per column.
        let covered = |column: u32| {
            let left = GAP + column * (TILE.0 + GAP);
            let top = LINE + GAP;
            (top..top + TILE.1)
                .flat_map(|y| (left..left + TILE.0).map(move |x| (x, y)))
                .filter(|&(x, y)| {
                    let p = picture.pixels[(y * picture.width + x) as usize];
                    p != crate::report::rasterizer::BACKGROUND
                })
                .count()
        };
        let (small, large) = (covered(0), covered(1));
        assert!(small > 0, "the small face is drawn");
        // Twice as wide is four times the area, in one framing.
        let ratio = large as f64 / small as f64;
        assert!((3.5..4.5).contains(&ratio), "{small} vs {large} pixels");
    }

    #[test]
    fn the_side_view_turns_the_depth_into_the_width() {
        let p = side_on(DVec3::new(0.0, 0.0, 1.0));
        assert!((p - DVec3::X).length() < 1e-12, "{p}");
    }
}
