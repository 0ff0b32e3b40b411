//! Step 1 of the seamless partial deformation transfer (§3.3, Fig. 3): the
//! personalized deformation of the mask carried onto the avatar's face
//! region, in the gradient domain.
//!
//! Every avatar face triangle `t` whose corners `M` maps into one mask
//! triangle `s(t)` (the triangle correspondence of Sumner & Popović 2004)
//! takes that triangle's deformation: the mask's
//! displacement gradient `Q_s − I` (from the person's neutral `B₀` to
//! `B₀ + B_j`), turned into the avatar's frame by the registration's
//! rotation `R`,
//!
//! ```text
//! G_t = R (Q_{s(t)} − I) Rᵀ
//! ```
//!
//! A triangle whose corners map into different mask triangles straddles a
//! mask edge, where the mask's gradient jumps; there the gradient of the
//! mapped displacement `M B_j` itself, on `t`'s rest shape, is taken:
//! `G_t = (V'_t − V_t) V_t⁻¹` with `V'_t` the edge matrix of `t` moved by
//! `M B_j` (by the mouth corners, where the lips move apart, a single mask
//! triangle's gradient would pull the lips' ends 5 mm off). That gradient
//! is the mask's times the map's own: where `M` squeezes a stretch of the
//! mask into less of the avatar (ARKit's brow-to-lid fold is about twice
//! as tall as the default avatar's), a compression the mask takes in its
//! stride folds the avatar's skin over (the brow slid over the lid in
//! `browDownLeft`, 54 triangles turned past 90°). So where the mapped
//! gradient turns a straddling `t` past facing its way
//! ([`facing_area_ratio`] at most 0), `t`'s corners' points on the mask
//! are taken as a triangle of their own (the chord, across the mask's
//! edges): if the person's shape keeps the chord facing, the map is what
//! folds `t`, and `t` takes the chord's gradient, as a triangle within one
//! mask triangle takes that triangle's. Where the chord folds too, the
//! person's skin does, and the mapped gradient stands
//!
//! (a gradient is scale-free: the registration's scale cancels). The face
//! patch's displacement `D` then minimizes
//!
//! ```text
//! Σ_t A_t ‖∇D_t − G_t‖²_F + Σ_v κ L_vv ‖D_v − (M B_j)_v‖²,
//! (L + κ diag L) D = Σ_t A_t G_t ∇φ + κ diag L · M B_j,
//! ```
//!
//! with `L` the patch's cotangent Laplacian (`L_vi = Σ_t A_t ∇φ_v · ∇φ_i`)
//! and the weak anchor ([`ANCHOR`] κ) to the mapped displacement `M B_j`
//! fixing what gradients cannot see (the translation) and nothing else: it
//! is relative to `L`'s own diagonal, so unit-free. The matrix depends only
//! on the avatar: factored once, all 52 shapes are one solve with 156
//! right-hand sides. The gradients act on the avatar's own triangles, so
//! the avatar keeps its face's proportions and detail while moving as the
//! person's mask does.

use super::lid_contacts::{LidClosingError, LidContact, least_energy_closing};
use crate::avatar::registration::CorrespondenceMap;
use crate::geometry::deformation_gradient::{
    RestTriangle, facing_area_ratio, hat_gradients, triangle_area,
};
use crate::geometry::laplacian::cotangent_lower;
use crate::geometry::sparse_cholesky::{self, FactorError};
use crate::personalize::blendshape_fit::in_parallel_map;
use faer::Mat;
use faer::linalg::solvers::Solve;
use faer::sparse::Triplet;
use faer::sparse::linalg::solvers::Llt;
use glam::{DMat3, DVec3};
use std::collections::HashMap;

/// κ: the anchor's weight relative to the Laplacian's diagonal.
pub const ANCHOR: f64 = 1e-3;

/// Why the face step cannot be prepared or run.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FaceStepError {
    /// No avatar triangle lies wholly in the face region.
    #[error("no avatar triangle lies wholly in the face region")]
    EmptyPatch,
    /// The patch's system could not be factored.
    #[error("the face patch's system could not be factored: {0}")]
    Factor(#[from] FactorError),
    /// The mask shapes do not match the map.
    #[error("the mask has {found} vertices, the correspondence map expects at least {expected}")]
    MaskSize {
        /// Vertices the map refers to.
        expected: usize,
        /// Vertices given.
        found: usize,
    },
}

