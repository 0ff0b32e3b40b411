//! §4.1: how faithfully a set of blendshapes reproduces held-out test
//! expressions.
//!
//! For a test expression with tracked weights `w` and recorded mesh `T_i`,
//! the reconstruction is `B_0 + Σ_j w_j B_j` ([`Blendshapes::reconstruct`]); Eq. (5) gives its RMSE over the
//! `n` vertices, `sqrt(1/n Σ_v ‖·‖²)`, and the maximum vertex error shows the
//! worst spot (the RMSE hides a small region that is badly off). Both are
//! reported in millimetres against the recorded mesh, as the paper does, and
//! against the simulator's noise-free face where the session carries it.

use crate::arkit::Blendshapes;
use crate::session::Session;
use glam::{DVec3, Vec3};

/// Eq. (5) RMSE and the maximum vertex error of one mesh against another.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshError {
    /// `sqrt(1/n Σ_v ‖a_v − b_v‖²)` in mm.
    pub rmse_mm: f64,
    /// `max_v ‖a_v − b_v‖` in mm.
    pub max_mm: f64,
}

/// Eq. (5) RMSE and the maximum vertex error of `a` against `b`, in mm.
pub fn mesh_error(a: &[DVec3], b: &[Vec3]) -> MeshError {
    let (mut sum, mut max) = (0.0, 0.0f64);
    for (p, q) in a.iter().zip(b) {
        let d2 = (*p - q.as_dvec3()).length_squared();
        sum += d2;
        max = max.max(d2);
    }
    MeshError {
        rmse_mm: (sum / a.len().max(1) as f64).sqrt() * 1e3,
        max_mm: max.sqrt() * 1e3,
    }
}

/// The error of every vertex of `a` against `b` (`‖a_v − b_v‖`), in mm:
/// where [`mesh_error`]'s maximum lies, for colour-coded error maps.
pub fn vertex_errors_mm<P: Copy + Into<DVec3>>(a: &[DVec3], b: &[P]) -> Vec<f64> {
    a.iter()
        .zip(b)
        .map(|(p, q)| (*p - (*q).into()).length() * 1e3)
        .collect()
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

/// Errors of `shapes` (`B_0`, `B_1 … B_52`) on every test expression of
/// `session`.
pub fn evaluate(shapes: &Blendshapes, session: &Session) -> Vec<ExpressionError> {
    session
        .tests
        .iter()
        .enumerate()
        .map(|(k, test)| {
            let model = shapes.reconstruct(&test.weights);
            let recorded = mesh_error(&model, &test.vertices);
            let truth = session
                .truth
                .as_ref()
                .and_then(|t| t.tests.get(k))
                .map(|true_mesh| mesh_error(&model, true_mesh));
            ExpressionError {
                id: test.id.clone(),
                rmse_mm: recorded.rmse_mm,
                max_mm: recorded.max_mm,
                truth_rmse_mm: truth.map(|t| t.rmse_mm),
                truth_max_mm: truth.map(|t| t.max_mm),
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
        let error = mesh_error(&a, &b);
        assert!(
            (error.rmse_mm - 0.5).abs() < 1e-6,
            "sqrt(1/4 · 1 mm²) = 0.5 mm, got {}",
            error.rmse_mm
        );
        assert!((error.max_mm - 1.0).abs() < 1e-6);
    }

    #[test]
    fn vertex_errors_locate_the_maximum() {
        let a = vec![DVec3::ZERO; 3];
        let b = vec![Vec3::ZERO, Vec3::new(0.0, 0.002, 0.0), Vec3::ZERO];
        let errors = vertex_errors_mm(&a, &b);
        assert_eq!(errors.len(), 3);
        assert!((errors[1] - 2.0).abs() < 1e-6 && errors[0] == 0.0);
        let largest = errors.iter().copied().fold(0.0, f64::max);
        assert!((largest - mesh_error(&a, &b).max_mm).abs() < 1e-9);
        let doubles = vertex_errors_mm(&a, &[DVec3::X * 0.001; 3]);
        assert!(doubles.iter().all(|e| (e - 1.0).abs() < 1e-12));
    }
}
