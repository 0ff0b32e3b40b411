//! `likeness-sim`: simulated people and iPhone TrueDepth captures.
//!
//! Likeness is tested without a phone: this crate plays the person, ARKit's
//! face tracker and the capture app. Every constant is documented where it is
//! defined and summarised, with its source, in `sim-data/README.md`.

#![warn(missing_docs)]

pub mod arkit_face;
pub mod avatar_variants;
pub mod capture_session;
pub mod compressed_glb;
pub mod default_avatar;
pub mod envelope;
pub mod face_basis;
pub mod face_mask;
pub mod face_model;
pub mod glb_edit;
pub mod grid_avatar;
pub mod performance;
pub mod real_takes;
pub mod regions;
pub mod shape_spec;
pub mod stream_statistics;
pub mod subject;
pub mod template;
pub mod test_expressions;
pub mod timeline;
pub mod tracker;

pub use capture_session::{
    FRAME_RATE, SAMPLE_GEOMETRY_WINDOW, SimulationOptions, simulate_session, simulate_session_with,
};
