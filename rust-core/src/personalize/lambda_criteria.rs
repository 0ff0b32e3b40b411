//! Criteria for the weight λ of `E_reg` computed from the fitted captures
//! alone, with no held-out frames: generalized cross-validation (the rule
//! `paper-cv` and `multi` use) and the marginal likelihood (evidence), and
//! how both are evaluated for any λ at a cost of O(k) per vertex once each
//! vertex's system has been reduced to tridiagonal form.
//!
//! # The fit as a linear smoother
//!
//! Per vertex `v` and axis, the fit of [`super::blendshape_fit`] is the
//! ridge problem
//!
//! ```text
//! min_b ‖y − W b‖² + λ ‖D (b − t)‖²,   A = WᵀW + λD²,   b̂ = t + δ,   δ = A⁻¹ Wᵀ y',
//! ```
//!
//! with `y` (m) the observed coordinates less `B₀` and the uncaptured
//! shapes, `W` (m × k) the tracked weights of the `k` unknown shapes, `t`
//! the generic shapes' coordinates, `y' = y − W t` the deviation of the
//! data from the generic prediction and `D = D_v` the Eq. (3) weights of
//! the vertex (importances `c_i` are folded in: `y ← C^½ y`, `W ← C^½ W`).
//! The fitted deviation is `W δ = H y'` with the hat (influence) matrix
//! `H = W A⁻¹ Wᵀ`.
//!
//! # Generalized cross-validation (the rule)
//!
//! GCV (Craven & Wahba 1979; Golub, Heath & Wahba 1979, Technometrics
//! 21(2)) estimates the error of predicting new observations from the
//! residuals and the degrees of freedom the fit leaves: pooled over `N`
//! coordinates (vertex × axis) of `m` observations,
//!
//! ```text
//! V(λ) = [Σ_c ‖(I − H_c) y'_c‖² / (N m)] / [Σ_c tr(I − H_c) / (N m)]²,
//! tr(I − H) = m − tr(A⁻¹ WᵀW) = m − k + λ tr(D² A⁻¹).
//! ```
//!
//! It assumes nothing about how a person's shapes deviate from the generic
//! ones, only that the data noise is exchangeable, and it is asymptotically
//! optimal for the prediction error (Li 1986, Annals of Statistics 14(3)).
//! With as many captures as unknown shapes (`m = k`, the paper's case) the
//! fit interpolates as `λ → 0`: the denominator vanishes like `λ` and the
//! numerator like `λ²`, so `V` tends to a finite value there and both are
//! computed without cancellation (below).
//!
//! # The evidence (for comparison)
//!
//! The fit is also the posterior mean of `b ~ N(t, σ²(λD²)⁻¹)`,
//! `y | b ~ N(W b, σ² I)` (MacKay 1992, "Bayesian interpolation", Neural
//! Computation 4(3)), under which `y' ~ N(0, σ² K)`, `K = I + W (λD²)⁻¹
//! Wᵀ`. By Woodbury `y'ᵀK⁻¹y' = y'ᵀy' − gᵀδ =: Q` with `g = Wᵀy'` (`Q` is
//! the minimum of the fit's energy, `‖y' − Wδ‖² + λ‖Dδ‖²`), and by the
//! matrix determinant lemma `det K = det A / det(λD²)`. With one `σ²` for
//! all coordinates, profiled out at `σ̂² = Σ_c Q_c / (N m)`,
//!
//! ```text
//! −2 ln p(y' | λ, σ̂²) / (N m) = ln σ̂²(λ) + Σ_c ln det K_c / (N m) + 1 + ln 2π,
//! ```
//!
//! minimized over λ (type-II maximum likelihood). Its optimum is right when
//! the prior is: when the person's deviations `b − t` really scale like
//! `D⁻¹`, i.e. like the template's own motion. Eq. (3) is a heuristic, not
//! a calibrated prior, and on the simulated subjects the evidence settles
//! one to three decades above the λ that predicts best, at a different
//! mode on different vertex samples; GCV, which needs no prior, is within a
//! few per cent of the best (Wahba 1985, Annals of Statistics 13(4),
//! compares the two: the likelihood wins when the prior is right, GCV when
//! it is not).
//!
//! # Every λ at O(k) per vertex
//!
//! `A = D (M + λI) D` with `M = D⁻¹ WᵀW D⁻¹`, which does not depend on λ.
//! Each sampled vertex's `M` is reduced once, by Householder reflections,
//! to a symmetric tridiagonal `T = Pᵀ M P` (diagonal `α`, off-diagonal
//! `β`), and `h' = Pᵀ D⁻¹ g` is formed. For a λ, with `J = T + λI`, its
//! forward pivots `p₀ = J₀₀`, `p_i = J_ii − β²_{i−1}/p_{i−1}`, backward
//! `u = J⁻¹ h'` (one tridiagonal solve per axis):
//!
//! - `gᵀδ = h'ᵀu` and `λ‖Dδ‖² = λ‖u‖²`, so `Q = y'ᵀy' − h'ᵀu` and
//!   `‖(I − H) y'‖² = Q − λ‖u‖²`;
//! - `ln det K = ln det J − k ln λ = Σ_i ln p_i − k ln λ`;
//! - `tr(D² A⁻¹) = tr(J⁻¹) = d ln det J / dλ = Σ_i p'_i / p_i`, with the
//!   derivatives of the pivots carried along the same recurrence,
//!   `p'₀ = 1`, `p'_i = 1 + β²_{i−1} p'_{i−1} / p²_{i−1}`.
//!
//! The only cancellation is in `Q` and the residual as the fit nears
//! interpolation, where they are a negligible part of the pooled sums.
//!
//! # Cost
//!
//! The reduction costs `4k³/3` flops per vertex, about four `k × k`
//! Cholesky factorizations, the criteria then O(k) per λ. They are evaluated on a fixed,
//! deterministic sample of vertices ([`criteria_sample`]), stratified by how
//! far the template moves them, so that preparing the criteria costs about
//! one fit and the search over λ ([`super::lambda_selection`]) a fraction
//! of one.

