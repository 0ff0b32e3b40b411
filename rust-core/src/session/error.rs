//! Why a session's parts do not make a session; every message names the part.

use crate::arkit::{BLENDSHAPE_COUNT, Blendshape};
use crate::geometry::topology::GeometryError;

/// A session whose parts contradict each other; the message names the part.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum SessionError {
    /// A mesh does not fit the topology.
    #[error(transparent)]
    Geometry(#[from] GeometryError),
    /// The template does not have one mesh per ARKit blendshape.
    #[error("template has {0} blendshapes, expected {BLENDSHAPE_COUNT}")]
    TemplateShapeCount(usize),
    /// A weight is NaN or infinite.
    #[error("{what}: weight {shape} is {value}")]
    BadWeight {
        /// Which frame or expression.
        what: String,
        /// Which weight.
        shape: Blendshape,
        /// Its value.
        value: f32,
    },
    /// Timestamps are not finite, or go backwards.
    #[error("frame {frame}: timestamp {timestamp} is not finite or earlier than the frame before")]
    Timestamp {
        /// Index of the offending frame.
        frame: usize,
        /// Its timestamp.
        timestamp: f64,
    },
    /// An expression refers to a frame that is not in the stream.
    #[error("{what}: refers to frame {frame}, but the stream has {frames} frames")]
    FrameIndex {
        /// Which expression.
        what: String,
        /// The frame it names.
        frame: u32,
        /// Number of frames.
        frames: usize,
    },
    /// The same prompt was captured twice.
    #[error("prompt {0} is captured more than once")]
    DuplicateCapture(Blendshape),
    /// The frame rate is not a positive finite number.
    #[error("frame rate {0} is not a positive number")]
    FrameRate(f32),
    /// Ground truth has the wrong number of entries for something.
    #[error("ground truth: {0}")]
    Truth(String),
}
