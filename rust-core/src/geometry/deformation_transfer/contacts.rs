//! Contacts: lid pairs that close in a source shape are closed in the target
//! (see the parent module's docs, "Eyes and contacts").
//!
//! A *hole edge* is an edge of a virtual triangle that is not an edge of the
//! mesh: it spans a hole, from one lid to the other. The hole edges of one
//! eye form one connected chain (each triangle of the zipped strip shares a
//! hole edge with the next). For an eye, with `s` the positions of a source
//! mesh,
//!
//! ```text
//! g(v) = min over hole edges (v, w) of ‖s_v − s_w‖    how far lid vertex v is from the other lid
//! O    = max_v g(v)                                    how far open the eye is
//! ```
//!
//! measured in the source rest (`O₀`) and in the source shape (`Oⱼ`). The
//! eye *closes* in shape `j` when `Oⱼ ≤ f · O₀`, `f` = [`CONTACT_FRACTION`]:
//! every lid vertex comes within `f` of the eye's rest opening of the other
//! lid. Its *contacts* are then the hole edges `(a, b)` at most `f · O₀` long
//! in the shape, shortest first, each lid vertex in at most one: the lids
//! close pair by pair, and a short diagonal between a closed pair's
//! neighbours cannot merge two vertices of one lid. (Where the lids have
//! different vertex counts, a vertex left without a partner follows the
//! virtual triangles; and a closed eye is recognized only if every lid
//! vertex has a partner within `f · O₀`, so the lid spacing must stay under
//! twice that, 3 mm for a 10 mm eye. The simulated mask pairs its lids one to
//! one.) Each contact constrains the target to close, whatever gap the
//! source leaves:
//!
//! ```text
//! x'_a − x'_b = 0.
//! ```
//!
//! Writing the contacts as `C D = h` (one row `e_a − e_b` per contact, the
//! same for each axis; `h = −C B₀`), the minimizer of the transfer energy
//! `½ DᵀLD − DᵀR` under them follows from the unconstrained solution
//! `D₀ = L⁻¹R` and Lagrange multipliers `λ`:
//!
//! ```text
//! D = D₀ − Y λ,   (C Y) λ = C D₀ − h = C (B₀ + D₀),   Y = L⁻¹ Cᵀ,
//! ```
//!
//! which reuses the factorization of `L` (one extra solve per contact) and a
//! small dense Cholesky factorization of `C Y`. The rows of a matching have
//! disjoint supports, so `C` has full rank and `C Y` is positive definite.
//! `Y λ` is also the correction of least `Σ_t A_t ‖J_t(Y λ)‖²` that closes
//! the contacts, which is how [`DeformationTransfer::close_contacts`] closes
//! a field that was not transferred (a fitted blendshape).
//!
//! Indexing: as in the parent module, every vertex index is checked against
//! the vertex count in `DeformationTransfer::new`, and the meshes indexed
//! have that many vertices (contacts made for another vertex count are
//! refused); contact rows are below the number of contacts.

use super::{CONTACT_FRACTION, DeformationTransfer, TransferError, check_positions, factor_error};
use crate::geometry::connected_components::components;
use crate::geometry::topology::GeometryError;
use faer::linalg::solvers::Solve;
use faer::{Mat, Side};
use glam::DVec3;
use std::collections::{BTreeMap, BTreeSet};

/// The lid pairs a source shape closes (module docs): the contacts imposed
/// on its transfer, and on the fitted blendshapes made from it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Contacts {
    pairs: Vec<[u32; 2]>,
    vertex_count: usize,
}

impl Contacts {
    /// The closed pairs `[a, b]`, `a < b`, one lid vertex and its partner on
    /// the other lid; no vertex is in two pairs.
    pub fn pairs(&self) -> &[[u32; 2]] {
        &self.pairs
    }

    /// Whether the shape closes no eye.
    pub fn is_empty(&self) -> bool {
        self.pairs.is_empty()
    }

    /// Vertex count of the meshes the pairs index.
    pub fn vertex_count(&self) -> usize {
        self.vertex_count
    }
}

/// Edges of the virtual triangles `triangles[mesh_triangles..]` that are not
/// edges of the mesh triangles before them, each as `[smaller, larger]`,
/// sorted, grouped by hole (connected chains of them; `n` vertices), holes
/// in order of their smallest vertex.
pub(super) fn hole_edges(
    n: usize,
    triangles: &[[u32; 3]],
    mesh_triangles: usize,
) -> Vec<Vec<[u32; 2]>> {
    let edge = |a: u32, b: u32| [a.min(b), a.max(b)];
    let edges_of = |tris: &[[u32; 3]]| -> BTreeSet<[u32; 2]> {
        tris.iter()
            .flat_map(|t| [edge(t[0], t[1]), edge(t[1], t[2]), edge(t[2], t[0])])
            .collect()
    };
    let mesh_edges = edges_of(&triangles[..mesh_triangles]);
    let edges: Vec<[u32; 2]> = edges_of(&triangles[mesh_triangles..])
        .difference(&mesh_edges)
        .copied()
        .collect();
    // An edge is a degenerate triangle for the component search.
    let as_triangles: Vec<[u32; 3]> = edges.iter().map(|&[a, b]| [a, b, b]).collect();
    let (component, _) = components(n, &as_triangles);
    let mut holes: BTreeMap<u32, Vec<[u32; 2]>> = BTreeMap::new();
    for e in edges {
        holes.entry(component[e[0] as usize]).or_default().push(e);
    }
    holes.into_values().collect()
}

