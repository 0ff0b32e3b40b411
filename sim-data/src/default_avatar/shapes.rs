//! The default avatar's own 52 ARKit blendshapes, as an artist's rig has
//! them.
//!
//! - **Face region.** Each face vertex lies at barycentric `b` in mask
//!   triangle `(i, j, k)`; its displacement under shape `s` is
//!   `Σ b_m (T_s − T₀)_m`, the template's delta interpolated the same way,
//!   so the avatar's face moves exactly as the template's surface does.
//! - **Beyond the outline.** A head vertex `p` takes the Gaussian-weighted
//!   mean (σ = [`SIGMA`], relative to the nearest) of the displacements of
//!   its [`NEIGHBOURS`] nearest outline vertices, faded by `κ(d/R)`,
//!   `κ(t) = (1 − t²)³`, with `d` its distance to the outline and `R =`
//!   [`REACH`]: mouth, cheek and brow shapes carry on smoothly past the
//!   mask's edge and stop within 3 cm.
//! - **Jaw.** jawOpen, jawForward, jawLeft, jawRight move the mandible: the
//!   lower teeth, lower gums and tongue fully, the skin beyond the outline
//!   by the continued jaw weight `ω` (the template's `jaw_weight` at the
//!   outline, continued as above with reach [`JAW_STRETCH`] times the
//!   outline's jaw motion, at least [`JAW_REACH`], so the skin under the
//!   chin and down the neck follows): `δ = ω (M p − p)`, `M` the generic
//!   jaw joint opened by `JAW_OPEN_ANGLE` (`shape_spec::JawJoint`) or the
//!   jaw translation of the template.
//! - **Eyes.** eyeLook* rotate the eyeball on their side rigidly about its
//!   centre (see [`super::eyes`]).
//! - **Tongue.** tongueOut slides the tongue forward [`TONGUE_OUT`] and up
//!   [`TONGUE_LIFT`], the tip fully, the root not at all (smoothstep along
//!   its length), while narrowing the protruding part by 25% and thinning
//!   it by 45%.

use super::face::MaskPoint;
use crate::regions::{kernel, smoothstep};
use crate::shape_spec::{GENERIC_JAW, JAW_OPEN_ANGLE, Special, generic_specs};
use glam::{DMat3, DVec3};
use likeness::{Blendshape, Template};

/// How far beyond the outline the face's shapes carry on (m).
pub const REACH: f64 = 0.025;
/// How far beyond the outline the mandible's pull carries on at least (m):
/// down the neck to about the larynx.
pub const JAW_REACH: f64 = 0.06;
/// How many times as far as an outline vertex moves with the mandible its
/// pull carries on, where that is beyond [`JAW_REACH`]. The fall-off
/// `κ(d/R)` tilts the skin by up to `atan(1.72 |δ|/R)` (1.72 is κ's
/// steepest slope): twice keeps that under 41°, and the sharpest bend of
/// any edge beyond the face in jawOpen is 18° (with 60 mm alone, 24° under
/// the chin). Three times (under 30°) carried the chin's motion so far
/// down the neck that skin 2–3 cm under the chin moved as much as the
/// chin, unlike ICT-FaceKit's neck (5 mm, 12 mm under its chin), and the
/// registration's jawOpen feature (what moves at least 80% of the most)
/// slid into the neck.
pub const JAW_STRETCH: f64 = 2.0;
/// Outline vertices averaged per head vertex.
pub const NEIGHBOURS: usize = 8;
/// Width of the averaging weights (m).
pub const SIGMA: f64 = 0.006;
/// How far tongueOut pushes the tongue tip forward (m): 3 cm, the tip
/// well past the lips.
pub const TONGUE_OUT: f64 = 0.03;
/// How far tongueOut raises the tongue's midline (m): from 8.5 mm below
/// the lip line to 4.5 mm below it, the middle of a half-open mouth.
pub const TONGUE_LIFT: f64 = 0.004;

/// Displacement of each face vertex under each shape: `[shape][vertex]`.
pub fn face_targets(
    on_mask: &[MaskPoint],
    template: &Template,
    tris: &[[u32; 3]],
) -> Vec<Vec<DVec3>> {
    template
        .shapes
        .iter()
        .map(|shape| {
            on_mask
                .iter()
                .map(|m| {
                    let t = tris[m.triangle as usize];
                    (0..3)
                        .map(|k| {
                            let i = t[k] as usize;
                            m.barycentric[k] * (shape[i] - template.neutral[i]).as_dvec3()
                        })
                        .sum()
                })
                .collect()
        })
        .collect()
}

