//! `other-proportions`: a head whose proportions differ clearly from the
//! default's (and so from the simulator's face mask), so that registering
//! the mask to it cannot succeed by construction.
//!
//! The default avatar moved by a smooth warp `W` (ARKit's frame, m), each
//! effect in a documented direction and amount:
//!
//! | effect | amount | region |
//! |---|---|---|
//! | face width | × [`FACE_WIDTH`] = 1.12 (wider) | everything, `x` scaled about the midline |
//! | eye spacing | each eye [`EYE_SHIFT`] = 2 mm towards the nose: 68.8 mm between the eyes (default 65 mm, 72.8 mm the wider face alone would give) | within 14 mm of an eye centre (x, y), fading to 30 mm; not behind z = −30 mm |
//! | nose length | × [`NOSE_LENGTH`] = 1.15 (longer, downwards) from its bridge at y = 15 mm to its base at y = −25 mm; below the base a 6 mm drop fading over 14 mm | within 12 mm of the midline, fading to 24 mm; in front of z = −20 mm |
//! | mouth width | × [`MOUTH_WIDTH`] = 0.88 (narrower) after the widening | within 12 mm of the mouth's line (y = −47 mm), fading to 25 mm; within 30 mm of the midline, fading to 45 mm; in front of z = −40 mm |
//!
//! Every fade is a smoothstep, so `W` is smooth and one-to-one (its
//! Jacobian stays positive: the steepest fade changes a length by at most
//! 64%). Targets move with it (`d' = W(p + d) − W(p)`); the eyeballs move
//! rigidly with their centre (`W(c) − c`) and keep their gaze rotations.
//! The teeth and gums are warped at rest, and each target keeps moving
//! them as one body by the mandible's motion `M` (a rigid motion, fitted
//! to the default's target): `d' = M(W(p)) − W(p)`, as an artist
//! narrowing the mouth keeps the jaw's hinge (warping their motion too
//! would bend the lower arch as it leaves the mouth's band).

use super::parts::{base, bounds, glb_of, plain_truth};
use super::truth::VariantTruth;
use glam::{DVec3, Vec3};
use likeness::avatar::Avatar;
use likeness::avatar::registration::similarity::fit_rigid;

/// Face width factor (x).
pub const FACE_WIDTH: f64 = 1.12;
/// How far each eye moves towards the midline after the widening (m).
pub const EYE_SHIFT: f64 = 0.002;
/// Nose length factor (downwards from the bridge).
pub const NOSE_LENGTH: f64 = 1.15;
/// Top (bridge) and base of the nose (y, m): the mask's eyes are at
/// y = 28 mm, its mouth at −47 mm.
pub const NOSE_SPAN: [f64; 2] = [0.015, -0.025];
/// Mouth width factor after the widening.
pub const MOUTH_WIDTH: f64 = 0.88;
/// The mouth's line (y, m): the mask's mouth centre.
pub const MOUTH_Y: f64 = -0.047;

fn smoothstep(e0: f64, e1: f64, x: f64) -> f64 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// 1 within `inner`, 0 beyond `outer`, smooth between.
fn plateau(d: f64, inner: f64, outer: f64) -> f64 {
    1.0 - smoothstep(inner, outer, d)
}

/// The warp.
pub fn warp(p: DVec3) -> DVec3 {
    let mut q = DVec3::new(FACE_WIDTH * p.x, p.y, p.z);
    // Eyes: towards the midline.
    let eye = crate::face_mask::EYE_CENTRE;
    let side = p.x.signum();
    let to_eye = (p.x - side * eye[0]).hypot(p.y - eye[1]);
    let w_eye = plateau(to_eye, 0.014, 0.030) * smoothstep(-0.06, -0.03, p.z);
    q.x -= side * EYE_SHIFT * w_eye;
    // Nose: stretched downwards from its bridge.
    let [top, bottom] = NOSE_SPAN;
    let w_nose = plateau(p.x.abs(), 0.012, 0.024) * smoothstep(-0.04, -0.02, p.z);
    let drop = (NOSE_LENGTH - 1.0) * (top - p.y.clamp(bottom, top));
    q.y -= w_nose * drop * plateau(bottom - p.y, 0.0, 0.014);
    // Mouth: narrower.
    let w_mouth = plateau((p.y - MOUTH_Y).abs(), 0.012, 0.025)
        * plateau(p.x.abs(), 0.030, 0.045)
        * smoothstep(-0.06, -0.04, p.z);
    q.x += (MOUTH_WIDTH - 1.0) * FACE_WIDTH * p.x * w_mouth;
    q
}

/// The GLB and its truth.
pub fn other_proportions() -> (Vec<u8>, VariantTruth) {
    let b = base();
    let (meshes, mut parts) = b.avatar.clone().into_parts();
    for (k, part) in parts.iter_mut().enumerate() {
        if let Some(side) = b.eye_side(k) {
            let c = b.eye_centres[side].as_dvec3();
            let shift = (warp(c) - c).as_vec3();
            part.positions.iter_mut().for_each(|p| *p += shift);
            continue;
        }
        if b.teeth.contains(&k) || b.gums.contains(&k) {
            let rest: Vec<DVec3> = part.positions.iter().map(|p| p.as_dvec3()).collect();
            let warped: Vec<DVec3> = rest.iter().map(|p| warp(*p)).collect();
            for t in part
                .targets
                .iter_mut()
                .filter(|t| t.iter().any(|d| *d != Vec3::ZERO))
            {
                let moved: Vec<DVec3> = rest
                    .iter()
                    .zip(t.iter())
                    .map(|(p, d)| *p + d.as_dvec3())
                    .collect();
                let m = fit_rigid(&rest, &moved, &vec![1.0; rest.len()])
                    .expect("a jaw part has vertices apart");
                for (d, p) in t.iter_mut().zip(&warped) {
                    *d = (m.apply(*p) - *p).as_vec3();
                }
            }
            for (p, w) in part.positions.iter_mut().zip(&warped) {
                *p = w.as_vec3();
            }
            continue;
        }
        for t in &mut part.targets {
            // A still vertex stays still (most are, for most targets).
            for (d, p) in t
                .iter_mut()
                .zip(&part.positions)
                .filter(|(d, _)| **d != Vec3::ZERO)
            {
                let p = p.as_dvec3();
                *d = (warp(p + d.as_dvec3()) - warp(p)).as_vec3();
            }
        }
        for p in &mut part.positions {
            *p = warp(p.as_dvec3()).as_vec3();
        }
    }
    let avatar =
        Avatar::new(meshes, parts).expect("the other-proportions variant's parts make an avatar");
    let mut truth = plain_truth(&avatar, 0, b.true_correspondence.len());
    truth.world_bounds = bounds(&avatar, |v: Vec3| v);
    let [l, r] = b.eye_centres.map(|c| warp(c.as_dvec3()));
    truth.eye_distance = l.distance(r) as f32;
    (glb_of(&avatar, None), truth)
}