/// How far open a hole is in `positions`: the largest distance from a lid
/// vertex to its nearest partner across the hole (module docs, `O`).
fn opening(hole: &[[u32; 2]], positions: &[DVec3]) -> f64 {
    let mut nearest: BTreeMap<u32, f64> = BTreeMap::new();
    for &[a, b] in hole {
        let gap = positions[a as usize].distance(positions[b as usize]);
        for v in [a, b] {
            let g = nearest.entry(v).or_insert(f64::INFINITY);
            *g = g.min(gap);
        }
    }
    nearest.into_values().fold(0.0, f64::max)
}

impl DeformationTransfer {
    /// The contacts of the source deformation `source_rest → source_shape`
    /// (module docs): for every eye that closes in it, its lid pairs. These
    /// are what [`DeformationTransfer::transfer_many`] imposes. The meshes
    /// must have this transfer's vertex count and finite positions.
    pub fn contacts(
        &self,
        source_rest: &[DVec3],
        source_shape: &[DVec3],
    ) -> Result<Contacts, TransferError> {
        let n = self.vertex_count();
        check_positions("source rest", source_rest, n)?;
        check_positions("source shape", source_shape, n)?;
        Ok(self.find_contacts(source_rest, source_shape))
    }

    /// [`DeformationTransfer::contacts`] of checked meshes.
    pub(super) fn find_contacts(&self, rest: &[DVec3], shape: &[DVec3]) -> Contacts {
        let mut pairs = Vec::new();
        for hole in &self.holes {
            let reach = CONTACT_FRACTION * opening(hole, rest);
            if opening(hole, shape) > reach {
                continue;
            }
            let mut closed: Vec<(f64, [u32; 2])> = hole
                .iter()
                .map(|&[a, b]| (shape[a as usize].distance(shape[b as usize]), [a, b]))
                .filter(|(gap, _)| *gap <= reach)
                .collect();
            closed.sort_by(|x, y| x.0.total_cmp(&y.0));
            let mut paired = BTreeSet::new();
            for (_, [a, b]) in closed {
                if !paired.contains(&a) && !paired.contains(&b) {
                    paired.extend([a, b]);
                    pairs.push([a, b]);
                }
            }
        }
        Contacts {
            pairs,
            vertex_count: self.vertex_count(),
        }
    }

    /// Closes the lid pairs `contacts` in `delta`, a displacement field on
    /// the target `B₀` (a fitted blendshape): adds the correction of least
    /// `Σ_t A_t ‖J_t‖²` that makes `x'_a = x'_b` for every pair (module
    /// docs), then fixes the translation as the parent module's docs
    /// describe, with `delta` as it was for the reference motion and `σ = 1`
    /// (the vertices it keeps still keep their mean motion). `delta` must have
    /// one finite vector per vertex, and `contacts` be made for this vertex
    /// count.
    pub fn close_contacts(
        &self,
        delta: &mut [DVec3],
        contacts: &Contacts,
    ) -> Result<(), TransferError> {
        let n = self.vertex_count();
        check_positions("displacements to close", delta, n)?;
        if contacts.vertex_count != n {
            return Err(GeometryError::VertexCount {
                what: "contacts".to_string(),
                expected: n,
                found: contacts.vertex_count,
            }
            .into());
        }
        if contacts.is_empty() {
            return Ok(());
        }
        let reference = delta.to_vec();
        self.enforce_contacts(delta, contacts)?;
        self.fix_translation(delta, &reference, 1.0);
        Ok(())
    }

    /// Imposes `contacts` on `delta` (module docs): `x'_a − x'_b = 0` for
    /// every pair.
    pub(super) fn enforce_contacts(
        &self,
        delta: &mut [DVec3],
        contacts: &Contacts,
    ) -> Result<(), TransferError> {
        let pairs = contacts.pairs();
        if pairs.is_empty() {
            return Ok(());
        }
        // Y = L⁻¹ Cᵀ, one column per contact; row c of C is e_a − e_b.
        let c = pairs.len();
        let mut y = Mat::<f64>::zeros(self.unknown_count, c);
        for (k, &[a, b]) in pairs.iter().enumerate() {
            for (v, sign) in [(a, 1.0), (b, -1.0)] {
                if let Some(r) = self.row(v) {
                    y[(r, k)] = sign;
                }
            }
        }
        self.llt.solve_in_place(&mut y);
        let y_at = |v: u32, k: usize| self.row(v).map_or(0.0, |r| y[(r, k)]);
        // C Y (SPD: a matching's rows are independent) and the residual
        // C (B₀ + D₀), the gaps left open.
        let cy = Mat::<f64>::from_fn(c, c, |i, k| y_at(pairs[i][0], k) - y_at(pairs[i][1], k));
        let gap = |[a, b]: [u32; 2]| {
            let (a, b) = (a as usize, b as usize);
            self.target_rest[a] + delta[a] - self.target_rest[b] - delta[b]
        };
        let mut lambda = Mat::<f64>::from_fn(c, 3, |i, axis| gap(pairs[i])[axis]);
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
