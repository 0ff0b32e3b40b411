//! Contacts: hole edges that close in a source shape stay closed in the
//! target (see the parent module's docs, "Eyes and contacts").
//!
//! A *hole edge* is an edge of a virtual triangle that is not an edge of the
//! mesh: it spans a hole, from one lid to the other. If it shrinks in the
//! source shape to at most [`CONTACT_FRACTION`] of its rest length, it is a
//! *contact*, and the target solution is constrained to keep the source's gap,
//! scaled by the size ratio `σ`:
//!
//! ```text
//! x'_a − x'_b = σ (s'_a − s'_b)      (≈ 0 for a closed eye).
//! ```
//!
//! Writing the contacts as `C D = h` (one row `e_a − e_b` per contact, the
//! same for each axis), the minimizer of the transfer energy `½ DᵀLD − DᵀR`
//! under them follows from the unconstrained solution `D₀ = L⁻¹R` and
//! Lagrange multipliers `λ`:
//!
//! ```text
//! D = D₀ − Y λ,   (C Y) λ = C D₀ − h,   Y = L⁻¹ Cᵀ,
//! ```
//!
//! which reuses the factorization of `L` (one extra solve per contact) and a
//! small dense Cholesky factorization of `C Y`. Contacts that close a cycle
//! would make `C` rank-deficient, so only a spanning forest of them is kept;
//! the others then hold too, up to the source's own (tiny) gaps.
//!
//! Indexing: as in the parent module, every vertex index is checked against
//! the vertex count in `DeformationTransfer::new`, and the meshes indexed
//! have that many vertices; contact rows are below the number of contacts.

use super::{CONTACT_FRACTION, DeformationTransfer, TransferError, factor_error};
use faer::linalg::solvers::Solve;
use faer::{Mat, Side};
use glam::DVec3;
use std::collections::{BTreeSet, HashMap};

/// Edges of the virtual triangles `triangles[mesh_triangles..]` that are not
/// edges of the mesh triangles before them, each as `[smaller, larger]`,
/// sorted.
pub(super) fn hole_edges(triangles: &[[u32; 3]], mesh_triangles: usize) -> Vec<[u32; 2]> {
    let edge = |a: u32, b: u32| [a.min(b), a.max(b)];
    let edges_of = |tris: &[[u32; 3]]| -> BTreeSet<[u32; 2]> {
        tris.iter()
            .flat_map(|t| [edge(t[0], t[1]), edge(t[1], t[2]), edge(t[2], t[0])])
            .collect()
    };
    let mesh_edges = edges_of(&triangles[..mesh_triangles]);
    edges_of(&triangles[mesh_triangles..])
        .difference(&mesh_edges)
        .copied()
        .collect()
}

impl DeformationTransfer {
    /// Imposes the source's contacts on `delta` (module docs): for every hole
    /// edge `(a, b)` closed in `shape`, `x'_a − x'_b = σ (s'_a − s'_b)`.
    pub(super) fn enforce_contacts(
        &self,
        delta: &mut [DVec3],
        rest: &[DVec3],
        shape: &[DVec3],
        sigma: f64,
    ) -> Result<(), TransferError> {
        // Closed hole edges, reduced to a spanning forest.
        fn find(parent: &HashMap<u32, u32>, mut v: u32) -> u32 {
            while let Some(&p) = parent.get(&v) {
                v = p;
            }
            v
        }
        let mut parent: HashMap<u32, u32> = HashMap::new();
        let mut contacts = Vec::new();
        for &[a, b] in &self.hole_edges {
            let (i, j) = (a as usize, b as usize);
            if shape[i].distance(shape[j]) > CONTACT_FRACTION * rest[i].distance(rest[j]) {
                continue;
            }
            let (ra, rb) = (find(&parent, a), find(&parent, b));
            if ra != rb {
                parent.insert(ra.max(rb), ra.min(rb));
                // Required change of x'_a − x'_b from B₀ + delta.
                let gap = sigma * (shape[i] - shape[j]);
                let now = self.target_rest[i] + delta[i] - self.target_rest[j] - delta[j];
                contacts.push((a, b, now - gap));
            }
        }
        if contacts.is_empty() {
            return Ok(());
        }

        // Y = L⁻¹ Cᵀ, one column per contact; row c of C is e_a − e_b.
        let c = contacts.len();
        let mut y = Mat::<f64>::zeros(self.unknown_count, c);
        for (k, &(a, b, _)) in contacts.iter().enumerate() {
            for (v, sign) in [(a, 1.0), (b, -1.0)] {
                if let Some(r) = self.row(v) {
                    y[(r, k)] = sign;
                }
            }
        }
        self.llt.solve_in_place(&mut y);
        let y_at = |v: u32, k: usize| self.row(v).map_or(0.0, |r| y[(r, k)]);
        // C Y (SPD, contacts independent) and the residual C D₀ − h.
        let cy = Mat::<f64>::from_fn(c, c, |i, k| y_at(contacts[i].0, k) - y_at(contacts[i].1, k));
        let mut lambda = Mat::<f64>::from_fn(c, 3, |i, axis| contacts[i].2[axis]);
        cy.llt(Side::Lower)
            .map_err(factor_error)?
            .solve_in_place(&mut lambda);
        for (v, d) in delta.iter_mut().enumerate() {
            if let Some(r) = self.row(v as u32) {
                for k in 0..c {
                    let l = DVec3::new(lambda[(k, 0)], lambda[(k, 1)], lambda[(k, 2)]);
                    *d -= y[(r, k)] * l;
                }
            }
        }
        Ok(())
    }
}
