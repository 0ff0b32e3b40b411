//! ARKit's vocabulary: the 52 facial blendshapes, the weights a tracker
//! reports for them, and a person's (or a template's) 52 shapes as one value.
//!
//! Every stage of the pipeline speaks these types; they depend on nothing
//! else in the crate.
//!
//! | paper | what | file |
//! |---|---|---|
//! | §3.1, `m = 52` | the names in Apple's order, mirrors, the one parser for spellings in the wild | [`blendshape`] |
//! | §3.1, `w_{i,1..52}` | one tracked weight per shape | [`weights`] |
//! | §3.2, `B₀ + Σ_j w_j B_j` | a neutral plus exactly 52 delta shapes, checked | [`blendshapes`] |

pub mod blendshape;
pub mod blendshapes;
pub mod weights;

pub use blendshape::{BLENDSHAPE_COUNT, Blendshape, Side, UnknownBlendshape};
pub use blendshapes::{Blendshapes, BlendshapesError};
pub use weights::Weights;
