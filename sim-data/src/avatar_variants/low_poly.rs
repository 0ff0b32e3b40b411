//! `low-poly`: a game or web avatar's head of 2,336 vertices.
//!
//! The default avatar's skin resampled coarser ([`FACE_SPACING`],
//! [`HEAD_SPACING`]): the same surface (every face vertex on the mask) on
//! other, fewer vertices, its 52 shapes resampled the same way (the
//! template interpolated at each new face vertex and continued past the
//! outline). No ears, sockets, mouth lining, teeth or tongue, as in many
//! web avatars; the eyes are low-poly globes turned by their eyeLook
//! targets.

use super::parts::{arkit_mesh, dpart, plain_truth, sorted};
use super::truth::{Piece, VariantTruth};
use crate::default_avatar::{DefaultAvatar, shape_rotation, shapes::rotate_about, skin::skin};
use glam::DVec3;
use likeness::Blendshape;
use likeness::avatar::Avatar;
use std::f64::consts::{PI, TAU};

/// Face sampling (m): 4.2 mm, 2.5 times the default's 1.7 mm, about
/// 1,375 face vertices (the mask's 1,220 are ARKit's own density).
pub const FACE_SPACING: f64 = 0.0042;
/// Head sampling (m): 12 mm, 961 more vertices over cranium, neck and
/// shoulders: a game head's back is coarse.
pub const HEAD_SPACING: f64 = 0.012;
/// Eyeball rings pole to pole and vertices per ring: 10 × 16 = 146
/// vertices, a game eye's resolution.
pub const EYE_RINGS: usize = 10;
/// See [`EYE_RINGS`].
pub const EYE_SEGMENTS: usize = 16;

/// A UV sphere about `centre`: the front pole (+z), `rings − 1` rings of
/// `segments` vertices, the back pole; its triangles face inwards (wound
/// clockwise seen from outside, as some exporters leave them), which the
/// product must see through.
pub fn uv_sphere(
    centre: DVec3,
    radius: f64,
    rings: usize,
    segments: usize,
) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let mut p = vec![centre + DVec3::Z * radius];
    for k in 1..rings {
        let theta = PI * k as f64 / rings as f64;
        for s in 0..segments {
            let phi = TAU * s as f64 / segments as f64;
            let d = DVec3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            );
            p.push(centre + radius * d);
        }
    }
    p.push(centre - DVec3::Z * radius);
    let (n, seg) = (p.len() as u32, segments as u32);
    let ring = |k: u32, s: u32| 1 + k * seg + s % seg;
    let mut t = Vec::new();
    for s in 0..seg {
        t.push([0, ring(0, s + 1), ring(0, s)]);
        t.push([
            n - 1,
            ring(rings as u32 - 2, s),
            ring(rings as u32 - 2, s + 1),
        ]);
    }
    for k in 0..rings as u32 - 2 {
        for s in 0..seg {
            let (a, b, c, d) = (
                ring(k, s),
                ring(k, s + 1),
                ring(k + 1, s),
                ring(k + 1, s + 1),
            );
            t.push([a, b, d]);
            t.push([a, d, c]);
        }
    }
    (p, t)
}

/// The low-poly avatar (meshes `Head`, `EyeLeft`, `EyeRight`) and its truth.
pub fn low_poly(base: &DefaultAvatar) -> (Avatar, VariantTruth) {
    let s = skin(FACE_SPACING, HEAD_SPACING);
    let mut parts = vec![dpart("Head", 0, 0, &s.positions, &s.triangles, &s.targets)];
    for (side, centre) in base.eye_centres.iter().enumerate() {
        let c = centre.as_dvec3();
        let (p, t) = uv_sphere(c, f64::from(base.eye_radius), EYE_RINGS, EYE_SEGMENTS);
        let targets: Vec<Vec<DVec3>> = Blendshape::ALL
            .iter()
            .map(|&shape| rotate_about(&p, c, shape_rotation(side, shape)))
            .collect();
        let name = ["EyeLeft", "EyeRight"][side];
        parts.push(dpart(name, 1 + side, 0, &p, &t, &targets));
    }
    let meshes = ["Head", "EyeLeft", "EyeRight"].map(|n| arkit_mesh(n, &[]));
    let avatar = sorted(
        Avatar::new(meshes.to_vec(), parts).expect("the low-poly variant's parts make an avatar"),
    );
    let mut truth = plain_truth(&avatar, 0, s.face.positions.len());
    truth.eyeballs = [1, 2].map(|k| Piece::whole(&avatar, k));
    truth.teeth = None;
    (avatar, truth)
}
