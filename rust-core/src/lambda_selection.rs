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
//! peak ([`crate::frame_selection::validation_frames`]), where the tracked
//! weights are intermediate values no capture has. The score is the mean
//! squared vertex error of `B₀ + Σ w_j B_j` against those frames' meshes; the
//! smallest wins. Leave-one-capture-out would be biased: without capture `i`
//! the shape `i` is identified almost only by the regularizer, which favours
//! a large λ.

use crate::blendshape_fit::{BlendshapeFit, SingularFit};
use crate::evaluation::reconstruct;
use crate::frame_selection::validation_frames;
use crate::session::Session;
use glam::DVec3;

/// The λ candidates, strongest first: 1 (the paper) down to 10⁻⁴.
pub const LAMBDA_GRID: [f64; 5] = [1.0, 1e-1, 1e-2, 1e-3, 1e-4];

/// The chosen λ, its blendshapes, and every candidate's score.
#[derive(Clone, Debug)]
pub struct LambdaChoice {
    /// The winning λ.
    pub lambda: f64,
    /// The blendshapes fitted with it.
    pub deltas: Vec<Vec<DVec3>>,
    /// `(λ, mean squared error in m²)` per candidate, in grid order.
    pub scores: Vec<(f64, f64)>,
}

/// Mean squared vertex error of the blendshapes on `frames` of `session`.
pub fn validation_error(
    session: &Session,
    neutral: &[DVec3],
    deltas: &[Vec<DVec3>],
    frames: &[usize],
) -> f64 {
    let mut sum = 0.0;
    let mut count = 0usize;
    for &f in frames {
        let frame = &session.frames[f];
        let Some(mesh) = &frame.vertices else {
            continue;
        };
        let model = reconstruct(neutral, deltas, &frame.weights);
        sum += model
            .iter()
            .zip(mesh)
            .map(|(p, q)| (*p - q.as_dvec3()).length_squared())
            .sum::<f64>();
        count += mesh.len();
    }
    sum / count.max(1) as f64
}

/// Solves `fit` for each λ of `grid` and keeps the one with the smallest
/// error on the session's validation frames. A session without usable stream
/// frames (or an empty grid) keeps the paper's λ = 1 and reports no scores.
pub fn choose_lambda(
    session: &Session,
    neutral: &[DVec3],
    fit: &BlendshapeFit<'_>,
    grid: &[f64],
) -> Result<LambdaChoice, SingularFit> {
    let frames = validation_frames(session);
    if frames.is_empty() || grid.is_empty() {
        return Ok(LambdaChoice {
            lambda: 1.0,
            deltas: fit.solve(1.0)?,
            scores: Vec::new(),
        });
    }
    let mut best: Option<(f64, f64, Vec<Vec<DVec3>>)> = None;
    let mut scores = Vec::with_capacity(grid.len());
    for &lambda in grid {
        let deltas = fit.solve(lambda)?;
        let score = validation_error(session, neutral, &deltas, &frames);
        scores.push((lambda, score));
        if best.as_ref().is_none_or(|b| score < b.1) {
            best = Some((lambda, score, deltas));
        }
    }
    let (lambda, _, deltas) = best.expect("the grid is not empty");
    Ok(LambdaChoice {
        lambda,
        deltas,
        scores,
    })
}