use super::blendshape_fit::{BlendshapeFit, in_parallel_ranges};
use super::error::PersonalizeError;
use crate::arkit::Blendshapes;
use faer::Mat;

/// One vertex in every this many is used by the criteria (at least
/// [`MIN_SAMPLE`]), stratified by template motion (see
/// [`criteria_sample`]).
pub const SAMPLE_STRIDE: usize = 6;

/// The fewest vertices the criteria use (all of them on a smaller mesh).
pub const MIN_SAMPLE: usize = 32;

/// The vertices whose coordinates the criteria use: of the `n` vertices of
/// `generic`, sorted by how far the unknown shapes (`unknowns`, Apple's
/// indices) move them in the template (`Σ_j ‖t_vj‖`, ties by index), one
/// in every `stride` (the middle one of each run of `stride`), where
/// `stride` is [`SAMPLE_STRIDE`], or less to keep at least [`MIN_SAMPLE`].
/// Every level of motion, from the still forehead to the lips, is
/// represented in proportion. Returned in increasing vertex order.
pub fn criteria_sample(generic: &Blendshapes, unknowns: &[usize]) -> Vec<usize> {
    let n = generic.vertex_count();
    let deltas = generic.deltas();
    // Indexing: `unknowns` are shape indices below 52 and every delta has
    // `n` vertices (a checked set of blendshapes).
    let motion: Vec<f64> = (0..n)
        .map(|v| unknowns.iter().map(|&j| deltas[j][v].length()).sum())
        .collect();
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|a, b| motion[*a].total_cmp(&motion[*b]).then(a.cmp(b)));
    let stride = SAMPLE_STRIDE.min(n / MIN_SAMPLE).max(1);
    let mut sample: Vec<usize> = order.into_iter().skip(stride / 2).step_by(stride).collect();
    sample.sort_unstable();
    sample
}

/// The sums over the sampled coordinates that the criteria need, at one λ.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RidgeTerms {
    /// The λ they were computed for.
    pub lambda: f64,
    /// `N`: coordinates (vertex × axis) summed over.
    pub coordinates: usize,
    /// `m`: observations per coordinate.
    pub observations: usize,
    /// `Σ_c Q_c = Σ_c ‖y' − Wδ‖² + λ‖Dδ‖²` (m²).
    pub energy: f64,
    /// `Σ_c ‖y' − Wδ‖²` (m²), the residual sum of squares.
    pub residual: f64,
    /// `Σ_c tr(I − H_c)`.
    pub residual_dof: f64,
    /// `Σ_c ln det K_c`, if computed (for the evidence).
    pub log_det: Option<f64>,
}

