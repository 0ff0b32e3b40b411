//! The red of the lips on the default avatar's face: where it lies in the
//! mask's parameter plane (`uv`, m, face seen from the front, +u the
//! person's left, +v up), and each skin vertex's share of its colour,
//! written as a vertex tint over the skin's material.
//!
//! | what | how | constants |
//! |---|---|---|
//! | vermilion border | `h (1 − s²)^½` above and below the mouth line, a Cupid's bow on the upper lip ([`vermilion_border`]) | [`VERMILION_HEIGHT`] |
//! | lips' colour | the share of the lips' colour at a point ([`lip_share`]), blending across the border | [`LIP_BLEND`] |

use crate::face_mask::{MOUTH_CENTRE, MOUTH_HALF_WIDTH};

/// Height of the red of the lips at the middle, above and below the mouth
/// line, in the parameter plane (m): the upper vermilion is about 8–9 mm
/// tall and the lower 9–10 mm (Farkas 1994); the plane is stretched 10–15%
/// near the mouth on the mask, so `[upper, lower]` = 10.5 and 9.5 mm.
pub const VERMILION_HEIGHT: [f64; 2] = [0.0105, 0.0095];

/// The vermilion border's distance from the mouth line at `u` (m), for the
/// upper (`0`) or lower (`1`) lip: `h (1 − s²)^½` with `s = u / w`, the
/// upper one with a Cupid's bow (1 mm peaks 5 mm either side of a 0.8 mm
/// dip in the middle). Zero past the mouth's corners.
pub fn vermilion_border(u: f64, lip: usize) -> f64 {
    let s = u / MOUTH_HALF_WIDTH;
    if s.abs() >= 1.0 {
        return 0.0;
    }
    let base = VERMILION_HEIGHT[lip] * (1.0 - s * s).sqrt();
    if lip == 1 {
        return base;
    }
    let gauss = |t: f64| (-t * t).exp();
    base + 0.001 * gauss((u.abs() - 0.005) / 0.003) - 0.0008 * gauss(u / 0.002)
}

/// How far the colour of the lips blends into the skin's across their
/// border, each way (m): the border is sharp on a face, but a blend
/// narrower than the face's 1.7 mm grid shows its triangles as steps
/// along the border, so it spans one grid step each way.
pub const LIP_BLEND: f64 = 0.0017;

/// Share of the lips' colour at `uv`: 1 on the red of the lips, 0 on the
/// skin, blending across the border over ±[`LIP_BLEND`].
pub fn lip_share(uv: [f64; 2]) -> f64 {
    let (u, v) = (uv[0] - MOUTH_CENTRE[0], uv[1] - MOUTH_CENTRE[1]);
    let border = vermilion_border(u, usize::from(v < 0.0));
    if border <= 0.0 {
        return 0.0; // past the mouth's corners
    }
    let inside = border - v.abs();
    let t = ((inside + LIP_BLEND) / (2.0 * LIP_BLEND)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}
