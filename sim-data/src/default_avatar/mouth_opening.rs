//! A rounded mouth opening: the default avatar's jawOpen spreads the jaw's
//! pull at the mouth's corners, as a face's does.
//!
//! The template's jawOpen (the simulator's people's) moves the whole lower
//! lip with the jaw and the upper lip not at all, so its opening is nearly
//! a rectangle: the lower lip's weight stays above 0.9 of the centre's out
//! to 0.9 of the half-width. In a face the lips stretch between the jaw and
//! the corners, which move only part of the way. ICT-FaceKit's jawOpen
//! (`../shared/avatars/`, measured 2026-12-04 on its `Head` mesh) moves its
//! mouth corner 0.34 of its lower lip's centre, and the lower lip by about
//! 0.88, 0.80 and 0.68 of it at 0.5, 0.7 and 0.9 of the half-width: an
//! ellipse through the corner, `w_c + (1 − w_c) √(1 − s²)`, gives 0.91,
//! 0.81 and 0.63.
//!
//! So the avatar's jawOpen takes the jaw weight `W` (the template's) at
//! each mask vertex `i` towards the corner's [`CORNER_SHARE`] by
//!
//! `c_i = (w_c − W) (1 − √(1 − s²)₊) κ(|v − v₀| / h) κ((|u| − a)₊ / b)`
//!
//! and moves it by `r_i = c_i J(p_i)`, `J(p)` the jaw's full motion at
//! `p` ([`on_mask`]): `(u, v)` the vertex's parameter-plane point, `s =
//! u / a` across the mouth (`a` its half-width), `h` the lip's height
//! above ([`UPPER_FADE`]) or below ([`LOWER_FADE`]) the lip line `v₀`,
//! `b =` [`SIDE_FADE`] beyond the corners, `κ(t) = (1 − t²)³`. On the
//! lips' edges the weight becomes `w_c + (W − w_c) √(1 − s²)`: the lower
//! lip an ellipse down from the corners, the upper lip dipping towards
//! them.
//!
//! Each avatar face vertex takes `r` interpolated at its point on the
//! mask ([`round`]), as it takes the template's shapes: the rounding is
//! one the mask resolves, and the template plus `r` is the avatar's own
//! rig as the mask sees it (`DefaultAvatar::own_rig_on_mask`). So a
//! person's motion replaces it wherever the face map reaches (step 1 of
//! the transfer keeps of the avatar's own only what is finer than the
//! mask, `A_j − T S(A_j)`). Worked out at the avatar's own vertices
//! instead, the ellipse's steep end at the corners was finer than the
//! mask's triangles, and committed subjects 1 and 2 implanted kept up to
//! 1.5 mm of it on the lips beside the corners.
//!
//! mouthClose takes the same `r` back, since ARKit's mouthClose is
//! the lips' motion relative to the open jaw: jawOpen + mouthClose is the
//! template's, lips closed as before.

use super::face::MaskPoint;
use super::shapes::jaw_motion;
use crate::face_mask::{MOUTH_CENTRE, MOUTH_HALF_WIDTH, face_mask};
use crate::regions::kernel;
use crate::template::generic_model;
use glam::DVec3;
use likeness::Blendshape;

/// Share of the lower lip's jaw motion the mouth's corners take (ICT-
/// FaceKit's jawOpen, measured: 0.34).
pub const CORNER_SHARE: f64 = 0.34;
/// How far up from the lip line the rounding fades out (m): the upper
/// lip's height, vermilion and skin to the nose (about 15 mm in adults,
/// Farkas 1994, the upper lip's height sn–sto ≈ 20 mm less the nostrils').
pub const UPPER_FADE: f64 = 0.015;
/// How far down from the lip line the rounding fades out (m): the lower
/// lip to the labiomental fold (sto–sl ≈ 15–18 mm, Farkas 1994), so the
/// chin moves with the jaw as before.
pub const LOWER_FADE: f64 = 0.016;
/// How far beyond the corners the rounding fades out (m).
pub const SIDE_FADE: f64 = 0.012;

/// Change of jaw weight at parameter-plane point `uv` whose template jaw
/// weight is `w` (the `c` of the module's formula, before `J(p)`).
pub fn weight_change(uv: [f64; 2], w: f64) -> f64 {
    let u = uv[0] - MOUTH_CENTRE[0];
    let dv = uv[1] - MOUTH_CENTRE[1];
    let s = u / MOUTH_HALF_WIDTH;
    let ellipse = (1.0 - s * s).max(0.0).sqrt();
    let fade = if dv >= 0.0 { UPPER_FADE } else { LOWER_FADE };
    let side = (u.abs() - MOUTH_HALF_WIDTH).max(0.0);
    (CORNER_SHARE - w) * (1.0 - ellipse) * kernel(dv.abs() / fade) * kernel(side / SIDE_FADE)
}

/// The rounding at each mask vertex, `r_i = c_i J(p_i)` (module docs),
/// on the template's neutral with its jaw weights.
pub fn on_mask() -> Vec<DVec3> {
    let model = generic_model();
    let jaw = jaw_motion(Blendshape::JawOpen).expect("jawOpen moves the jaw");
    face_mask()
        .uv
        .iter()
        .zip(&model.jaw_weights)
        .zip(&model.neutral)
        .map(|((uv, w), p)| weight_change(*uv, *w) * jaw(*p))
        .collect()
}

/// Rounds the face's jawOpen and takes the same motion back in mouthClose
/// (`targets[shape][face vertex]`): each face vertex takes the mask's
/// rounding `rounding` ([`on_mask`]) interpolated at its point on the
/// mask (`on_mask`, over the mask's `triangles`).
pub fn round(
    targets: &mut [Vec<DVec3>],
    on_mask: &[MaskPoint],
    rounding: &[DVec3],
    triangles: &[[u32; 3]],
) {
    for (v, m) in on_mask.iter().enumerate() {
        let t = triangles[m.triangle as usize];
        let r: DVec3 = (0..3)
            .map(|k| m.barycentric[k] * rounding[t[k] as usize])
            .sum();
        targets[Blendshape::JawOpen.index()][v] += r;
        targets[Blendshape::MouthClose.index()][v] -= r;
    }
}
