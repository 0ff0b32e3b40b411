//! Deformation transfer between two meshes of the same topology, solved in
//! the gradient domain (Botsch, Sumner, Pauly & Gross 2006, *Deformation
//! transfer for detail-preserving surface editing*; equivalent to Sumner &
//! Popović 2004 for meshes of equal connectivity).
//!
//! The paper (§3.2) uses it to carry the generic ARKit template's 52 shapes
//! onto the person's neutral scan `B₀`, giving the *generic blendshapes*
//! `T₁ … T₅₂` that regularize the personalized fit.
//!
//! # Method
//!
//! A source mesh deforms from `S₀` to `Sⱼ`. For every triangle `t`, its
//! deformation gradient `Q_t = [e₁' e₂' ñ'][e₁ e₂ ñ]⁻¹` (see
//! [`crate::geometry::deformation_gradient`]) says how the triangle was stretched,
//! sheared and turned. The target, at rest in `B₀`, should deform so that the
//! Jacobian of its piecewise-linear deformation, `J_t(X') = Σᵢ x'ᵢ ∇φᵢᵀ` (sum
//! over the corners of `t`, `∇φᵢ` the hat gradients of the *target* rest
//! triangle), matches `Q_t` in the area-weighted least-squares sense:
//!
//! ```text
//! E(X') = Σ_t A_t ‖J_t(X') − Q_t‖²_F.
//! ```
//!
//! Setting `∂E/∂x'_k = 0` gives the normal equations `L X' = R` with
//!
//! ```text
//! L_ki = Σ_t A_t ∇φ_k · ∇φ_i        (the cotangent Laplacian)
//! R_k  = Σ_t A_t Q_t ∇φ_k.
//! ```
//!
//! Because the target rest triangle reproduces affine functions,
//! `L B₀ = Σ_t A_t I ∇φ_k`, so the displacement `D = X' − B₀` solves
//! `L D = Σ_t A_t (Q_t − I) ∇φ_k`. Solving for `D` directly keeps a zero
//! deformation exactly zero ([`RestTriangle::displacement_gradient`]). `L`
//! depends only on the target rest mesh: it is factored once (sparse
//! Cholesky), and `m` shapes are one batched solve with `3m` right-hand sides.
//!
//! # Translation
//!
//! Gradients do not see translations: `L` is singular, with the constants on
//! each connected component as its null space. The system is made positive
//! definite by *pinning* one vertex per component (its smallest index): its
//! row and column are removed and its displacement is set to zero. This only
//! picks one solution out of the family `D + c`; the constant `c` is then
//! chosen per component by this rule:
//!
//! * the *still* vertices of a shape are those whose source displacement is at
//!   most [`STILL_FRACTION`] (1%) of the largest in the component,
//!   `‖sⱼᵢ − s₀ᵢ‖ ≤ 0.01 · maxₖ ‖sⱼₖ − s₀ₖ‖`; if there are none (every vertex
//!   moves about equally, e.g. a pure translation), the vertex of least
//!   source motion alone;
//! * the target's still vertices move on average as the source's do, scaled
//!   by the size ratio `σ = √(A_target / A_source)` of the two rest meshes
//!   (total areas): `mean_still(D + c) = σ · mean_still(Sⱼ − S₀)`.
//!
//! Regions that do not move in the source therefore stay put in the target.
//! Matching the source's mean (rather than zero) makes the transfer onto the
//! source itself reproduce the source exactly, and `σ` makes the transfer
//! onto a uniformly scaled copy `s·S₀` give exactly `s` times the
//! displacements. The still region's mean source motion is itself below 1%
//! of the shape's largest motion, so the choice matters only at that level.
//!
//! # Eyes and contacts
//!
//! The virtual eye triangles of [`crate::geometry::mesh_boundary::eye_hole_triangles`]
//! (computed once from the template) are added to both meshes: a source
//! blink collapses them, and their gradients ask the target strip to collapse
//! too. On its own that closes a target eye only roughly: `Q_t` is applied to
//! the target's own triangle, and where the target's lids are shaped or placed
//! differently the collapsed strip's gradients no longer fit together.
//!
//! So contacts are kept explicitly: where an eye closes in the source shape,
//! each of its lid vertices is paired with its partner across the hole
//! (a virtual-triangle edge) and the target is constrained to
//! `x'_a − x'_b = 0`: closed, whatever gap the source leaves. The constrained
//! minimizer reuses the factorization of `L` (one extra solve per contact; the
//! maths is in `deformation_transfer/contacts.rs`).
//!
//! *When an eye closes* is judged by the source's own motion, relative to how
//! open the eye was: the eye closes in a shape when every lid vertex comes
//! within [`CONTACT_FRACTION`] (15%) of the eye's rest opening `O₀` of the
//! other lid, and its contacts are the virtual-triangle edges then at most
//! `0.15 · O₀` long (shortest first, one per lid vertex). A fraction of the
//! opening means the same on a template in metres or centimetres, counts
//! Apple's blinks (lids 4–6% of the opening apart) as closed and a squint
//! (72% of the opening) as open, and keeps the short lid pairs at the
//! corners from counting as closed at rest. How the 15% was placed, and
//! what the plain transfer left open, is in
//! `docs/notes/2026-12-eye-contacts.md`.
//!
//! When the target is the source, or a scaled copy, and the source closes
//! exactly, the unconstrained solution already satisfies the contacts and
//! nothing changes. [`DeformationTransfer::with_contacts`] switches them off
//! for a plain Sumner–Popović transfer. [`DeformationTransfer::contacts`]
//! reports a shape's contacts, and [`DeformationTransfer::close_contacts`]
//! closes them in any displacement field on the target (a fitted
//! blendshape), by the correction of least gradient energy.
//!
//! # Files
//!
//! | paper | what | file |
//! |---|---|---|
//! | Botsch et al. 2006, Eq. `L X' = R` | the factored system, right-hand sides, solves | `mod.rs` |
//! | §3.2 "eyes are completely closed" | lid contacts as constraints on the factored system | `contacts.rs` |
//! | (ours) | the translation gradients do not see, per component | `translation.rs` |

