//! Creases finer than the mask, smoothed out of the person's motion
//! (beyond the paper).
//!
//! The mask samples the face every 3–8 mm; an avatar's skin is often
//! three or four times finer. Where the person's motion bends the mask
//! sharply within one row of its triangles (ARKit's own `browDownLeft`
//! pushes the brow 9.5 mm down onto the single row between brow and lid
//! margin, squeezing it into a ridge), the transfer carries that bend onto
//! several rows of the avatar, and they crumple: a jagged shelf over the
//! lid, pleats at a puckered mouth's corners. Nothing the mask measured
//! is that narrow, so the crumple is the transfer's, not the person's.
//!
//! **Which edges.** An edge between two skin triangles is *creased* in
//! shape `j` where `D_j` changes its dihedral angle by more than
//! [`CREASE_ANGLE`] while the avatar's own shape changes it by less than
//! [`OWN_CREASE_ANGLE`] (half, as for folds in
//! [`crate::avatar::implant_check`]): an edge the artist made to crease,
//! as a lid margin rolls in a blink, is the rig's and stays; and one the
//! person's mask makes, bent by the person's shape as much (less
//! [`OWN_CREASE_ANGLE`]) at the mask triangle under it, is the person's and
//! stays (the corners of the mouth pressed shut in `mouthClose`). A
//! folded triangle (turned past 90° where the own shape turns it under
//! 45°, the fold check's rule) always counts: the mask is the surface a
//! depth camera sees, which never folds over itself, so a fold in a
//! person's capture is the fit's, not the face's (the simulator's seed 4
//! folds its brow), and the avatar's skin should not carry it.
//!
//! **What changes.** Around the creased edges and the folded triangles
//! (a flap folded over whole has creases only along its sides), the region `R` of skin within [`FILL_REACH_MM`]
//! of them along the edges, the person's
//! deviation from the automatic retargeting, `E = D_j − A_j`, is replaced
//! by the smoothest field that meets it around `R`:
//!
//! ```text
//! min Σ_r ‖(L E)_r‖²  over the rows r of R and of the vertices next to it,
//! E fixed outside R,      (L_Rᵀ L_R) E_R = −L_Rᵀ L_K E_K,
//! ```
//!
//! with `L` the skin's uniform Laplacian (as in step 2,
//! [`super::adjacent_step`]): `A_j`, the avatar's own detail, stays, and
//! the person's motion passes through `R` as smoothly as around it. Lid
//! vertices the closing of a blink placed ([`super::lid_contacts`],
//! [`super::closed_lids`]) are held, so a closed eye stays closed, and so
//! are the lips' edges the caller names. Up to
//! [`ROUNDS`] times, `R` grows by the edges still creased and the
//! triangles still folded, each round reaching [`FILL_REACH_MM`] further
//! from them (a brow folded over as a flap 6 mm deep needs more room to
//! unfold than a pleat), and on to [`FOLD_ROUNDS`] while more triangles
//! are folded than the check allows ([`FOLDED_SHARE`] of the skin's): the
//! check warns of folds, not creases, and a fold where the deviation
//! around it folds too needs a wider region before the fill from around no
//! longer folds (ICT-FaceKit's inner mouth corner in a simulated person's
//! mouthSmileLeft: 102 folded triangles as made, 77 after three rounds, 23
//! after five; limit 56). Of the shape as made and after each round, the
//! one with the fewest folded triangles, then the fewest creased edges, is
//! kept: a lip's corner, rolled tight, can take a smooth deviation worse
//! than a creased one.

use crate::avatar::implant_check::{FOLD_ANGLE, FOLDED_SHARE, OWN_FOLD_ANGLE};
use crate::geometry::dihedral_angle::Hinges;
use crate::geometry::edge_distance::EdgeGraph;
use crate::geometry::laplacian::{normal_lower, uniform_row};
use crate::geometry::one_ring::one_rings;
use crate::geometry::sparse_cholesky::{self, FactorError};
use faer::Mat;
use faer::linalg::solvers::Solve;
use faer::sparse::Triplet;
use glam::DVec3;
use std::collections::{BTreeSet, HashMap};
use std::f64::consts::{FRAC_PI_4, FRAC_PI_8};

