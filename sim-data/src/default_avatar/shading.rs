//! The skin's shading normals, written in the GLB in place of the
//! surface's own.
//!
//! Each face vertex lies at a barycentric point of a mask triangle
//! ([`super::face`]), so the face is flat across each of the mask's
//! triangles (about 5–10 mm wide) and its own normals show the mask's
//! facets. Phong's interpolation removes them: at barycentric point
//! `(b₀, b₁, b₂)` of mask triangle `(i, j, k)` the normal is
//! `normalize(b₀ nᵢ + b₁ nⱼ + b₂ nₖ)`, with `n` the mask's area-weighted
//! vertex normals on its neutral. The head is sampled from a smooth
//! implicit surface ([`super::head`]), so its own area-weighted normals
//! serve. The two fields differ where they meet at the outline, so the
//! normals are averaged with their one-ring's [`OUTLINE_SMOOTHING`] times
//! on the face within [`OUTLINE_BAND`] of the outline (along edges) and on
//! the head within [`HEAD_BAND`] of it. The head's band must be wide: the
//! smoothed field has to meet the head's own normals where they agree
//! again, or the band's edge (jagged, as it follows the mesh's edges)
//! shows. A band of 12 mm on both sides did: streaks down the neck under
//! the chin, where the written normals turned up to 0.54 rad across a
//! triangle against the surface's own 0.20. Only shading changes:
//! positions and shapes stay as they are.

use crate::face_mask::face_mask;
use glam::{DVec3, Vec3};
use likeness::avatar::glb::write_new::vertex_normals;
use likeness::geometry::edge_distance::edge_distances;
use likeness::geometry::one_ring::one_rings;

use super::face::MaskPoint;

/// How far inside the face's outline, along the skin's edges, normals are
/// smoothed across the join (m): seven of the face's 1.7 mm rings.
pub const OUTLINE_BAND: f64 = 0.012;

/// How far outside the outline, along the skin's edges, the head's normals
/// are smoothed (m): the reach of the head's bend to meet the outline
/// ([`super::head::BLEND_ANGLE`], 0.45 rad at the 8–10 cm from the head's
/// centre the jaw and chin lie at, about 4 cm), with a margin: beyond it
/// the head is its own implicit surface and its normals need no help.
pub const HEAD_BAND: f64 = 0.045;

/// How many times normals in the bands are averaged with their one-ring's:
/// a diffusion reaching about `√k` rings each way: 5 of the head's 5.5 mm
/// rows, so the join's difference is spread over the band, while the
/// head's own curvature (radii of 5 cm and more) is kept.
pub const OUTLINE_SMOOTHING: usize = 24;

/// Shading normals of the skin at `positions` (triangles `triangles`), whose
/// first `on_mask.len()` vertices lie on the mask at `on_mask` and whose
/// face outline is `outline`: unit, one per vertex.
pub fn skin_normals(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    on_mask: &[MaskPoint],
    outline: &[u32],
) -> Vec<Vec3> {
    let mask = face_mask();
    let mask_tris = mask.topology.triangles();
    let mask_normals = vertex_normals(&mask.neutral, mask_tris);
    let points: Vec<Vec3> = positions.iter().map(|p| p.as_vec3()).collect();
    let mut normals = vertex_normals(&points, triangles);
    for (n, m) in normals.iter_mut().zip(on_mask) {
        let t = mask_tris[m.triangle as usize];
        let blend: Vec3 = (0..3)
            .map(|k| m.barycentric[k] as f32 * mask_normals[t[k] as usize])
            .sum();
        *n = blend.try_normalize().unwrap_or(*n);
    }
    let mut on_outline = vec![false; positions.len()];
    for &v in outline {
        on_outline[v as usize] = true;
    }
    let distance = edge_distances(positions, triangles, &on_outline, HEAD_BAND);
    let rings = one_rings(positions.len(), triangles);
    let reach = |v: usize| match v < on_mask.len() {
        true => OUTLINE_BAND,
        false => HEAD_BAND,
    };
    let band: Vec<u32> = (0..positions.len() as u32)
        .filter(|&v| distance[v as usize] <= reach(v as usize) && rings.contains_key(&v))
        .collect();
    for _ in 0..OUTLINE_SMOOTHING {
        let next: Vec<Vec3> = band
            .iter()
            .map(|v| {
                let sum = rings[v]
                    .iter()
                    .fold(normals[*v as usize], |s, &w| s + normals[w as usize]);
                sum.try_normalize().unwrap_or(normals[*v as usize])
            })
            .collect();
        for (v, n) in band.iter().zip(next) {
            normals[*v as usize] = n;
        }
    }
    normals
}
