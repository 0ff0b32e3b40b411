//! The eyeballs: a 24 mm sphere with a corneal cap, one separate mesh per
//! eye, rotated rigidly about its centre by the eyeLook shapes.
//!
//! The cornea is the cap of a sphere of radius `R_k = (c² + s²)/(2s)` whose
//! base circle (diameter `2c` = 11.5 mm) lies on the eyeball and which
//! bulges `s` = 2.5 mm beyond that base plane (adult corneal diameter
//! 11.5–12 mm, sagitta ≈ 2.5 mm: Atchison & Smith, *Optics of the Human
//! Eye*, 2000). Its centre is `k = √(R² − c²) + s − R_k` in front of the eye
//! centre; along a ray at angle `θ` from the visual axis the surface is at
//! `r(θ) = max(R, k cos θ + √(R_k² − k² sin² θ))`.

use super::uv_sphere::{direction, open_inwards, uv_sphere};
use glam::{DMat3, DVec3};
use std::f64::consts::{PI, TAU};

/// Eyeball radius (m): the adult globe is about 24 mm across.
pub const EYE_RADIUS: f64 = 0.012;
/// Half the corneal diameter (m).
pub const CORNEA_HALF_WIDTH: f64 = 0.00575;
/// Corneal sagitta above its base plane (m).
pub const CORNEA_SAGITTA: f64 = 0.0025;
/// Horizontal eye rotation of eyeLookIn/Out at weight one (rad): 28°. Eyes
/// turn up to ~45° but rigs and trackers use the customary gaze range
/// of 25–30° for a full weight.
pub const LOOK_HORIZONTAL: f64 = 28.0 * PI / 180.0;
/// Vertical eye rotation of eyeLookUp/Down at weight one (rad): 22°, the
/// customary vertical range being smaller (20–25°).
pub const LOOK_VERTICAL: f64 = 22.0 * PI / 180.0;

/// Radius of the corneal sphere (m).
pub fn cornea_radius() -> f64 {
    (CORNEA_HALF_WIDTH.powi(2) + CORNEA_SAGITTA.powi(2)) / (2.0 * CORNEA_SAGITTA)
}

/// Distance of the corneal sphere's centre in front of the eye centre (m).
pub fn cornea_offset() -> f64 {
    (EYE_RADIUS.powi(2) - CORNEA_HALF_WIDTH.powi(2)).sqrt() + CORNEA_SAGITTA - cornea_radius()
}

/// Signed distance from `p` to an eye at `centre` looking along
/// `rotation · +z` (negative inside): the union of globe and cornea.
pub fn eye_distance(p: DVec3, centre: DVec3, rotation: DMat3) -> f64 {
    let q = rotation.transpose() * (p - centre);
    let globe = q.length() - EYE_RADIUS;
    let cornea = (q - DVec3::Z * cornea_offset()).length() - cornea_radius();
    globe.min(cornea)
}

/// Distance from the eye centre to the surface along a ray at `theta`
/// from the visual axis.
fn surface_radius(theta: f64) -> f64 {
    let (k, rk) = (cornea_offset(), cornea_radius());
    let t = k * theta.cos() + (rk * rk - (k * theta.sin()).powi(2)).max(0.0).sqrt();
    EYE_RADIUS.max(t)
}

/// The farthest the surface of an eye turned by any of `gazes` reaches
/// from its centre along the unit direction `d` (m): the globe's radius
/// where the cornea never passes, more where it does.
pub fn farthest_reach(d: DVec3, gazes: &[DMat3]) -> f64 {
    gazes
        .iter()
        .map(|g| surface_radius((g.transpose() * d).z.clamp(-1.0, 1.0).acos()))
        .fold(EYE_RADIUS, f64::max)
}

/// Rings from the front pole to the back pole (front pole excluded).
pub const RINGS: usize = 34;
/// Vertices per ring.
pub const SEGMENTS: usize = 40;

/// An eyeball mesh centred at `centre`, looking along +z: the front pole,
/// [`RINGS`] − 1 rings of [`SEGMENTS`] vertices, the back pole. Rings are
/// nearly twice as dense at the front as at the back.
pub fn eyeball(centre: DVec3) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let thetas: Vec<f64> = (1..RINGS)
        .map(|k| {
            let t = k as f64 / RINGS as f64;
            // θ(t) = π(t − 0.3 sin(πt)/π): θ' = π(1 − 0.3 cos πt), so the
            // rings are 0.7/1.3 ≈ half as far apart at the front.
            PI * (t - 0.3 * (PI * t).sin() / PI)
        })
        .collect();
    let point = |theta: f64, phi: f64| centre + direction(theta, phi) * surface_radius(theta);
    uv_sphere(
        centre + DVec3::Z * surface_radius(0.0),
        &thetas,
        SEGMENTS,
        point,
        centre - DVec3::Z * EYE_RADIUS,
    )
}