/// A head vertex's outline neighbours: `(rim index, weight)` with weights
/// summing to one, and its distance to the outline.
pub struct Continuation {
    /// Neighbours and normalized weights.
    pub weights: Vec<(usize, f64)>,
    /// Distance to the nearest outline vertex (m).
    pub distance: f64,
}

/// Continuation weights of `p` from the outline points `rim`.
pub fn continuation(p: DVec3, rim: &[DVec3]) -> Continuation {
    let mut near: Vec<(usize, f64)> = rim
        .iter()
        .enumerate()
        .map(|(k, r)| (k, r.distance(p)))
        .collect();
    near.sort_by(|a, b| a.1.total_cmp(&b.1));
    near.truncate(NEIGHBOURS);
    let distance = near.first().map_or(f64::INFINITY, |n| n.1);
    let mut weights: Vec<(usize, f64)> = near
        .iter()
        .map(|(k, d)| (*k, (-((d - distance) / SIGMA).powi(2)).exp()))
        .collect();
    let total: f64 = weights.iter().map(|w| w.1).sum();
    weights.iter_mut().for_each(|w| w.1 /= total);
    Continuation { weights, distance }
}

/// How a jaw shape moves a point that follows the mandible fully.
pub fn jaw_motion(shape: Blendshape) -> Option<Box<dyn Fn(DVec3) -> DVec3>> {
    let spec = &generic_specs()[shape.index()];
    match spec.special {
        Special::JawRotation { .. } => {
            Some(Box::new(|p: DVec3| GENERIC_JAW.open(p, JAW_OPEN_ANGLE) - p))
        }
        Special::JawTranslation { offset } => Some(Box::new(move |_| offset)),
        _ => None,
    }
}

/// Displacements of the head's own vertices `[shape][vertex]`, continued
/// from the outline's (`rim_deltas[shape][rim vertex]`) and, for the jaw
/// shapes, from the outline's jaw weights.
pub fn head_targets(
    positions: &[DVec3],
    rim: &[DVec3],
    rim_deltas: &[Vec<DVec3>],
    rim_jaw: &[f64],
) -> Vec<Vec<DVec3>> {
    let cont: Vec<Continuation> = positions.iter().map(|p| continuation(*p, rim)).collect();
    Blendshape::ALL
        .iter()
        .map(|&shape| {
            let motion = jaw_motion(shape);
            positions
                .iter()
                .zip(&cont)
                .map(|(p, c)| match &motion {
                    Some(m) => {
                        let w: f64 = c.weights.iter().map(|(k, w)| w * rim_jaw[*k]).sum();
                        let reach: f64 = c
                            .weights
                            .iter()
                            .map(|(k, w)| {
                                let moved = rim_jaw[*k] * m(rim[*k]).length();
                                w * (JAW_STRETCH * moved).max(JAW_REACH)
                            })
                            .sum();
                        kernel(c.distance / reach) * w * m(*p)
                    }
                    None if c.distance < REACH => {
                        let d: DVec3 = c
                            .weights
                            .iter()
                            .map(|(k, w)| *w * rim_deltas[shape.index()][*k])
                            .sum();
                        kernel(c.distance / REACH) * d
                    }
                    None => DVec3::ZERO,
                })
                .collect()
        })
        .collect()
}

/// Displacements of a part that follows the mandible, for `shapes`.
pub fn jaw_part_targets(positions: &[DVec3], shapes: &[Blendshape]) -> Vec<Vec<DVec3>> {
    shapes
        .iter()
        .map(|&s| match jaw_motion(s) {
            Some(m) => positions.iter().map(|p| m(*p)).collect(),
            None => vec![DVec3::ZERO; positions.len()],
        })
        .collect()
}

/// tongueOut on the tongue centred at `centre` with the given back and tip
/// depths (z): with `s` the smoothstep from back to tip, a point moves
/// `s · (−¼ (x − c_x), TONGUE_LIFT − 0.45 (y − c_y), TONGUE_OUT)`: forward,
/// narrower by a quarter, thinner by 45% and raised towards the lip line,
/// so the protruding part passes between the lips of a half-open mouth.
pub fn tongue_out(positions: &[DVec3], centre: DVec3, back: f64, tip: f64) -> Vec<DVec3> {
    positions
        .iter()
        .map(|p| {
            let s = smoothstep(back, tip, p.z);
            DVec3::new(
                -0.25 * s * (p.x - centre.x),
                s * (TONGUE_LIFT - 0.45 * (p.y - centre.y)),
                TONGUE_OUT * s,
            )
        })
        .collect()
}

/// Rigid rotation of an eye's vertices about `centre`.
pub fn rotate_about(positions: &[DVec3], centre: DVec3, rotation: DMat3) -> Vec<DVec3> {
    positions
        .iter()
        .map(|p| rotation * (*p - centre) + centre - *p)
        .collect()
}
