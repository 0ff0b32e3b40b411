//! Step 2 of the seamless partial deformation transfer (§3.3, Fig. 3): the
//! region next to the face (under the chin, the neck, around the ears)
//! deformed from the automatic retargeting `A_j`, with the face fixed.
//!
//! The adjacent region `N` is every vertex of the face's parts within a
//! blend margin of the face along the surface
//! ([`super::BLEND_MARGIN_MM`]) that is not a face vertex. With `D_F` the face step's
//! displacement, the result is `D = A_j + C`: `A_j` with a correction `C`
//! that is `D_F − A_j` on the face, zero beyond `N`, and as smooth as can
//! be in between. Smooth means bi-Laplacian: `C` minimizes `Σ_r ‖(L C)_r‖²`
//! over the rows `r` of `N` and of the vertices next to it on both sides,
//! the face's and those beyond the margin (`L` the uniform graph Laplacian
//! of the parts' triangles). A bi-Laplacian system needs two rings of
//! boundary values for its solution to join its surroundings with a
//! continuous slope (`Δᵏ` with `k` rings gives `C^{k−1}`: Botsch & Sorkine
//! 2008, "On linear variational surface deformation methods"): the face's
//! ring makes `C` leave the face with the face's own slope, not only its
//! position, and the ring beyond makes it reach zero at the margin with
//! zero slope. Without the outer ring `C` ran down to zero at a slant and
//! stopped there: on ICT-FaceKit, a person's jawOpen folded the skin under
//! the chin by 39° along the margin. With `R` those rows and `F` the face,
//!
//! ```text
//! (L_RNᵀ L_RN) C_N = − L_RNᵀ L_RF C_F.
//! ```
//!
//! The matrix depends only on the avatar: factored once, every shape is a
//! solve. Vertices outside the face and `N` take `A_j` exactly; a vertex
//! of `N` that a particular `A_j` does not move may take a small part of
//! `C`. `N` stops at the margin, not where `A_j` stops moving, because the
//! bi-Laplacian costs nothing for a `C` that runs on linearly: where `N`
//! reached an open edge of the mesh (a neck's cut), `C` ran on to it
//! unchecked, and ICT-FaceKit's neck moved 16 mm in `jawOpen`.

use super::lid_contacts::{LidClosingError, LidContact, least_energy_closing};
use crate::geometry::edge_distance::edge_distances;
use crate::geometry::laplacian::{normal_lower, uniform_row};
use crate::geometry::one_ring::one_rings;
use crate::geometry::sparse_cholesky::{self, FactorError};
use faer::Mat;
use faer::linalg::solvers::Solve;
use faer::sparse::Triplet;
use faer::sparse::linalg::solvers::Llt;
use glam::DVec3;
use std::collections::{BTreeSet, HashMap};

/// One row of `L` restricted: its entries on `N` (local indices) and on the
/// face (avatar indices).
struct Row {
    on_region: Vec<(usize, f64)>,
    on_face: Vec<(u32, f64)>,
}

/// The adjacent region of an avatar, its system factored.
pub struct AdjacentStep {
    /// Avatar vertices of `N`, increasing.
    region: Vec<u32>,
    /// Avatar vertex → its index in `region`.
    local: HashMap<u32, usize>,
    rows: Vec<Row>,
    llt: Option<Llt<usize, f64>>,
}

impl AdjacentStep {
    /// Prepares `N` (module docs) from the parts' `triangles` (avatar
    /// indices), the face vertices `face` and `near` (whether a vertex is
    /// within the blend margin of the face), all indexed by avatar vertex,
    /// and factors its system.
    pub fn new(
        triangles: &[[u32; 3]],
        face: &[bool],
        near: &[bool],
    ) -> Result<AdjacentStep, FactorError> {
        let n = face.len().min(near.len());
        let neighbours = one_rings(n, triangles);
        let region: Vec<u32> = (0..n as u32)
            .filter(|&v| near[v as usize] && !face[v as usize] && neighbours.contains_key(&v))
            .collect();
        let local: HashMap<u32, usize> = region.iter().enumerate().map(|(i, v)| (*v, i)).collect();
        // The rows: every vertex of N, and every vertex next to N on
        // either side of it, in the face or beyond the margin.
        let mut row_vertices: BTreeSet<u32> = region.iter().copied().collect();
        for v in &region {
            row_vertices.extend(neighbours[v].iter().copied());
        }
        let rows: Vec<Row> = row_vertices
            .iter()
            .map(|&r| {
                let mut row = Row {
                    on_region: Vec::new(),
                    on_face: Vec::new(),
                };
                for (v, value) in uniform_row(r, &neighbours[&r]) {
                    if let Some(&i) = local.get(&v) {
                        row.on_region.push((i, value));
                    } else if face[v as usize] {
                        row.on_face.push((v, value));
                    }
                }
                row
            })
            .collect();
        let m = region.len();
        let mut entries = normal_lower(rows.iter().map(|row| row.on_region.as_slice()));
        // A tiny diagonal keeps a piece of N that touches nothing outside
        // itself definite (it then stays at C = 0).
        for i in 0..m {
            entries.push(Triplet::new(i, i, 1e-9));
        }
        let llt = match m {
            0 => None,
            _ => Some(sparse_cholesky::factor(m, &entries)?),
        };
        Ok(AdjacentStep {
            region,
            local,
            rows,
            llt,
        })
    }

