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
//! - **Uniform** (graph): `(L u)_v = deg(v) u_v − Σ_{w ~ v} u_w`, each
//!   vertex against its one-ring ([`uniform_row`]); the avatar stage's
//!   bi-Laplacian solves minimize `Σ_r ‖(L u)_r‖²`, whose matrix
//!   `Σ_r a_r a_rᵀ` over the rows `a_r` is [`normal_lower`].
//!
//! Each builder gives the lower triangle (row ≥ column), duplicates to be
//! summed, as [`super::sparse_cholesky::factor`] takes it.

use faer::sparse::Triplet;
use glam::DVec3;
use std::collections::BTreeSet;

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
