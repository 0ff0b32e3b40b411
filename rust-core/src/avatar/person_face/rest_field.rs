//! The change of the skin's rest that takes the person's face: smooth
//! everywhere, through the wanted changes at points of the skin, zero far
//! from the face.
//!
//! With `R` the skin within [`super::REACH_MM`] of the face region, `a_v`
//! the skin's Laplace–Beltrami rows (`a_v · u = √A_v (Δu)_v`, the
//! area-normalized cotangent Laplacian,
//! [`crate::geometry::laplacian::laplace_beltrami_rows`]), and for each
//! point `i` its place on the skin `Σ_k β_ik x_{v_ik}` and wanted change
//! `d_i`, the change `u` (zero beyond `R`) minimizes
//!
//! ```text
//! Σ_r (a_r · u)² + w Σ_i ‖Σ_k β_ik u_{v_ik} − d_i‖²,
//! (L_Rᵀ L_R + w Bᵀ B) u_R = w Bᵀ d,
//! ```
//!
//! over the rows `r` of `R` and of the skin next to it (so `u` leaves
//! zero with zero slope), `B` the points' barycentric rows, and `w` the
//! caller's point weight times the mean diagonal of `L_Rᵀ L_R`. The first
//! sum is the thin-plate energy of the change (Botsch & Sorkine 2008): it
//! measures bending per area, so a change that turns a narrow row of
//! triangles (a lid's margin, a nostril's rim) costs what it turns them
//! by. The uniform graph Laplacian used before counted every edge alike,
//! and where the avatar's triangles are small it let the change turn them
//! sharply: five people on ARKit's mesh creased 106–128 of the default
//! avatar's edges with it, 7–8 with this (the closest-point rounds of
//! [`super::surface_fit`] alike). Skin that touches itself at rest
//! without sharing a triangle (the lips along the mouth's line, the lids
//! at the corners of the eyes: vertices within [`TOUCH_MM`],
//! [`touching_pairs`]) is held together, `‖u_a − u_b‖²` with
//! [`TIE_WEIGHT`] times that mean diagonal: moved apart by the person's
//! face, the two copies of a lip's corner crossed each other. Between the
//! points `u` is smooth across the mask's edges (the map's
//! piecewise-linear interpolation of `d` would crease the skin along every
//! one of them).

use crate::geometry::connected_components::component_vertices;
use crate::geometry::laplacian::normal_lower;
use crate::geometry::self_intersection::intersecting_pairs;
use crate::geometry::sparse_cholesky::{self, FactorError, FixedPattern};
use faer::Mat;
use faer::linalg::solvers::Solve;
use faer::sparse::Triplet;
use glam::DVec3;
use std::collections::{BTreeMap, BTreeSet, HashMap};

/// Skin vertices closer than this at rest (mm at the mask's scale) that
/// share no triangle touch ([`touching_pairs`]): the default avatar's
/// lips meet within 0.01–0.2 mm along the mouth's line and its lids
/// within 0.47 mm at the outer corners of the eyes; distinct surfaces of
/// a head are otherwise millimetres apart.
pub const TOUCH_MM: f64 = 0.5;

/// The pairs of vertices of `triangles` (over `positions`) closer than
/// `reach` that share no triangle, binned in cells of `reach`.
pub fn touching_pairs(positions: &[DVec3], triangles: &[[u32; 3]], reach: f64) -> Vec<(u32, u32)> {
    let mut sharing: std::collections::HashSet<(u32, u32)> = std::collections::HashSet::new();
    let mut used: BTreeSet<u32> = BTreeSet::new();
    for t in triangles {
        for a in t {
            used.insert(*a);
            for b in t {
                sharing.insert((*a, *b));
            }
        }
    }
    let key = |p: DVec3| (p / reach).floor().as_ivec3().to_array();
    let mut cells: HashMap<[i32; 3], Vec<u32>> = HashMap::new();
    for &v in &used {
        if let Some(p) = positions.get(v as usize) {
            cells.entry(key(*p)).or_default().push(v);
        }
    }
    let mut pairs = Vec::new();
    for &a in &used {
        let Some(&p) = positions.get(a as usize) else {
            continue;
        };
        let [x, y, z] = key(p);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    for &b in cells.get(&[x + dx, y + dy, z + dz]).into_iter().flatten() {
                        if b < a
                            && (positions[b as usize] - p).length() < reach
                            && !sharing.contains(&(a, b))
                        {
                            pairs.push((b, a));
                        }
                    }
                }
            }
        }
    }
    pairs.sort_unstable();
    pairs
}

