//! A closed surface around an axis, triangulated pole to pole: the ears,
//! the teeth's crowns, the tongue and the eyeballs are each one, placed by
//! their own map from polar angles.
//!
//! Vertex `0` is the first pole, then one ring of `segments` vertices per
//! polar angle `θ_k`, at azimuths `φ_j = 2πj / segments`, then the last
//! pole. A fan closes each pole; two triangles join each quad between
//! neighbouring rings. The triangles face outwards where `(θ, φ)` runs
//! like the spherical angles about a right-handed axis (`φ` counter-
//! clockwise seen from the first pole).
//!
//! A lining ([`open_inwards`]) is the same surface without its first pole
//! and fan, open there, facing inwards: the eye sockets and the mouth's
//! lining.

use glam::DVec3;
use std::f64::consts::{PI, TAU};

/// The unit vector at polar angle `theta` from +z and azimuth `phi` from
/// +x: `(sin θ cos φ, sin θ sin φ, cos θ)`.
pub fn direction(theta: f64, phi: f64) -> DVec3 {
    DVec3::new(
        theta.sin() * phi.cos(),
        theta.sin() * phi.sin(),
        theta.cos(),
    )
}

/// The polar angles of `rings − 1` rings evenly spaced between the poles:
/// `θ_k = π k / rings`, `k = 1 … rings − 1`.
pub fn even_rings(rings: usize) -> Vec<f64> {
    (1..rings).map(|k| PI * k as f64 / rings as f64).collect()
}

/// The surface with poles `first` and `last` and a ring at each of
/// `thetas` (module docs), ring vertices at `point(θ, φ)`.
pub fn uv_sphere(
    first: DVec3,
    thetas: &[f64],
    segments: usize,
    point: impl Fn(f64, f64) -> DVec3,
    last: DVec3,
) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let mut p = vec![first];
    for &theta in thetas {
        for j in 0..segments {
            p.push(point(theta, TAU * j as f64 / segments as f64));
        }
    }
    p.push(last);
    let ring = |k: usize, j: usize| (1 + k * segments + j % segments) as u32;
    let mut t = Vec::new();
    for j in 0..segments {
        t.push([0, ring(0, j), ring(0, j + 1)]);
    }
    for k in 0..thetas.len() - 1 {
        for j in 0..segments {
            t.push([ring(k, j), ring(k + 1, j), ring(k + 1, j + 1)]);
            t.push([ring(k, j), ring(k + 1, j + 1), ring(k, j + 1)]);
        }
    }
    let back = (p.len() - 1) as u32;
    let last_ring = thetas.len() - 1;
    for j in 0..segments {
        t.push([ring(last_ring, j), back, ring(last_ring, j + 1)]);
    }
    (p, t)
}

/// A lining: a ring at each of `thetas`, ring vertices at `point(θ, φ)`,
/// then the pole `last`; open before the first ring and facing inwards
/// (module docs). Vertex `k · segments + j` is ring `k`'s `j`-th.
pub fn open_inwards(
    thetas: &[f64],
    segments: usize,
    point: impl Fn(f64, f64) -> DVec3,
    last: DVec3,
) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let mut p = Vec::with_capacity(thetas.len() * segments + 1);
    for &theta in thetas {
        for j in 0..segments {
            p.push(point(theta, TAU * j as f64 / segments as f64));
        }
    }
    p.push(last);
    let ring = |k: usize, j: usize| (k * segments + j % segments) as u32;
    let mut t = Vec::new();
    for k in 0..thetas.len() - 1 {
        for j in 0..segments {
            t.push([ring(k, j), ring(k + 1, j + 1), ring(k + 1, j)]);
            t.push([ring(k, j), ring(k, j + 1), ring(k + 1, j + 1)]);
        }
    }
    let back = (p.len() - 1) as u32;
    let last_ring = thetas.len() - 1;
    for j in 0..segments {
        t.push([ring(last_ring, j), ring(last_ring, j + 1), back]);
    }
    (p, t)
}
