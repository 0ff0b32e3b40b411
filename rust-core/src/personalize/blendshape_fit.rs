//! §3.2, Eq. (1)–(2): the regularized fit of personalized blendshapes.
//!
//! Minimize over the delta blendshapes `B_1 … B_m`
//!
//! ```text
//! E = Σ_i c_i ‖B_0 + Σ_j w_ij B_j − S_i‖²  +  λ Σ_j ‖D_j (B_j − T_j)‖²
//! ```
//!
//! where `S_i` are observed meshes with tracked weights `w_i` (the captured
//! expressions; for the `multi` method also frames around them, with
//! importances `c_i`), `T_j` the generic blendshapes transferred to `B_0`,
//! and `D_j` the weights of Eq. (3). The paper's energy is `λ = 1`,
//! `c_i = 1`.
//!
//! Neither term couples vertices, so the normal equations split into one
//! small system per vertex `v`, with three right-hand sides (x, y, z):
//!
//! ```text
//! (Wᵀ C W + λ D_v²) b_v = Wᵀ C r_v + λ D_v² t_v
//! ```
//!
//! `Wᵀ C W` (m × m) is the same for every vertex and is formed once; only
//! the diagonal `λ D_v²` changes, so each vertex costs one m × m Cholesky
//! factorization. Shapes that were not captured are not unknowns: they keep
//! their generic shape `T_j` and their contribution is moved to the data side.
//!
//! # Closed eyes
//!
//! §3.2 adds virtual triangles so "that the eyes are completely closed" in the
//! generic blinks `T_j`, and deformation transfer closes them exactly (the lid
//! contacts of [`crate::geometry::deformation_transfer`]). The fit does not
//! keep that: it pulls `B_j` towards the captured blink, a tracked mesh whose
//! lids need not touch, scaled by a tracked weight that need not be the true
//! activation. On the simulated subjects the fitted eyeBlink shapes stayed
//! up to 0.7 mm (`paper`), 1.6 mm (`paper-cv`) and 2.3 mm (`multi`) open or
//! overlapping at weight one. A closed eye must close, so the solution is
//! constrained: for every lid pair `(a, b)` that the template closes in
//! shape `j` (its contacts, [`Contacts`]),
//!
//! ```text
//! b₀_a + B_{j,a} = b₀_b + B_{j,b}.
//! ```
//!
//! `E` is minimized under these constraints over the lid vertices' entries
//! of `B_j` alone: the other shapes keep their fit, so closing a blink does
//! not move the lids of, say, eyeSquint. `E` couples no vertices and the
//! unconstrained solution has zero gradient, so moving entry `(v, j)` by `δ`
//! costs exactly `k_v ‖δ‖²`, with `k_v = (Wᵀ C W)_jj + λ (D_j)²_vv` the
//! diagonal entry of vertex `v`'s own system. Minimizing
//! `k_a ‖δ_a‖² + k_b ‖δ_b‖²` under `δ_a − δ_b = −(x_a − x_b)` (`x = b₀ + B_j`,
//! the fitted positions) gives the closed form
//!
//! ```text
//! x_a, x_b  ←  (k_a x_a + k_b x_b) / (k_a + k_b),
//! ```
//!
//! the stiffness-weighted mean of the two lid points: the lid that the data
//! and the regularizer hold harder moves less; with `k_a = k_b` (small λ, or
//! equal weights) it is the midpoint. No vertex is in two pairs, so the pairs
//! are independent. Only lid vertices move, each by its share of the gap
//! (why not a smooth correction, as EBFR's
//! [`crate::geometry::deformation_transfer::DeformationTransfer::close_contacts`]:
//! `docs/notes/2026-12-lid-closing-in-the-fit.md`).

use super::error::{PersonalizeError, SingularFit, check_size};
use crate::arkit::{BLENDSHAPE_COUNT, Blendshape, Blendshapes};
use crate::geometry::deformation_transfer::Contacts;
use faer::{Mat, Par};
use glam::{DVec3, Vec3};