/// How strongly touching vertices are held together, against one
/// Laplacian row squared: enough to keep the lips' two copies of a mouth
/// corner from crossing (untied, one committed subject's did), weak enough that lips the
/// person's neutral holds parted stay parted (at 10³, as strong as the points once were, the ties
/// pulled them shut, 0.65 mm from the scan, crossing at the corners).
pub const TIE_WEIGHT: f64 = 10.0;

/// A wanted change at a point of the skin: its triangle's corners
/// (avatar vertices), barycentrics, and the change.
pub type PointChange = ([u32; 3], [f64; 3], DVec3);

/// The skin's Laplace–Beltrami rows by vertex (avatar indices; module
/// docs), as [`crate::geometry::laplacian::laplace_beltrami_rows`] gives
/// them for the face parts' triangles at rest.
pub type SkinRows = BTreeMap<u32, Vec<(u32, f64)>>;

/// The bending energy over `R` and the ties (module docs), assembled once
/// for every solve a take makes: only the points change from one solve to
/// the next ([`RestSystem::rest_field`]).
pub struct RestSystem {
    /// Avatar vertices.
    n: usize,
    /// The vertices of `R`, increasing: the unknowns.
    inside: Vec<u32>,
    /// Each one's unknown.
    local: HashMap<u32, usize>,
    /// The lower triangle of `L_Rᵀ L_R`.
    bending: Vec<Triplet<usize, usize, f64>>,
    /// The sum of its diagonal: over the unknowns, the unit the weights
    /// are given in.
    diagonal: f64,
    /// The ties' entries, at [`TIE_WEIGHT`].
    tied: Vec<Triplet<usize, usize, f64>>,
    /// The pattern of the bending energy and the ties, which holds every
    /// point's entries too (a point's corners are a skin triangle's, each
    /// pair of them an edge, which the Laplacian's rows hold), analysed
    /// once for every solve.
    pattern: FixedPattern,
}

impl RestSystem {
    /// The system over the skin whose Laplace–Beltrami rows are `skin`
    /// (`n` avatar vertices), `region` saying which vertices are in `R`,
    /// `ties` the pairs that move as one; an error if its pattern cannot
    /// be analysed.
    pub fn new(
        n: usize,
        skin: &SkinRows,
        region: &[bool],
        ties: &[(u32, u32)],
    ) -> Result<RestSystem, FactorError> {
        let inside: Vec<u32> = (0..n as u32)
            .filter(|&v| region.get(v as usize) == Some(&true) && skin.contains_key(&v))
            .collect();
        let local: HashMap<u32, usize> = inside.iter().enumerate().map(|(i, v)| (*v, i)).collect();
        let mut rows: BTreeSet<u32> = inside.iter().copied().collect();
        for v in &inside {
            rows.extend(skin[v].iter().map(|(w, _)| *w));
        }
        let laplacian_rows: Vec<Vec<(usize, f64)>> = rows
            .iter()
            .map(|&r| {
                skin.get(&r)
                    .into_iter()
                    .flatten()
                    .filter_map(|(v, x)| Some((*local.get(v)?, *x)))
                    .collect()
            })
            .collect();
        let bending = normal_lower(laplacian_rows.iter().map(|r| r.as_slice()));
        let diagonal: f64 = bending
            .iter()
            .filter(|e| e.row == e.col)
            .map(|e| e.val)
            .sum();
        let tie = TIE_WEIGHT * diagonal / inside.len().max(1) as f64;
        let mut tied = Vec::new();
        for (a, b) in ties {
            let (Some(&i), Some(&j)) = (local.get(a), local.get(b)) else {
                continue;
            };
            tied.push(Triplet::new(i, i, tie));
            tied.push(Triplet::new(j, j, tie));
            tied.push(Triplet::new(i.max(j), i.min(j), -tie));
        }
        let fixed: Vec<Triplet<usize, usize, f64>> = bending.iter().chain(&tied).copied().collect();
        let pattern = FixedPattern::new(inside.len(), &fixed)?;
        Ok(RestSystem {
            n,
            inside,
            local,
            bending,
            diagonal,
            tied,
            pattern,
        })
    }

