//! One tile: the avatar in one pose (a shape at weight one, or at rest)
//! seen through one view, lit by the report's rasterizer with each vertex
//! darkened by its depth (over the depth range the view shows), so that
//! what lies behind (an eyeball under a lid, the inside of the mouth)
//! reads darker than what lies in front, and a part pushed through
//! another shows in its own colour.

use crate::report::colour_map::{PALE, SKIN};
use crate::report::image::Image;
use crate::report::rasterizer::{BACKGROUND, FrontView, Mesh, render};
use glam::DVec3;
use likeness::Blendshape;

/// The poses of the preview, one row each after the neutral row. ARKit's
/// `mouthClose` is made to be used on top of `jawOpen` (it closes the
/// lips while the jaw stays open; alone, most rigs push the lips through
/// each other), so it is shown that way.
pub const POSES: [Row; 11] = [
    Row::Shape(Blendshape::JawOpen),
    Row::Together(Blendshape::JawOpen, Blendshape::MouthClose),
    Row::Shape(Blendshape::EyeBlinkLeft),
    Row::Shape(Blendshape::EyeBlinkRight),
    Row::Shape(Blendshape::MouthSmileLeft),
    Row::Shape(Blendshape::MouthFunnel),
    Row::Shape(Blendshape::BrowInnerUp),
    Row::Shape(Blendshape::BrowDownLeft),
    Row::Shape(Blendshape::EyeSquintLeft),
    Row::Shape(Blendshape::CheekPuff),
    Row::Shape(Blendshape::EyeLookUpLeft),
];

/// One row of the contact sheet: the avatar at rest, one shape at weight
/// one, or two shapes at weight one together.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Row {
    /// Every weight zero.
    Neutral,
    /// This shape at weight one, every other at zero.
    Shape(Blendshape),
    /// Both shapes at weight one, every other at zero.
    Together(Blendshape, Blendshape),
}

impl Row {
    /// Every row, in order: neutral, then [`POSES`].
    pub fn all() -> Vec<Row> {
        std::iter::once(Row::Neutral).chain(POSES).collect()
    }

    /// Its name: `neutral`, ARKit's spelling, or both joined by `+`.
    pub fn name(self) -> String {
        match self {
            Row::Neutral => "neutral".into(),
            Row::Shape(s) => s.name().into(),
            Row::Together(a, b) => format!("{}+{}", a.name(), b.name()),
        }
    }

    /// The shapes at weight one (none at rest).
    pub fn shapes(self) -> Vec<Blendshape> {
        match self {
            Row::Neutral => Vec::new(),
            Row::Shape(s) => vec![s],
            Row::Together(a, b) => vec![a, b],
        }
    }
}

/// Whose shapes a tile shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Set {
    /// The avatar's own morph targets, as read.
    Own,
    /// The shapes written into the output GLB (the person's implanted, or
    /// `A_j` with `--retargeted`).
    Written,
}

/// What part of the face a tile shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum View {
    /// The whole face from the front.
    Front,
    /// Both eyes, close.
    Eyes,
    /// The mouth, close.
    Mouth,
}

impl View {
    /// Every view, in the sheet's order.
    pub const ALL: [View; 3] = [View::Front, View::Eyes, View::Mouth];

    /// The tile's size in pixels.
    pub const fn size(self) -> (u32, u32) {
        match self {
            View::Front => (216, 264),
            View::Eyes => (362, 150),
            View::Mouth => (240, 160),
        }
    }

    /// The size of each of the two pictures of a tile that holds two
    /// side by side (the eyes), [`GAP`] pixels apart.
    pub const fn half_size(self) -> (u32, u32) {
        let (w, h) = self.size();
        ((w - GAP) / 2, h)
    }

    /// Its name in file names and captions.
    pub const fn name(self) -> &'static str {
        match self {
            View::Front => "front",
            View::Eyes => "eyes",
            View::Mouth => "mouth",
        }
    }
}

