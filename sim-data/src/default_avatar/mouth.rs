//! Teeth, gums and tongue: what shows through the mouth slit.
//!
//! The dental arch is the parabola `x = W s, z = z₀ − D s²`, `s ∈ [−1, 1]`
//! (half width `W` at the last molars, depth `D` from the incisors back).
//! Seven teeth per quadrant (incisors to second molars) stand on it,
//! spaced by their crown widths along the arch; each tooth is a rounded
//! box (a sphere mapped by `q ↦ sign(q)|q|^0.55` per axis and scaled to the
//! crown). Upper incisal edges sit 1.5 mm below the lip line; the lower
//! arch sits 2 mm higher and 2.5 mm further back (overbite 2 mm, overjet
//! 2.5 mm, the normal occlusion). Gums are elliptic tubes along the arch
//! over the crowns' roots. The tongue is an ellipsoid flattened on its
//! underside, resting inside the lower arch, its tip behind the lower
//! incisors.

use super::uv_sphere::{direction, even_rings, open_inwards, uv_sphere};
use glam::DVec3;
use std::f64::consts::{PI, TAU};

/// Half width of the arch at the last molars (m): adult inter-molar width
/// is 45–55 mm.
pub const ARCH_HALF_WIDTH: f64 = 0.025;
/// Depth of the arch from the incisors to the last molars (m): 40–45 mm.
pub const ARCH_DEPTH: f64 = 0.040;
/// Labial face of the upper central incisors (m, z): 1 cm behind the lip
/// surface of the mask (lips are about 1 cm thick).
pub const UPPER_FRONT_Z: f64 = 0.026;
/// Upper incisal edge height (m, y): 1.5 mm below the mask's lip line.
pub const UPPER_EDGE_Y: f64 = -0.0485;
/// Vertical overlap of the incisors (m).
pub const OVERBITE: f64 = 0.002;
/// Horizontal overlap of the incisors (m).
pub const OVERJET: f64 = 0.0025;

/// Crown widths (along the arch), heights and thicknesses (m) from the
/// central incisor to the second molar: adult mean crown dimensions
/// (Wheeler's *Dental Anatomy*), rounded.
const CROWNS: [[f64; 3]; 7] = [
    [0.0085, 0.0105, 0.007],
    [0.0065, 0.009, 0.006],
    [0.0075, 0.010, 0.008],
    [0.007, 0.0085, 0.009],
    [0.0065, 0.008, 0.009],
    [0.010, 0.0075, 0.0105],
    [0.009, 0.007, 0.010],
];

/// A closed triangle mesh.
pub type Mesh = (Vec<DVec3>, Vec<[u32; 3]>);

/// Point on an arch with its front at `z0` and the unit tangent there.
fn arch(s: f64, z0: f64) -> (DVec3, DVec3) {
    let p = DVec3::new(ARCH_HALF_WIDTH * s, 0.0, z0 - ARCH_DEPTH * s * s);
    let t = DVec3::new(ARCH_HALF_WIDTH, 0.0, -2.0 * ARCH_DEPTH * s).normalize();
    (p, t)
}

/// Arch parameter reached after arc length `len` from the front.
fn arch_at_length(len: f64) -> f64 {
    let (mut s, mut at) = (0.0, 0.0);
    while at < len && s < 1.2 {
        let ds = 1e-4;
        at += arch(s + ds, 0.0).0.distance(arch(s, 0.0).0);
        s += ds;
    }
    s
}

/// A UV sphere of `rings` × `segments` around the y axis (poles up/down),
/// outward-facing, as unit vectors.
fn unit_sphere(rings: usize, segments: usize) -> Mesh {
    let point = |th: f64, ph: f64| DVec3::new(th.sin() * ph.sin(), th.cos(), th.sin() * ph.cos());
    uv_sphere(DVec3::Y, &even_rings(rings), segments, point, -DVec3::Y)
}

fn append(mesh: &mut Mesh, part: Mesh) {
    let o = mesh.0.len() as u32;
    mesh.0.extend(part.0);
    mesh.1.extend(part.1.into_iter().map(|t| t.map(|i| i + o)));
}

/// One row of 14 teeth: `upper` crowns hang down from the gum line.
pub fn teeth(upper: bool) -> Mesh {
    let (z0, edge) = if upper {
        (UPPER_FRONT_Z, UPPER_EDGE_Y)
    } else {
        (UPPER_FRONT_Z - OVERJET, UPPER_EDGE_Y + OVERBITE)
    };
    let (unit, tris) = unit_sphere(8, 12);
    let mut mesh: Mesh = (Vec::new(), Vec::new());
    for side in [1.0, -1.0] {
        let mut along = 0.0;
        for [w, h, t] in CROWNS {
            let s = arch_at_length(along + 0.5 * w) * side;
            along += w;
            let (base, tangent) = arch(s, z0);
            let inward = DVec3::Y.cross(tangent).normalize();
            // Centre of the crown: half its thickness behind the labial face.
            let dir = if upper { 1.0 } else { -1.0 };
            let centre = base + inward * (0.5 * t) + DVec3::Y * (edge + dir * 0.5 * h);
            let verts = unit.iter().map(|q| {
                let r = DVec3::new(
                    q.x.signum() * q.x.abs().powf(0.55),
                    q.y.signum() * q.y.abs().powf(0.55),
                    q.z.signum() * q.z.abs().powf(0.55),
                );
                centre + tangent * (0.47 * w * r.x) + DVec3::Y * (0.5 * h * r.y)
                    - inward * (0.5 * t * r.z)
            });
            append(&mut mesh, (verts.collect(), tris.clone()));
        }
    }
    mesh
}