impl RidgeTerms {
    /// Generalized cross-validation `V(λ)` (m², smaller is better).
    pub fn gcv(&self) -> f64 {
        let data = (self.coordinates * self.observations).max(1) as f64;
        let dof = self.residual_dof / data;
        (self.residual / data) / (dof * dof)
    }

    /// The profiled negative log evidence per datum, `ln σ̂² + Σ ln det K /
    /// (N m)` (module docs; smaller is better), if `ln det K` was computed.
    /// `σ̂²` is in m², so the value is dominated by `ln σ̂²` ≈ −20 for
    /// tenths of a millimetre.
    pub fn evidence(&self) -> Option<f64> {
        let data = (self.coordinates * self.observations).max(1) as f64;
        Some((self.energy / data).ln() + self.log_det? / data)
    }
}

/// The criteria of one assembled fit on a sample of its vertices, each
/// vertex's system reduced to tridiagonal form once (module docs); each λ
/// then costs O(k) per sampled vertex.
pub struct RidgeCriteria {
    /// `k`, the unknown shapes.
    k: usize,
    /// `m`, the observations.
    m: usize,
    /// The diagonal `α` of `T`, `k` per sampled vertex.
    alpha: Vec<f64>,
    /// The off-diagonal `β` of `T`, `k` per sampled vertex (the last 0).
    beta: Vec<f64>,
    /// `h' = Pᵀ D⁻¹ Wᵀ y'`, `3k` per sampled vertex (axis-major).
    h: Vec<f64>,
    /// `y'ᵀy'` of each axis, 3 per sampled vertex.
    yy: Vec<f64>,
    /// The sampled vertices.
    vertices: Vec<usize>,
    /// Why the fit cannot be evaluated (its parts do not fit together).
    mismatch: Option<PersonalizeError>,
}

/// One sampled vertex reduced: `α`, `β`, `h'` and `y'ᵀy'`.
type Reduced = (Vec<f64>, Vec<f64>, Vec<f64>, [f64; 3]);

impl RidgeCriteria {
    /// Prepares the criteria of `fit` on its [`criteria_sample`].
    pub fn new(fit: &BlendshapeFit<'_>) -> RidgeCriteria {
        let vertices = criteria_sample(fit.generic(), fit.unknowns());
        RidgeCriteria::on_vertices(fit, vertices)
    }

    /// Prepares the criteria of `fit` on the given `vertices` (all of them,
    /// for a check of the sample; indices past the mesh are skipped).
    pub fn on_vertices(fit: &BlendshapeFit<'_>, vertices: Vec<usize>) -> RidgeCriteria {
        let k = fit.unknowns().len();
        let m = fit.design().nrows();
        let n = fit.generic().vertex_count();
        // Indexing: the fit's columns are `3n` when its parts fit together
        // (otherwise nothing is sampled), and every vertex kept is below `n`.
        let mismatch = fit.mismatch().cloned();
        let vertices: Vec<usize> = match mismatch {
            Some(_) => Vec::new(),
            None => vertices.into_iter().filter(|v| *v < n).collect(),
        };
        let parts = in_parallel_ranges(vertices.len(), |range| {
            let mut scratch = Reduction::new(k);
            range
                .map(|s| scratch.reduce(fit, vertices[s]))
                .collect::<Vec<Reduced>>()
        });
        let mut criteria = RidgeCriteria {
            k,
            m,
            alpha: Vec::with_capacity(vertices.len() * k),
            beta: Vec::with_capacity(vertices.len() * k),
            h: Vec::with_capacity(vertices.len() * 3 * k),
            yy: Vec::with_capacity(vertices.len() * 3),
            vertices,
            mismatch,
        };
        for (alpha, beta, h, yy) in parts.into_iter().flatten().flatten() {
            criteria.alpha.extend(alpha);
            criteria.beta.extend(beta);
            criteria.h.extend(h);
            criteria.yy.extend(yy);
        }
        if criteria.yy.len() != 3 * criteria.vertices.len() {
            // A reduction thread panicked: evaluate nothing rather than
            // something partial.
            criteria.mismatch = Some(PersonalizeError::Size {
                what: "reduced vertices of the λ criteria".to_string(),
                expected: criteria.vertices.len(),
                found: criteria.yy.len() / 3,
            });
        }
        criteria
    }

    /// The sampled vertices.
    pub fn vertices(&self) -> &[usize] {
        &self.vertices
    }