    /// The change `u` of every avatar vertex (module docs) through
    /// `points`, held at `point_weight` (against one row squared); `None`
    /// if the system cannot be solved.
    pub fn rest_field(&self, points: &[PointChange], point_weight: f64) -> Option<Vec<DVec3>> {
        let m = self.inside.len();
        let w = point_weight * self.diagonal / m.max(1) as f64;
        let mut entries = self.bending.clone();
        let mut rhs = Mat::<f64>::zeros(m, 3);
        for (corners, beta, d) in points {
            let row: Vec<(usize, f64)> = corners
                .iter()
                .zip(beta)
                .filter_map(|(v, b)| Some((*self.local.get(v)?, *b)))
                .collect();
            for &(a, x) in &row {
                for axis in 0..3 {
                    rhs[(a, axis)] += w * x * d[axis];
                }
                for &(b, y) in &row {
                    if a >= b {
                        entries.push(Triplet::new(a, b, w * x * y));
                    }
                }
            }
        }
        entries.extend_from_slice(&self.tied);
        let mut work = self.pattern.work(3);
        match self.pattern.factor_entries(&entries, &mut work) {
            Ok(mut llt) => llt.solve_in_place(rhs.as_mut()),
            // A pattern the system did not foresee: analysed afresh.
            Err(FactorError::Entries(_)) => {
                sparse_cholesky::factor(m, &entries)
                    .ok()?
                    .solve_in_place(&mut rhs);
            }
            Err(_) => return None,
        }
        let mut u = vec![DVec3::ZERO; self.n];
        for (i, &v) in self.inside.iter().enumerate() {
            u[v as usize] = DVec3::new(rhs[(i, 0)], rhs[(i, 1)], rhs[(i, 2)]);
        }
        Some(u)
    }
}

/// Touching skin kept from passing through itself, in rounds: each group
/// of vertices that touch at rest (`ties`, joined transitively) moves
/// exactly as one, by the mean of their changes in `field`, where the
/// field moves a tied pair alike (their changes differing by less than
/// `still`) or where the `triangles` of the two (those with a tied vertex)
/// cut through each other once moved; a round joins the ties between every
/// pair of triangles that cross, until none is left or no tie links what
/// crosses ([`MAX_ROUNDS`]). The ties hold touching vertices together only
/// approximately (at [`TIE_WEIGHT`]): two copies of a lip's corner 0.01
/// mm apart slid 0.03 mm against each other and the nearly coplanar sheets
/// they bound crossed; lips 0.2 mm apart slid through each other where a
/// person's upper lip sits lower on the lower one than the stock face's.
/// Where the person's lips part and nothing crosses, they stay parted, as
/// the scan has them. Returns how many vertices were moved.
pub fn keep_touching(
    positions: &[DVec3],
    field: &mut [DVec3],
    triangles: &[[u32; 3]],
    ties: &[(u32, u32)],
    still: f64,
) -> usize {
    let solved = field.to_vec();
    let mut joined: BTreeSet<(u32, u32)> = ties
        .iter()
        .filter(
            |&&(a, b)| match (field.get(a as usize), field.get(b as usize)) {
                (Some(ua), Some(ub)) => (*ua - *ub).length() < still,
                _ => false,
            },
        )
        .copied()
        .collect();
    let tied: BTreeSet<u32> = ties.iter().flat_map(|&(a, b)| [a, b]).collect();
    let seam: Vec<[u32; 3]> = triangles
        .iter()
        .filter(|t| t.iter().any(|v| tied.contains(v)))
        .copied()
        .collect();
    let mut moved = 0;
    for _ in 0..MAX_ROUNDS {
        field.copy_from_slice(&solved);
        let list: Vec<(u32, u32)> = joined.iter().copied().collect();
        moved = move_as_one(field, &list);
        let now: Vec<DVec3> = positions
            .iter()
            .zip(field.iter())
            .map(|(p, u)| *p + *u)
            .collect();
        let mut more = false;
        for (i, j) in intersecting_pairs(&now, &seam) {
            let (s, t) = (seam[i], seam[j]);
            for &(a, b) in ties {
                if (s.contains(&a) && t.contains(&b)) || (t.contains(&a) && s.contains(&b)) {
                    more |= joined.insert((a, b));
                }
            }
        }
        if !more {
            break;
        }
    }
    moved
}

