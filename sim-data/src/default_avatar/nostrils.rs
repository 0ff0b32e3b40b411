//! The nostrils on the default avatar's face, painted: two dark ovals on
//! the underside of the nose, a tint of the skin's vertices as the red of
//! the lips is ([`super::lips`]). The face is a height field over the
//! mask's parameter plane (`uv`, m, +u the person's left, +v up), which
//! cannot hold the hole a nostril is; seen from the front or from below, a
//! dark oval where the hole would be reads as one.
//!
//! | what | how | constants |
//! |---|---|---|
//! | where | an ellipse either side of the columella, on the underside of the nose (where the surface faces down, `∂h/∂v` > 1 in `face_mask::height`) | [`NOSTRIL_CENTRE`], [`NOSTRIL_RADII`] |
//! | share of the nostril's colour | 1 inside, 0 outside, blending across the edge | [`NOSTRIL_BLEND`] |

/// Centre of the left nostril in the parameter plane (m); the right one
/// mirrors it. 5.5 mm either side of the midline leaves a columella about
/// 5 mm wide (Farkas 1994: 6–7 mm); 19.5 mm below the nose's root line
/// puts it in the middle of the nose's underside, between the tip (v =
/// −12 mm) and the base (v ≈ −24 mm).
pub const NOSTRIL_CENTRE: [f64; 2] = [0.0055, -0.0195];

/// Half-axes of a nostril's ellipse in the plane, `[across, along]` (m).
/// The underside rises about 2 mm per mm of `v`, so 2.5 mm along `v` is
/// about 11 mm on the surface: a nostril 5.6 mm wide and 11 mm long, as
/// adults' are (Farkas 1994: width 5–7 mm, length 10–13 mm).
pub const NOSTRIL_RADII: [f64; 2] = [0.0028, 0.0025];

/// How far the nostril's colour blends into the skin's, each way, as a
/// share of the ellipse's size: half the face's 1.7 mm grid at the
/// ellipse's size, so its edge shows no triangles.
pub const NOSTRIL_BLEND: f64 = 0.3;

/// Share of the nostril's colour at `uv`: 1 inside either nostril, 0
/// outside, blending across the edge over ±[`NOSTRIL_BLEND`] (as a share
/// of the ellipse's radius).
pub fn nostril_share(uv: [f64; 2]) -> f64 {
    let (u, v) = (uv[0].abs() - NOSTRIL_CENTRE[0], uv[1] - NOSTRIL_CENTRE[1]);
    let r = (u / NOSTRIL_RADII[0]).hypot(v / NOSTRIL_RADII[1]);
    let t = ((1.0 + NOSTRIL_BLEND - r) / (2.0 * NOSTRIL_BLEND)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn both_nostrils_are_dark_inside_and_the_skin_around_them_is_not() {
        let [u, v] = NOSTRIL_CENTRE;
        assert_eq!(nostril_share([u, v]), 1.0);
        assert_eq!(nostril_share([-u, v]), 1.0, "the right mirrors the left");
        assert_eq!(nostril_share([0.0, v]), 0.0, "the columella");
        assert_eq!(nostril_share([u, -0.012]), 0.0, "the tip");
        assert_eq!(nostril_share([u, -0.026]), 0.0, "the lip below");
        let edge = nostril_share([u + NOSTRIL_RADII[0], v]);
        assert!((edge - 0.5).abs() < 1e-9, "half way at the ellipse: {edge}");
    }
}
