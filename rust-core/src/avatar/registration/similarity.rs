//! Similarity transforms `x ↦ s R x + t` and their least-squares fit to
//! point pairs (Umeyama 1991, "Least-squares estimation of transformation
//! parameters between two point patterns", IEEE TPAMI 13(4)).
//!
//! For pairs `(p_i, q_i)` with weights `w_i`, centroids `p̄`, `q̄`, the
//! weighted cross-covariance `Σ = Σ_i w_i (q_i − q̄)(p_i − p̄)ᵀ / W` has the
//! SVD `U D Vᵀ`; with `S = diag(1, 1, det(U Vᵀ))` (no reflection),
//!
//! ```text
//! R = U S Vᵀ,   s = tr(D S) / σ_p²,   t = q̄ − s R p̄,
//! ```
//!
//! where `σ_p² = Σ_i w_i ‖p_i − p̄‖² / W`. This minimizes
//! `Σ_i w_i ‖s R p_i + t − q_i‖²`.

use faer::Mat;
use glam::{DMat3, DVec3};

/// `x ↦ scale · rotation · x + translation`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Similarity {
    /// Uniform scale (> 0).
    pub scale: f64,
    /// Rotation (orthonormal, determinant +1).
    pub rotation: DMat3,
    /// Translation.
    pub translation: DVec3,
}

impl Similarity {
    /// The identity.
    pub const IDENTITY: Similarity = Similarity {
        scale: 1.0,
        rotation: DMat3::IDENTITY,
        translation: DVec3::ZERO,
    };

    /// Maps a point.
    pub fn apply(&self, p: DVec3) -> DVec3 {
        self.scale * (self.rotation * p) + self.translation
    }

    /// Maps a displacement (no translation).
    pub fn apply_vector(&self, d: DVec3) -> DVec3 {
        self.scale * (self.rotation * d)
    }

    /// `self` after `first`: `x ↦ self(first(x))`.
    pub fn after(&self, first: &Similarity) -> Similarity {
        Similarity {
            scale: self.scale * first.scale,
            rotation: self.rotation * first.rotation,
            translation: self.apply(first.translation),
        }
    }
}

/// The similarity minimizing `Σ_i w_i ‖s R p_i + t − q_i‖²` (module docs).
/// `None` when fewer than three pairs carry weight or the `p_i` are all
/// one point (no scale is defined).
pub fn fit_similarity(p: &[DVec3], q: &[DVec3], w: &[f64]) -> Option<Similarity> {
    fit(p, q, w, true)
}

/// The rigid motion (`s = 1`) minimizing `Σ_i w_i ‖R p_i + t − q_i‖²`:
/// the same construction with the scale held at 1.
pub fn fit_rigid(p: &[DVec3], q: &[DVec3], w: &[f64]) -> Option<Similarity> {
    fit(p, q, w, false)
}

fn fit(p: &[DVec3], q: &[DVec3], w: &[f64], with_scale: bool) -> Option<Similarity> {
    let total: f64 = w.iter().filter(|w| **w > 0.0).sum();
    if w.iter().filter(|w| **w > 0.0).count() < 3 || total <= 0.0 {
        return None;
    }
    let mean = |x: &[DVec3]| x.iter().zip(w).map(|(x, w)| *x * w.max(0.0)).sum::<DVec3>() / total;
    let (pc, qc) = (mean(p), mean(q));
    let mut sigma = [[0.0f64; 3]; 3];
    let mut var_p = 0.0;
    for ((pi, qi), wi) in p.iter().zip(q).zip(w) {
        let wi = wi.max(0.0);
        let (a, b) = (*pi - pc, *qi - qc);
        var_p += wi * a.length_squared();
        for (r, row) in sigma.iter_mut().enumerate() {
            for (c, v) in row.iter_mut().enumerate() {
                *v += wi * b[r] * a[c];
            }
        }
    }
    var_p /= total;
    if var_p <= 0.0 || !var_p.is_finite() {
        return None;
    }
    let m = Mat::<f64>::from_fn(3, 3, |r, c| sigma[r][c] / total);
    let svd = m.svd().ok()?;
    let (u, v, d) = (svd.U(), svd.V(), svd.S());
    let to_glam = |x: faer::MatRef<'_, f64>| {
        DMat3::from_cols_array(&std::array::from_fn(|i| x[(i % 3, i / 3)]))
    };
    let (u, v) = (to_glam(u), to_glam(v));
    let flip = if (u * v.transpose()).determinant() < 0.0 {
        -1.0
    } else {
        1.0
    };
    let s_diag = DVec3::new(1.0, 1.0, flip);
    let rotation = u * DMat3::from_diagonal(s_diag) * v.transpose();
    let d = DVec3::new(d[0], d[1], d[2]);
    let scale = if with_scale {
        d.dot(s_diag) / var_p
    } else {
        1.0
    };
    if !(scale.is_finite() && scale > 0.0) {
        return None;
    }
    Some(Similarity {
        scale,
        rotation,
        translation: qc - scale * (rotation * pc),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_known_similarity_is_recovered() {
        let truth = Similarity {
            scale: 37.5,
            rotation: DMat3::from_euler(glam::EulerRot::XYZ, 0.3, -1.2, 2.0),
            translation: DVec3::new(4.0, -2.0, 100.0),
        };
        let p: Vec<DVec3> = (0..20)
            .map(|i| {
                let f = i as f64;
                DVec3::new((f * 0.7).sin(), (f * 1.3).cos(), (f * 0.4).sin() * 0.5)
            })
            .collect();
        let q: Vec<DVec3> = p.iter().map(|x| truth.apply(*x)).collect();
        let fit = fit_similarity(&p, &q, &[1.0; 20]).expect("well posed");
        assert!((fit.scale - truth.scale).abs() < 1e-9);
        assert!((fit.translation - truth.translation).length() < 1e-8);
        assert!(fit.rotation.abs_diff_eq(truth.rotation, 1e-10));
        assert!(fit_similarity(&p[..2], &q[..2], &[1.0; 2]).is_none());
    }
}