    /// The sums at `lambda` (> 0); with `with_log_det`, also `Σ ln det K`
    /// (for the evidence).
    pub fn terms(&self, lambda: f64, with_log_det: bool) -> Result<RidgeTerms, PersonalizeError> {
        if let Some(mismatch) = &self.mismatch {
            return Err(mismatch.clone());
        }
        let mut terms = RidgeTerms {
            lambda,
            coordinates: 3 * self.vertices.len(),
            observations: self.m,
            log_det: with_log_det.then_some(0.0),
            ..RidgeTerms::default()
        };
        // One thread: an evaluation is too short (~0.2 ms) to pay for
        // spawning more.
        let part = self.partial_terms(0..self.vertices.len(), lambda, with_log_det);
        terms.energy = part.energy;
        terms.residual = part.residual;
        terms.residual_dof = part.residual_dof;
        terms.log_det = part.log_det;
        Ok(terms)
    }

    /// The sums over the sampled vertices of `range` (module docs: the
    /// pivots of `J = T + λI`, `u = J⁻¹h'` and the diagonal of `J⁻¹`).
    fn partial_terms(
        &self,
        range: std::ops::Range<usize>,
        lambda: f64,
        with_log_det: bool,
    ) -> RidgeTerms {
        let (k, m) = (self.k, self.m);
        let mut terms = RidgeTerms {
            log_det: with_log_det.then_some(0.0),
            ..RidgeTerms::default()
        };
        // `r` the reciprocals of the forward pivots `p_i` of `J = T + λI`,
        // `u` the three solutions, axis-major.
        let (mut r, mut u) = (vec![0.0; k], vec![0.0; 3 * k]);
        // Indexing: `alpha`, `beta` have `k`, `h` `3k` and `yy` 3 entries
        // per sampled vertex (checked in `on_vertices`); `i - 1` is taken
        // for `i > 0` only.
        for s in range {
            let alpha = &self.alpha[s * k..(s + 1) * k];
            let beta = &self.beta[s * k..(s + 1) * k];
            let h = &self.h[3 * s * k..3 * (s + 1) * k];
            // Forward elimination, fused: the pivots `p_i`, their
            // derivatives `p'_i = dp_i/dλ` (so that `tr J⁻¹ = d ln det J / dλ
            // = Σ p'_i / p_i`, no second pass), `ln det J = Σ ln p_i`, and
            // the eliminated right-hand sides.
            let mut dp = 1.0;
            let (mut trace_inverse, mut product, mut log_det) = (0.0, 1.0, 0.0);
            for i in 0..k {
                let p;
                if i > 0 {
                    let b2r = beta[i - 1] * beta[i - 1] * r[i - 1];
                    p = alpha[i] + lambda - b2r;
                    dp = 1.0 + b2r * r[i - 1] * dp;
                    let l = beta[i - 1] * r[i - 1];
                    for axis in 0..3 {
                        u[axis * k + i] = h[axis * k + i] - l * u[axis * k + i - 1];
                    }
                } else {
                    p = alpha[0] + lambda;
                    for axis in 0..3 {
                        u[axis * k] = h[axis * k];
                    }
                }
                r[i] = 1.0 / p;
                trace_inverse += dp * r[i];
                if with_log_det {
                    // One logarithm per eight pivots (each within 10^±30
                    // here, so eight never overflow).
                    product *= p;
                    if i % 8 == 7 || i + 1 == k {
                        log_det += product.ln();
                        product = 1.0;
                    }
                }
            }
            terms.residual_dof += 3.0 * ((m as f64) - (k as f64) + lambda * trace_inverse);
            if let Some(total) = terms.log_det.as_mut() {
                *total += 3.0 * (log_det - k as f64 * lambda.ln());
            }
            // Back substitution of the three axes together (independent
            // chains), then `h'ᵀu` and `‖u‖²` of each.
            let mut next = [0.0; 3];
            for i in (0..k).rev() {
                let b = if i + 1 < k { beta[i] } else { 0.0 };
                for (axis, next) in next.iter_mut().enumerate() {
                    let ui = (u[axis * k + i] - b * *next) * r[i];
                    u[axis * k + i] = ui;
                    *next = ui;
                }
            }
            for axis in 0..3 {
                let u = &u[axis * k..(axis + 1) * k];
                let h = &h[axis * k..(axis + 1) * k];
                let hu: f64 = h.iter().zip(u).map(|(a, b)| a * b).sum();
                let uu: f64 = u.iter().map(|x| x * x).sum();
                let energy = (self.yy[3 * s + axis] - hu).max(0.0);
                terms.energy += energy;
                terms.residual += (energy - lambda * uu).max(0.0);
            }
        }
        terms
    }
}

