//! The full-body avatar's hair and glasses, fitted to the default head:
//! meshes without morph targets that sit on the face, as users' avatars
//! have them.
//!
//! - Hair: the head's own skin (not the face region) above the temples and
//!   over the back of the head, pushed out along its normals by
//!   [`HAIR_THICKNESS`].
//! - Glasses: a wire ring before each eye, a bridge over the nose and two
//!   temples back over the ears, each [`WIRE_RADIUS`] thick and held
//!   [`FRAME_CLEARANCE`] off the skin nearest it.

use super::body::{Mesh, Section, join, tube};
use super::parts::base;
use glam::{DVec3, Vec3};
use likeness::avatar::glb::write_new::vertex_normals;
use std::f64::consts::TAU;

/// How far the hair stands off the scalp (m): a short haircut.
pub const HAIR_THICKNESS: f64 = 0.008;
/// Hair covers the head above this height (m, ARKit frame: the eyes are
/// at 28 mm, the top of the face's outline near 85 mm)…
pub const HAIR_ABOVE_Y: f32 = 0.045;
/// …and the back of the head behind this depth (m) down to
/// [`HAIR_NAPE_Y`].
pub const HAIR_BEHIND_Z: f32 = -0.10;
/// The nape: the hair's lowest point at the back (m).
pub const HAIR_NAPE_Y: f32 = -0.06;
/// Radius of the lenses' rims (m): 50 mm lenses, a common frame size.
pub const LENS_RADIUS: f64 = 0.025;
/// Thickness of the frame's wire (m).
pub const WIRE_RADIUS: f64 = 0.0018;
/// Distance of the frame from the skin nearest it (m).
pub const FRAME_CLEARANCE: f64 = 0.006;

/// The hair shell over the default head (ARKit frame, m).
pub fn hair() -> Mesh {
    let b = base();
    let skin = &b.avatar.parts()[b.skin];
    let first_own = b.true_correspondence.len();
    let normals = vertex_normals(&skin.positions, &skin.triangles);
    let keep: Vec<bool> = skin
        .positions
        .iter()
        .enumerate()
        .map(|(v, p)| {
            v >= first_own && (p.y > HAIR_ABOVE_Y || (p.z < HAIR_BEHIND_Z && p.y > HAIR_NAPE_Y))
        })
        .collect();
    let mut index = vec![u32::MAX; skin.positions.len()];
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    for t in &skin.triangles {
        if !t.iter().all(|&i| keep[i as usize]) {
            continue;
        }
        triangles.push(t.map(|i| {
            let i = i as usize;
            if index[i] == u32::MAX {
                index[i] = positions.len() as u32;
                let p = skin.positions[i] + normals[i] * HAIR_THICKNESS as f32;
                positions.push(p.as_dvec3());
            }
            index[i]
        }));
    }
    (positions, triangles)
}

/// Skin and ear vertices of the default head (m).
fn head_points() -> Vec<Vec3> {
    let b = base();
    [b.skin, b.ears]
        .iter()
        .flat_map(|&k| b.avatar.parts()[k].positions.iter().copied())
        .collect()
}

/// The most forward skin depth among `points` for which `near` holds.
fn front(points: &[Vec3], near: impl Fn(Vec3) -> bool) -> f64 {
    points
        .iter()
        .filter(|p| near(**p))
        .map(|p| f64::from(p.z))
        .fold(-1.0, f64::max)
}

/// A wire ring of radius `r` about `centre`, facing +z.
fn ring(centre: DVec3, r: f64) -> Mesh {
    let (around, wire) = (32u32, 8u32);
    let mut p = Vec::new();
    for i in 0..around {
        let a = TAU * f64::from(i) / f64::from(around);
        let radial = DVec3::new(a.cos(), a.sin(), 0.0);
        for j in 0..wire {
            let b = TAU * f64::from(j) / f64::from(wire);
            p.push(
                centre + radial * (r + WIRE_RADIUS * b.cos()) + DVec3::Z * WIRE_RADIUS * b.sin(),
            );
        }
    }
    let at = |i: u32, j: u32| (i % around) * wire + j % wire;
    let mut t = Vec::new();
    for i in 0..around {
        for j in 0..wire {
            t.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            t.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    (p, t)
}

/// A thin wire through `points`.
fn wire(points: &[DVec3]) -> Mesh {
    let sections: Vec<Section> = points
        .iter()
        .map(|&centre| Section {
            centre,
            radii: [WIRE_RADIUS; 2],
        })
        .collect();
    tube(&sections, 8, 0.0)
}

/// The glasses (ARKit frame, m).
pub fn glasses() -> Mesh {
    let b = base();
    let pts = head_points();
    let eyes = b.eye_centres.map(|c| c.as_dvec3());
    let reach = (LENS_RADIUS + 0.004) as f32;
    let lens_z = eyes
        .iter()
        .map(|c| {
            let c = c.as_vec3();
            front(&pts, |p| (p.x - c.x).hypot(p.y - c.y) < reach)
        })
        .fold(-1.0, f64::max)
        + FRAME_CLEARANCE;
    let y = eyes[0].y;
    let mut parts: Vec<Mesh> = eyes
        .iter()
        .map(|c| ring(DVec3::new(c.x, c.y, lens_z), LENS_RADIUS))
        .collect();
    let bridge_y = y + 0.006;
    let bridge_z = front(&pts, |p| {
        p.x.abs() < 0.012 && (f64::from(p.y) - bridge_y).abs() < 0.006
    })
    .max(lens_z - 0.01)
        + FRAME_CLEARANCE;
    let inner = eyes.map(|c| c.x - c.x.signum() * LENS_RADIUS);
    parts.push(wire(&[
        DVec3::new(inner[0], y, lens_z),
        DVec3::new(0.0, bridge_y, bridge_z),
        DVec3::new(inner[1], y, lens_z),
    ]));
    for c in eyes {
        let side = c.x.signum();
        let mut path = vec![DVec3::new(c.x + side * LENS_RADIUS, y, lens_z)];
        for k in 1..=8 {
            let z = lens_z - (lens_z + 0.095) * f64::from(k) / 8.0;
            let side_x = pts
                .iter()
                .filter(|p| (f64::from(p.y) - y).abs() < 0.012 && (f64::from(p.z) - z).abs() < 0.01)
                .map(|p| f64::from(p.x) * side)
                .fold(0.0, f64::max);
            path.push(DVec3::new(side * (side_x + FRAME_CLEARANCE), y, z));
        }
        parts.push(wire(&path));
    }
    join(&parts)
}
