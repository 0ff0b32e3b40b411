//! The capture session: everything the app records in one sitting, and the
//! two ways it is stored.
//!
//! | paper | what | file |
//! |---|---|---|
//! | §3.1: `B₀`, `(w_{i,1..52}, S_i)`, the tracked stream; §4.1 test expressions | the parts of a session | [`model`] |
//! | | a session whose parts agree, obtainable only through a check | [`validated`] |
//! | | why parts do not make a session | [`error`] |
//! | | the binary `.likeness` file: header, checksum, compressed payload | [`mod@file`] |
//! | §4 (the paper's own data: a neutral, peak meshes, weights) | a folder of OBJ + CSV files | [`interchange`] |

pub mod error;
pub mod file;
pub mod interchange;
pub mod model;
pub mod validated;

pub use error::SessionError;
pub use model::{
    CapturedExpression, DeviceInfo, Frame, GroundTruth, SessionParts, Template, TestExpression,
    TruePeak,
};
pub use validated::Session;
