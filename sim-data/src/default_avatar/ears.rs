//! The ears: simple but recognisable shells, part of the head mesh but not
//! of the skin surface (their roots are sunk 3 mm into the head, as game
//! avatars' ears often are).
//!
//! An ear is an ellipsoid 32 mm wide, 62 mm tall and 10 mm thick (adult
//! ear length ≈ 6.2 cm, width ≈ 3.3 cm: Farkas 1994) whose front half is
//! pressed in by a bowl `z −= 7 mm · exp(−(r/0.55)²)` (`r` the normalized
//! distance from the ear's centre in its plane), which leaves a raised rim
//! (the helix) around a hollow (the concha). It stands in front of the
//! hinge's vertical, leans back 15° and stands out 20° from the head
//! (typical auricle inclination and protrusion angles).

use super::head::{CENTRE, ray_radius};
use super::mouth::Mesh;
use super::uv_sphere::{direction, even_rings, uv_sphere};
use glam::{DMat3, DVec3};
use std::f64::consts::PI;

/// Half width, half height, half thickness of an ear (m).
pub const EAR_RADII: DVec3 = DVec3::new(0.016, 0.031, 0.005);
/// Height of the ear's centre (m): its top level with the brows, its lobe
/// level with the nose base.
pub const EAR_CENTRE_Y: f64 = 0.012;
/// Depth of the ear's front edge (m): 1.5 cm behind the jaw hinge.
pub const EAR_FRONT_Z: f64 = -0.05;

/// The ear on `side` (0 = left, +x).
pub fn ear(side: usize) -> Mesh {
    let sign = if side == 0 { 1.0 } else { -1.0 };
    let (rings, segments) = (14, 28);
    // Local frame: w backwards and out, u up leaning back, n outward.
    let protrusion = 20.0 * PI / 180.0;
    let lean = 15.0 * PI / 180.0;
    let w = DVec3::new(sign * protrusion.sin(), 0.0, -protrusion.cos());
    let u = DMat3::from_rotation_x(-lean) * DVec3::Y;
    let n = w.cross(u).normalize() * sign;
    // The head's side at the ear's front edge.
    let towards = DVec3::new(sign, 0.0, 0.0) * 0.08 + DVec3::new(0.0, EAR_CENTRE_Y, EAR_FRONT_Z);
    let d = (towards - CENTRE).normalize();
    let front_edge = CENTRE + d * (ray_radius(CENTRE, d) - 0.003);
    let centre = front_edge + w * EAR_RADII.x;
    let local = |th: f64, ph: f64| {
        let q = direction(th, ph);
        let r = (q.x * q.x + q.y * q.y).sqrt();
        let z = if q.z > 0.0 {
            q.z * EAR_RADII.z - 0.007 * (-(r / 0.55).powi(2)).exp()
        } else {
            q.z * EAR_RADII.z
        };
        centre + w * (q.x * EAR_RADII.x) + u * (q.y * EAR_RADII.y) + n * z
    };
    let (p, mut t) = uv_sphere(
        local(0.0, 0.0),
        &even_rings(rings),
        segments,
        local,
        local(PI, 0.0),
    );
    // The frame (w, u, n) is left-handed on the right side: flip there.
    if w.cross(u).dot(n) < 0.0 {
        t.iter_mut().for_each(|tri| tri.swap(1, 2));
    }
    (p, t)
}
