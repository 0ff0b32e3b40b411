//! A face's 52 ARKit blendshapes as one value: the paper's linear model
//! (§3.2)
//!
//! ```text
//! B₀ + Σ_j w_j B_j
//! ```
//!
//! with `B₀` the neutral face (n vertices) and `B_1 … B_52` the *delta*
//! blendshapes, each a displacement per vertex, in Apple's order. Generic,
//! personalized and evaluated shapes all travel as [`Blendshapes`], so a
//! set with 51 shapes or a shape with a vertex too few is an error where it
//! is built, never a silently short `zip` where it is used.

use super::blendshape::{BLENDSHAPE_COUNT, Blendshape};
use super::weights::Weights;
use glam::DVec3;

/// A neutral face and exactly 52 delta blendshapes of its vertex count, all
/// finite. Built only through [`Blendshapes::new`], which checks.
#[derive(Clone, Debug, PartialEq)]
pub struct Blendshapes {
    neutral: Vec<DVec3>,
    /// Exactly [`BLENDSHAPE_COUNT`] fields of `neutral.len()` vectors
    /// (checked in `new`), so `Blendshape::index()` always indexes it.
    deltas: Vec<Vec<DVec3>>,
}

/// Why a neutral and a list of deltas do not make a set of blendshapes.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum BlendshapesError {
    /// Not one delta per ARKit blendshape.
    #[error("{0} delta blendshapes, expected {BLENDSHAPE_COUNT}")]
    ShapeCount(usize),
    /// A delta has another vertex count than the neutral.
    #[error("blendshape {shape}: {found} vertices, but the neutral has {expected}")]
    VertexCount {
        /// The shape.
        shape: Blendshape,
        /// Vertex count of the neutral.
        expected: usize,
        /// Vertex count of the shape.
        found: usize,
    },
    /// A coordinate is NaN or infinite.
    #[error("{}: vertex {vertex} is not finite", shape.map_or("neutral", Blendshape::name))]
    NotFinite {
        /// The shape, `None` for the neutral.
        shape: Option<Blendshape>,
        /// The vertex.
        vertex: usize,
    },
}

fn first_non_finite(points: &[DVec3]) -> Option<usize> {
    points.iter().position(|p| !p.is_finite())
}

impl Blendshapes {
    /// Checks and joins the neutral `B₀` and the deltas `B_1 … B_52` (Apple's
    /// order): exactly 52 deltas, each with one finite vector per neutral
    /// vertex, and a finite neutral.
    pub fn new(neutral: Vec<DVec3>, deltas: Vec<Vec<DVec3>>) -> Result<Self, BlendshapesError> {
        if deltas.len() != BLENDSHAPE_COUNT {
            return Err(BlendshapesError::ShapeCount(deltas.len()));
        }
        if let Some(vertex) = first_non_finite(&neutral) {
            return Err(BlendshapesError::NotFinite {
                shape: None,
                vertex,
            });
        }
        for (shape, delta) in Blendshape::ALL.into_iter().zip(&deltas) {
            if delta.len() != neutral.len() {
                return Err(BlendshapesError::VertexCount {
                    shape,
                    expected: neutral.len(),
                    found: delta.len(),
                });
            }
            if let Some(vertex) = first_non_finite(delta) {
                return Err(BlendshapesError::NotFinite {
                    shape: Some(shape),
                    vertex,
                });
            }
        }
        Ok(Blendshapes { neutral, deltas })
    }

    /// Number of vertices `n`.
    pub fn vertex_count(&self) -> usize {
        self.neutral.len()
    }

    /// The neutral face `B₀`.
    pub fn neutral(&self) -> &[DVec3] {
        &self.neutral
    }

    /// The delta blendshape `B_j` of `shape`.
    pub fn delta(&self, shape: Blendshape) -> &[DVec3] {
        &self.deltas[shape.index()]
    }

    /// All 52 deltas, in Apple's order.
    pub fn deltas(&self) -> &[Vec<DVec3>] {
        &self.deltas
    }

    /// The face with `shape` at weight one: `B₀ + B_j`.
    pub fn shape(&self, shape: Blendshape) -> Vec<DVec3> {
        self.neutral
            .iter()
            .zip(self.delta(shape))
            .map(|(p, d)| *p + *d)
            .collect()
    }

    /// The linear blendshape model `B₀ + Σ_j w_j B_j` at `weights`.
    pub fn reconstruct(&self, weights: &Weights) -> Vec<DVec3> {
        let mut out = self.neutral.clone();
        for (delta, w) in self.deltas.iter().zip(weights.0) {
            if w != 0.0 {
                let w = f64::from(w);
                out.iter_mut().zip(delta).for_each(|(p, d)| *p += w * *d);
            }
        }
        out
    }

    /// The same neutral with `deltas` in place of these: checked as
    /// [`Blendshapes::new`] checks.
    pub fn with_deltas(&self, deltas: Vec<Vec<DVec3>>) -> Result<Self, BlendshapesError> {
        Blendshapes::new(self.neutral.clone(), deltas)
    }

    /// Takes the set apart: `(B₀, [B_1 … B_52])`.
    pub fn into_parts(self) -> (Vec<DVec3>, Vec<Vec<DVec3>>) {
        (self.neutral, self.deltas)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn zeros(n: usize) -> Vec<Vec<DVec3>> {
        vec![vec![DVec3::ZERO; n]; BLENDSHAPE_COUNT]
    }

    #[test]
    fn reconstruction_is_linear_in_the_weights() {
        let mut deltas = zeros(2);
        deltas[Blendshape::JawOpen.index()] = vec![DVec3::X, DVec3::Y];
        let shapes = Blendshapes::new(vec![DVec3::ONE; 2], deltas).unwrap();
        let mut w = Weights::ZERO;
        w.set(Blendshape::JawOpen, 0.5);
        assert_eq!(
            shapes.reconstruct(&w),
            vec![DVec3::new(1.5, 1.0, 1.0), DVec3::new(1.0, 1.5, 1.0)]
        );
        assert_eq!(
            shapes.shape(Blendshape::JawOpen),
            vec![DVec3::new(2.0, 1.0, 1.0), DVec3::new(1.0, 2.0, 1.0)]
        );
    }

    #[test]
    fn wrong_counts_and_non_finite_values_are_errors() {
        let neutral = vec![DVec3::ZERO; 3];
        let mut short = zeros(3);
        short.pop();
        assert_eq!(
            Blendshapes::new(neutral.clone(), short),
            Err(BlendshapesError::ShapeCount(51))
        );
        let mut ragged = zeros(3);
        ragged[Blendshape::TongueOut.index()].pop();
        let err = Blendshapes::new(neutral.clone(), ragged).unwrap_err();
        assert_eq!(
            err.to_string(),
            "blendshape tongueOut: 2 vertices, but the neutral has 3"
        );
        let mut nan = zeros(3);
        nan[0][1].y = f64::NAN;
        let err = Blendshapes::new(neutral.clone(), nan).unwrap_err();
        assert_eq!(err.to_string(), "eyeBlinkLeft: vertex 1 is not finite");
        let bad_neutral = vec![DVec3::ZERO, DVec3::INFINITY, DVec3::ZERO];
        assert_eq!(
            Blendshapes::new(bad_neutral, zeros(3)),
            Err(BlendshapesError::NotFinite {
                shape: None,
                vertex: 1
            })
        );
    }
}
