//! The rest of the skin: the head around the face, the neck and the top of
//! the shoulders, joined to the face region along the mask's outline.
//!
//! The shape is an implicit surface `F(p) = 0`, a smooth union
//! (`smin(a, b, k) = min(a, b) − h²k/4`, `h = max(k − |a − b|, 0)/k`) of
//! approximate distances to a cranium (horizontal sections superelliptic
//! with exponent 3, so the head is broad just behind the face's outline), a
//! jaw, an elliptic neck and an ellipsoidal dome for the shoulders. It is
//! nearly star-shaped: the skin at parameters `(γ, ψ)` (angle from
//! straight up, azimuth) is `o(γ) + ρ d(γ, ψ)`, with `d` the unit direction,
//! `o(γ)` the ray's origin ([`CENTRE`] for the upper half, sliding down the
//! vertical axis below it, see [`origin`]) and `ρ` the first crossing of `F`
//! along the ray.
//!
//! Near the face the radius is corrected so the head meets the mask's
//! outline exactly: `ρ += δ · κ(α/α₀)`, where `δ` is Shepard's interpolation
//! (weights `1/α_k⁴`, `α_k²` taken as the squared chord `2(1 − d·d_k)`) of
//! the mismatches `|x_k − o| − ρ_k` at the rim points, `α` the angle to the
//! nearest one, `κ(t) = (1 − t²)³` and `α₀ =` [`BLEND_ANGLE`].
//!
//! Vertices are laid out on rings about the vertical axis through `C`, from
//! the crown down to the horizontal cut at [`BOTTOM_Y`], [`HEAD_SPACING`]
//! apart in arc length down every meridian and along each ring, and
//! triangulated by a constrained Delaunay triangulation in a plane where
//! triangles keep their shape on the skin ([`super::meridians`]), with the
//! face's outline as a hole and the bottom ring as the outer boundary.

use super::face::triangulate;
use super::meridians::{AZIMUTHS, Meridians};
use crate::face_mask::inside;
use glam::DVec3;
use std::f64::consts::{PI, TAU};

/// Centre of the star-shaped head (m): behind the eyes, 5 cm behind the
/// face's outline.
pub const CENTRE: DVec3 = DVec3::new(0.0, 0.0, -0.05);
/// How far the rays' origin slides down for the lower half (m).
pub const DROP: f64 = 0.18;
/// Height of the cut through the neck and shoulders (m): 20 cm below the
/// eye line's origin, the top of the shoulders.
pub const BOTTOM_Y: f64 = -0.19;
/// Target edge length of the head and neck (m).
pub const HEAD_SPACING: f64 = 0.0055;
/// How far from the outline the head bends to meet the mask (rad).
pub const BLEND_ANGLE: f64 = 0.45;

fn smin(a: f64, b: f64, k: f64) -> f64 {
    let h = (k - (a - b).abs()).max(0.0) / k;
    a.min(b) - h * h * k * 0.25
}

fn ellipsoid(p: DVec3, c: DVec3, r: DVec3) -> f64 {
    let q = (p - c) / r;
    (q.length() - 1.0) * r.min_element()
}

/// Approximate signed distance to the head, neck and shoulders (m).
///
/// Cranium: a 16 cm wide, 19.4 cm long, 23.6 cm tall superellipsoid
/// (adult head breadth 15–16 cm, length 19–20 cm: Farkas 1994); neck 11 cm
/// wide, 11 cm deep (adult neck circumference ≈ 36–38 cm); the shoulders a
/// dome 34 cm across (steep enough that every ray meets it once).
pub fn head_field(p: DVec3) -> f64 {
    let (ax, az, ay) = (0.080, 0.097, 0.118);
    let (yc, zc) = (0.02, -0.065);
    let horizontal = ((p.x.abs() / ax).powi(3) + ((p.z - zc).abs() / az).powi(3)).powf(2.0 / 3.0);
    let cranium = ((horizontal + ((p.y - yc) / ay).powi(2)).sqrt() - 1.0) * ax;
    let jaw = ellipsoid(
        p,
        DVec3::new(0.0, -0.055, -0.025),
        DVec3::new(0.060, 0.050, 0.058),
    );
    let neck_q = (p.x / 0.056).powi(2) + ((p.z + 0.052) / 0.055).powi(2);
    // The neck runs from inside the skull down into the shoulders.
    let neck = ((neck_q.sqrt() - 1.0) * 0.055)
        .max(p.y + 0.03)
        .max(-0.26 - p.y);
    let shoulders = ellipsoid(
        p,
        DVec3::new(0.0, -0.29, -0.055),
        DVec3::new(0.17, 0.14, 0.08),
    );
    let head = smin(cranium, jaw, 0.03);
    smin(smin(head, neck, 0.025), shoulders, 0.08)
}

