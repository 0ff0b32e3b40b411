//! Criteria for the weight λ of `E_reg` computed from the fitted captures
//! alone, with no held-out frames: generalized cross-validation (the rule
//! `paper-cv` and `multi` use) and, for the study, the marginal likelihood
//! (evidence), and
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
//! # The evidence (the study's only, with the `study` feature)
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
//! Each sampled vertex's `M` is reduced once, by Householder reflections
//! (`lambda_criteria/tridiagonal_reduction.rs`),
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
use tridiagonal_reduction::Reduction;

mod tridiagonal_reduction;

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
    /// (N m)` (module docs; smaller is better), if `ln det K` was computed
    /// (the study's only).
    /// `σ̂²` is in m², so the value is dominated by `ln σ̂²` ≈ −20 for
    /// tenths of a millimetre.
    #[cfg(feature = "study")]
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

    /// The sums at `lambda` (> 0).
    pub fn terms(&self, lambda: f64) -> Result<RidgeTerms, PersonalizeError> {
        self.sums(lambda, false)
    }

    /// The sums at `lambda` (> 0) and `Σ ln det K`, for the study's
    /// evidence.
    #[cfg(feature = "study")]
    pub fn terms_with_log_det(&self, lambda: f64) -> Result<RidgeTerms, PersonalizeError> {
        self.sums(lambda, true)
    }

    /// The sums at `lambda`; with `with_log_det`, also `Σ ln det K`.
    fn sums(&self, lambda: f64, with_log_det: bool) -> Result<RidgeTerms, PersonalizeError> {
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

#[cfg(test)]
mod tests;