/// Pixels between the two pictures of a tile.
pub const GAP: u32 = 2;

/// Eyeballs: a cool white, so one showing through a lid stands out from
/// the skin.
pub const EYEBALL: [u8; 3] = [214, 226, 246];

/// Teeth, gums and tongue (the avatar's other rigid parts).
pub const MOUTH_PARTS: [u8; 3] = PALE;

/// The nearest surface keeps its colour; the farthest of the face is
/// darkened to this share of it.
const FARTHEST: f64 = 0.55;

/// In the close-ups, triangles wholly this many times the view's depth
/// range behind the farthest face vertex it shows are not drawn: the back
/// of the head and of the eyeballs, hidden behind the face, would
/// otherwise cost most of the drawing. (The front view draws everything:
/// the ears lie that far back.)
const HIDDEN_BEHIND: f64 = 2.0;

/// A tile for a shape the avatar lacks: light grey, crossed.
pub fn missing_tile(view: View) -> Image {
    let (w, h) = view.size();
    let mut image = Image::filled(w, h, [236, 236, 236]);
    for x in 0..w {
        for y in [x * h / w, (w - 1 - x) * h / w] {
            if y < h {
                image.pixels[(y * w + x) as usize] = [170, 170, 170];
            }
        }
    }
    image
}

/// The avatar as the tiles draw it, in the mask's frame.
pub struct Scene {
    /// Every vertex at rest.
    pub rest: Vec<DVec3>,
    /// Every triangle.
    pub triangles: Vec<[u32; 3]>,
    /// Each vertex's colour before shading: the file's own where it says
    /// ([`Scene::painted`]), else skin, [`EYEBALL`] or [`MOUTH_PARTS`].
    pub colours: Vec<[u8; 3]>,
    /// The face region's vertices, whose depth at rest sets the range of
    /// the depth shading in each view.
    pub face: Vec<u32>,
}

impl Scene {
    /// A scene of `rest` and `triangles`; `eyeballs` and `mouth_parts`
    /// are vertex ranges, `face` the face region (for the depth range).
    pub fn new(
        rest: Vec<DVec3>,
        triangles: Vec<[u32; 3]>,
        eyeballs: &[std::ops::Range<usize>],
        mouth_parts: &[std::ops::Range<usize>],
        face: &[u32],
    ) -> Scene {
        let mut colours = vec![SKIN; rest.len()];
        for (ranges, colour) in [(mouth_parts, MOUTH_PARTS), (eyeballs, EYEBALL)] {
            for r in ranges {
                if let Some(c) = colours.get_mut(r.clone()) {
                    c.fill(colour);
                }
            }
        }
        Scene {
            rest,
            triangles,
            colours,
            face: face.to_vec(),
        }
    }

    /// The scene with each vertex of `own` that is `Some` in that colour
    /// (the avatar's own materials and vertex tints, as
    /// [`likeness::avatar::glb::look`] reads them), the rest as they were.
    pub fn painted(mut self, own: &[Option<[u8; 3]>]) -> Scene {
        for (c, own) in self.colours.iter_mut().zip(own) {
            if let Some(own) = own {
                *c = *own;
            }
        }
        self
    }