/// Where the ray for angle `gamma` starts: [`CENTRE`] for the upper half,
/// sliding down the vertical axis by up to [`DROP`] towards straight down,
/// so the rays fan out over the neck and shoulders without crossing
/// (neighbouring rays start lower and point lower).
pub fn origin(gamma: f64) -> DVec3 {
    CENTRE - DVec3::Y * DROP * crate::regions::smoothstep(PI / 2.0, PI, gamma)
}

/// First crossing of the head's surface along the ray `o + t d` (m).
pub fn ray_radius(o: DVec3, d: DVec3) -> f64 {
    let mut t = 0.0;
    while t < 0.6 && head_field(o + t * d) < 0.0 {
        t += 0.004;
    }
    let (mut lo, mut hi) = ((t - 0.004).max(0.0), t);
    for _ in 0..30 {
        let mid = 0.5 * (lo + hi);
        if head_field(o + mid * d) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The parameters `(γ, ψ)` of the ray through `p`: `ψ` its azimuth about
/// the vertical axis, `γ` solving `∠(ŷ, p − o(γ)) = γ` by bisection (the
/// left side falls as `γ` grows).
pub fn parameters(p: DVec3) -> (f64, f64) {
    let psi = p.x.atan2(p.z - CENTRE.z);
    let (mut lo, mut hi) = (0.0, PI);
    for _ in 0..50 {
        let mid = 0.5 * (lo + hi);
        if (p - origin(mid)).angle_between(DVec3::Y) > mid {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    (0.5 * (lo + hi), psi)
}

/// Unit direction at angle `gamma` from straight up and azimuth `psi`
/// (0 = forward, +z; π/2 = the person's left, +x).
pub fn direction(gamma: f64, psi: f64) -> DVec3 {
    DVec3::new(
        gamma.sin() * psi.sin(),
        gamma.cos(),
        gamma.sin() * psi.cos(),
    )
}

/// The outline the head must meet: rim points and their directions.
struct Rim {
    points: Vec<DVec3>,
    params: Vec<(f64, f64)>,
    dirs: Vec<DVec3>,
    mismatch: Vec<f64>,
}

/// The head's surface at parameters `(γ, ψ)` before meeting the rim:
/// origin, direction and radius.
fn ray(gamma: f64, psi: f64) -> (DVec3, DVec3, f64) {
    let (o, d) = (origin(gamma), direction(gamma, psi));
    (o, d, ray_radius(o, d))
}

impl Rim {
    fn new(points: &[DVec3]) -> Rim {
        let params: Vec<(f64, f64)> = points.iter().map(|p| parameters(*p)).collect();
        let dirs: Vec<DVec3> = params.iter().map(|(g, s)| direction(*g, *s)).collect();
        let mismatch = points
            .iter()
            .zip(&params)
            .map(|(p, (g, s))| {
                let (o, _, r) = ray(*g, *s);
                (*p - o).length() - r
            })
            .collect();
        Rim {
            points: points.to_vec(),
            params,
            dirs,
            mismatch,
        }
    }

    /// The surface at `(γ, ψ)` corrected to meet the rim.
    fn surface(&self, gamma: f64, psi: f64) -> DVec3 {
        let (o, d, r) = ray(gamma, psi);
        // Squared chords |d − d_k|² = 2(1 − d·d_k) stand in for squared
        // angles in the weights (equal to second order, and no arccosine).
        let (mut sum, mut wsum, mut closest) = (0.0, 0.0, -1.0f64);
        for (rd, m) in self.dirs.iter().zip(&self.mismatch) {
            let cos = rd.dot(d);
            let w = 1.0 / (2.0 * (1.0 - cos) + 1e-8).powi(2);
            sum += w * m;
            wsum += w;
            closest = closest.max(cos);
        }
        let nearest = closest.clamp(-1.0, 1.0).acos();
        o + d * (r + crate::regions::kernel(nearest / BLEND_ANGLE) * sum / wsum)
    }
}

/// The head's vertices and triangles; vertex `k < rim.len()` is rim point
/// `k` (in the order given), the rest are the head's own.
pub struct HeadRegion {
    /// Positions of the head's own vertices (not the rim's) (m).
    pub positions: Vec<DVec3>,
    /// Triangles over rim points then own vertices, outward-facing.
    pub triangles: Vec<[u32; 3]>,
    /// Indices (in the same numbering) of the bottom loop, in order.
    pub bottom: Vec<u32>,
}

/// The rim points' plane positions `plane`, those between corners
/// interpolated linearly (by index) between the corners'.
fn collinear_plane(mut plane: Vec<[f64; 2]>, anchor: &[bool]) -> Vec<[f64; 2]> {
    let n = plane.len();
    let corners: Vec<usize> = (0..n).filter(|&k| anchor[k]).collect();
    for (c, &a) in corners.iter().enumerate() {
        let b = corners[(c + 1) % corners.len()];
        let span = (b + n - a) % n;
        for s in 1..span {
            let t = s as f64 / span as f64;
            plane[(a + s) % n] = [0, 1].map(|d| plane[a][d] + t * (plane[b][d] - plane[a][d]));
        }
    }
    plane
}

/// Angle from the top where the skin reaches [`BOTTOM_Y`] at azimuth `psi`.
fn bottom_angle(psi: f64) -> f64 {
    let y_at = |g: f64| {
        let (o, d, r) = ray(g, psi);
        o.y + r * d.y
    };
    let (mut lo, mut hi) = (PI / 2.0, PI - 0.02);
    for _ in 0..40 {
        let mid = 0.5 * (lo + hi);
        if y_at(mid) > BOTTOM_Y {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Builds the head around a rim loop (the face region's outline, in order).
///
/// `anchor[k]` tells whether rim point `k` is a corner of the outline;
/// points between two corners lie on a straight edge, and their plane
/// positions are interpolated between the corners' so they stay collinear
/// in the plane too (else the triangulation fills the slivers between
/// them with triangles of zero area).
pub fn head_region(rim_points: &[DVec3], anchor: &[bool]) -> HeadRegion {
    head_region_with(rim_points, anchor, HEAD_SPACING)
}

/// [`head_region`] with rings and ring points `spacing` apart (m) instead
/// of [`HEAD_SPACING`] (the low-poly test avatar's head is coarser).
pub fn head_region_with(rim_points: &[DVec3], anchor: &[bool], spacing: f64) -> HeadRegion {
    let rim = Rim::new(rim_points);
    let h = spacing;
    let gmax: Vec<f64> = (0..AZIMUTHS)
        .map(|k| bottom_angle(TAU * k as f64 / AZIMUTHS as f64))
        .collect();
    let gmax_at = |psi: f64| {
        let s = psi.rem_euclid(TAU) / TAU * AZIMUTHS as f64;
        let (k, f) = (s.floor() as usize % AZIMUTHS, s.fract());
        gmax[k] * (1.0 - f) + gmax[(k + 1) % AZIMUTHS] * f
    };
    let surface = |tau: f64, psi: f64| rim.surface(tau * gmax_at(psi), psi);
    let meridians = Meridians::new(&surface);
    let rings = (meridians.length / h).round() as usize;
    let rim_plane = collinear_plane(
        rim.params
            .iter()
            .map(|(g, psi)| meridians.plane(meridians.sigma(g / gmax_at(*psi), *psi), *psi))
            .collect(),
        anchor,
    );
    let mut plane = rim_plane.clone();
    let mut positions = Vec::new();
    let mut bottom = Vec::new();
    for k in 0..=rings {
        let sigma = k as f64 / rings as f64;
        let n = if k == 0 {
            1
        } else {
            ((meridians.circumference(&surface, sigma) / h).round() as usize).max(6)
        };
        for j in 0..n {
            let psi = TAU * (j as f64 + 0.5 * (k % 2) as f64) / n as f64;
            let p = surface(meridians.tau(sigma, psi), psi);
            let s = meridians.plane(sigma, psi);
            let near_rim = rim.points.iter().any(|r| r.distance(p) < 0.7 * h);
            if k < rings && (near_rim || inside(&rim_plane, s)) {
                continue;
            }
            if k == rings {
                bottom.push(plane.len() as u32);
            }
            plane.push(s);
            positions.push(p);
        }
    }
    let loops = [0..rim_plane.len(), bottom[0] as usize..plane.len()];
    let mut triangles = triangulate(&plane, &loops, &[]);
    let all: Vec<DVec3> = rim.points.iter().chain(&positions).copied().collect();
    let outward: f64 = triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| all[i as usize]);
            let m = (a + b + c) / 3.0;
            (b - a)
                .cross(c - a)
                .dot(m - DVec3::new(0.0, m.y.min(CENTRE.y), CENTRE.z))
        })
        .sum();
    if outward < 0.0 {
        triangles.iter_mut().for_each(|t| t.swap(1, 2));
    }
    HeadRegion {
        positions,
        triangles,
        bottom,
    }
}