/// A shape changes a creased edge's dihedral angle by more than this
/// (radians, 45°): the angle by which taking the person's face may not
/// crease the skin at rest ([`crate::avatar::rest_check::REST_CREASE_ANGLE`]).
pub const CREASE_ANGLE: f64 = FRAC_PI_4;

/// The avatar's own shape changes a creased edge's dihedral angle by less
/// than this (radians, 22.5°): half of [`CREASE_ANGLE`], as the fold check
/// allows a fold where the own shape turns a triangle by half as much.
pub const OWN_CREASE_ANGLE: f64 = FRAC_PI_8;

/// How far from a creased edge, along the skin, the person's deviation is
/// smoothed (mm at the mask's scale): half the mask's closest vertex
/// spacing (3–8 mm on ARKit's mesh and the simulator's), so what is
/// replaced is narrower than anything the mask can measure. The creased
/// edges' own triangles are always in it, however coarse the avatar.
pub const FILL_REACH_MM: f64 = 3.0;

/// Rounds of finding creases and smoothing around them, `R` growing each
/// round.
pub const ROUNDS: usize = 3;

/// Rounds while more triangles are folded than the check allows (module
/// docs): the region reaches up to 18 mm from the fold.
pub const FOLD_ROUNDS: usize = 6;

/// The skin of an avatar prepared for smoothing creases.
pub struct CreaseSmoothing {
    hinges: Hinges,
    rings: HashMap<u32, BTreeSet<u32>>,
    graph: EdgeGraph,
    /// [`FILL_REACH_MM`] in avatar units.
    reach: f64,
}

/// One shape's displacements: what was made, the avatar's own shape where
/// it has one (else `A_j`), `A_j`, and the vertices held.
pub struct ShapeToSmooth<'a> {
    /// `D_j`, every avatar vertex; smoothed in place.
    pub made: &'a mut [DVec3],
    /// The avatar's own shape `Ã_j`, or `A_j` where it has none.
    pub own: &'a [DVec3],
    /// `A_j`.
    pub retargeted: &'a [DVec3],
    /// Vertices that keep their displacement whatever the creases.
    pub held: &'a [bool],
    /// For each vertex, how much the person's own shape changes the
    /// dihedral angles of the mask where the vertex lies on it (radians,
    /// the largest at the mask triangle's edges; empty where the mask says
    /// nothing): a crease the person's mask makes is the person's.
    pub mask_bend: &'a [f64],
}

impl CreaseSmoothing {
    /// The skin `triangles` (avatar indices) of the avatar at rest
    /// `positions`; `to_avatar` avatar units per mask millimetre.
    pub fn new(positions: &[DVec3], triangles: &[[u32; 3]], to_avatar: f64) -> CreaseSmoothing {
        CreaseSmoothing {
            hinges: Hinges::new(positions, triangles),
            rings: one_rings(positions.len(), triangles),
            graph: EdgeGraph::new(positions, triangles),
            reach: FILL_REACH_MM * to_avatar,
        }
    }

    /// The creased edges (module docs) of displacement `made`, where the
    /// own shape changes the dihedral angle by little (`own_smooth`) and
    /// the made one by more than [`OWN_CREASE_ANGLE`] past what the
    /// person's mask bends there (`mask_bend`, per vertex), as indices into
    /// the pairs.
    fn creased(
        &self,
        rest: &[DVec3],
        (made, cosines): (&[DVec3], &[Option<f64>]),
        own_smooth: &[bool],
        mask_bend: &[f64],
    ) -> Vec<usize> {
        let triangles = self.hinges.triangles();
        let allowed = |k: usize| {
            self.hinges.pairs()[k]
                .iter()
                .flat_map(|&t| triangles[t])
                .filter_map(|v| mask_bend.get(v as usize).copied())
                .fold(0.0, f64::max)
        };
        self.hinges
            .changes_beyond(rest, made, cosines, CREASE_ANGLE)
            .iter()
            .zip(own_smooth)
            .enumerate()
            .filter(|(k, (change, smooth))| {
                **smooth && **change > CREASE_ANGLE && **change > allowed(*k) + OWN_CREASE_ANGLE
            })
            .map(|(k, _)| k)
            .collect()
    }

