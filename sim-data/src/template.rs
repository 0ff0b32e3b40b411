//! The generic ARKit template: the mask's neutral face with the generic
//! anatomy, purely linear. It plays `ARFaceGeometry(blendShapes:)` on a phone.

use crate::face_mask::face_mask;
use crate::face_model::FaceModel;
use crate::shape_spec::{HINGE, generic_specs};
use glam::{DMat3, DVec3, Vec3};
use likeness::{Blendshape, Template};

/// The generic face as a linear model.
pub fn generic_model() -> FaceModel {
    let mask = face_mask();
    let neutral: Vec<DVec3> = mask.neutral.iter().map(|p| p.as_dvec3()).collect();
    let mut model = FaceModel::build(mask, neutral, &generic_specs(), DMat3::IDENTITY, HINGE);
    model.nonlinear = None;
    model
}

/// Converts positions to the session's single precision.
pub fn to_f32(points: &[DVec3]) -> Vec<Vec3> {
    points.iter().map(|p| p.as_vec3()).collect()
}

/// The template as the phone reports it: neutral and each shape at weight one.
pub fn generic_template() -> Template {
    let model = generic_model();
    Template {
        neutral: to_f32(&model.neutral),
        shapes: Blendshape::ALL.map(|s| to_f32(&model.shape(s))),
    }
}
