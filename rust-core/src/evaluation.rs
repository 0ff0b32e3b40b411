//! §4.1: how faithfully a set of blendshapes reproduces held-out test
//! expressions.
//!
//! For a test expression with tracked weights `w` and recorded mesh `T_i`,
//! the reconstruction is `B_0 + Σ_j w_j B_j`; Eq. (5) gives its RMSE over the
//! `n` vertices, `sqrt(1/n Σ_v ‖·‖²)`, and the maximum vertex error shows the
//! worst spot (the RMSE hides a small region that is badly off). Both are
//! reported in millimetres against the recorded mesh, as the paper does, and
//! against the simulator's noise-free face where the session carries it.

use crate::arkit_names::Weights;
use crate::session::Session;
use glam::{DVec3, Vec3};

/// `B_0 + Σ_j w_j B_j` (the linear blendshape model).
pub fn reconstruct(neutral: &[DVec3], deltas: &[Vec<DVec3>], weights: &Weights) -> Vec<DVec3> {
    let mut out = neutral.to_vec();
    for (delta, w) in deltas.iter().zip(weights.0) {
        if w != 0.0 {
            let w = f64::from(w);
            out.iter_mut().zip(delta).for_each(|(p, d)| *p += w * *d);
        }
    }
    out
}

/// Eq. (5) RMSE and the maximum vertex error of `a` against `b`, in mm.
pub fn rmse_and_max_mm(a: &[DVec3], b: &[Vec3]) -> (f64, f64) {
    let (mut sum, mut max) = (0.0, 0.0f64);
    for (p, q) in a.iter().zip(b) {
        let d2 = (*p - q.as_dvec3()).length_squared();
        sum += d2;
        max = max.max(d2);
    }
    ((sum / a.len().max(1) as f64).sqrt() * 1e3, max.sqrt() * 1e3)
}

/// The errors of one test expression.
#[derive(Clone, Debug, PartialEq)]
pub struct ExpressionError {
    /// The test expression's id.
    pub id: String,
    /// Eq. (5) RMSE against the recorded mesh (mm).
    pub rmse_mm: f64,
    /// Maximum vertex error against the recorded mesh (mm).
    pub max_mm: f64,
    /// RMSE against the noise-free face, if known (mm).
    pub truth_rmse_mm: Option<f64>,
    /// Maximum vertex error against the noise-free face, if known (mm).
    pub truth_max_mm: Option<f64>,
}

/// Errors of the blendshapes (`neutral` = `B_0`, `deltas` = `B_1…B_52`) on
/// every test expression of `session`.
pub fn evaluate(
    neutral: &[DVec3],
    deltas: &[Vec<DVec3>],
    session: &Session,
) -> Vec<ExpressionError> {
    session
        .tests
        .iter()
        .enumerate()
        .map(|(k, test)| {
            let model = reconstruct(neutral, deltas, &test.weights);
            let (rmse_mm, max_mm) = rmse_and_max_mm(&model, &test.vertices);
            let truth = session
                .truth
                .as_ref()
                .and_then(|t| t.tests.get(k))
                .map(|true_mesh| rmse_and_max_mm(&model, true_mesh));
            ExpressionError {
                id: test.id.clone(),
                rmse_mm,
                max_mm,
                truth_rmse_mm: truth.map(|t| t.0),
                truth_max_mm: truth.map(|t| t.1),
            }
        })
        .collect()
}

/// Means over test expressions.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MeanErrors {
    /// Mean RMSE against the recorded meshes (mm).
    pub rmse_mm: f64,
    /// Mean maximum error against the recorded meshes (mm).
    pub max_mm: f64,
    /// Mean RMSE against the noise-free faces (mm), if every test has one.
    pub truth_rmse_mm: Option<f64>,
    /// Mean maximum error against the noise-free faces (mm).
    pub truth_max_mm: Option<f64>,
}

/// Averages per-expression errors (the paper's "averaged over all test
/// expressions").
pub fn mean_errors(errors: &[ExpressionError]) -> MeanErrors {
    let n = errors.len().max(1) as f64;
    let mean = |f: &dyn Fn(&ExpressionError) -> f64| errors.iter().map(f).sum::<f64>() / n;
    let all_truth = !errors.is_empty() && errors.iter().all(|e| e.truth_rmse_mm.is_some());
    MeanErrors {
        rmse_mm: mean(&|e| e.rmse_mm),
        max_mm: mean(&|e| e.max_mm),
        truth_rmse_mm: all_truth.then(|| mean(&|e| e.truth_rmse_mm.unwrap_or(0.0))),
        truth_max_mm: all_truth.then(|| mean(&|e| e.truth_max_mm.unwrap_or(0.0))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rmse_and_max_of_a_known_offset() {
        let a = vec![DVec3::ZERO; 4];
        let b = vec![
            Vec3::new(0.001, 0.0, 0.0),
            Vec3::ZERO,
            Vec3::ZERO,
            Vec3::ZERO,
        ];
        let (rmse, max) = rmse_and_max_mm(&a, &b);
        assert!(
            (rmse - 0.5).abs() < 1e-6,
            "sqrt(1/4 · 1 mm²) = 0.5 mm, got {rmse}"
        );
        assert!((max - 1.0).abs() < 1e-6);
    }

    #[test]
    fn reconstruction_is_linear_in_the_weights() {
        let neutral = vec![DVec3::ONE; 2];
        let mut deltas = vec![vec![DVec3::ZERO; 2]; 52];
        deltas[17] = vec![DVec3::X, DVec3::Y];
        let mut w = Weights::ZERO;
        w.0[17] = 0.5;
        let r = reconstruct(&neutral, &deltas, &w);
        assert_eq!(
            r,
            vec![DVec3::new(1.5, 1.0, 1.0), DVec3::new(1.0, 1.5, 1.0)]
        );
    }
}