use super::deformation_gradient::{RestTriangle, hat_gradients, triangle_area};
use super::laplacian::cotangent_lower;
use super::sparse_cholesky::{self, FactorError};
use super::topology::{GeometryError, Topology, TopologyError};
use faer::Mat;
use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::Llt;
use glam::{DMat3, DVec3};

mod contacts;
mod translation;

use crate::geometry::connected_components::components;
pub use contacts::Contacts;

/// Fraction of a shape's largest source displacement below which a vertex
/// counts as still when the translation is fixed (see the module docs).
pub const STILL_FRACTION: f64 = 0.01;

/// Fraction of an eye's rest opening within which its lids count as closed
/// in a source shape, making contacts (see the module docs, "Eyes and
/// contacts"): 15%, a factor of three above the gap Apple's template leaves
/// (5%) and below the narrowest eye of a shape that does not close it
/// (eyeSquint's 72% on the simulated template).
pub const CONTACT_FRACTION: f64 = 0.15;

/// Marks a pinned vertex in the reduced system.
const PINNED: u32 = u32::MAX;

/// Why a deformation transfer cannot be set up or carried out.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum TransferError {
    /// The virtual triangles refer to vertices that do not exist.
    #[error("virtual triangles: {0}")]
    Topology(#[from] TopologyError),
    /// A mesh has the wrong vertex count or a NaN or infinite coordinate.
    #[error(transparent)]
    Geometry(#[from] GeometryError),
    /// A rest triangle has (numerically) zero area, so it has no gradients.
    #[error(
        "{mesh}: {} triangle {triangle} (vertices {vertices:?}) has zero area",
        if *is_virtual { "virtual" } else { "mesh" }
    )]
    DegenerateTriangle {
        /// Which mesh, e.g. `"target rest"` or `"source rest"`.
        mesh: &'static str,
        /// Index into [`DeformationTransfer::triangles`]: the topology's
        /// triangles, then the virtual ones.
        triangle: usize,
        /// Its corners.
        vertices: [u32; 3],
        /// Whether it is one of the virtual triangles.
        is_virtual: bool,
    },
    /// Per-triangle gradients given for a shape do not match the triangles
    /// of this transfer, or not one reference field per shape.
    #[error("shape {shape}: {found} {what}, expected {expected}")]
    ShapeMismatch {
        /// Index of the shape in the batch.
        shape: usize,
        /// What was counted (`"gradients"`, `"reference shapes"`).
        what: &'static str,
        /// How many there should be.
        expected: usize,
        /// How many there are.
        found: usize,
    },
    /// The sparse system could not be factored.
    #[error("the transfer's system could not be factored: {0}")]
    Factor(#[from] FactorError),
    /// A dense factorization failed, or a solver thread stopped.
    #[error("factorization failed: {0}")]
    Factorization(String),
}

