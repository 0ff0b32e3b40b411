//! The two Laplacians the stages solve with, as sparse matrix entries for
//! [`super::sparse_cholesky`].
//!
//! - **Cotangent** (gradient form): for piecewise-linear hat functions
//!   `φ` on triangles `t` of area `A_t`,
//!
//!   ```text
//!   L_ki = Σ_t A_t ∇φ_k · ∇φ_i,
//!   ```
//!
//!   which for `k ≠ i` is `−½ (cot α_ki + cot β_ki)` over the two angles
//!   facing edge `ki` (Pinkall & Polthier 1993; Botsch et al. 2010,
//!   *Polygon Mesh Processing* §3.3). It is the matrix of
//!   `Σ_t A_t ‖∇u_t‖²`, the energy of deformation transfer (Eq. 2 of
//!   Botsch et al. 2006) and of the face step ([`cotangent_lower`]).
//! - **Laplace–Beltrami rows** (area-normalized cotangent): for vertex
//!   `v` with Voronoi-like area `A_v` (a third of its triangles' areas),
//!
//!   ```text
//!   (Δu)_v = (1 / A_v) Σ_{w ~ v} ½ (cot α_vw + cot β_vw) (u_w − u_v),
//!   ```
//!
//!   and rows `a_v = √A_v (Δu)_v`, so that `Σ_v (a_v · u)² = Σ_v A_v
//!   ‖(Δu)_v‖²`, the discrete thin-plate (bending) energy of a displacement
//!   (Botsch & Sorkine 2008, *On linear variational surface deformation
//!   methods*, §3): unlike the uniform rows, it knows how long an edge is,
//!   so a change across a narrow row of triangles (a lid's margin) costs
//!   as much as it turns them ([`laplace_beltrami_rows`]).
//! - **Uniform** (graph): `(L u)_v = deg(v) u_v − Σ_{w ~ v} u_w`, each
//!   vertex against its one-ring ([`uniform_row`]); the avatar stage's
//!   bi-Laplacian solves minimize `Σ_r ‖(L u)_r‖²`, whose matrix
//!   `Σ_r a_r a_rᵀ` over the rows `a_r` is [`normal_lower`].
//!
//! Each builder gives the lower triangle (row ≥ column), duplicates to be
//! summed, as [`super::sparse_cholesky::factor`] takes it.

use faer::sparse::Triplet;
use glam::DVec3;
use std::collections::{BTreeMap, BTreeSet};

/// The lower triangle of the cotangent Laplacian `L_ki = Σ_t A_t ∇φ_k ·
/// ∇φ_i` (module docs) over `triangles`, with `gradients[t]` the three
/// hat-function gradients `∇φ` of triangle `t` and `weighted[t]` the same
/// times its area, `A_t ∇φ`; `unknown(v)` is vertex `v`'s row and column
/// (`None`: fixed, left out).
pub fn cotangent_lower(
    triangles: &[[u32; 3]],
    gradients: &[[DVec3; 3]],
    weighted: &[[DVec3; 3]],
    unknown: impl Fn(u32) -> Option<usize>,
) -> Vec<Triplet<usize, usize, f64>> {
    let mut entries = Vec::with_capacity(6 * triangles.len());
    for ((t, g), wg) in triangles.iter().zip(gradients).zip(weighted) {
        for k in 0..3 {
            for i in 0..3 {
                if let (Some(row), Some(col)) = (unknown(t[k]), unknown(t[i]))
                    && row >= col
                {
                    entries.push(Triplet::new(row, col, wg[k].dot(g[i])));
                }
            }
        }
    }
    entries
}

/// Largest cotangent weight of an angle: at 20 (an angle of 2.9°) a
/// sliver's weight stops growing, so one needle triangle cannot stiffen
/// its edge past its neighbours' by orders of magnitude. Negative
/// cotangents (angles past 90°) count as zero, which keeps every weight
/// of a row non-negative, as the uniform rows' are.
pub const MAX_COTANGENT: f64 = 20.0;