/// One observed expression: tracked weights and mesh, and its importance.
#[derive(Clone, Copy, Debug)]
pub struct Observation<'a> {
    /// The 52 tracked weights `w_i`.
    pub weights: [f64; BLENDSHAPE_COUNT],
    /// The tracked mesh `S_i`.
    pub vertices: &'a [Vec3],
    /// Importance `c_i` of this observation in `E_fit` (1 for a capture).
    pub importance: f64,
}

/// The assembled fit, reusable for several λ.
pub struct BlendshapeFit<'a> {
    generic: &'a Blendshapes,
    /// Squared Eq. (3) weights, `d2[v * m + j]`.
    d2: Vec<f64>,
    /// The unknown shapes (the captured prompts), in Apple's order.
    captured: Vec<usize>,
    /// `Wᵀ C W` over the captured shapes.
    gram: Mat<f64>,
    /// `Wᵀ C r` over the captured shapes: row = shape, column = 3v + axis.
    cross: Mat<f64>,
    /// `C^½ W` over the captured shapes (`m × k`), kept for the choice of λ
    /// ([`super::lambda_criteria`]).
    w: Mat<f64>,
    /// `C^½ r`: row = observation, column = 3v + axis, kept likewise.
    r: Mat<f64>,
    /// Why the parts given to [`BlendshapeFit::new`] do not fit together,
    /// reported by [`BlendshapeFit::solve`].
    mismatch: Option<PersonalizeError>,
    /// The lid pairs each shape closes, 52 lists, if the solution closes
    /// them ([`BlendshapeFit::closing_lids`]).
    lids: Option<&'a [Contacts]>,
}

