//! Likeness core: personalized ARKit blendshapes from a two-minute iPhone
//! capture, after Menzel, Botsch & Latoschik, *Automated Blendshape
//! Personalization for Faithful Face Animations Using Commodity Smartphones*
//! (VRST 2022).
//!
//! The pipeline runs one way: capture (§3.1) → [`session_file`] →
//! personalization (§3.2) → avatar transfer (§3.3) → export. This crate holds
//! every algorithm and every decision; it has no FFI and no command-line
//! dependencies, so it stays small on the phone.

#![warn(missing_docs)]

pub mod arkit_names;
pub mod atomic_write;
pub mod blendshape_fit;
pub mod deformation_gradient;
pub mod deformation_transfer;
pub mod ebfr;
pub mod evaluation;
pub mod frame_selection;
pub mod guided_capture;
pub mod interchange;
pub mod lambda_selection;
pub mod mesh_boundary;
pub mod obj_export;
pub mod peak_detector;
pub mod personalization;
pub mod prompt_order;
pub mod regularization_weights;
pub mod replay;
pub mod session;
pub mod session_file;
pub mod topology;

pub use arkit_names::{BLENDSHAPE_COUNT, Blendshape, UnknownBlendshape, Weights};
pub use session::{
    CapturedExpression, DeviceInfo, Frame, GroundTruth, Session, SessionError, Template,
    TestExpression,
};
pub use topology::{GeometryError, Topology, TopologyError};
