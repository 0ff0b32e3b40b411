//! Likeness core: personalized ARKit blendshapes from a two-minute iPhone
//! capture, after Menzel, Botsch & Latoschik, *Automated Blendshape
//! Personalization for Faithful Face Animations Using Commodity Smartphones*
//! (VRST 2022).
//!
//! The pipeline runs one way, and the crate's folders follow it:
//!
//! | stage | paper | folder |
//! |---|---|---|
//! | ARKit's 52 names, weights and blendshape sets | §3.1 | [`arkit`] |
//! | meshes, eye holes, deformation gradients and transfer | §3.2 (ref. 47), §3.3 | [`geometry`] |
//! | atomic writes, OBJ in and out | | [`io`] |
//! | the session model, its binary file and OBJ + CSV folders | §3.1 | [`session`] |
//! | peak detection and the guided capture | §3.1 | [`capture`] |
//! | personalized blendshapes, baselines and evaluation | §3.2, §4.1 | [`personalize`] |
//! | the avatar: glTF, its face, retargeting and transfer | §3.3 | [`avatar`] |
//!
//! A folder uses only the folders above it in this table (a test in
//! `tests/tests/module_layers.rs` checks it). This crate holds every
//! algorithm and every decision; it has no FFI and no command-line
//! dependencies, so it stays small on the phone.

#![warn(missing_docs)]

pub mod arkit;
pub mod avatar;
pub mod capture;
pub mod geometry;
pub mod io;
pub mod personalize;
pub mod session;

#[cfg(test)]
mod test_support;

/// This crate's version (`Cargo.toml`), for reports and the app's about
/// screen.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

pub use arkit::{
    BLENDSHAPE_COUNT, Blendshape, Blendshapes, BlendshapesError, UnknownBlendshape, Weights,
};
pub use geometry::{GeometryError, Topology, TopologyError};
pub use session::{
    CapturedExpression, DeviceInfo, Frame, GroundTruth, Session, SessionError, SessionParts,
    Template, TestExpression, TruePeak,
};