/// Checks that `weights` has 52 fields and every field and observed mesh
/// one entry per each of the `n` vertices.
fn check_sizes(
    n: usize,
    weights: &[Vec<f64>],
    observations: &[Observation<'_>],
) -> Result<(), PersonalizeError> {
    check_size(
        || "regularization weight fields".to_string(),
        BLENDSHAPE_COUNT,
        weights.len(),
    )?;
    for (shape, d) in Blendshape::ALL.iter().zip(weights) {
        check_size(|| format!("regularization weights of {shape}"), n, d.len())?;
    }
    for (i, o) in observations.iter().enumerate() {
        check_size(|| format!("observation {i}"), n, o.vertices.len())?;
    }
    Ok(())
}

impl<'a> BlendshapeFit<'a> {
    /// Assembles the fit of the shapes flagged in `captured` (the others
    /// keep their generic shape) to `observations` of a face whose neutral
    /// `B_0` and generic deltas `T_j` are `generic`, with Eq. (3) weights
    /// `weights` (`D_j`, 52 fields of one weight per vertex). Parts that do
    /// not fit together (a field or an observed mesh without one entry per
    /// vertex of `generic`) make [`BlendshapeFit::solve`] return
    /// [`PersonalizeError::Size`].
    pub fn new(
        generic: &'a Blendshapes,
        weights: &[Vec<f64>],
        captured: &[bool; BLENDSHAPE_COUNT],
        observations: &[Observation<'_>],
    ) -> BlendshapeFit<'a> {
        let neutral = generic.neutral();
        let n = neutral.len();
        // Indexing: past this check (mismatched parts are replaced by none)
        // every observed mesh has `n` vertices and `weights` 52 fields of
        // `n`; shape indices are below 52, and `generic` is a checked set of
        // 52 deltas of `n` vertices.
        let mismatch = check_sizes(n, weights, observations).err();
        let (weights, observations) = match mismatch {
            Some(_) => (&[][..], &[][..]),
            None => (weights, observations),
        };
        let unknowns: Vec<usize> = (0..BLENDSHAPE_COUNT).filter(|j| captured[*j]).collect();
        let fixed: Vec<usize> = (0..BLENDSHAPE_COUNT)
            .filter(|j| !unknowns.contains(j))
            .collect();
        let k = unknowns.len();
        let m = observations.len();
        // W (m × k) scaled by √c_i, and residuals r_i = S_i − B_0 − Σ_fixed w_ij T_j.
        let w = Mat::from_fn(m, k, |i, a| {
            observations[i].importance.sqrt() * observations[i].weights[unknowns[a]]
        });
        let r = Mat::from_fn(m, 3 * n, |i, c| {
            let (v, axis) = (c / 3, c % 3);
            let o = &observations[i];
            let mut x = o.vertices[v].as_dvec3()[axis] - neutral[v][axis];
            for &j in &fixed {
                x -= o.weights[j] * generic.deltas()[j][v][axis];
            }
            o.importance.sqrt() * x
        });
        let gram = w.transpose() * &w;
        let cross = w.transpose() * &r;
        let mut d2 = vec![0.0; n * BLENDSHAPE_COUNT];
        for (j, dj) in weights.iter().enumerate() {
            for (v, d) in dj.iter().enumerate() {
                d2[v * BLENDSHAPE_COUNT + j] = d * d;
            }
        }
        BlendshapeFit {
            generic,
            d2,
            captured: unknowns,
            gram,
            cross,
            w,
            r,
            mismatch,
            lids: None,
        }
    }

    /// Makes [`BlendshapeFit::solve`] close, in each fitted shape, the lid
    /// pairs `contacts` of its generic shape (52 lists, in Apple's order;
    /// [`GenericBlendshapes::contacts`]; see the module docs, "Closed eyes").
    /// Lists for another vertex count, or not 52 of them, make
    /// [`BlendshapeFit::solve`] return [`PersonalizeError::Size`].
    ///
    /// [`GenericBlendshapes::contacts`]: super::generic_blendshapes::GenericBlendshapes::contacts
    pub fn closing_lids(mut self, contacts: &'a [Contacts]) -> BlendshapeFit<'a> {
        let n = self.generic.vertex_count();
        let checked = check_size(
            || "lid contact lists".to_string(),
            BLENDSHAPE_COUNT,
            contacts.len(),
        )
        .and_then(|()| {
            Blendshape::ALL
                .iter()
                .zip(contacts)
                .try_for_each(|(shape, c)| {
                    check_size(|| format!("lid contacts of {shape}"), n, c.vertex_count())
                })
        });
        if let Err(e) = checked {
            self.mismatch.get_or_insert(e);
        }
        self.lids = Some(contacts);
        self
    }

    /// The generic blendshapes `B₀`, `T_j` the fit starts from.
    pub(crate) fn generic(&self) -> &'a Blendshapes {
        self.generic
    }

    /// Apple's indices of the unknown (captured) shapes, in order.
    pub(crate) fn unknowns(&self) -> &[usize] {
        &self.captured
    }

    /// `C^½ W` (`m × k`): the importance-scaled weights of the unknowns.
    pub(crate) fn design(&self) -> &Mat<f64> {
        &self.w
    }

    /// `C^½ r` of column `3v + axis`: the importance-scaled observations of
    /// that coordinate, less `B₀` and the uncaptured shapes.
    pub(crate) fn observed(&self, column: usize) -> faer::ColRef<'_, f64> {
        self.r.col(column)
    }

    /// `Wᵀ C W` over the unknown shapes (`k × k`).
    pub(crate) fn gram(&self) -> &Mat<f64> {
        &self.gram
    }

    /// `D²` of Apple's shape `j` at vertex `v`.
    pub(crate) fn d2(&self, v: usize, j: usize) -> f64 {
        self.d2[v * BLENDSHAPE_COUNT + j]
    }

    /// The fit's parts do not fit together (see [`BlendshapeFit::new`]).
    pub(crate) fn mismatch(&self) -> Option<&PersonalizeError> {
        self.mismatch.as_ref()
    }

    /// Solves for regularization strength `λ` (the paper: 1). Returns `B₀`
    /// and the 52 personalized delta blendshapes; shapes that were not
    /// captured are their generic `T_j`.
    pub fn solve(&self, lambda: f64) -> Result<Blendshapes, PersonalizeError> {
        if let Some(mismatch) = &self.mismatch {
            return Err(mismatch.clone());
        }
        // Indexing: `x` has `3k` values per vertex (`solve_shared_gram`),
        // `d2` 52 per vertex, and every shape index is below 52.
        let n = self.cross.ncols() / 3;
        let generic = self.generic.deltas();
        let mut out: Vec<Vec<DVec3>> = generic.to_vec();
        let unknowns = &self.captured;
        let k = unknowns.len();
        let x = solve_shared_gram(
            &self.gram,
            n,
            3,
            |v, a| lambda * self.d2[v * BLENDSHAPE_COUNT + unknowns[a]],
            |v, a, axis| self.cross[(a, 3 * v + axis)],
            |v, a, axis| generic[unknowns[a]][v][axis],
        )
        .map_err(|vertex| SingularFit { vertex, lambda })?;
        for v in 0..n {
            for (a, &j) in unknowns.iter().enumerate() {
                let b = &x[(v * k + a) * 3..(v * k + a) * 3 + 3];
                out[j][v] = DVec3::new(b[0], b[1], b[2]);
            }
        }
        if let Some(contacts) = self.lids {
            self.close_lids(&mut out, contacts, lambda);
        }
        Ok(self.generic.with_deltas(out)?)
    }

    /// Closes the lid pairs of each fitted shape (module docs, "Closed
    /// eyes"): both vertices of a pair move to their mean weighted by the
    /// stiffness `k_v = (Wᵀ C W)_jj + λ (D_j)²_vv` of their own system.
    /// `k_v > 0`: it is a diagonal entry of a matrix that was just factored
    /// as positive definite, so the division is safe.
    fn close_lids(&self, out: &mut [Vec<DVec3>], contacts: &[Contacts], lambda: f64) {
        // Indexing: `contacts` has 52 lists of vertices below `n`
        // (`closing_lids`), `d2` 52 entries per vertex.
        let neutral = self.generic.neutral();
        for (a, &j) in self.captured.iter().enumerate() {
            let stiffness =
                |v: usize| self.gram[(a, a)] + lambda * self.d2[v * BLENDSHAPE_COUNT + j];
            for &[p, q] in contacts[j].pairs() {
                let (p, q) = (p as usize, q as usize);
                let (kp, kq) = (stiffness(p), stiffness(q));
                let meet =
                    (kp * (neutral[p] + out[j][p]) + kq * (neutral[q] + out[j][q])) / (kp + kq);
                out[j][p] = meet - neutral[p];
                out[j][q] = meet - neutral[q];
            }
        }
    }
}