    /// Smooths the creases of one shape (module docs), `rest` the avatar at
    /// rest. Returns the creased edges found first and left at the end; on
    /// an error the shape is left as it was made.
    pub fn smooth(
        &self,
        rest: &[DVec3],
        shape: ShapeToSmooth,
    ) -> Result<(usize, usize), FactorError> {
        let own_cosines = self.hinges.turn_cosines(rest, shape.own);
        let own_smooth: Vec<bool> = self
            .hinges
            .changes_beyond(rest, shape.own, &own_cosines, OWN_CREASE_ANGLE)
            .iter()
            .map(|change| *change <= OWN_CREASE_ANGLE)
            .collect();
        let own_unturned: Vec<bool> = Hinges::turned(&own_cosines, OWN_FOLD_ANGLE)
            .iter()
            .map(|turned| !turned)
            .collect();
        // The creased edges and the folded triangles of a state of the
        // shape, its triangles' turns found once for both. A fold is never
        // the person's: the mask is the surface a depth camera sees, which
        // does not fold over itself.
        let faults = |made: &[DVec3]| -> (Vec<usize>, Vec<usize>) {
            let cosines = self.hinges.turn_cosines(rest, made);
            let creased = self.creased(rest, (made, &cosines), &own_smooth, shape.mask_bend);
            let folds = Hinges::turned(&cosines, FOLD_ANGLE)
                .iter()
                .zip(&own_unturned)
                .enumerate()
                .filter(|(_, (folded, unturned))| **folded && **unturned)
                .map(|(t, _)| t)
                .collect();
            (creased, folds)
        };
        let original = shape.made.to_vec();
        let (mut creased, mut folds) = faults(shape.made);
        let first = creased.len();
        // The best state so far: fewest folds, then fewest creases.
        let mut best = ((folds.len(), first), None::<Vec<DVec3>>);
        let mut region = vec![false; rest.len()];
        let fold_limit = (FOLDED_SHARE * self.hinges.triangles().len() as f64) as usize;
        for round in 1..=FOLD_ROUNDS {
            let go_on = match round <= ROUNDS {
                true => !(creased.is_empty() && folds.is_empty()),
                false => folds.len() > fold_limit,
            };
            if !go_on {
                break;
            }
            let mut source = vec![false; rest.len()];
            let triangles = creased
                .iter()
                .flat_map(|&k| self.hinges.pairs()[k])
                .chain(folds.iter().copied());
            for t in triangles {
                for v in self.hinges.triangles()[t] {
                    source[v as usize] = true;
                }
            }
            let reach = self.reach * round as f64;
            let distance = self.graph.distances(&source, reach);
            for (v, inside) in region.iter_mut().enumerate() {
                *inside |= (source[v] || distance[v] <= reach)
                    && !shape.held.get(v).copied().unwrap_or(false)
                    && self.rings.contains_key(&(v as u32));
            }
            if let Err(e) = self.fill(&region, shape.made, shape.retargeted) {
                shape.made.copy_from_slice(&original);
                return Err(e);
            }
            (creased, folds) = faults(shape.made);
            let score = (folds.len(), creased.len());
            if score < best.0 {
                best = (score, Some(shape.made.to_vec()));
            }
        }
        // Where no round did better, the shape as it was made.
        shape
            .made
            .copy_from_slice(best.1.as_deref().unwrap_or(&original));
        Ok((first, best.0.1))
    }