/// The face patch of an avatar, its system factored.
pub struct FaceStep {
    /// Avatar vertex of each patch vertex (the map's face vertices, in order).
    vertices: Vec<u32>,
    /// Patch triangles (patch indices), their hat gradients and areas.
    triangles: Vec<[u32; 3]>,
    hats: Vec<[DVec3; 3]>,
    areas: Vec<f64>,
    /// The mask triangle each patch triangle takes its gradient from, or
    /// `None` where its corners map into different mask triangles.
    sources: Vec<Option<u32>>,
    /// Each patch vertex's point on the mask: its triangle and barycentric
    /// coordinates (the map's).
    points: Vec<(u32, [f64; 3])>,
    /// Each patch triangle's rest corners and rest shape (for the
    /// straddling ones).
    corners: Vec<[DVec3; 3]>,
    rests: Vec<Option<RestTriangle>>,
    /// `κ L_vv` per patch vertex.
    anchor: Vec<f64>,
    llt: Llt<usize, f64>,
    /// Avatar vertex → patch vertex.
    local: HashMap<u32, u32>,
}

impl FaceStep {
    /// Prepares the patch of `map` on the avatar with `positions` and
    /// `triangles` (avatar indices): the triangles whose corners are all
    /// face vertices.
    pub fn new(
        positions: &[DVec3],
        triangles: &[[u32; 3]],
        map: &CorrespondenceMap,
    ) -> Result<FaceStep, FaceStepError> {
        let local: HashMap<u32, u32> = map
            .face
            .iter()
            .enumerate()
            .map(|(i, f)| (f.vertex, i as u32))
            .collect();
        let n = map.face.len();
        let (mut patch, mut hats, mut areas, mut sources) = (vec![], vec![], vec![], vec![]);
        let (mut rests, mut corners) = (Vec::new(), Vec::new());
        for t in triangles {
            let Some(l) = t
                .iter()
                .map(|v| local.get(v).copied())
                .collect::<Option<Vec<u32>>>()
            else {
                continue;
            };
            let Some(x) = t
                .iter()
                .map(|&v| positions.get(v as usize).copied())
                .collect::<Option<Vec<DVec3>>>()
            else {
                continue;
            };
            let x = [x[0], x[1], x[2]];
            let Some(hat) = hat_gradients(x) else {
                continue;
            };
            let mapped_into: Vec<u32> = l.iter().map(|&i| map.face[i as usize].triangle).collect();
            let s = (mapped_into[0] == mapped_into[1] && mapped_into[1] == mapped_into[2])
                .then_some(mapped_into[0]);
            rests.push(RestTriangle::new(x));
            corners.push(x);
            patch.push([l[0], l[1], l[2]]);
            hats.push(hat);
            areas.push(triangle_area(x));
            sources.push(s);
        }
        if patch.is_empty() {
            return Err(FaceStepError::EmptyPatch);
        }
        let weighted: Vec<[DVec3; 3]> = hats
            .iter()
            .zip(&areas)
            .map(|(hat, a)| hat.map(|g| a * g))
            .collect();
        let mut entries = cotangent_lower(&patch, &hats, &weighted, |v| Some(v as usize));
        let mut diagonal = vec![0.0; n];
        for e in entries.iter().filter(|e| e.row == e.col) {
            diagonal[e.row] += e.val;
        }
        // A vertex in no patch triangle is held by the anchor alone, at a
        // weight that keeps the system definite.
        let typical = diagonal.iter().sum::<f64>() / n.max(1) as f64;
        let anchor: Vec<f64> = diagonal
            .iter()
            .map(|d| ANCHOR * if *d > 0.0 { *d } else { typical.max(1.0) })
            .collect();
        for (v, a) in anchor.iter().enumerate() {
            entries.push(Triplet::new(v, v, *a));
        }
        let llt = sparse_cholesky::factor(n, &entries)?;
        Ok(FaceStep {
            vertices: map.face.iter().map(|f| f.vertex).collect(),
            triangles: patch,
            hats,
            areas,
            sources,
            points: map
                .face
                .iter()
                .map(|f| (f.triangle, f.barycentric))
                .collect(),
            corners,
            rests,
            anchor,
            llt,
            local,
        })
    }

    /// The avatar vertex of each patch vertex.
    pub fn vertices(&self) -> &[u32] {
        &self.vertices
    }

