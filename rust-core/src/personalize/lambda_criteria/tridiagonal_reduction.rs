//! Householder reduction of one vertex's system to symmetric tridiagonal
//! form (Golub & Van Loan, Matrix Computations, §8.3.1), once per sampled
//! vertex, after which the λ criteria of [`super`] cost O(k) per λ.

use super::Reduced;
use crate::personalize::blendshape_fit::BlendshapeFit;
use faer::Mat;

/// Scratch space for reducing one vertex after another.
pub(super) struct Reduction {
    k: usize,
    /// `M`, then its reduction in progress: `k × k`, row-major, full.
    m_mat: Vec<f64>,
    /// A Householder vector, and `p`, `w` of its update.
    v: Vec<f64>,
    p: Vec<f64>,
}

impl Reduction {
    pub(super) fn new(k: usize) -> Reduction {
        Reduction {
            k,
            m_mat: vec![0.0; k * k],
            v: vec![0.0; k],
            p: vec![0.0; k],
        }
    }

    /// Vertex `v` of `fit`: `y' = y − W t` and `g = Wᵀ y'` of its three
    /// axes, `M = D⁻¹ WᵀW D⁻¹` reduced to `T = Pᵀ M P`, and `h' = Pᵀ D⁻¹ g`.
    pub(super) fn reduce(&mut self, fit: &BlendshapeFit<'_>, v: usize) -> Reduced {
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