/// The Laplace–Beltrami rows `a_v = √A_v (Δu)_v` (module docs) of every
/// vertex of `triangles` over `positions`, as `(column, value)` pairs by
/// vertex, each cotangent within `[0, MAX_COTANGENT]`.
pub fn laplace_beltrami_rows(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
) -> BTreeMap<u32, Vec<(u32, f64)>> {
    let mut weights: BTreeMap<(u32, u32), f64> = BTreeMap::new();
    let mut areas: BTreeMap<u32, f64> = BTreeMap::new();
    for t in triangles {
        let p = t.map(|v| positions[v as usize]);
        let doubled = (p[1] - p[0]).cross(p[2] - p[0]).length();
        for k in 0..3 {
            *areas.entry(t[k]).or_default() += doubled / 6.0;
            // The angle at corner k faces the edge of the other two.
            let (a, b) = (p[(k + 1) % 3] - p[k], p[(k + 2) % 3] - p[k]);
            let cot = a.dot(b) / a.cross(b).length().max(f64::MIN_POSITIVE);
            let (i, j) = (t[(k + 1) % 3], t[(k + 2) % 3]);
            *weights.entry((i.min(j), i.max(j))).or_default() +=
                0.5 * cot.clamp(0.0, MAX_COTANGENT);
        }
    }
    let mut rows: BTreeMap<u32, Vec<(u32, f64)>> = BTreeMap::new();
    for (&(i, j), &w) in &weights {
        rows.entry(i).or_default().push((j, -w));
        rows.entry(j).or_default().push((i, -w));
    }
    for (v, row) in rows.iter_mut() {
        let diagonal: f64 = row.iter().map(|(_, w)| -w).sum();
        row.push((*v, diagonal));
        let scale = 1.0 / areas[v].max(f64::MIN_POSITIVE).sqrt();
        for (_, w) in row.iter_mut() {
            *w *= scale;
        }
    }
    rows
}

/// Row `v` of the uniform Laplacian (module docs) with one-ring `ring`:
/// `(v, deg v)` and `(w, −1)` for every neighbour `w`.
pub fn uniform_row(v: u32, ring: &BTreeSet<u32>) -> impl Iterator<Item = (u32, f64)> + '_ {
    std::iter::once((v, ring.len() as f64)).chain(ring.iter().map(|&w| (w, -1.0)))
}