/// The gum over one row of teeth: an elliptic tube along the arch, closed
/// at both ends.
pub fn gums(upper: bool) -> Mesh {
    let (z0, edge, dir) = if upper {
        (UPPER_FRONT_Z, UPPER_EDGE_Y, 1.0)
    } else {
        (UPPER_FRONT_Z - OVERJET, UPPER_EDGE_Y + OVERBITE, -1.0)
    };
    let (along, around) = (48, 16);
    let s_end = arch_at_length(CROWNS.iter().map(|c| c[0]).sum::<f64>());
    let mut p = Vec::new();
    for k in 0..=along {
        let s = s_end * (2.0 * k as f64 / along as f64 - 1.0);
        let (base, tangent) = arch(s, z0);
        let inward = DVec3::Y.cross(tangent).normalize();
        let centre = base + inward * 0.0045 + DVec3::Y * (edge + dir * 0.0125);
        for j in 0..around {
            let a = TAU * j as f64 / around as f64;
            p.push(centre + inward * (0.0065 * a.cos()) + DVec3::Y * (0.005 * a.sin()));
        }
    }
    let r = |k: usize, j: usize| (k * around + j % around) as u32;
    let mut t = Vec::new();
    for k in 0..along {
        for j in 0..around {
            t.push([r(k, j), r(k, j + 1), r(k + 1, j + 1)]);
            t.push([r(k, j), r(k + 1, j + 1), r(k + 1, j)]);
        }
    }
    for (k, flip) in [(0, false), (along, true)] {
        let c = p[k * around..(k + 1) * around].iter().sum::<DVec3>() / around as f64;
        let ci = p.len() as u32;
        p.push(c);
        for j in 0..around {
            let tri = [ci, r(k, j + 1), r(k, j)];
            t.push(if flip {
                [ci, r(k, j), r(k, j + 1)]
            } else {
                tri
            });
        }
    }
    (p, t)
}

/// Tongue centre, half extents (m): 36 mm wide, 18 mm thick, 56 mm long
/// from tip to the back of the oral part (adult tongue ≈ 5 cm wide at
/// most, the oral part ≈ 5–6 cm long), tip 2 mm behind the lower incisors.
pub const TONGUE_CENTRE: DVec3 = DVec3::new(0.0, -0.0555, -0.0125);
/// Half extents of the tongue's ellipsoid (m).
pub const TONGUE_RADII: DVec3 = DVec3::new(0.018, 0.009, 0.028);

/// The tongue: an ellipsoid whose lower half is flattened to 60%.
pub fn tongue() -> Mesh {
    let (unit, tris) = unit_sphere(20, 32);
    let p = unit
        .iter()
        .map(|q| {
            let y = if q.y < 0.0 { 0.6 * q.y } else { q.y };
            TONGUE_CENTRE + DVec3::new(q.x, y, q.z) * TONGUE_RADII
        })
        .collect();
    (p, tris)
}

/// Centre of the mouth's lining (m): behind the lips, around the teeth.
pub const CAVITY_CENTRE: DVec3 = DVec3::new(0.0, -0.048, -0.002);
/// Half extents of the lining's ellipsoid (m).
pub const CAVITY_RADII: DVec3 = DVec3::new(0.031, 0.026, 0.040);
/// The lining stops at this depth (m), 2 mm or more behind the skin of the
/// lips, chin and cheeks, leaving the front open towards the mouth slit.
pub const CAVITY_FRONT_Z: f64 = 0.017;

/// The mouth's lining: an ellipsoid around teeth and tongue, cut open at
/// [`CAVITY_FRONT_Z`], facing inwards. Through the open mouth one sees it
/// rather than the inside of the head.
pub fn cavity() -> Mesh {
    let (rings, segments) = (18, 40);
    // Rings around the z axis, from the opening (θ₀, where the ellipsoid
    // reaches the cut) to the back pole.
    let theta0 = ((CAVITY_FRONT_Z - CAVITY_CENTRE.z) / CAVITY_RADII.z).acos();
    let thetas: Vec<f64> = (0..rings)
        .map(|k| theta0 + (PI - theta0) * k as f64 / rings as f64)
        .collect();
    let point = |th: f64, ph: f64| CAVITY_CENTRE + direction(th, ph) * CAVITY_RADII;
    let back = CAVITY_CENTRE - DVec3::Z * CAVITY_RADII.z;
    open_inwards(&thetas, segments, point, back)
}

/// How much of the lining follows the mandible: its floor fully, its roof
/// not at all, blended between 3 mm and 15 mm below the lining's centre.
pub fn cavity_jaw_weight(p: DVec3) -> f64 {
    crate::regions::smoothstep(CAVITY_CENTRE.y - 0.003, CAVITY_CENTRE.y - 0.015, p.y)
}