/// Deformation transfer onto one target rest mesh: the factored gradient
/// system of the target, reusable for any number of source deformations.
#[derive(Clone, Debug)]
pub struct DeformationTransfer {
    triangles: Vec<[u32; 3]>,
    mesh_triangles: usize,
    target_rest: Vec<DVec3>,
    /// Total area of the target rest mesh, virtual triangles included.
    target_area: f64,
    /// `A_t ∇φ_k` for the three corners of every triangle (target rest).
    weighted_gradients: Vec<[DVec3; 3]>,
    /// Connected component of each vertex.
    component: Vec<u32>,
    component_count: usize,
    /// Row of each vertex in the reduced system, or [`PINNED`].
    unknown: Vec<u32>,
    unknown_count: usize,
    /// Edges of virtual triangles that are not mesh edges, sorted, one list
    /// per hole.
    holes: Vec<Vec<[u32; 2]>>,
    /// Whether `transfer_many` imposes the contacts.
    impose_contacts: bool,
    llt: Llt<usize, f64>,
}

/// Checks that `positions` has `n` finite points.
fn check_positions(what: &str, positions: &[DVec3], n: usize) -> Result<(), GeometryError> {
    if positions.len() != n {
        return Err(GeometryError::VertexCount {
            what: what.to_string(),
            expected: n,
            found: positions.len(),
        });
    }
    match positions.iter().position(|p| !p.is_finite()) {
        Some(vertex) => Err(GeometryError::NotFinite {
            what: what.to_string(),
            vertex,
        }),
        None => Ok(()),
    }
}

fn factor_error(e: impl std::fmt::Debug) -> TransferError {
    TransferError::Factorization(format!("{e:?}"))
}

// Indexing: every triangle, virtual ones included, is checked against the
// vertex count `n` in `new()` (through `Topology::new`), and every position
// slice and displacement field is checked to have `n` entries before it is
// indexed by vertex (`new()`, `transfer_many()`,
// `solve_displacement_gradients()`); per-vertex arrays (`unknown`,
// `component`) have `n` entries, per-triangle ones (`weighted_gradients`,
// source rest triangles, gradients) one per triangle, and component ids are
// below `component_count`.
impl DeformationTransfer {
    /// Sets up transfer onto the target rest mesh `target_rest` (`B₀`) with
    /// connectivity `topology` plus `virtual_triangles` (e.g. the eye
    /// triangles of [`crate::geometry::mesh_boundary::eye_hole_triangles`]; may be
    /// empty). Assembles `L = Σ_t A_t G_tᵀ G_t` over all triangles, pins one
    /// vertex per connected component and factors the rest with a sparse
    /// Cholesky factorization (see the module docs). Contacts are on.
    ///
    /// Errors: virtual triangles with bad indices, a wrong vertex count or a
    /// non-finite position, a zero-area triangle (named), or a failed
    /// factorization.
    pub fn new(
        topology: &Topology,
        virtual_triangles: &[[u32; 3]],
        target_rest: &[DVec3],
    ) -> Result<DeformationTransfer, TransferError> {
        let n = topology.vertex_count();
        check_positions("target rest", target_rest, n)?;
        let mesh_triangles = topology.triangles().len();
        let all = topology.triangles().iter().chain(virtual_triangles);
        let triangles = Topology::new(n, all.copied().collect())?
            .triangles()
            .to_vec();

        let mut gradients = Vec::with_capacity(triangles.len());
        let mut weighted_gradients = Vec::with_capacity(triangles.len());
        let mut target_area = 0.0;
        for (t, tri) in triangles.iter().enumerate() {
            let x = tri.map(|v| target_rest[v as usize]);
            let g = hat_gradients(x).ok_or(TransferError::DegenerateTriangle {
                mesh: "target rest",
                triangle: t,
                vertices: *tri,
                is_virtual: t >= mesh_triangles,
            })?;
            let area = triangle_area(x);
            target_area += area;
            gradients.push(g);
            weighted_gradients.push(g.map(|g| area * g));
        }

        let (component, component_count) = components(n, &triangles);
        let mut unknown = vec![PINNED; n];
        let mut pinned = vec![false; component_count];
        let mut unknown_count = 0;
        for v in 0..n {
            let c = component[v] as usize;
            if pinned[c] {
                unknown[v] = unknown_count as u32;
                unknown_count += 1;
            } else {
                pinned[c] = true;
            }
        }

        // Lower triangle of L over the unknowns; duplicates are summed.
        let entries = cotangent_lower(&triangles, &gradients, &weighted_gradients, |v| {
            let u = unknown[v as usize];
            (u != PINNED).then_some(u as usize)
        });
        let llt = sparse_cholesky::factor(unknown_count, &entries)?;

        let holes = contacts::hole_edges(n, &triangles, mesh_triangles);

        Ok(DeformationTransfer {
            triangles,
            mesh_triangles,
            target_rest: target_rest.to_vec(),
            target_area,
            weighted_gradients,
            component,
            component_count,
            unknown,
            unknown_count,
            holes,
            impose_contacts: true,
            llt,
        })
    }

