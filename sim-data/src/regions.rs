//! Where on the face a motion acts: smooth kernels and the masks that keep
//! the two lips, and the two lids, apart.
//!
//! Everything is a function of a vertex's parameter-plane position `(u, v)`
//! (see [`crate::face_mask`]), so a region means the same on every face.

use crate::face_mask::{EYE_CENTRE, EYE_HALF_WIDTH, MOUTH_CENTRE, MOUTH_HALF_WIDTH};

/// Which part of the face a handle may move.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Region {
    /// Anything under the kernel.
    Any,
    /// Only above the mouth line (upper lip and above).
    UpperLip,
    /// Only below the mouth line (lower lip and below).
    LowerLip,
    /// Only above the eye line of the eye on `side` (0 = left, +x).
    UpperLid(usize),
    /// Only below the eye line of the eye on `side`.
    LowerLid(usize),
}

/// Smooth compact kernel `(1 − t²)³` for `t < 1`, else 0 (C² at the rim).
pub fn kernel(t: f64) -> f64 {
    if t >= 1.0 {
        0.0
    } else {
        let s = 1.0 - t * t;
        s * s * s
    }
}

/// Hermite smoothstep from 0 at `edge0` to 1 at `edge1`.
pub fn smoothstep(edge0: f64, edge1: f64, x: f64) -> f64 {
    let t = ((x - edge0) / (edge1 - edge0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Share of a point that belongs to the lower side of a slit whose centre
/// line is at height `centre` and whose corners are `half_width` from `cx`.
/// Inside the slit's span the split is sharp (the rows are distinct
/// vertices); beyond the corners it blends over a width growing with the
/// distance, so the skin beside a corner follows both sides.
fn lower_share(u: f64, v: f64, cx: f64, centre: f64, half_width: f64) -> f64 {
    let beyond = ((u - cx).abs() - half_width).max(0.0);
    let width = 1e-4 + 0.5 * beyond;
    1.0 - smoothstep(-width, width, v - centre)
}

/// Lower-lip share of a point: 1 on and below the lower lip, 0 on and above
/// the upper lip.
pub fn lower_lip_share(uv: [f64; 2]) -> f64 {
    lower_share(
        uv[0],
        uv[1],
        MOUTH_CENTRE[0],
        MOUTH_CENTRE[1],
        MOUTH_HALF_WIDTH,
    )
}

/// Centre of the eye on `side` (0 = left, +x).
pub fn eye_centre(side: usize) -> [f64; 2] {
    [side_sign(side) * EYE_CENTRE[0], EYE_CENTRE[1]]
}

/// +1 for the left side (+x), −1 for the right.
pub fn side_sign(side: usize) -> f64 {
    if side == 0 { 1.0 } else { -1.0 }
}

/// Lower-lid share of a point for the eye on `side`.
pub fn lower_lid_share(uv: [f64; 2], side: usize) -> f64 {
    let c = eye_centre(side);
    lower_share(uv[0], uv[1], c[0], c[1], EYE_HALF_WIDTH)
}

/// How much of `region` a point is, in `[0, 1]`.
pub fn region_weight(region: Region, uv: [f64; 2]) -> f64 {
    match region {
        Region::Any => 1.0,
        Region::LowerLip => lower_lip_share(uv),
        Region::UpperLip => 1.0 - lower_lip_share(uv),
        Region::LowerLid(side) => lower_lid_share(uv, side),
        Region::UpperLid(side) => 1.0 - lower_lid_share(uv, side),
    }
}

/// How far a point follows the mandible when the jaw rotates, in `[0, 1]`.
///
/// Below the mouth the lower lip follows 85% (its soft tissue stretches) and
/// the chin fully; towards the rim, over the ramus near the hinge, the skin
/// follows less. Above the mouth only the cheek skin beside the corners is
/// dragged along, by up to half.
pub fn jaw_weight(uv: [f64; 2]) -> f64 {
    let [u, v] = uv;
    let au = u.abs();
    let jaw_line = MOUTH_CENTRE[1] + 0.9 * (au - MOUTH_HALF_WIDTH).max(0.0);
    let lower = lower_lip_share(uv);
    let below = (0.85 + 0.15 * smoothstep(0.0, -0.02, v - MOUTH_CENTRE[1]))
        * (1.0 - 0.6 * smoothstep(0.04, 0.075, au))
        * smoothstep(0.012, -0.004, v - jaw_line);
    let beside = 0.5
        * smoothstep(0.012, -0.002, v - jaw_line)
        * smoothstep(MOUTH_HALF_WIDTH - 0.005, MOUTH_HALF_WIDTH + 0.01, au);
    lower * below + (1.0 - lower) * beside
}