    /// The patch's displacement for each shape (module docs): `rest` and
    /// `deltas` the person's mask (neutral and per-shape displacements, mask
    /// topology `mask_triangles`), `rotation` the registration's (mask →
    /// avatar), `mapped[j]` the anchor `M B_j` at the patch vertices (avatar
    /// frame). One displacement per patch vertex per shape.
    pub fn transfer(
        &self,
        rest: &[DVec3],
        deltas: &[&[DVec3]],
        mask_triangles: &[[u32; 3]],
        rotation: DMat3,
        mapped: &[Vec<DVec3>],
    ) -> Result<Vec<Vec<DVec3>>, FaceStepError> {
        let needed = mask_triangles
            .iter()
            .flatten()
            .map(|&i| i as usize + 1)
            .max()
            .unwrap_or(0);
        if let Some(short) = std::iter::once(rest.len())
            .chain(deltas.iter().map(|d| d.len()))
            .find(|l| *l < needed)
        {
            return Err(FaceStepError::MaskSize {
                expected: needed,
                found: short,
            });
        }
        let n = self.vertices.len();
        let shapes = deltas.len();
        // The mask's displacement gradients, shape by shape.
        let rests: Vec<Option<RestTriangle>> = mask_triangles
            .iter()
            .map(|t| RestTriangle::new(t.map(|i| rest[i as usize])))
            .collect();
        // Shape by shape, shared out between the cores: each shape's right
        // side of Eq. (7), solved with the one factor.
        let shape = |j: usize| -> Vec<DVec3> {
            let delta = deltas[j];
            let mut rhs = Mat::<f64>::zeros(n, 3);
            let gradients: Vec<DMat3> = mask_triangles
                .iter()
                .zip(&rests)
                .map(|(t, r)| match r {
                    Some(r) => {
                        let deformed = t.map(|i| rest[i as usize] + delta[i as usize]);
                        rotation * r.displacement_gradient(deformed) * rotation.transpose()
                    }
                    None => DMat3::ZERO,
                })
                .collect();
            let anchor = mapped.get(j);
            for (p, t) in self.triangles.iter().enumerate() {
                let g = match (self.sources[p], &self.rests[p], anchor) {
                    (Some(s), _, _) => gradients.get(s as usize).copied().unwrap_or(DMat3::ZERO),
                    (None, Some(at_rest), Some(m)) => {
                        let moved = |k: usize| {
                            self.corners[p][k]
                                + m.get(t[k] as usize).copied().unwrap_or(DVec3::ZERO)
                        };
                        let mapped = at_rest.displacement_gradient([moved(0), moved(1), moved(2)]);
                        // Only a folding mapped gradient needs the chord.
                        if facing_area_ratio(self.corners[p], mapped) > 0.0 {
                            mapped
                        } else {
                            // The corner's point on the mask, at rest or moved.
                            let on_mask = |k: usize, moved: bool| {
                                let (s, b) = *self.points.get(t[k] as usize)?;
                                let m = mask_triangles.get(s as usize)?;
                                let corner = |i: usize| {
                                    let v = m[i] as usize;
                                    if moved { rest[v] + delta[v] } else { rest[v] }
                                };
                                Some((0..3).map(|i| corner(i) * b[i]).sum::<DVec3>())
                            };
                            let chord = [0, 1, 2].map(|k| on_mask(k, false));
                            let chord_moved = [0, 1, 2].map(|k| on_mask(k, true));
                            match (chord, chord_moved) {
                                ([Some(a), Some(b), Some(c)], [Some(d), Some(e), Some(f)]) => {
                                    unfolded(
                                        self.corners[p],
                                        mapped,
                                        ([a, b, c], [d, e, f]),
                                        rotation,
                                    )
                                }
                                _ => mapped,
                            }
                        }
                    }
                    _ => DMat3::ZERO,
                };
                let (hat, a) = (self.hats[p], self.areas[p]);
                for k in 0..3 {
                    let r = g * hat[k] * a;
                    for axis in 0..3 {
                        rhs[(t[k] as usize, axis)] += r[axis];
                    }
                }
            }
            for v in 0..n {
                let target = anchor
                    .and_then(|m| m.get(v))
                    .copied()
                    .unwrap_or(DVec3::ZERO);
                for axis in 0..3 {
                    rhs[(v, axis)] += self.anchor[v] * target[axis];
                }
            }
            self.llt.solve_in_place(&mut rhs);
            (0..n)
                .map(|v| DVec3::new(rhs[(v, 0)], rhs[(v, 1)], rhs[(v, 2)]))
                .collect()
        };
        Ok(in_parallel_map(shapes, shape))
    }

    /// The patch vertex of avatar vertex `v`, if it is one.
    pub fn index(&self, v: u32) -> Option<usize> {
        self.local.get(&v).map(|&i| i as usize)
    }