    /// Switches the contact constraints of [`DeformationTransfer::transfer_many`]
    /// on or off (on by default; see the module docs). Off gives the plain
    /// Sumner–Popović transfer.
    pub fn with_contacts(mut self, enabled: bool) -> DeformationTransfer {
        self.impose_contacts = enabled;
        self
    }

    /// Number of vertices of the meshes this transfer works on.
    pub fn vertex_count(&self) -> usize {
        self.target_rest.len()
    }

    /// All triangles used: the topology's, then the virtual ones.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Number of the topology's own triangles; the virtual ones follow them in
    /// [`DeformationTransfer::triangles`].
    pub fn mesh_triangle_count(&self) -> usize {
        self.mesh_triangles
    }

    /// The target rest positions `B₀`.
    pub fn target_rest(&self) -> &[DVec3] {
        &self.target_rest
    }

    /// Transfers one source deformation `source_rest → source_deformed` onto
    /// the target and returns the target displacement `D = X' − B₀`, one
    /// vector per vertex. See [`DeformationTransfer::transfer_many`].
    pub fn transfer(
        &self,
        source_rest: &[DVec3],
        source_deformed: &[DVec3],
    ) -> Result<Vec<DVec3>, TransferError> {
        let mut out = self.transfer_many(source_rest, &[source_deformed])?;
        Ok(out.pop().unwrap_or_default())
    }

    /// Transfers every source deformation `source_rest → source_shapes[j]`
    /// onto the target in one batched solve (`3m` right-hand sides) and
    /// returns the target displacements `Dⱼ = X'ⱼ − B₀`.
    ///
    /// Right-hand side of shape `j` at vertex `k`: `Σ_t A_t (Q_{t,j} − I) ∇φ_k`,
    /// with `Q_{t,j}` from the source and `A_t`, `∇φ_k` from the target rest
    /// triangle. Contacts, then the translation, are fixed as the module docs
    /// describe. The source meshes must have the target's vertex count and
    /// finite positions, and no source rest triangle may be degenerate;
    /// deformed triangles may collapse.
    pub fn transfer_many<S: AsRef<[DVec3]> + Sync>(
        &self,
        source_rest: &[DVec3],
        source_shapes: &[S],
    ) -> Result<Vec<Vec<DVec3>>, TransferError> {
        let n = self.vertex_count();
        check_positions("source rest", source_rest, n)?;
        for (j, shape) in source_shapes.iter().enumerate() {
            check_positions(&format!("source shape {j}"), shape.as_ref(), n)?;
        }
        let mut source_area = 0.0;
        let mut rest = Vec::with_capacity(self.triangles.len());
        for (t, tri) in self.triangles.iter().enumerate() {
            let x = tri.map(|v| source_rest[v as usize]);
            source_area += triangle_area(x);
            rest.push(
                RestTriangle::new(x).ok_or(TransferError::DegenerateTriangle {
                    mesh: "source rest",
                    triangle: t,
                    vertices: *tri,
                    is_virtual: t >= self.mesh_triangles,
                })?,
            );
        }

        let sigma = (self.target_area / source_area).sqrt();
        // The shapes are independent: split them over the machine's cores.
        let threads = std::thread::available_parallelism()
            .map_or(1, |n| n.get())
            .clamp(1, 8)
            .min(source_shapes.len().max(1));
        let chunk = source_shapes.len().div_ceil(threads).max(1);
        let parts: Vec<Result<Vec<Vec<DVec3>>, TransferError>> = std::thread::scope(|scope| {
            let handles: Vec<_> = source_shapes
                .chunks(chunk)
                .map(|shapes| {
                    let rest = &rest;
                    scope.spawn(move || self.transfer_chunk(rest, source_rest, shapes, sigma))
                })
                .collect();
            handles
                .into_iter()
                .map(|h| {
                    h.join().unwrap_or_else(|_| {
                        Err(TransferError::Factorization(
                            "a solver thread panicked".into(),
                        ))
                    })
                })
                .collect()
        });
        let mut deltas = Vec::with_capacity(source_shapes.len());
        for part in parts {
            deltas.extend(part?);
        }
        Ok(deltas)
    }