    /// The avatar vertices of `N`.
    pub fn region(&self) -> &[u32] {
        &self.region
    }

    /// Completes each shape's displacement `full[j]` (all avatar vertices:
    /// `A_j` everywhere but the face, the face step's result there) on `N`:
    /// `A_j + C` (module docs). `retargeted[j]` is `A_j`.
    pub fn complete(&self, full: &mut [Vec<DVec3>], retargeted: &[Vec<DVec3>]) {
        let Some(llt) = &self.llt else {
            return;
        };
        let m = self.region.len();
        let shapes = full.len().min(retargeted.len());
        let mut rhs = Mat::<f64>::zeros(m, 3 * shapes);
        for j in 0..shapes {
            for row in &self.rows {
                // (L_RF C_F)_r
                let mut known = DVec3::ZERO;
                for &(u, x) in &row.on_face {
                    let u = u as usize;
                    if let (Some(d), Some(a)) = (full[j].get(u), retargeted[j].get(u)) {
                        known += (*d - *a) * x;
                    }
                }
                for &(i, x) in &row.on_region {
                    for axis in 0..3 {
                        rhs[(i, 3 * j + axis)] -= x * known[axis];
                    }
                }
            }
        }
        llt.solve_in_place(&mut rhs);
        for j in 0..shapes {
            for (i, &v) in self.region.iter().enumerate() {
                let v = v as usize;
                if let (Some(d), Some(a)) = (full[j].get_mut(v), retargeted[j].get(v)) {
                    *d = *a + DVec3::new(rhs[(i, 3 * j)], rhs[(i, 3 * j + 1)], rhs[(i, 3 * j + 2)]);
                }
            }
        }
    }

    /// Closes the lid `contacts` in one completed shape `d` (displacements
    /// of every avatar vertex, `rest` the avatar at rest): the change of the
    /// correction `C` on `N` of least bending `ΔCᵀ K ΔC`, `K = L_RNᵀ L_RN`
    /// the matrix above, that meets them
    /// ([`super::lid_contacts::least_energy_closing`]; a contact moves
    /// whichever of its vertices are in `N`). Nothing is changed on an
    /// error.
    pub fn close(
        &self,
        rest: &[DVec3],
        d: &mut [DVec3],
        contacts: &[LidContact],
    ) -> Result<(), LidClosingError> {
        let Some(llt) = &self.llt else {
            return Ok(());
        };
        let change = least_energy_closing(
            llt,
            self.region.len(),
            |v| self.local.get(&v).copied(),
            |v| Some(*rest.get(v as usize)? + *d.get(v as usize)?),
            contacts,
        )?;
        for (i, delta) in change {
            if let Some(x) = self.region.get(i).and_then(|&v| d.get_mut(v as usize)) {
                *x += delta;
            }
        }
        Ok(())
    }
}

/// The vertices within `reach` of a `face` vertex along the edges of
/// `triangles` (shortest paths, edge lengths from `positions`), the face's
/// own included.
pub fn within(positions: &[DVec3], triangles: &[[u32; 3]], face: &[bool], reach: f64) -> Vec<bool> {
    let distance = edge_distances(positions, triangles, face, reach);
    let mut out: Vec<bool> = distance.iter().map(|d| *d <= reach).collect();
    out.resize(face.len(), false);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat strip of `columns × rows` unit squares' corners, two
    /// triangles per square ([`crate::test_support::flat_sheet`]).
    fn strip(columns: usize, rows: usize) -> Vec<[u32; 3]> {
        crate::test_support::flat_sheet(columns, rows).1
    }

    /// The face (columns 0–5) moves by one; `A_j` is zero everywhere; `N`
    /// is columns 6–25. The correction falls from the face's one to zero,
    /// and reaches zero at the margin with zero slope: on the middle row,
    /// the last column of `N` keeps 0.43 of the fall from the column before
    /// it (a parabola touching zero keeps 1/3; a slant keeps all of it).
    /// Without the ring beyond the margin among the rows it kept 0.90.
    #[test]
    fn the_correction_leaves_the_face_with_its_slope_and_stops_without_a_kink() {
        let (columns, rows) = (40, 9);
        let n = columns * rows;
        let face: Vec<bool> = (0..n).map(|v| v % columns <= 5).collect();
        let near: Vec<bool> = (0..n).map(|v| v % columns <= 25).collect();
        let step = AdjacentStep::new(&strip(columns, rows), &face, &near).unwrap();
        assert_eq!(step.region().len(), 20 * rows);
        let one = DVec3::new(0.0, 0.0, 1.0);
        let mut full = vec![
            (0..n)
                .map(|v| if face[v] { one } else { DVec3::ZERO })
                .collect(),
        ];
        step.complete(&mut full, &[vec![DVec3::ZERO; n]]);
        let middle = rows / 2 * columns;
        let c: Vec<f64> = (0..columns).map(|i| full[0][middle + i].z).collect();
        assert!(
            c[5..27].windows(2).all(|w| w[1] <= w[0] + 1e-9),
            "falls from the face to the margin: {c:?}"
        );
        assert!(c[6] > 0.9, "leaves the face without a step: {c:?}");
        assert!(
            c[25] < 0.6 * (c[24] - c[25]),
            "stops with zero slope: {c:?}"
        );
        assert_eq!(c[26], 0.0);
    }
}
