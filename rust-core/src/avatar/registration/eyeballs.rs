//! The avatar's eyeballs, found by their shape: many rigs turn the eyes
//! with bones, so no eyeLook target moves them, and many keep them in the
//! head's mesh. An eyeball is a connected component of some part that is
//! a nearly whole sphere of a human eye's size, behind a lid opening:
//!
//! - its algebraic sphere fit ([`fit_sphere`]) has a radius between
//!   [`RADIUS_MM`] (mask scale: the registration's similarity turns it
//!   into avatar units), an RMS residual at most [`MAX_RESIDUAL`] of the
//!   radius (a cornea's bulge is allowed, a lid or an ear is not), and
//!   points all round its centre: the mean of the unit directions from
//!   the centre is at most [`MAX_DIRECTION_BIAS`] long (a whole sphere
//!   gives about 0, the bowl of an eye socket much more);
//! - its centre is within [`NEAR_LID_MM`] of an eyeBlink feature (the
//!   upper lid's middle, [`super::features`]);
//! - or some eyeLook target moves at least [`EYEBALL_SHARE`] of it (the
//!   rig says so: the name of the shape is the hint).
//!
//! A component that lies wholly inside a found eyeball's sphere (an iris
//! disc, a lens, an inner shell) belongs to that eye too. Each eye is
//! returned as the avatar vertices of its components.

use crate::avatar::model::Avatar;
use crate::geometry::connected_components::component_vertices;
use crate::geometry::sphere_fit::{Sphere, fit_sphere};
use glam::DVec3;

/// Share of a component's vertices an eyeLook shape must move for it to
/// count as an eyeball whatever its shape.
pub const EYEBALL_SHARE: f64 = 0.9;

/// Radii a human eyeball's sphere may have (mm, mask scale): the adult
/// globe is 24 mm across (radius 12; Bekerman et al. 2014); stylized
/// avatars' eyes run from two thirds to twice that, and a rig's sclera
/// shell often sits a little outside the globe.
pub const RADIUS_MM: (f64, f64) = (8.0, 24.0);

/// Largest RMS distance from the fitted sphere, as a share of its radius.
pub const MAX_RESIDUAL: f64 = 0.12;

/// Largest length of the mean unit direction from the centre to the
/// component's vertices.
pub const MAX_DIRECTION_BIAS: f64 = 0.35;

/// Largest distance of an eyeball's centre from an eyeBlink feature (mm,
/// mask scale): the globe's centre lies about 12 mm behind the lid.
pub const NEAR_LID_MM: f64 = 25.0;

/// Fewest vertices of a component taken for a sphere.
pub const MIN_VERTICES: usize = 12;

/// One eyeball found: its avatar vertices and sphere.
#[derive(Clone, Debug, PartialEq)]
pub struct FoundEyeball {
    /// The avatar vertices (indices into `Avatar::positions`) of every
    /// component of this eye, increasing.
    pub vertices: Vec<u32>,
    /// The sphere of the component that made it an eyeball.
    pub sphere: Sphere,
}

/// The eyeballs of `avatar` (module docs): `positions` its concatenated
/// rest positions, `lids` its eyeBlink features, `mm` avatar units per
/// millimetre of the mask's scale, `looks` the displacement fields of its
/// eyeLook targets (over all vertices).
pub fn find_eyeballs(
    avatar: &Avatar,
    positions: &[DVec3],
    lids: &[DVec3],
    mm: f64,
    looks: &[Vec<DVec3>],
) -> Vec<FoundEyeball> {
    let offsets = avatar.vertex_offsets();
    let largest_look = looks
        .iter()
        .flatten()
        .map(|d| d.length())
        .fold(0.0, f64::max);
    let mut pieces: Vec<Vec<u32>> = Vec::new();
    for (i, part) in avatar.parts().iter().enumerate() {
        let o = offsets[i] as u32;
        for c in component_vertices(part.positions.len(), &part.triangles) {
            if c.len() >= 3 {
                pieces.push(c.into_iter().map(|v| v + o).collect());
            }
        }
    }
    let at = |v: &u32| positions.get(*v as usize).copied().unwrap_or(DVec3::ZERO);
    let mut found: Vec<FoundEyeball> = Vec::new();
    let mut taken = vec![false; pieces.len()];
    for (k, piece) in pieces.iter().enumerate() {
        let points: Vec<DVec3> = piece.iter().map(at).collect();
        let Some(sphere) = fit_sphere(&points).filter(|_| piece.len() >= MIN_VERTICES) else {
            continue;
        };
        let moved_by_look = largest_look > 0.0
            && looks.iter().any(|f| {
                let moved = piece
                    .iter()
                    .filter(|&&v| {
                        f.get(v as usize)
                            .is_some_and(|d| d.length() > 1e-3 * largest_look)
                    })
                    .count();
                moved as f64 >= EYEBALL_SHARE * piece.len() as f64
            });
        let bias = (points
            .iter()
            .map(|p| (*p - sphere.centre).normalize_or_zero())
            .sum::<DVec3>()
            / points.len() as f64)
            .length();
        let shaped = sphere.radius >= RADIUS_MM.0 * mm
            && sphere.radius <= RADIUS_MM.1 * mm
            && sphere.rms_residual <= MAX_RESIDUAL * sphere.radius
            && bias <= MAX_DIRECTION_BIAS;
        let near_lid = lids
            .iter()
            .any(|l| (*l - sphere.centre).length() <= NEAR_LID_MM * mm);
        if moved_by_look || (shaped && near_lid) {
            taken[k] = true;
            found.push(FoundEyeball {
                vertices: piece.clone(),
                sphere,
            });
        }
    }
    // Two shells of one eye (a sclera and a cornea) are one eyeball.
    let mut eyes: Vec<FoundEyeball> = Vec::new();
    for e in found {
        match eyes.iter_mut().find(|x| {
            (x.sphere.centre - e.sphere.centre).length()
                < 0.5 * x.sphere.radius.max(e.sphere.radius)
        }) {
            Some(x) => {
                x.vertices.extend(e.vertices);
                if e.sphere.radius > x.sphere.radius {
                    x.sphere = e.sphere;
                }
            }
            None => eyes.push(e),
        }
    }
    // What lies inside an eye belongs to it.
    for (k, piece) in pieces.iter().enumerate() {
        if taken[k] {
            continue;
        }
        if let Some(eye) = eyes.iter_mut().find(|e| {
            piece
                .iter()
                .all(|v| (at(v) - e.sphere.centre).length() <= 1.05 * e.sphere.radius)
        }) {
            eye.vertices.extend(piece);
        }
    }
    for e in &mut eyes {
        e.vertices.sort_unstable();
        e.vertices.dedup();
    }
    eyes
}