/// Rounds of [`keep_touching`] at most: each joins the ties across the
/// triangles that still cross; on the simulated subjects one or two
/// rounds leave none.
pub const MAX_ROUNDS: usize = 8;

/// Makes each group of `ties` (joined transitively) move exactly as one,
/// by the mean of the group's changes in `field`. Returns how many
/// vertices were moved.
fn move_as_one(field: &mut [DVec3], ties: &[(u32, u32)]) -> usize {
    // A tie is a degenerate triangle for the components.
    let joined: Vec<[u32; 3]> = ties.iter().map(|&(a, b)| [a, b, b]).collect();
    let mut moved = 0;
    for group in component_vertices(field.len(), &joined) {
        if group.len() < 2 {
            continue;
        }
        let mean = group.iter().map(|&v| field[v as usize]).sum::<DVec3>() / group.len() as f64;
        for &v in &group {
            field[v as usize] = mean;
        }
        moved += group.len();
    }
    moved
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ties_moved_alike_move_as_one_and_parted_ones_are_left() {
        let positions = vec![DVec3::ZERO; 5];
        let mut field = vec![
            DVec3::X * 0.1,
            DVec3::Y * 0.1,
            DVec3::Z * 0.1,
            DVec3::ZERO,
            DVec3::splat(5.0),
        ];
        // 0-1-2 a chain moved alike; 3-4 parted by the field.
        let ties = [(0, 1), (1, 2), (3, 4)];
        assert_eq!(keep_touching(&positions, &mut field, &[], &ties, 0.5), 3);
        let mean = (DVec3::X + DVec3::Y + DVec3::Z) * 0.1 / 3.0;
        for (v, u) in field.iter().enumerate().take(3) {
            assert!((*u - mean).length() < 1e-12, "{v}: {u}");
        }
        assert_eq!(field[3], DVec3::ZERO);
        assert_eq!(field[4], DVec3::splat(5.0));
    }

    #[test]
    fn sheets_that_would_cross_are_held_together() {
        // Two flat sheets 0.2 apart in z, each a triangle; the field pushes
        // the lower one up through the upper one (an overlap in x, y).
        let positions = vec![
            DVec3::new(0.0, 0.0, 0.2),
            DVec3::new(2.0, 0.0, 0.2),
            DVec3::new(0.0, 2.0, 0.2),
            DVec3::new(0.1, 0.1, 0.0),
            DVec3::new(2.1, 0.1, -0.5),
            DVec3::new(0.1, 2.1, 0.5),
        ];
        let triangles = [[0, 1, 2], [3, 4, 5]];
        let ties = [(0, 3)];
        let mut field = vec![DVec3::ZERO; 6];
        field[3] = DVec3::Z * 0.5;
        let crossing: Vec<DVec3> = positions.iter().zip(&field).map(|(p, u)| *p + *u).collect();
        assert_eq!(intersecting_pairs(&crossing, &triangles).len(), 1);
        assert_eq!(
            keep_touching(&positions, &mut field, &triangles, &ties, 0.1),
            2
        );
        assert_eq!(field[0], DVec3::Z * 0.25);
        assert_eq!(field[3], DVec3::Z * 0.25);
    }
}