    /// Replaces `E = made − retargeted` on `region` by the bi-Laplacian
    /// fill from around it (module docs).
    fn fill(
        &self,
        region: &[bool],
        made: &mut [DVec3],
        retargeted: &[DVec3],
    ) -> Result<(), FactorError> {
        let vertices: Vec<u32> = (0..region.len() as u32)
            .filter(|&v| region[v as usize])
            .collect();
        if vertices.is_empty() {
            return Ok(());
        }
        let local: HashMap<u32, usize> =
            vertices.iter().enumerate().map(|(i, v)| (*v, i)).collect();
        let deviation = |v: u32| {
            let v = v as usize;
            made[v] - retargeted.get(v).copied().unwrap_or(DVec3::ZERO)
        };
        let mut row_vertices: BTreeSet<u32> = vertices.iter().copied().collect();
        for v in &vertices {
            row_vertices.extend(self.rings[v].iter().copied());
        }
        let mut rows: Vec<Vec<(usize, f64)>> = Vec::with_capacity(row_vertices.len());
        let mut known: Vec<DVec3> = Vec::with_capacity(row_vertices.len());
        for r in &row_vertices {
            let (mut row, mut fixed) = (Vec::new(), DVec3::ZERO);
            for (v, x) in uniform_row(*r, &self.rings[r]) {
                match local.get(&v) {
                    Some(&i) => row.push((i, x)),
                    None => fixed += deviation(v) * x,
                }
            }
            rows.push(row);
            known.push(fixed);
        }
        let m = vertices.len();
        let mut entries = normal_lower(rows.iter().map(|r| r.as_slice()));
        // A piece of R that touches nothing fixed stays as it is (E there
        // is pulled, ever so weakly, towards its value).
        let tiny = 1e-9;
        entries.extend((0..m).map(|i| Triplet::new(i, i, tiny)));
        let llt = sparse_cholesky::factor(m, &entries)?;
        let mut rhs = Mat::<f64>::zeros(m, 3);
        for (i, &v) in vertices.iter().enumerate() {
            let e = deviation(v) * tiny;
            for axis in 0..3 {
                rhs[(i, axis)] += e[axis];
            }
        }
        for (row, fixed) in rows.iter().zip(&known) {
            for &(i, x) in row {
                for axis in 0..3 {
                    rhs[(i, axis)] -= x * fixed[axis];
                }
            }
        }
        llt.solve_in_place(&mut rhs);
        for (i, &v) in vertices.iter().enumerate() {
            let v = v as usize;
            let a = retargeted.get(v).copied().unwrap_or(DVec3::ZERO);
            made[v] = a + DVec3::new(rhs[(i, 0)], rhs[(i, 1)], rhs[(i, 2)]);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_support::flat_sheet as sheet;

    /// Columns 10 and on lifted by 3 in one step: the squares between
    /// columns 9 and 10 stand at 72°, a crease along each side of them.
    fn step(positions: &[DVec3]) -> Vec<DVec3> {
        positions
            .iter()
            .map(|p| DVec3::new(0.0, 0.0, if p.x >= 10.0 { 3.0 } else { 0.0 }))
            .collect()
    }

    const COLUMNS: usize = 20;
    const ROWS: usize = 8;

    /// What is around the step: the own shape, `A_j`, the vertices held
    /// and the mask's bend (`None`: zero, nothing held, the mask silent).
    #[derive(Default)]
    struct Around {
        own: Option<Vec<DVec3>>,
        retargeted: Option<Vec<DVec3>>,
        held: Option<Vec<bool>>,
        mask_bend: Vec<f64>,
    }

    /// The step smoothed on the sheet (one unit per mask millimetre): the
    /// sheet at rest, the shape after, and the creases found and left.
    fn smooth_step(around: Around) -> (Vec<DVec3>, Vec<DVec3>, (usize, usize)) {
        let (rest, triangles) = sheet(COLUMNS, ROWS);
        let zero = vec![DVec3::ZERO; rest.len()];
        let mut made = step(&rest);
        let shape = ShapeToSmooth {
            made: &mut made,
            own: around.own.as_deref().unwrap_or(&zero),
            retargeted: around.retargeted.as_deref().unwrap_or(&zero),
            held: around.held.as_deref().unwrap_or(&[]),
            mask_bend: &around.mask_bend,
        };
        let counts = CreaseSmoothing::new(&rest, &triangles, 1.0)
            .smooth(&rest, shape)
            .unwrap();
        (rest, made, counts)
    }

    /// The step becomes a ramp within the reach (3 units) of its creases'
    /// triangles (the flat ones beside the standing squares reach columns
    /// 8 and 11), and nothing beyond the reach changes: columns 4 and below
    /// stay down, 15 and on stay up.
    #[test]
    fn a_step_finer_than_the_mask_becomes_a_ramp_within_the_reach() {
        let (rest, made, (found, left)) = smooth_step(Around::default());
        assert!(found >= ROWS - 1, "the step's creases: {found}");
        assert_eq!(left, 0);
        for (p, d) in rest.iter().zip(&made) {
            if p.x <= 4.0 {
                assert_eq!(d.z, 0.0, "beyond the reach below, at {p}");
            } else if p.x >= 15.0 {
                assert_eq!(d.z, 3.0, "beyond the reach above, at {p}");
            }
        }
        // The ramp climbs all the way, without a step left in it.
        let middle: Vec<f64> = (0..COLUMNS)
            .map(|i| made[ROWS / 2 * COLUMNS + i].z)
            .collect();
        assert!(middle.windows(2).all(|w| w[1] >= w[0] - 1e-9), "{middle:?}");
        assert!(middle.windows(2).all(|w| w[1] - w[0] < 1.0), "{middle:?}");
    }

    /// A fold wider than three rounds reach (30 units pushed back over the
    /// sheet at one column: within ±9 units the fill must climb more than
    /// one unit per unit, and folds again; with three rounds all 14
    /// triangles stay folded) is smoothed on, round by round, until
    /// nothing is folded: within ±18 it climbs gently enough.
    #[test]
    fn a_wide_fold_is_smoothed_on_past_the_crease_rounds() {
        let (rest, triangles) = sheet(100, 8);
        let zero = vec![DVec3::ZERO; rest.len()];
        let mut made: Vec<DVec3> = rest
            .iter()
            .map(|p| DVec3::new(if p.x >= 50.0 { -30.0 } else { 0.0 }, 0.0, 0.0))
            .collect();
        let folded = |made: &[DVec3]| {
            let normal = |t: &[u32; 3], d: &[DVec3]| {
                let at = |k: usize| rest[t[k] as usize] + d[t[k] as usize];
                (at(1) - at(0)).cross(at(2) - at(0))
            };
            triangles
                .iter()
                .filter(|t| normal(t, made).dot(normal(t, &zero)) < 0.0)
                .count()
        };
        assert!(folded(&made) >= 8, "the fold as made: {}", folded(&made));
        let shape = ShapeToSmooth {
            made: &mut made,
            own: &zero,
            retargeted: &zero,
            held: &[],
            mask_bend: &[],
        };
        CreaseSmoothing::new(&rest, &triangles, 1.0)
            .smooth(&rest, shape)
            .unwrap();
        assert_eq!(folded(&made), 0);
    }

    /// What the avatar's own shape creases is the rig's and stays, and so
    /// does what the person's mask bends as much; a vertex held (a lid a
    /// closing placed) keeps its place while its neighbours are smoothed.
    #[test]
    fn the_rigs_and_the_persons_own_creases_and_held_vertices_stay() {
        let (rest, _) = sheet(COLUMNS, ROWS);
        let own = Around {
            own: Some(step(&rest)),
            ..Around::default()
        };
        let (_, made, counts) = smooth_step(own);
        assert_eq!(counts, (0, 0));
        assert_eq!(made, step(&rest));

        // The mask bends by 72° where the step stands: the person's crease.
        let persons = Around {
            mask_bend: vec![72f64.to_radians(); rest.len()],
            ..Around::default()
        };
        let (_, made, counts) = smooth_step(persons);
        assert_eq!(counts, (0, 0));
        assert_eq!(made, step(&rest));

        // Held: the lifted column next to the step, on one row.
        let pinned = 3 * COLUMNS + 10;
        let mut held = vec![false; rest.len()];
        held[pinned] = true;
        let (_, made, _) = smooth_step(Around {
            held: Some(held),
            ..Around::default()
        });
        assert_eq!(made[pinned].z, 3.0);
        assert!(made[pinned + COLUMNS].z < 3.0, "its neighbour is smoothed");
    }

    /// The deviation from `A_j` is smoothed, not `A_j`: where the
    /// retargeting makes the step itself, the shape stays as made.
    #[test]
    fn the_retargetings_own_detail_is_kept() {
        let (rest, _) = sheet(COLUMNS, ROWS);
        let (_, made, (found, left)) = smooth_step(Around {
            retargeted: Some(step(&rest)),
            ..Around::default()
        });
        assert!(found > 0);
        // The deviation is zero everywhere, so is its fill: the crease is
        // `A_j`'s and stays (and is left, counted).
        assert_eq!(left, found);
        assert_eq!(made, step(&rest));
    }
}