    /// The depth (z) of the farthest and nearest face vertex at rest that
    /// `view` shows (of every face vertex if it shows none): the range over
    /// which the depth shading runs, so that a close-up shades the relief
    /// it shows rather than the whole face's.
    fn depth_range(&self, view: &FrontView) -> (f64, f64) {
        let half = glam::DVec2::new(f64::from(view.width), f64::from(view.height))
            * (view.metres_per_pixel / 2.0);
        let range = |inside: bool| {
            self.face
                .iter()
                .filter_map(|&v| self.rest.get(v as usize))
                .filter(|p| {
                    !inside || ((p.truncate() - view.centre).abs() - half).max_element() <= 0.0
                })
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                    (lo.min(p.z), hi.max(p.z))
                })
        };
        let (lo, hi) = range(true);
        let (lo, hi) = if lo < hi { (lo, hi) } else { range(false) };
        if lo < hi { (lo, hi) } else { (-0.1, 0.1) }
    }

    /// The avatar moved by `displacement` (one per vertex; `None` for the
    /// rest pose).
    pub fn posed(&self, displacement: Option<&[DVec3]>) -> Vec<DVec3> {
        match displacement {
            Some(d) => self.rest.iter().zip(d).map(|(p, d)| *p + *d).collect(),
            None => self.rest.clone(),
        }
    }

    /// The colours of `positions`, darkened by depth from `far` to `near`
    /// (module docs).
    fn depth_shaded(&self, positions: &[DVec3], (far, near): (f64, f64)) -> Vec<[u8; 3]> {
        positions
            .iter()
            .zip(&self.colours)
            .map(|(p, c)| {
                let t = ((p.z - far) / (near - far)).clamp(0.0, 1.0);
                let k = FARTHEST + (1.0 - FARTHEST) * t;
                c.map(|v| (f64::from(v) * k).round() as u8)
            })
            .collect()
    }

    /// `positions` (a pose of this scene) as `views` show them, side by
    /// side [`GAP`] pixels apart on white; `close` for a close-up (see
    /// [`HIDDEN_BEHIND`]).
    pub fn render(&self, positions: &[DVec3], views: &[FrontView], close: bool) -> Image {
        views
            .iter()
            .map(|view| {
                let (far, near) = self.depth_range(view);
                let colours = self.depth_shaded(positions, (far, near));
                let behind = if close {
                    far - HIDDEN_BEHIND * (near - far)
                } else {
                    f64::NEG_INFINITY
                };
                let at = |v: u32| positions.get(v as usize).map_or(f64::INFINITY, |p| p.z);
                let triangles: Vec<[u32; 3]> = self
                    .triangles
                    .iter()
                    .filter(|t| t.iter().any(|&v| at(v) >= behind))
                    .copied()
                    .collect();
                let mesh = Mesh {
                    positions,
                    triangles: &triangles,
                    colours: &colours,
                };
                render(&[mesh], view)
            })
            .reduce(|left, right| left.beside(&right, GAP, BACKGROUND))
            .unwrap_or_else(|| Image::filled(1, 1, BACKGROUND))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_start_neutral_and_cover_the_asked_shapes() {
        let rows = Row::all();
        assert_eq!(rows[0], Row::Neutral);
        for name in [
            "jawOpen",
            "eyeBlinkLeft",
            "eyeBlinkRight",
            "mouthSmileLeft",
            "mouthFunnel",
            "browInnerUp",
            "eyeSquintLeft",
            "jawOpen+mouthClose",
            "cheekPuff",
        ] {
            assert!(rows.iter().any(|r| r.name() == name), "{name}");
        }
    }

    #[test]
    fn farther_is_darker_and_eyeballs_have_their_colour() {
        let rest = vec![DVec3::ZERO, DVec3::new(0.0, 0.0, 1.0), DVec3::X];
        let eyeball = 2..3;
        let scene = Scene::new(
            rest.clone(),
            vec![[0, 1, 2]],
            std::slice::from_ref(&eyeball),
            &[],
            &[0, 1],
        );
        let view = FrontView::framing(&rest, 10, 10, 0.1);
        assert_eq!(scene.depth_range(&view), (0.0, 1.0));
        let shaded = scene.depth_shaded(&rest, (0.0, 1.0));
        assert_eq!(shaded[1], SKIN);
        assert!(shaded[0][0] < shaded[1][0]);
        assert_eq!(scene.colours[2], EYEBALL);
    }

    #[test]
    fn a_missing_tile_is_crossed() {
        let tile = missing_tile(View::Mouth);
        assert_eq!((tile.width, tile.height), View::Mouth.size());
        assert_eq!(tile.pixels[0], [170, 170, 170]);
    }
}