/// Solves, for every element `e` of `count` (a vertex here, a triangle in
/// EBFR), the `k × k` ridge system with `r` right-hand sides
///
/// ```text
/// (G + diag(s_e)) X_e = C_e + diag(s_e) P_e
/// ```
///
/// where the Gram matrix `G` is shared and only the diagonal `s_e` (the
/// regularization weights, `s_e[a] = diagonal(e, a)`) changes. `C_e` is
/// `cross(e, a, c)` and the prior `P_e` is `prior(e, a, c)`. Returns the
/// solutions, entry `(e, a, c)` at `(e·k + a)·r + c`, or the first element
/// whose system is not positive definite. The elements are independent, so
/// they are split over the machine's cores ([`in_parallel_ranges`]); each factorization is faer's
/// in-place Cholesky, with no allocation per element.
pub(crate) fn solve_shared_gram(
    gram: &Mat<f64>,
    count: usize,
    r: usize,
    diagonal: impl Fn(usize, usize) -> f64 + Sync,
    cross: impl Fn(usize, usize, usize) -> f64 + Sync,
    prior: impl Fn(usize, usize, usize) -> f64 + Sync,
) -> Result<Vec<f64>, usize> {
    use faer::dyn_stack::{MemBuffer, MemStack};
    use faer::linalg::cholesky::llt;
    let k = gram.nrows();
    let solve_range = |range: std::ops::Range<usize>| -> Result<Vec<f64>, usize> {
        let mut out = Vec::with_capacity(range.len() * k * r);
        let mut system = Mat::<f64>::zeros(k, k);
        let mut rhs = Mat::<f64>::zeros(k, r);
        let scratch =
            llt::factor::cholesky_in_place_scratch::<f64>(k, Par::Seq, Default::default());
        let mut buffer = MemBuffer::new(scratch);
        let stack = MemStack::new(&mut buffer);
        for e in range {
            system.copy_from(gram);
            for a in 0..k {
                let s = diagonal(e, a);
                system[(a, a)] += s;
                for c in 0..r {
                    rhs[(a, c)] = cross(e, a, c) + s * prior(e, a, c);
                }
            }
            llt::factor::cholesky_in_place(
                system.as_mut(),
                Default::default(),
                Par::Seq,
                stack,
                Default::default(),
            )
            .map_err(|_| e)?;
            llt::solve::solve_in_place(system.as_ref(), rhs.as_mut(), Par::Seq, stack);
            for a in 0..k {
                for c in 0..r {
                    out.push(rhs[(a, c)]);
                }
            }
        }
        Ok(out)
    };
    let parts = in_parallel_ranges(count, solve_range);
    let mut out = Vec::with_capacity(count * k * r);
    for part in parts {
        out.extend(part.unwrap_or(Err(0))?);
    }
    Ok(out)
}