/// Scratch space for reducing one vertex after another.
struct Reduction {
    k: usize,
    /// `M`, then its reduction in progress: `k × k`, row-major, full.
    m_mat: Vec<f64>,
    /// A Householder vector, and `p`, `w` of its update.
    v: Vec<f64>,
    p: Vec<f64>,
}

impl Reduction {
    fn new(k: usize) -> Reduction {
        Reduction {
            k,
            m_mat: vec![0.0; k * k],
            v: vec![0.0; k],
            p: vec![0.0; k],
        }
    }

    /// Vertex `v` of `fit`: `y' = y − W t` and `g = Wᵀ y'` of its three
    /// axes, `M = D⁻¹ WᵀW D⁻¹` reduced to `T = Pᵀ M P`, and `h' = Pᵀ D⁻¹ g`.
    fn reduce(&mut self, fit: &BlendshapeFit<'_>, v: usize) -> Reduced {
        let k = self.k;
        let unknowns = fit.unknowns();
        let design = fit.design();
        let deltas = fit.generic().deltas();
        // Indexing: `v` is a vertex of the fit, shape indices are below 52,
        // and `m_mat` is `k × k`, `v`, `p` and each axis of `h` `k` long.
        let inverse_d: Vec<f64> = unknowns
            .iter()
            .map(|&j| 1.0 / fit.d2(v, j).sqrt())
            .collect();
        let t = Mat::from_fn(k, 3, |a, axis| deltas[unknowns[a]][v][axis]);
        let predicted = design * &t;
        let y = Mat::from_fn(design.nrows(), 3, |i, axis| {
            fit.observed(3 * v + axis)[i] - predicted[(i, axis)]
        });
        let yy = [0, 1, 2].map(|axis| y.col(axis).squared_norm_l2());
        let g = design.transpose() * &y;
        let gram = fit.gram();
        let mut h: Vec<f64> = (0..3)
            .flat_map(|axis| (0..k).map(move |a| (axis, a)))
            .map(|(axis, a)| g[(a, axis)] * inverse_d[a])
            .collect();
        for a in 0..k {
            for b in 0..k {
                self.m_mat[a * k + b] = gram[(a, b)] * inverse_d[a] * inverse_d[b];
            }
        }
        self.tridiagonalize(&mut h);
        let alpha: Vec<f64> = (0..k).map(|i| self.m_mat[i * k + i]).collect();
        let beta: Vec<f64> = (0..k)
            .map(|i| {
                if i + 1 < k {
                    self.m_mat[(i + 1) * k + i]
                } else {
                    0.0
                }
            })
            .collect();
        (alpha, beta, h, yy)
    }

