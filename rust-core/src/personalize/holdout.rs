//! The study's rule `LambdaRule::Holdout` (built with the `study` feature
//! only): λ scored by the error on held-out stream frames near the captures
//! (`frame_selection::validation_frames`), which needs stream meshes. The
//! product chooses λ by GCV on the captures alone
//! ([`super::lambda_selection`]); this rule is kept to compare with it.

use super::error::{PersonalizeError, check_size};
use crate::arkit::{BLENDSHAPE_COUNT, Blendshapes};
use crate::session::Session;
use faer::Mat;
use glam::{DVec3, Vec3};

/// The validation error `Σ_f ‖B₀ + Σ_j w_fj B_j − S_f‖²` over a fixed set of
/// frames, expanded so that scoring a candidate costs no pass over the
/// frames: with `R_f = S_f − B₀` and per vertex the 52 × 3 block `b` of the
/// blendshapes,
///
/// ```text
/// Σ_f ‖w_fᵀ b − r_f‖² = tr(bᵀ H b) − 2 tr(bᵀ C_v) + Σ_f ‖r_f‖²,
/// H = Σ_f w_f w_fᵀ (shared),  C_v = Σ_f w_f r_fᵀ (per vertex).
/// ```
pub struct ValidationError {
    h: Mat<f64>,
    c: Mat<f64>,
    constant: f64,
    samples: usize,
}

impl ValidationError {
    /// Prepares the error over `frames` of `session` for a face with
    /// neutral `neutral`; frames without a mesh of `neutral.len()` vertices,
    /// and indices past the end of the stream, are skipped.
    pub fn new(session: &Session, neutral: &[DVec3], frames: &[usize]) -> ValidationError {
        let n = neutral.len();
        // Indexing: every mesh used has the neutral's `n` vertices.
        let used: Vec<(&[f32; BLENDSHAPE_COUNT], &[Vec3])> = frames
            .iter()
            .filter_map(|&f| {
                let frame = session.frames.get(f)?;
                let vertices = frame.vertices.as_deref().filter(|v| v.len() == n)?;
                Some((&frame.weights.0, vertices))
            })
            .collect();
        let w = Mat::from_fn(used.len(), BLENDSHAPE_COUNT, |i, j| f64::from(used[i].0[j]));
        let r = Mat::from_fn(used.len(), 3 * n, |i, c| {
            f64::from(used[i].1[c / 3][c % 3]) - neutral[c / 3][c % 3]
        });
        let constant = r.squared_norm_l2();
        ValidationError {
            h: w.transpose() * &w,
            c: w.transpose() * &r,
            constant,
            samples: used.len() * n,
        }
    }

    /// Mean squared vertex error (m²) of the delta blendshapes of `shapes`
    /// (their neutral is taken to be the one given to
    /// [`ValidationError::new`]): with `B` the 52 × 3n matrix of all
    /// blendshape coordinates, the sum over vertices is
    /// `tr(H B Bᵀ) − 2⟨B, C⟩ + Σ‖r‖²`, two matrix products. Shapes of
    /// another vertex count are [`PersonalizeError::Size`].
    pub fn mean_squared(&self, shapes: &Blendshapes) -> Result<f64, PersonalizeError> {
        let deltas = shapes.deltas();
        let n = self.c.ncols() / 3;
        // Indexing: 52 deltas (a checked set) of `n` vertices (checked here).
        check_size(
            || "blendshapes scored".to_string(),
            n,
            shapes.vertex_count(),
        )?;
        let b = Mat::from_fn(BLENDSHAPE_COUNT, 3 * n, |j, c| deltas[j][c / 3][c % 3]);
        let bbt = &b * b.transpose();
        let mut total = self.constant;
        for i in 0..BLENDSHAPE_COUNT {
            for j in 0..BLENDSHAPE_COUNT {
                total += self.h[(i, j)] * bbt[(j, i)];
            }
        }
        for c in 0..3 * n {
            for j in 0..BLENDSHAPE_COUNT {
                total -= 2.0 * b[(j, c)] * self.c[(j, c)];
            }
        }
        Ok(total.max(0.0) / self.samples.max(1) as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::arkit::Weights;
    use crate::geometry::topology::Topology;
    use crate::session::{DeviceInfo, Frame, SessionParts, Template};

    #[test]
    fn the_expanded_error_equals_the_direct_one() {
        let n = 3;
        let neutral: Vec<DVec3> = (0..n).map(|v| DVec3::splat(v as f64 * 0.01)).collect();
        let frames: Vec<Frame> = (0..4)
            .map(|f| {
                let mut w = Weights::ZERO;
                w.0[f] = 0.5;
                w.0[f + 10] = 0.2;
                Frame {
                    timestamp: f as f64,
                    weights: w,
                    tracked: true,
                    vertices: Some(
                        (0..n)
                            .map(|v| Vec3::splat(0.001 * (f + v) as f32))
                            .collect(),
                    ),
                }
            })
            .collect();
        let session = Session::new(SessionParts {
            device: DeviceInfo::default(),
            frame_rate: 60.0,
            topology: Topology::new(n, vec![[0, 1, 2]]).unwrap(),
            template: Template {
                neutral: vec![Vec3::ZERO; n],
                shapes: std::array::from_fn(|_| vec![Vec3::ZERO; n]),
            },
            neutral: neutral.iter().map(|p| p.as_vec3()).collect(),
            frames,
            captures: vec![],
            tests: vec![],
            truth: None,
        })
        .unwrap();
        let deltas: Vec<Vec<DVec3>> = (0..52)
            .map(|j| {
                (0..n)
                    .map(|v| DVec3::new(j as f64, v as f64, 1.0) * 1e-4)
                    .collect()
            })
            .collect();
        let shapes = Blendshapes::new(neutral.clone(), deltas).unwrap();
        let used = [0, 1, 3];
        let direct: f64 = used
            .iter()
            .map(|&f| {
                let model = shapes.reconstruct(&session.frames[f].weights);
                let mesh = session.frames[f].vertices.as_ref().unwrap();
                model
                    .iter()
                    .zip(mesh)
                    .map(|(p, q)| (*p - q.as_dvec3()).length_squared())
                    .sum::<f64>()
            })
            .sum::<f64>()
            / (used.len() * n) as f64;
        let expanded = ValidationError::new(&session, &neutral, &used)
            .mean_squared(&shapes)
            .unwrap();
        assert!(
            (direct - expanded).abs() < 1e-12 * direct.max(1e-12),
            "{direct} vs {expanded}"
        );

        // Indices past the stream are skipped; parts of another face are
        // an error, not a panic.
        let past = ValidationError::new(&session, &neutral, &[0, 1, 3, 4, usize::MAX]);
        assert_eq!(past.mean_squared(&shapes), Ok(expanded));
        let other = ValidationError::new(&session, &neutral[..2], &used);
        assert!(matches!(
            other.mean_squared(&shapes),
            Err(PersonalizeError::Size {
                expected: 2,
                found: 3,
                ..
            })
        ));
    }
}