/// Splits `0..count` into one contiguous range per core (at most 8) and
/// runs `work` on each in its own thread; returns the results in the order
/// of the ranges, `None` for a range whose thread panicked.
pub(crate) fn in_parallel_ranges<T: Send>(
    count: usize,
    work: impl Fn(std::ops::Range<usize>) -> T + Sync,
) -> Vec<Option<T>> {
    let threads = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .clamp(1, 8)
        .min(count.max(1));
    let chunk = count.div_ceil(threads);
    let work = &work;
    std::thread::scope(|scope| {
        let handles: Vec<_> = (0..threads)
            .map(|t| {
                let range = (t * chunk).min(count)..((t + 1) * chunk).min(count);
                scope.spawn(move || work(range))
            })
            .collect();
        handles.into_iter().map(|h| h.join().ok()).collect()
    })
}

/// `work(i)` for every `i` of `0..count`, in that order, over the cores
/// ([`in_parallel_ranges`]). A run whose thread panicked is done again on
/// the caller's thread, so the panic surfaces there rather than as missing
/// results.
pub(crate) fn in_parallel_map<T: Send>(count: usize, work: impl Fn(usize) -> T + Sync) -> Vec<T> {
    let runs = in_parallel_ranges(count, |range| range.map(&work).collect::<Vec<_>>());
    match runs.into_iter().collect::<Option<Vec<_>>>() {
        Some(runs) => runs.into_iter().flatten().collect(),
        None => (0..count).map(work).collect(),
    }
}