/// Rotation of the eye on `side` (0 = left, +x) for the gaze shapes:
/// `look_out`, `look_in`, `look_up`, `look_down` weights. Positive
/// rotation about +y turns the gaze towards +x; about +x, downwards.
pub fn gaze_rotation(side: usize, look: [f64; 4]) -> DMat3 {
    let [out, inward, up, down] = look;
    let sign = if side == 0 { 1.0 } else { -1.0 };
    let yaw = sign * (out - inward) * LOOK_HORIZONTAL;
    let pitch = (down - up) * LOOK_VERTICAL;
    DMat3::from_rotation_y(yaw) * DMat3::from_rotation_x(pitch)
}

/// Radius of the eye socket's lining (m): 2.5 mm wider than the globe, so
/// the turning cornea (13 mm from the centre) stays inside it.
pub const SOCKET_RADIUS: f64 = 0.0145;
/// Opening of the socket's lining, from the visual axis (rad): 62°, so its
/// rim lies 7 mm in front of the eye centre, behind the lids and corners.
pub const SOCKET_OPENING: f64 = 62.0 * PI / 180.0;

/// The socket behind the eye at `centre`: the back of a sphere of
/// [`SOCKET_RADIUS`] beyond [`SOCKET_OPENING`], facing inwards. Through the
/// corners of the eye, wider than the globe, one sees it rather than the
/// inside of the head.
pub fn socket(centre: DVec3) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let rings = 12;
    let thetas: Vec<f64> = (0..rings)
        .map(|k| SOCKET_OPENING + (PI - SOCKET_OPENING) * k as f64 / rings as f64)
        .collect();
    let point = |theta: f64, phi: f64| centre + direction(theta, phi) * SOCKET_RADIUS;
    open_inwards(&thetas, SEGMENTS, point, centre - DVec3::Z * SOCKET_RADIUS)
}

/// Radius of the pupil (m): 3.8 mm across, an adult's pupil in ordinary
/// indoor light (2–4 mm in bright light, up to 8 mm in the dark; Watson &
/// Yellott, *A unified formula for light-adapted pupil size*, 2012).
pub const PUPIL_RADIUS: f64 = 0.0019;
/// Radius of the visible iris (m): 11.2 mm across, just inside the
/// cornea's base ([`CORNEA_HALF_WIDTH`]), where the limbus lies.
pub const IRIS_RADIUS: f64 = 0.0056;
/// How far the iris and pupil lie outside the cornea (m): painted on it,
/// clear of it in a depth buffer at arm's length, far inside
/// `super::LID_CLEARANCE`.
pub const PAINT_LIFT: f64 = 0.00005;

/// The iris (a ring from [`PUPIL_RADIUS`] to [`IRIS_RADIUS`] about the
/// visual axis) and the pupil (a disc of [`PUPIL_RADIUS`]), as two meshes
/// on the cornea of the eye at `centre`, [`PAINT_LIFT`] outside it. Each
/// has rings of [`SEGMENTS`] vertices at the given distances from the
/// axis; the pupil also its centre.
pub fn iris_and_pupil(centre: DVec3) -> [(Vec<DVec3>, Vec<[u32; 3]>); 2] {
    let (k, rk) = (cornea_offset(), cornea_radius() + PAINT_LIFT);
    let on_cornea = |rho: f64, phi: f64| {
        let z = k + (rk * rk - rho * rho).sqrt();
        centre + DVec3::new(rho * phi.cos(), rho * phi.sin(), z)
    };
    let rings = |radii: &[f64], first: u32| {
        let mut positions = Vec::new();
        for &rho in radii {
            for j in 0..SEGMENTS {
                positions.push(on_cornea(rho, TAU * j as f64 / SEGMENTS as f64));
            }
        }
        let at = |r: usize, j: usize| first + (r * SEGMENTS + j % SEGMENTS) as u32;
        let mut triangles = Vec::new();
        for r in 0..radii.len() - 1 {
            for j in 0..SEGMENTS {
                triangles.push([at(r, j), at(r + 1, j), at(r + 1, j + 1)]);
                triangles.push([at(r, j), at(r + 1, j + 1), at(r, j + 1)]);
            }
        }
        (positions, triangles)
    };
    let iris_radii: Vec<f64> = (0..=4)
        .map(|r| PUPIL_RADIUS + (IRIS_RADIUS - PUPIL_RADIUS) * r as f64 / 4.0)
        .collect();
    let iris = rings(&iris_radii, 0);
    let (mut pupil_p, mut pupil_t) = rings(&[0.5 * PUPIL_RADIUS, PUPIL_RADIUS], 1);
    pupil_p.insert(0, on_cornea(0.0, 0.0));
    for j in 0..SEGMENTS {
        pupil_t.push([0, 1 + j as u32, 1 + ((j + 1) % SEGMENTS) as u32]);
    }
    [iris, (pupil_p, pupil_t)]
}
