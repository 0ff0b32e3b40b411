//! Personalization (§3.2) and its evaluation (§4.1): from a capture session
//! to the person's own 52 blendshapes, and how faithfully they reproduce
//! held-out expressions.
//!
//! | paper | what | file |
//! |---|---|---|
//! | §3.2 "we transfer the blendshapes of the ARKit template to `B₀`" | the generic blendshapes `T_j` | [`mod@generic_blendshapes`] |
//! | Eq. (3) | per-vertex regularization weights `D_j` | [`regularization_weights`] |
//! | Eq. (1)–(2) | `E_fit + λ·E_reg`, one 52 × 52 system per vertex | [`blendshape_fit`] |
//! | (ours) | λ chosen per session | [`lambda_selection`] |
//! | (ours; Golub, Heath & Wahba 1979) | GCV of λ (and, for the study, the evidence: MacKay 1992), for every λ at O(k) per vertex | [`lambda_criteria`] |
//! | (ours) | stream frames fitted (`multi`) | [`frame_selection`] |
//! | (the study's, `study` feature) | λ scored on held-out stream frames | `holdout` |
//! | §4.1, Li et al. 2010 | the EBFR baseline | [`ebfr`] |
//! | §3.2, §4.1 | the methods, and which one the product uses | [`method`], [`personalization`] |
//! | | why a session cannot be personalized | [`error`] |
//! | Eq. (5) | RMSE and maximum error on the test expressions | [`evaluation`] |

pub mod blendshape_fit;
pub mod ebfr;
pub mod error;
pub mod evaluation;
pub mod frame_selection;
pub mod generic_blendshapes;
#[cfg(feature = "study")]
pub mod holdout;
pub mod lambda_criteria;
pub mod lambda_selection;
pub mod method;
pub mod personalization;
pub mod regularization_weights;

pub use error::PersonalizeError;
pub use generic_blendshapes::{GenericBlendshapes, generic_blendshapes};
pub use method::{FitFrames, Method, PersonalizeStage};
pub use personalization::{Personalized, personalize, personalize_with_progress};