    /// [`DeformationTransfer::transfer_many`] for one batch of shapes, with
    /// the source rest triangles and the size ratio `sigma` already computed.
    fn transfer_chunk<S: AsRef<[DVec3]>>(
        &self,
        rest: &[RestTriangle],
        source_rest: &[DVec3],
        source_shapes: &[S],
        sigma: f64,
    ) -> Result<Vec<Vec<DVec3>>, TransferError> {
        let n = self.vertex_count();
        let mut rhs = Mat::<f64>::zeros(self.unknown_count, 3 * source_shapes.len());
        for (j, shape) in source_shapes.iter().enumerate() {
            let shape = shape.as_ref();
            for (t, (tri, rest)) in self.triangles.iter().zip(rest).enumerate() {
                let dq = rest.displacement_gradient(tri.map(|v| shape[v as usize]));
                self.add_to_rhs(&mut rhs, j, t, dq);
            }
        }
        let mut deltas = self.solve(rhs);
        let mut motion = vec![DVec3::ZERO; n];
        for (delta, shape) in deltas.iter_mut().zip(source_shapes) {
            let shape = shape.as_ref();
            if self.impose_contacts {
                let contacts = self.find_contacts(source_rest, shape);
                self.enforce_contacts(delta, &contacts)?;
            }
            for ((m, s), s0) in motion.iter_mut().zip(shape).zip(source_rest) {
                *m = *s - *s0;
            }
            self.fix_translation(delta, &motion, sigma);
        }
        Ok(deltas)
    }

    /// Displacements `D_j` whose per-triangle displacement gradients best
    /// match `gradients[j][t]` (one 3×3 matrix `Q_t − I` per triangle of
    /// [`DeformationTransfer::triangles`], relative to the *target* rest
    /// mesh): solves `L D_j = Σ_t A_t G_{t,j} ∇φ_k` with the factored `L`.
    ///
    /// No contacts are imposed. The translation follows the rule of the
    /// module docs with `reference[j]`, a displacement field on the target,
    /// in place of the source motion and with `σ = 1`: the vertices still in
    /// `reference[j]` keep its mean motion there.
    ///
    /// Errors, naming the shape: not one reference field per gradient
    /// list, a list without one matrix per triangle, a field without one
    /// vector per vertex.
    pub fn solve_displacement_gradients(
        &self,
        gradients: &[Vec<DMat3>],
        reference: &[Vec<DVec3>],
    ) -> Result<Vec<Vec<DVec3>>, TransferError> {
        let mismatch = |shape, what, expected, found| TransferError::ShapeMismatch {
            shape,
            what,
            expected,
            found,
        };
        if gradients.len() != reference.len() {
            let shape = gradients.len().min(reference.len());
            return Err(mismatch(
                shape,
                "reference shapes",
                gradients.len(),
                reference.len(),
            ));
        }
        for (j, (shape, field)) in gradients.iter().zip(reference).enumerate() {
            if shape.len() != self.triangles.len() {
                return Err(mismatch(j, "gradients", self.triangles.len(), shape.len()));
            }
            check_positions(&format!("reference shape {j}"), field, self.vertex_count())?;
        }
        let mut rhs = Mat::<f64>::zeros(self.unknown_count, 3 * gradients.len());
        for (j, shape) in gradients.iter().enumerate() {
            for (t, g) in shape.iter().enumerate() {
                self.add_to_rhs(&mut rhs, j, t, *g);
            }
        }
        let mut deltas = self.solve(rhs);
        for (delta, reference) in deltas.iter_mut().zip(reference) {
            self.fix_translation(delta, reference, 1.0);
        }
        Ok(deltas)
    }

