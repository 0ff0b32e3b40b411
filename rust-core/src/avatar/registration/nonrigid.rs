//! Non-rigid registration of the mask onto the avatar's face surface, in
//! the spirit of Achenbach et al. 2017 (the paper's \[1\]): a closest-point
//! data term, a smoothness term on the displacement, and a few outer
//! iterations from stiff to supple.
//!
//! With `x⁰` the mask placed by ICP, `d = x − x⁰` its displacement, `c_i`
//! the closest avatar point of `x_i` and `w_i ∈ {0, 1}` the kept pairs
//! ([`super::rigid_icp::trimmed_weights`]), each step minimizes
//!
//! ```text
//! E(d) = Σ_i w_i ‖x⁰_i + d_i − c_i‖² + α Σ_{(i,j) ∈ edges} ‖d_i − d_j‖²,
//! ```
//!
//! i.e. solves `(W + α L) d = W (c − x⁰)` with `L` the mask's graph
//! Laplacian (uniform edge weights): a membrane on the displacement, which
//! keeps the mask's own shape where the avatar offers no good match. Both
//! terms are squared lengths in the avatar's units, so α is dimensionless
//! and means the same on a centimetre and a metre avatar. α runs through
//! [`STIFFNESS`], [`STEPS_PER_STIFFNESS`] closest-point updates each.

use super::rigid_icp::{KEEP_WITHIN, trimmed_weights};
use crate::geometry::closest_point::TriangleGrid;
use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::sparse::{SparseColMat, Triplet};
use faer::{Mat, Side};
use glam::DVec3;

/// The stiffness schedule α of the outer iterations (module docs).
pub const STIFFNESS: [f64; 5] = [100.0, 30.0, 10.0, 3.0, 1.0];

/// Closest-point updates per stiffness.
pub const STEPS_PER_STIFFNESS: usize = 2;

/// The registered mask and how well it fits.
#[derive(Clone, Debug, PartialEq)]
pub struct NonRigidResult {
    /// The mask's vertices on the avatar (avatar units).
    pub positions: Vec<DVec3>,
    /// Each vertex's distance to the avatar surface at the end.
    pub distances: Vec<f64>,
}

/// Deforms `start` (the mask placed by ICP; `triangles` its topology) onto
/// the surface in `target` (module docs). `None` if a system cannot be
/// factored (no kept pair at all).
pub fn register_nonrigid(
    start: &[DVec3],
    triangles: &[[u32; 3]],
    target: &TriangleGrid,
) -> Option<NonRigidResult> {
    let n = start.len();
    let edges = unique_edges(triangles, n);
    let centre = start.iter().sum::<DVec3>() / n.max(1) as f64;
    let radius = (start
        .iter()
        .map(|p| (*p - centre).length_squared())
        .sum::<f64>()
        / n.max(1) as f64)
        .sqrt();
    let floor = KEEP_WITHIN * radius;
    let mut x = start.to_vec();
    for alpha in STIFFNESS {
        for _ in 0..STEPS_PER_STIFFNESS {
            let pairs: Vec<(DVec3, f64)> = x
                .iter()
                .map(|p| {
                    target
                        .closest(*p)
                        .map_or((*p, f64::INFINITY), |c| (c.point, c.distance))
                })
                .collect();
            let w = trimmed_weights(&pairs.iter().map(|p| p.1).collect::<Vec<_>>(), floor);
            let d = solve_step(start, &pairs, &w, &edges, alpha)?;
            for ((xi, si), di) in x.iter_mut().zip(start).zip(d) {
                *xi = *si + di;
            }
        }
    }
    let distances = x
        .iter()
        .map(|p| target.closest(*p).map_or(f64::INFINITY, |c| c.distance))
        .collect();
    Some(NonRigidResult {
        positions: x,
        distances,
    })
}

/// Each undirected edge of `triangles` once, `(i, j)` with `i < j < n`.
fn unique_edges(triangles: &[[u32; 3]], n: usize) -> Vec<(usize, usize)> {
    let mut edges: Vec<(usize, usize)> = triangles
        .iter()
        .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
        .map(|(a, b)| (a.min(b) as usize, a.max(b) as usize))
        .filter(|(a, b)| a != b && *b < n)
        .collect();
    edges.sort_unstable();
    edges.dedup();
    edges
}

/// One solve of `(W + α L) d = W (c − x⁰)`; a tiny multiple of α on the
/// diagonal keeps a component without kept pairs at `d = 0`.
fn solve_step(
    start: &[DVec3],
    pairs: &[(DVec3, f64)],
    w: &[f64],
    edges: &[(usize, usize)],
    alpha: f64,
) -> Option<Vec<DVec3>> {
    let n = start.len();
    let mut entries: Vec<Triplet<usize, usize, f64>> = Vec::with_capacity(n + 3 * edges.len());
    for (i, wi) in w.iter().enumerate() {
        entries.push(Triplet::new(i, i, wi + 1e-9 * alpha));
    }
    for &(i, j) in edges {
        entries.push(Triplet::new(i, i, alpha));
        entries.push(Triplet::new(j, j, alpha));
        entries.push(Triplet::new(j, i, -alpha));
    }
    let matrix = SparseColMat::<usize, f64>::try_new_from_triplets(n, n, &entries).ok()?;
    let symbolic = SymbolicLlt::try_new(matrix.symbolic(), Side::Lower).ok()?;
    let llt = Llt::try_new_with_symbolic(symbolic, matrix.as_ref(), Side::Lower).ok()?;
    let mut rhs = Mat::<f64>::zeros(n, 3);
    for (i, ((c, _), wi)) in pairs.iter().zip(w).enumerate() {
        let r = (*c - start[i]) * *wi;
        for axis in 0..3 {
            rhs[(i, axis)] = r[axis];
        }
    }
    llt.solve_in_place(&mut rhs);
    Some(
        (0..n)
            .map(|i| DVec3::new(rhs[(i, 0)], rhs[(i, 1)], rhs[(i, 2)]))
            .collect(),
    )
}
