//! Why a session cannot be personalized: one error for every method.
//!
//! A [`Session`](crate::Session) is checked when it is made, so nothing here
//! is about contradictory input: these are the failures of the methods
//! themselves.

use crate::arkit::BlendshapesError;
use crate::geometry::deformation_transfer::TransferError;
use crate::geometry::mesh_boundary::EyeHoleError;

/// Why a session cannot be personalized.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PersonalizeError {
    /// The mask's eye holes could not be found.
    #[error("template: {0}")]
    EyeHoles(#[from] EyeHoleError),
    /// Deformation transfer failed.
    #[error("deformation transfer: {0}")]
    Transfer(#[from] TransferError),
    /// A per-vertex fit was singular.
    #[error(transparent)]
    Fit(#[from] SingularFit),
    /// A method produced shapes that are not a valid set (a non-finite
    /// coordinate): refused rather than passed on to export.
    #[error("personalized blendshapes: {0}")]
    Shapes(#[from] BlendshapesError),
    /// Nothing was captured, so there is nothing to personalize from.
    #[error("the session has no captured expressions")]
    NoCaptures,
    /// The caller of
    /// [`personalize_with_progress`](super::personalization::personalize_with_progress)
    /// asked to stop before this stage.
    #[error("cancelled before {}", .0.name())]
    Cancelled(super::method::PersonalizeStage),
    /// Parts given to a fitting step do not fit together: a mesh or a field
    /// without one entry per vertex, or not one field per shape. Only the
    /// low-level API ([`BlendshapeFit`](super::blendshape_fit::BlendshapeFit),
    /// [`ebfr_blendshapes`](super::ebfr::ebfr_blendshapes), …) called with
    /// parts of different faces gets here; [`personalize`](super::personalize)
    /// builds every part from one checked session.
    #[error("{what}: {found} entries, expected {expected}")]
    Size {
        /// What was counted.
        what: String,
        /// How many there should be.
        expected: usize,
        /// How many there are.
        found: usize,
    },
}

/// [`PersonalizeError::Size`] unless `found == expected`; `what` names the
/// part, and is only formatted on a mismatch.
pub(crate) fn check_size(
    what: impl FnOnce() -> String,
    expected: usize,
    found: usize,
) -> Result<(), PersonalizeError> {
    if found == expected {
        Ok(())
    } else {
        Err(PersonalizeError::Size {
            what: what(),
            expected,
            found,
        })
    }
}

/// A fit failed: the per-vertex system is not positive definite (possible
/// only with λ = 0 and too few observations).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error(
    "the fit at vertex {vertex} is singular (λ = {lambda}); too few observations for an unregularized fit"
)]
pub struct SingularFit {
    /// The vertex whose system failed.
    pub vertex: usize,
    /// The λ used.
    pub lambda: f64,
}