    /// Householder tridiagonalization of the symmetric `m_mat` in place
    /// (Golub & Van Loan, Matrix Computations, §8.3.1): for each column
    /// `j`, the reflection `I − τ x xᵀ` that zeroes the column below its
    /// subdiagonal is applied from both sides to the trailing block, as
    /// the rank-2 update `A ← A − x wᵀ − w xᵀ`, `w = p − (τ pᵀx / 2) x`,
    /// `p = τ A x`; and from the left to the three axes of `h`. Afterwards
    /// the diagonal and subdiagonal of `m_mat` hold `T`, and `h` is `Pᵀ h`.
    /// Full storage keeps every loop a contiguous, vectorizable `axpy`.
    /// Written out rather than calling faer's `tridiag_in_place` (plus its
    /// block Householder application to `h`): at k = 52 faer's blocked
    /// routine took 13.2 ms for the 203 sampled vertices against 9.2 ms for
    /// this one (criterion, `choice of λ: reduction`, this machine), which
    /// would make choosing λ cost more than one fit.
    fn tridiagonalize(&mut self, h: &mut [f64]) {
        let k = self.k;
        let (a, x, p) = (&mut self.m_mat, &mut self.v, &mut self.p);
        for j in 0..k.saturating_sub(2) {
            let (lo, n) = (j + 1, k - j - 1);
            // The column below the diagonal, and its reflection vector
            // x = c − σ e₁ with σ = −sign(c₀) ‖c‖.
            let mut norm2 = 0.0;
            for i in 0..n {
                x[i] = a[(lo + i) * k + j];
                norm2 += x[i] * x[i];
            }
            let sigma = if x[0] >= 0.0 {
                -norm2.sqrt()
            } else {
                norm2.sqrt()
            };
            let tail = norm2 - x[0] * x[0];
            if tail <= f64::MIN_POSITIVE {
                continue; // already tridiagonal in this column
            }
            x[0] -= sigma;
            let tau = 2.0 / (tail + x[0] * x[0]);
            // p = τ A₂₂ x, as a sum of the rows of the symmetric block.
            p[..n].fill(0.0);
            for l in 0..n {
                let row = &a[(lo + l) * k + lo..(lo + l) * k + k];
                let coefficient = tau * x[l];
                for (pi, ai) in p[..n].iter_mut().zip(row) {
                    *pi += coefficient * ai;
                }
            }
            let half: f64 = 0.5 * tau * p[..n].iter().zip(&x[..n]).map(|(a, b)| a * b).sum::<f64>();
            for i in 0..n {
                p[i] -= half * x[i];
            }
            // A₂₂ ← A₂₂ − x wᵀ − w xᵀ (w in `p`).
            for l in 0..n {
                let (xl, wl) = (x[l], p[l]);
                let row = &mut a[(lo + l) * k + lo..(lo + l) * k + k];
                for ((ai, xi), wi) in row.iter_mut().zip(&x[..n]).zip(&p[..n]) {
                    *ai -= xl * wi + wl * xi;
                }
            }
            // The reflected column: σ below the diagonal, zeros under it.
            a[lo * k + j] = sigma;
            a[j * k + lo] = sigma;
            for i in 1..n {
                a[(lo + i) * k + j] = 0.0;
                a[j * k + lo + i] = 0.0;
            }
            for axis in 0..3 {
                let part = &mut h[axis * k + lo..(axis + 1) * k];
                let dot: f64 = part.iter().zip(&x[..n]).map(|(a, b)| a * b).sum();
                for (hi, xi) in part.iter_mut().zip(&x[..n]) {
                    *hi -= tau * dot * xi;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::arkit::{BLENDSHAPE_COUNT, Blendshapes};
    use crate::personalize::blendshape_fit::Observation;
    use glam::{DVec3, Vec3};

    /// A tiny problem: 6 vertices, 4 captured shapes, 7 observations with
    /// unequal importances, Eq. (3)-like weights that differ per vertex.
    struct Tiny {
        generic: Blendshapes,
        weights: Vec<Vec<f64>>,
        captured: [bool; BLENDSHAPE_COUNT],
        ws: Vec<[f64; BLENDSHAPE_COUNT]>,
        meshes: Vec<Vec<Vec3>>,
        importance: Vec<f64>,
    }

    fn wave(x: f64) -> f64 {
        (x * 12.9898).sin() * 0.5 + (x * 4.1414).cos() * 0.5
    }

    fn tiny() -> Tiny {
        let n = 6;
        let neutral: Vec<DVec3> = (0..n).map(|v| DVec3::splat(v as f64 * 0.01)).collect();
        let deltas: Vec<Vec<DVec3>> = (0..BLENDSHAPE_COUNT)
            .map(|j| {
                (0..n)
                    .map(|v| {
                        let x = (j * 7 + v * 3) as f64;
                        DVec3::new(wave(x), wave(x + 0.3), wave(x + 0.7)) * 1e-3
                    })
                    .collect()
            })
            .collect();
        let generic = Blendshapes::new(neutral.clone(), deltas).unwrap();
        let weights: Vec<Vec<f64>> = (0..BLENDSHAPE_COUNT)
            .map(|j| (0..n).map(|v| 1.0 + ((j + 2 * v) % 5) as f64).collect())
            .collect();
        let mut captured = [false; BLENDSHAPE_COUNT];
        for j in [2, 5, 11, 30] {
            captured[j] = true;
        }
        let ws: Vec<[f64; BLENDSHAPE_COUNT]> = (0..7)
            .map(|i| std::array::from_fn(|j| 0.5 + 0.5 * wave((i * 52 + j) as f64)))
            .collect();
        let meshes: Vec<Vec<Vec3>> = (0..7)
            .map(|i| {
                (0..n)
                    .map(|v| {
                        let x = (i * 13 + v * 5) as f64;
                        (neutral[v] + DVec3::new(wave(x), wave(x + 1.1), wave(x + 2.3)) * 2e-3)
                            .as_vec3()
                    })
                    .collect()
            })
            .collect();
        let importance = vec![1.0, 0.5, 2.0, 1.0, 0.25, 1.0, 1.5];
        Tiny {
            generic,
            weights,
            captured,
            ws,
            meshes,
            importance,
        }
    }

    /// Natural logarithm of the determinant of a symmetric positive definite
    /// matrix, and the solution of `M x = b`, by plain Gaussian elimination.
    fn log_det_and_solve(m: &Mat<f64>, b: &Mat<f64>) -> (f64, Mat<f64>) {
        let n = m.nrows();
        let mut a = m.clone();
        let mut x = b.clone();
        let mut log_det = 0.0;
        for p in 0..n {
            log_det += a[(p, p)].ln();
            for i in p + 1..n {
                let f = a[(i, p)] / a[(p, p)];
                for j in p..n {
                    a[(i, j)] -= f * a[(p, j)];
                }
                for c in 0..x.ncols() {
                    x[(i, c)] -= f * x[(p, c)];
                }
            }
        }
        for p in (0..n).rev() {
            for c in 0..x.ncols() {
                let mut s = x[(p, c)];
                for j in p + 1..n {
                    s -= a[(p, j)] * x[(j, c)];
                }
                x[(p, c)] = s / a[(p, p)];
            }
        }
        (log_det, x)
    }

    /// Brute force: per vertex and axis, the m × m covariance `K = I + W
    /// (λD²)⁻¹ Wᵀ` formed explicitly, `y'ᵀK⁻¹y'` and `ln det K` by
    /// elimination; the hat matrix `H = W (WᵀW + λD²)⁻¹ Wᵀ` likewise.
    fn brute_force(t: &Tiny, lambda: f64) -> RidgeTerms {
        let unknowns: Vec<usize> = (0..BLENDSHAPE_COUNT).filter(|j| t.captured[*j]).collect();
        let (m, k, n) = (t.ws.len(), unknowns.len(), t.generic.vertex_count());
        let w = Mat::from_fn(m, k, |i, a| t.importance[i].sqrt() * t.ws[i][unknowns[a]]);
        let mut terms = RidgeTerms {
            lambda,
            coordinates: 3 * n,
            observations: m,
            log_det: Some(0.0),
            ..RidgeTerms::default()
        };
        for v in 0..n {
            let d2: Vec<f64> = unknowns.iter().map(|&j| t.weights[j][v].powi(2)).collect();
            let k_mat = Mat::from_fn(m, m, |i, l| {
                let prior: f64 = (0..k)
                    .map(|a| w[(i, a)] * w[(l, a)] / (lambda * d2[a]))
                    .sum();
                prior + if i == l { 1.0 } else { 0.0 }
            });
            let a_mat = Mat::from_fn(k, k, |a, b| {
                (0..m).map(|i| w[(i, a)] * w[(i, b)]).sum::<f64>()
                    + if a == b { lambda * d2[a] } else { 0.0 }
            });
            let (_, a_inv) = log_det_and_solve(&a_mat, &Mat::identity(k, k));
            let hat = &w * &a_inv * w.transpose();
            let mut vertex_energy = 0.0;
            for axis in 0..3 {
                let y = Mat::from_fn(m, 1, |i, _| {
                    let o = &t.ws[i];
                    let mut x = f64::from(t.meshes[i][v][axis]) - t.generic.neutral()[v][axis];
                    for (wj, tj) in o.iter().zip(t.generic.deltas()) {
                        x -= wj * tj[v][axis];
                    }
                    t.importance[i].sqrt() * x
                });
                let (log_det, solved) = log_det_and_solve(&k_mat, &y);
                vertex_energy += (y.transpose() * &solved)[(0, 0)];
                *terms.log_det.as_mut().unwrap() += log_det;
                let fitted = &y - &hat * &y;
                terms.residual += fitted.squared_norm_l2();
                terms.residual_dof += (0..m).map(|i| 1.0 - hat[(i, i)]).sum::<f64>();
            }
            terms.energy += vertex_energy;
        }
        terms
    }

    #[test]
    fn the_criteria_from_the_tridiagonal_form_equal_the_brute_force_ones() {
        let t = tiny();
        let observations: Vec<Observation> =
            t.ws.iter()
                .zip(&t.meshes)
                .zip(&t.importance)
                .map(|((w, m), c)| Observation {
                    weights: *w,
                    vertices: m,
                    importance: *c,
                })
                .collect();
        let fit = BlendshapeFit::new(&t.generic, &t.weights, &t.captured, &observations);
        let all = RidgeCriteria::on_vertices(&fit, (0..6).collect());
        assert_eq!(all.vertices(), RidgeCriteria::new(&fit).vertices());
        for lambda in [1e-8, 1e-6, 1e-3, 0.1, 1.0, 30.0] {
            let fast = all.terms(lambda, true).unwrap();
            let slow = brute_force(&t, lambda);
            // The brute force's K has entries up to 1/λ: at λ = 1e-8 it is
            // itself good to only about eight digits.
            let tol = if lambda < 1e-6 { 1e-7 } else { 1e-9 };
            let close = |a: f64, b: f64| (a - b).abs() <= tol * a.abs().max(b.abs()).max(1e-12);
            assert!(close(fast.energy, slow.energy), "{fast:?} vs {slow:?}");
            assert!(close(fast.residual, slow.residual), "{fast:?} vs {slow:?}");
            let (fl, sl) = (fast.log_det.unwrap(), slow.log_det.unwrap());
            assert!(
                (fl - sl).abs() < tol * sl.abs().max(1.0),
                "{fast:?} vs {slow:?}"
            );
            assert!(
                close(fast.residual_dof, slow.residual_dof),
                "{fast:?} vs {slow:?}"
            );
            assert!(close(fast.gcv(), slow.gcv()));
            assert!((fast.evidence().unwrap() - slow.evidence().unwrap()).abs() < tol);
            assert_eq!((fast.coordinates, fast.observations), (18, 7));
            // The energy is the fit's own minimum: E_fit + λ E_reg at the
            // solution, with the generic deviation of the fixed shapes.
            let shapes = fit.solve(lambda).unwrap();
            let mut energy = 0.0;
            for (i, w) in t.ws.iter().enumerate() {
                let mut e = 0.0;
                for v in 0..6 {
                    let mut p = t.generic.neutral()[v];
                    for (wj, bj) in w.iter().zip(shapes.deltas()) {
                        p += *wj * bj[v];
                    }
                    e += (p - t.meshes[i][v].as_dvec3()).length_squared();
                }
                energy += t.importance[i] * e;
            }
            for (j, shape) in shapes.deltas().iter().enumerate() {
                for (v, b) in shape.iter().enumerate() {
                    let dev = *b - t.generic.deltas()[j][v];
                    energy += lambda * t.weights[j][v].powi(2) * dev.length_squared();
                }
            }
            assert!(close(fast.energy, energy), "{} vs {energy}", fast.energy);
        }
        // Without `ln det K` there is no evidence, and a subset is a subset.
        let two = RidgeCriteria::on_vertices(&fit, vec![1, 4, 99]);
        assert_eq!(two.vertices(), &[1, 4]);
        let terms = two.terms(0.1, false).unwrap();
        assert_eq!(terms.log_det, None);
        assert_eq!(terms.evidence(), None);
        assert_eq!(terms.coordinates, 6);
    }

    #[test]
    fn the_sample_is_stratified_and_deterministic() {
        let t = tiny();
        let unknowns = [2, 5, 11, 30];
        // Six vertices: fewer than MIN_SAMPLE, so every one is used.
        assert_eq!(
            criteria_sample(&t.generic, &unknowns),
            (0..6).collect::<Vec<_>>()
        );
        let n = 1000;
        let neutral = vec![DVec3::ZERO; n];
        let deltas: Vec<Vec<DVec3>> = (0..BLENDSHAPE_COUNT)
            .map(|_| (0..n).map(|v| DVec3::X * ((v * 7919) % n) as f64).collect())
            .collect();
        let big = Blendshapes::new(neutral, deltas).unwrap();
        let sample = criteria_sample(&big, &unknowns);
        assert_eq!(sample, criteria_sample(&big, &unknowns));
        assert!(sample.windows(2).all(|w| w[0] < w[1]));
        // Motions (v · 7919) mod n are a permutation of 0..n: the sample
        // takes the middle one of every run of SAMPLE_STRIDE, by motion.
        let mut motions: Vec<usize> = sample.iter().map(|v| (v * 7919) % n).collect();
        motions.sort_unstable();
        let expected: Vec<usize> = (SAMPLE_STRIDE / 2..n).step_by(SAMPLE_STRIDE).collect();
        assert_eq!(motions, expected);
        assert_eq!(sample.len(), n.div_ceil(SAMPLE_STRIDE));
    }
}