/// Splits `items` into one contiguous run per core (at most 8) and runs
/// `work` on each in its own thread, with the index of the run's first
/// item; returns the results in the order of the runs, `None` for a run
/// whose thread panicked.
pub(crate) fn in_parallel_chunks<T: Send, R: Send>(
    items: &mut [T],
    work: impl Fn(usize, &mut [T]) -> R + Sync,
) -> Vec<Option<R>> {
    let count = items.len();
    let threads = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .clamp(1, 8)
        .min(count.max(1));
    let chunk = count.div_ceil(threads).max(1);
    let work = &work;
    std::thread::scope(|scope| {
        let handles: Vec<_> = items
            .chunks_mut(chunk)
            .enumerate()
            .map(|(t, run)| scope.spawn(move || work(t * chunk, run)))
            .collect();
        handles.into_iter().map(|h| h.join().ok()).collect()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parallel_chunks_see_every_item_once_with_its_index() {
        for count in [0, 1, 5, 52] {
            let mut items = vec![0usize; count];
            let sums = in_parallel_chunks(&mut items, |first, run| {
                for (k, x) in run.iter_mut().enumerate() {
                    *x += first + k + 1;
                }
                run.len()
            });
            let seen: usize = sums.into_iter().map(|s| s.expect("no panic")).sum();
            assert_eq!(seen, count);
            assert_eq!(items, (1..=count).collect::<Vec<_>>());
        }
    }

    fn shapes(n: usize, seed: f64) -> Vec<Vec<DVec3>> {
        (0..BLENDSHAPE_COUNT)
            .map(|j| {
                (0..n)
                    .map(|v| {
                        let x = (j * 7 + v * 3) as f64 + seed;
                        DVec3::new(x.sin(), (1.3 * x).cos(), (0.7 * x).sin()) * 1e-3
                    })
                    .collect()
            })
            .collect()
    }

    fn render(neutral: &[DVec3], deltas: &[Vec<DVec3>], w: &[f64; 52]) -> Vec<Vec3> {
        (0..neutral.len())
            .map(|v| (neutral[v] + (0..52).map(|j| w[j] * deltas[j][v]).sum::<DVec3>()).as_vec3())
            .collect()
    }

    /// 52 captures: a dominant prompted weight plus co-activation.
    fn capture_weights() -> Vec<[f64; 52]> {
        (0..52)
            .map(|i| {
                std::array::from_fn(|j| {
                    if i == j {
                        0.9
                    } else {
                        0.03 * (((i * 31 + j * 17) % 7) as f64) / 7.0
                    }
                })
            })
            .collect()
    }

    fn captures<'a>(ws: &[[f64; 52]], meshes: &'a [Vec<Vec3>]) -> Vec<Observation<'a>> {
        ws.iter()
            .zip(meshes)
            .map(|(w, m)| Observation {
                weights: *w,
                vertices: m,
                importance: 1.0,
            })
            .collect()
    }

    #[test]
    fn without_regularization_a_linear_subject_is_recovered_exactly() {
        let n = 20;
        let neutral: Vec<DVec3> = (0..n).map(|v| DVec3::splat(v as f64 * 0.01)).collect();
        let truth = shapes(n, 0.0);
        let generic = Blendshapes::new(neutral.clone(), shapes(n, 1.0)).unwrap();
        let d = vec![vec![1.0; n]; 52];
        let ws = capture_weights();
        let meshes: Vec<Vec<Vec3>> = ws.iter().map(|w| render(&neutral, &truth, w)).collect();
        let obs = captures(&ws, &meshes);
        let fit = BlendshapeFit::new(&generic, &d, &[true; 52], &obs);
        let b = fit.solve(1e-12).unwrap();
        assert_eq!(b.neutral(), neutral.as_slice());
        for (bj, tj) in b.deltas().iter().zip(&truth) {
            for (x, y) in bj.iter().zip(tj) {
                // f32 meshes: exact up to single-precision rounding.
                assert!((*x - *y).length() < 1e-7, "{x} vs {y}");
            }
        }
        // With the regularizer, a subject whose shapes ARE the generic ones
        // is still recovered exactly (both energy terms vanish).
        let meshes: Vec<Vec<Vec3>> = ws
            .iter()
            .map(|w| render(&neutral, generic.deltas(), w))
            .collect();
        let obs = captures(&ws, &meshes);
        let b = BlendshapeFit::new(&generic, &d, &[true; 52], &obs)
            .solve(1.0)
            .unwrap();
        for (bj, tj) in b.deltas().iter().zip(generic.deltas()) {
            for (x, y) in bj.iter().zip(tj) {
                assert!((*x - *y).length() < 1e-7);
            }
        }
    }

    #[test]
    fn parts_of_different_sizes_are_an_error_not_a_panic() {
        use crate::geometry::deformation_transfer::{Contacts, DeformationTransfer};
        use crate::geometry::topology::Topology;
        let n = 4;
        let generic = Blendshapes::new(vec![DVec3::ZERO; n], shapes(n, 0.0)).unwrap();
        let d = vec![vec![1.0; n]; 52];
        let ws = capture_weights();
        let meshes: Vec<Vec<Vec3>> = ws.iter().map(|_| vec![Vec3::ZERO; n]).collect();
        // A shape's lid contacts on a mesh of `vertices` (none: it has no eyes).
        let contacts_on = |vertices: usize| -> Contacts {
            let topology = Topology::new(vertices, vec![[0, 1, 2]]).unwrap();
            let rest: Vec<DVec3> = (0..vertices)
                .map(|v| DVec3::new(v as f64, (v * v) as f64, 0.0) * 0.01)
                .collect();
            let dt = DeformationTransfer::new(&topology, &[], &rest).unwrap();
            dt.contacts(&rest, &rest).unwrap()
        };
        let own = vec![contacts_on(n); 52];
        let sized = |weights: &[Vec<f64>], meshes: &[Vec<Vec3>], contacts: &[Contacts]| {
            let obs = captures(&ws, meshes);
            let fit = BlendshapeFit::new(&generic, weights, &[true; 52], &obs);
            match fit.closing_lids(contacts).solve(1.0) {
                Err(PersonalizeError::Size {
                    expected, found, ..
                }) => (expected, found),
                other => panic!("expected a size error, got {other:?}"),
            }
        };
        let size = |weights: &[Vec<f64>], meshes: &[Vec<Vec3>]| sized(weights, meshes, &own);
        assert_eq!(sized(&d, &meshes, &vec![contacts_on(3); 52]), (n, 3));
        assert_eq!(sized(&d, &meshes, &own[..51]), (52, 51));
        let mut short = meshes.clone();
        short[7].pop();
        assert_eq!(size(&d, &short), (n, n - 1));
        let mut long = meshes.clone();
        long[0].push(Vec3::ZERO);
        assert_eq!(size(&d, &long), (n, n + 1));
        assert_eq!(size(&d[..51], &meshes), (52, 51));
        let mut ragged = d.clone();
        ragged[3].push(1.0);
        assert_eq!(size(&ragged, &meshes), (n, n + 1));
        // Contacts of this face that close nothing change nothing.
        let fit = || BlendshapeFit::new(&generic, &d, &[true; 52], &captures(&ws, &meshes));
        let closed = fit().closing_lids(&own).solve(1.0).unwrap();
        assert_eq!(closed.deltas(), fit().solve(1.0).unwrap().deltas());
    }

    #[test]
    fn strong_regularization_returns_the_generic_shapes_and_uncaptured_shapes_stay_generic() {
        let n = 5;
        let neutral = vec![DVec3::ZERO; n];
        let truth = shapes(n, 0.0);
        let generic = Blendshapes::new(neutral.clone(), shapes(n, 2.0)).unwrap();
        let ws = capture_weights();
        let meshes: Vec<Vec<Vec3>> = ws.iter().map(|w| render(&neutral, &truth, w)).collect();
        let obs = captures(&ws, &meshes);
        let mut captured = [true; 52];
        captured[3] = false;
        let d = vec![vec![1e5; n]; 52];
        let b = BlendshapeFit::new(&generic, &d, &captured, &obs)
            .solve(1.0)
            .unwrap();
        assert_eq!(b.deltas()[3], generic.deltas()[3]);
        for (bj, tj) in b.deltas().iter().zip(generic.deltas()) {
            for (x, y) in bj.iter().zip(tj) {
                assert!((*x - *y).length() < 1e-9);
            }
        }
    }
}