    /// Adds triangle `t`'s `A_t G ∇φ_k` to the rows of its corners in the
    /// three columns of shape `j`.
    fn add_to_rhs(&self, rhs: &mut Mat<f64>, j: usize, t: usize, g: DMat3) {
        for (&v, wg) in self.triangles[t].iter().zip(&self.weighted_gradients[t]) {
            let row = self.unknown[v as usize];
            if row != PINNED {
                for (axis, value) in (g * *wg).to_array().into_iter().enumerate() {
                    rhs[(row as usize, 3 * j + axis)] += value;
                }
            }
        }
    }

    /// Solves `L D = rhs` and unpacks each shape's three columns into one
    /// displacement per vertex (pinned vertices zero).
    fn solve(&self, mut rhs: Mat<f64>) -> Vec<Vec<DVec3>> {
        self.llt.solve_in_place(&mut rhs);
        let at = |v: usize, j: usize| match self.unknown[v] {
            PINNED => DVec3::ZERO,
            r => {
                let r = r as usize;
                DVec3::new(rhs[(r, 3 * j)], rhs[(r, 3 * j + 1)], rhs[(r, 3 * j + 2)])
            }
        };
        (0..rhs.ncols() / 3)
            .map(|j| (0..self.vertex_count()).map(|v| at(v, j)).collect())
            .collect()
    }

    /// Row of vertex `v` in the reduced system, `None` if it is pinned.
    fn row(&self, v: u32) -> Option<usize> {
        match self.unknown[v as usize] {
            PINNED => None,
            r => Some(r as usize),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn corner(v: u32) -> DVec3 {
        DVec3::new(
            f64::from(v * 7 % 5),
            f64::from(v * 3 % 4),
            0.3 * f64::from(v),
        ) * 0.01
    }

    #[test]
    fn hostile_meshes_and_shapes_are_errors_not_panics() {
        // Two triangles and an isolated vertex: two components and a lone pin.
        let topology = Topology::new(7, vec![[0, 1, 2], [3, 4, 5]]).unwrap();
        let rest: Vec<DVec3> = (0..7).map(corner).collect();
        assert!(matches!(
            DeformationTransfer::new(&topology, &[[0, 1, 7]], &rest),
            Err(TransferError::Topology(_))
        ));
        assert!(matches!(
            DeformationTransfer::new(&topology, &[], &rest[..6]),
            Err(TransferError::Geometry(_))
        ));
        let transfer = DeformationTransfer::new(&topology, &[[0, 2, 4]], &rest).unwrap();
        let moved: Vec<DVec3> = rest.iter().map(|p| *p * 1.1).collect();
        let out = transfer
            .transfer_many(&rest, &[&moved[..], &rest[..]])
            .unwrap();
        assert_eq!(out.len(), 2);
        assert!(out.iter().flatten().all(|d| d.is_finite()));
        assert!(transfer.transfer_many(&rest, &[&moved[..6]]).is_err());
        assert!(transfer.transfer_many(&rest[..6], &[&moved[..]]).is_err());
        let mut nan = moved.clone();
        nan[6].x = f64::NAN;
        assert!(transfer.transfer_many(&rest, &[&nan[..]]).is_err());
        assert!(
            transfer
                .transfer_many(&rest, &[] as &[Vec<DVec3>])
                .unwrap()
                .is_empty()
        );
        // A source whose rest triangles are points.
        let flat = vec![DVec3::ZERO; 7];
        assert!(matches!(
            transfer.transfer_many(&flat, &[&moved[..]]),
            Err(TransferError::DegenerateTriangle { .. })
        ));
        // Coordinates far beyond any face: an error or a result, never a panic.
        let huge: Vec<DVec3> = rest.iter().map(|p| *p * 1e300).collect();
        let _ = DeformationTransfer::new(&topology, &[], &huge);
        let _ = transfer.transfer_many(&huge, &[&rest[..]]);
        // Gradients that do not match the triangles or the reference fields.
        let gradients = vec![vec![DMat3::ZERO; 3]];
        let reference = vec![vec![DVec3::ZERO; 7]];
        assert!(
            transfer
                .solve_displacement_gradients(&gradients, &reference)
                .is_ok()
        );
        for (g, r) in [
            (vec![vec![DMat3::ZERO; 2]], reference.clone()),
            (gradients.clone(), vec![]),
            (gradients.clone(), vec![vec![DVec3::ZERO; 6]]),
        ] {
            assert!(transfer.solve_displacement_gradients(&g, &r).is_err());
        }
    }
}