/// The lower triangle of `Σ_r a_r a_rᵀ` for the sparse rows `rows` (each
/// `(column, value)` pairs): the matrix of the least-squares energy
/// `Σ_r (a_r · u)²`.
pub fn normal_lower<'a>(
    rows: impl IntoIterator<Item = &'a [(usize, f64)]>,
) -> Vec<Triplet<usize, usize, f64>> {
    let mut entries = Vec::new();
    for row in rows {
        for &(a, x) in row {
            for &(b, y) in row {
                if a >= b {
                    entries.push(Triplet::new(a, b, x * y));
                }
            }
        }
    }
    entries
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::deformation_gradient::{hat_gradients, triangle_area};

    /// Entry `(r, c)` of the matrix `entries` make, duplicates summed.
    fn sum_at(entries: &[Triplet<usize, usize, f64>], r: usize, c: usize) -> f64 {
        entries
            .iter()
            .filter(|e| e.row == r && e.col == c)
            .map(|e| e.val)
            .sum()
    }

    #[test]
    fn the_gradient_form_is_the_cotangent_formula() {
        // Two triangles over edge 0–1: its weight is −½ (cot α + cot β).
        let x = [
            DVec3::ZERO,
            DVec3::X * 2.0,
            DVec3::new(0.5, 1.0, 0.0),
            DVec3::new(1.2, -0.7, 0.0),
        ];
        let triangles = [[0, 1, 2], [1, 0, 3]];
        let corners = |t: &[u32; 3]| t.map(|v| x[v as usize]);
        let gradients: Vec<[DVec3; 3]> = triangles
            .iter()
            .map(|t| hat_gradients(corners(t)).expect("not degenerate"))
            .collect();
        let weighted: Vec<[DVec3; 3]> = triangles
            .iter()
            .zip(&gradients)
            .map(|(t, g)| g.map(|g| triangle_area(corners(t)) * g))
            .collect();
        let entries = cotangent_lower(&triangles, &gradients, &weighted, |v| Some(v as usize));
        let at = |r: usize, c: usize| sum_at(&entries, r, c);
        let cot = |apex: DVec3, a: DVec3, b: DVec3| {
            let (u, v) = (a - apex, b - apex);
            u.dot(v) / u.cross(v).length()
        };
        let expected = -0.5 * (cot(x[2], x[0], x[1]) + cot(x[3], x[0], x[1]));
        assert!(
            (at(1, 0) - expected).abs() < 1e-12,
            "{} {expected}",
            at(1, 0)
        );
        // Rows sum to zero: constants are in the kernel.
        let row_sum = |r: usize| (0..4).map(|c| at(r.max(c), r.min(c))).sum::<f64>();
        assert!((0..4).all(|r| row_sum(r).abs() < 1e-12));
        // A fixed vertex has no row or column.
        let fixed = cotangent_lower(&triangles, &gradients, &weighted, |v| {
            (v != 3).then_some(v as usize)
        });
        assert!(fixed.iter().all(|e| e.row != 3 && e.col != 3));
    }

    #[test]
    fn laplace_beltrami_rows_are_the_cotangent_weights_over_the_root_of_the_area() {
        // A unit right triangle and its mirror over the hypotenuse: the
        // hypotenuse 1–2 faces two right angles (cot 0), each leg one 45°
        // angle (cot 1); every vertex's area is a third of what touches it.
        let x = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::new(1.0, 1.0, 0.0)];
        let rows = laplace_beltrami_rows(&x, &[[0, 1, 2], [3, 2, 1]]);
        let at = |v: u32, w: u32| -> f64 {
            rows[&v]
                .iter()
                .filter(|(c, _)| *c == w)
                .map(|(_, x)| x)
                .sum()
        };
        let root_area = (0.5f64 / 3.0).sqrt();
        assert!((at(0, 1) + 0.5 / root_area).abs() < 1e-12);
        assert!((at(0, 0) - 1.0 / root_area).abs() < 1e-12);
        assert!(at(1, 2).abs() < 1e-12);
        // Constants are in the kernel: every row sums to zero.
        for (v, row) in &rows {
            assert!(row.iter().map(|(_, x)| x).sum::<f64>().abs() < 1e-12, "{v}");
        }
        // A sliver: the edge facing its obtuse apex weighs nothing, the
        // edges facing its needle angles are capped.
        let sliver = [DVec3::ZERO, DVec3::X, DVec3::new(0.5, 1e-6, 0.0)];
        let rows = laplace_beltrami_rows(&sliver, &[[0, 1, 2]]);
        let weight = |v: u32, w: u32| -rows[&v].iter().find(|(c, _)| *c == w).map_or(0.0, |e| e.1);
        let root_area = (1e-6f64 / 2.0 / 3.0).sqrt();
        assert!(weight(0, 1).abs() < 1e-12);
        assert!((weight(1, 2) * root_area - 0.5 * MAX_COTANGENT).abs() < 1e-9);
    }

    #[test]
    fn uniform_rows_sum_to_zero_and_their_normal_matrix_is_lower() {
        let ring = BTreeSet::from([1, 2, 5]);
        let row: Vec<(u32, f64)> = uniform_row(0, &ring).collect();
        assert_eq!(row, vec![(0, 3.0), (1, -1.0), (2, -1.0), (5, -1.0)]);
        let rows = [vec![(0, 3.0), (2, -1.0)], vec![(1, 1.0), (2, 2.0)]];
        let entries = normal_lower(rows.iter().map(|r| r.as_slice()));
        assert!(entries.iter().all(|e| e.row >= e.col));
        let at = |r: usize, c: usize| sum_at(&entries, r, c);
        assert_eq!(
            (at(0, 0), at(2, 0), at(2, 2), at(2, 1)),
            (9.0, -3.0, 5.0, 2.0)
        );
    }
}
