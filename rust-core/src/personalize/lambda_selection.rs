//! `paper-cv`: choosing the weight λ of `E_reg` for each session.
//!
//! Eq. (3) makes every weight `D_j ≥ 1`, so with `E_fit + E_reg` the
//! regularizer weighs at least as much as the data even at a shape's most
//! moving vertex: read literally, the fit recovers at most about half of a
//! person's deviation from the template. The paper states no weight on
//! `E_reg`; this module picks one per session from the capture itself.
//!
//! For each λ of a decade grid the fit is solved (the per-vertex systems are
//! assembled once, see [`BlendshapeFit`]) and scored on stream frames it did
//! not use: frames a quarter to two thirds of a second from each captured
//! peak ([`crate::personalize::frame_selection::validation_frames`]), where the tracked
//! weights are intermediate values no capture has. The score is the mean
//! squared vertex error of `B₀ + Σ w_j B_j` against those frames' meshes; the
//! smallest wins. Leave-one-capture-out would be biased: without capture `i`
//! the shape `i` is identified almost only by the regularizer, which favours
//! a large λ.

use super::blendshape_fit::BlendshapeFit;
use super::error::{PersonalizeError, check_size};
use super::frame_selection::validation_frames;
use crate::arkit::{BLENDSHAPE_COUNT, Blendshapes};
use crate::session::Session;
use faer::Mat;
use glam::{DVec3, Vec3};

/// The λ candidates, strongest first: 1 (the paper) down to 10⁻⁶. The
/// accuracy study on the simulated subjects (README) keeps improving past
/// 10⁻⁴, so the grid goes two decades further than that.
pub const LAMBDA_GRID: [f64; 7] = [1.0, 1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6];

/// How well one candidate λ predicts the validation frames.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LambdaScore {
    /// The candidate.
    pub lambda: f64,
    /// Mean squared vertex error on the validation frames (m²).
    pub mean_squared_m2: f64,
}

/// The chosen λ, its blendshapes, and every candidate's score.
#[derive(Clone, Debug)]
pub struct LambdaChoice {
    /// The winning λ.
    pub lambda: f64,
    /// The blendshapes fitted with it.
    pub shapes: Blendshapes,
    /// Every candidate's score, in grid order.
    pub scores: Vec<LambdaScore>,
}

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

/// Solves `fit` for each λ of `grid` and keeps the one with the smallest
/// error on the session's validation frames. A session without usable stream
/// frames (or an empty grid) keeps the paper's λ = 1 and reports no scores.
pub fn choose_lambda(
    session: &Session,
    fit: &BlendshapeFit<'_>,
    grid: &[f64],
) -> Result<LambdaChoice, PersonalizeError> {
    let frames = validation_frames(session);
    let paper = || -> Result<LambdaChoice, PersonalizeError> {
        Ok(LambdaChoice {
            lambda: 1.0,
            shapes: fit.solve(1.0)?,
            scores: Vec::new(),
        })
    };
    if frames.is_empty() {
        return paper();
    }
    let neutral: Vec<DVec3> = session.neutral.iter().map(|p| p.as_dvec3()).collect();
    let error = ValidationError::new(session, &neutral, &frames);
    let mut best: Option<(f64, f64, Blendshapes)> = None;
    let mut scores = Vec::with_capacity(grid.len());
    for &lambda in grid {
        let shapes = fit.solve(lambda)?;
        let score = error.mean_squared(&shapes)?;
        scores.push(LambdaScore {
            lambda,
            mean_squared_m2: score,
        });
        if best.as_ref().is_none_or(|b| score < b.1) {
            best = Some((lambda, score, shapes));
        }
    }
    match best {
        Some((lambda, _, shapes)) => Ok(LambdaChoice {
            lambda,
            shapes,
            scores,
        }),
        None => paper(),
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