    /// Closes the lid `contacts` in one shape's patch displacement `d` (as
    /// [`FaceStep::transfer`] gives it; `rest` the avatar at rest, `beyond`
    /// the shape's displacement of every avatar vertex, taken where the
    /// patch does not reach): the change of least energy under this step's
    /// matrix that meets them
    /// ([`super::lid_contacts::least_energy_closing`]). Nothing is changed
    /// on an error.
    pub fn close(
        &self,
        rest: &[DVec3],
        beyond: &[DVec3],
        d: &mut [DVec3],
        contacts: &[LidContact],
    ) -> Result<(), LidClosingError> {
        let index = |v: u32| self.index(v);
        let at = |v: u32| {
            let moved = match index(v) {
                Some(i) => d.get(i)?,
                None => beyond.get(v as usize)?,
            };
            Some(*rest.get(v as usize)? + *moved)
        };
        let change = least_energy_closing(&self.llt, self.vertices.len(), index, at, contacts)?;
        for (i, delta) in change {
            if let Some(x) = d.get_mut(i) {
                *x += delta;
            }
        }
        Ok(())
    }
}

/// A straddling triangle's gradient (module docs): `mapped`, the gradient
/// of `M B_j` on the avatar triangle `x`, unless it turns `x` past facing
/// its way ([`facing_area_ratio`] at most 0) where the chord triangle does
/// not (`chord`, the corners' points on the mask at rest, and the same
/// points moved by the mask's shape): then the map, not the person, folds
/// it, and `x` takes the chord's gradient, turned into the avatar's frame
/// by `rotation`, as a triangle within one mask triangle does.
fn unfolded(
    x: [DVec3; 3],
    mapped: DMat3,
    (chord, moved): ([DVec3; 3], [DVec3; 3]),
    rotation: DMat3,
) -> DMat3 {
    if facing_area_ratio(x, mapped) > 0.0 {
        return mapped;
    }
    match RestTriangle::new(chord) {
        Some(r) => {
            let own = r.displacement_gradient(moved);
            if facing_area_ratio(chord, own) > 0.0 {
                rotation * own * rotation.transpose()
            } else {
                mapped
            }
        }
        None => mapped,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A triangle in the xy-plane; `squash(f)` scales its y by `f` (a
    /// displacement gradient), negative `f` folding it over.
    const X: [DVec3; 3] = [
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(0.0, 1.0, 0.0),
    ];

    fn squash(f: f64) -> DMat3 {
        DMat3::from_diagonal(DVec3::new(0.0, f - 1.0, 0.0))
    }

    fn moved(x: [DVec3; 3], g: DMat3) -> [DVec3; 3] {
        x.map(|p| p + g * p)
    }

    #[test]
    fn a_map_that_folds_what_the_mask_does_not_gives_way_to_the_mask() {
        // The map squeezes a mask triangle 2.3 times as tall into the
        // avatar's: the mask's halving (0.55) becomes a fold (1 − 2.3 ×
        // 0.45 < 0) in the mapped gradient.
        let chord = X.map(|p| DVec3::new(p.x, 2.3 * p.y, 0.0));
        let halved = squash(0.55);
        let folding = squash(1.0 - 2.3 * 0.45);
        let own = RestTriangle::new(chord)
            .expect("a triangle")
            .displacement_gradient(moved(chord, halved));
        assert!((own.y_axis.y + 0.45).abs() < 1e-12);
        let got = unfolded(X, folding, (chord, moved(chord, halved)), DMat3::IDENTITY);
        assert!((got - own).abs_diff_eq(DMat3::ZERO, 1e-12), "{got:?}");
        // Turned into the avatar's frame.
        let r = DMat3::from_rotation_z(0.3);
        let got = unfolded(X, folding, (chord, moved(chord, halved)), r);
        assert!((got - r * own * r.transpose()).abs_diff_eq(DMat3::ZERO, 1e-12));
        // A gradient that keeps the triangle facing is the map's to give
        // (the lips parting at the corners are such gradients).
        let opening = squash(3.0);
        assert_eq!(
            unfolded(X, opening, (chord, moved(chord, halved)), r),
            opening
        );
        // Where the mask folds it too, the person does: the map's stands.
        let folded = squash(-0.2);
        assert_eq!(
            unfolded(X, folding, (chord, moved(chord, folded)), r),
            folding
        );
        // A chord that is no triangle (points on one line) says nothing.
        let line = [X[0], X[1], 2.0 * X[1]];
        assert_eq!(unfolded(X, folding, (line, line), r), folding);
    }
}
