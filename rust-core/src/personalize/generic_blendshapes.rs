//! §3.2: "we transfer the blendshapes of the (non-personalized) ARKit
//! template to the recorded neutral expression `B₀` using deformation
//! transfer \[47\], resulting in the generic blendshapes `T_1, …, T_m`",
//! with virtual triangles across the eye holes (Saito 2013) so that the
//! transferred blinks close. Every method starts from them.
//!
//! "Close" is a constraint, not an approximation: the lid pairs that a
//! template shape closes (its [`Contacts`], judged by the template's own
//! motion, see [`crate::geometry::deformation_transfer`]) are exactly
//! closed in `T_j`, even where the template itself leaves them a little
//! apart, as Apple's does. The contacts are kept with the generic shapes so
//! that the fitted methods close the same pairs in their result
//! ([`crate::personalize::blendshape_fit`], [`crate::personalize::ebfr`]).

use super::error::PersonalizeError;
use crate::arkit::Blendshapes;
use crate::geometry::deformation_transfer::{Contacts, DeformationTransfer, TransferError};
use crate::geometry::mesh_boundary::eye_hole_triangles;
use crate::session::{Session, Template};
use glam::{DVec3, Vec3};

/// The template transferred onto the person: what every method starts from.
pub struct GenericBlendshapes {
    /// `B₀` and `T_1 … T_52` as deltas from it.
    pub shapes: Blendshapes,
    /// The factored transfer onto `B₀` (EBFR reuses it).
    pub transfer: DeformationTransfer,
    /// The lid pairs each template shape closes, in Apple's order: those of
    /// eyeBlinkLeft and eyeBlinkRight, none for a shape that does not shut
    /// an eye.
    pub contacts: Vec<Contacts>,
}

/// Single-precision mesh points in double precision.
pub(crate) fn to_f64(points: &[Vec3]) -> Vec<DVec3> {
    points.iter().map(|p| p.as_dvec3()).collect()
}

/// Transfers the 52 shapes of `template` (source rest: its neutral) onto the
/// target of `transfer`: the paper's generic blendshapes `T₁ … T₅₂`, as
/// displacements from `B₀`, in Apple's order.
pub fn transfer_template(
    transfer: &DeformationTransfer,
    template: &Template,
) -> Result<Vec<Vec<DVec3>>, TransferError> {
    let shapes: Vec<Vec<DVec3>> = template.shapes.iter().map(|s| to_f64(s)).collect();
    transfer.transfer_many(&to_f64(&template.neutral), &shapes)
}

/// Finds the template's eye holes, factors deformation transfer onto the
/// session's neutral scan `B₀` and carries the template's 52 shapes onto it.
pub fn generic_blendshapes(session: &Session) -> Result<GenericBlendshapes, PersonalizeError> {
    let virtual_triangles = eye_hole_triangles(&session.topology, &session.template.neutral)?;
    let neutral = to_f64(&session.neutral);
    let transfer = DeformationTransfer::new(&session.topology, &virtual_triangles, &neutral)?;
    let deltas = transfer_template(&transfer, &session.template)?;
    let source_rest = to_f64(&session.template.neutral);
    let contacts = session
        .template
        .shapes
        .iter()
        .map(|shape| transfer.contacts(&source_rest, &to_f64(shape)))
        .collect::<Result<_, _>>()?;
    Ok(GenericBlendshapes {
        shapes: Blendshapes::new(neutral, deltas)?,
        transfer,
        contacts,
    })
}
