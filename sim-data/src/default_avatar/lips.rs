//! The red of the lips on the default avatar's face: where it lies in the
//! mask's parameter plane (`uv`, m, face seen from the front, +u the
//! person's left, +v up). The lips wear a material of their own: the face
//! is triangulated with the vermilion border as a line of edges
//! ([`border_lines`], constraints of [`super::face::triangulate`]), and the
//! triangles inside it ([`on_the_lips`]) are written as a primitive of
//! their own sharing the skin's vertices.
//!
//! | what | how | constants |
//! |---|---|---|
//! | vermilion border | `h (1 − s²)^½` above and below the mouth line, a Cupid's bow on the upper lip ([`vermilion_border`]) | [`VERMILION_HEIGHT`] |
//! | the border as edges | the two border curves sampled at the face's spacing ([`border_lines`]) | |
//! | which triangles are the lips' | a triangle's centroid inside the border ([`on_the_lips`]) | |

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

/// Whether `uv` is on the red of the lips: within the vermilion border.
pub fn on_the_lips(uv: [f64; 2]) -> bool {
    let (u, v) = (uv[0] - MOUTH_CENTRE[0], uv[1] - MOUTH_CENTRE[1]);
    v.abs() < vermilion_border(u, usize::from(v < 0.0))
}

/// The upper and the lower vermilion border as polylines in the parameter
/// plane, corner to corner, points about `spacing` apart along each
/// (uniform in the arc of the curve, found by walking it in steps of a
/// hundredth of `spacing`).
pub fn border_lines(spacing: f64) -> [Vec<[f64; 2]>; 2] {
    [0, 1].map(|lip| {
        let sign = if lip == 0 { 1.0 } else { -1.0 };
        let at = |u: f64| {
            [
                MOUTH_CENTRE[0] + u,
                MOUTH_CENTRE[1] + sign * vermilion_border(u, lip),
            ]
        };
        let step = spacing / 100.0;
        let mut line = vec![at(-MOUTH_HALF_WIDTH)];
        let (mut u, mut walked, mut last) = (-MOUTH_HALF_WIDTH, 0.0, at(-MOUTH_HALF_WIDTH));
        while u < MOUTH_HALF_WIDTH {
            u = (u + step).min(MOUTH_HALF_WIDTH);
            let p = at(u);
            walked += ((p[0] - last[0]).powi(2) + (p[1] - last[1]).powi(2)).sqrt();
            last = p;
            if walked >= spacing {
                line.push(p);
                walked = 0.0;
            }
        }
        line
    })
}
