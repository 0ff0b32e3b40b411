//! The generic ARKit template: the mask's neutral face with the generic
//! anatomy, purely linear. It plays `ARFaceGeometry(blendShapes:)` on a phone.
//!
//! It comes in two variants, which differ only in how far its eyeBlink
//! shapes close the lids ([`TemplateVariant`]): exactly shut (the default,
//! which every simulated session carries), or stopping [`APPLE_BLINK_GAP`]
//! short, as Apple's own template does.

use crate::face_mask::face_mask;
use crate::face_model::FaceModel;
use crate::shape_spec::{GENERIC_JAW, Special, generic_specs};
use glam::{DMat3, DVec3, Vec3};
use likeness::{Blendshape, Template};

/// How far apart Apple's own template leaves the lids at eyeBlink = 1 (m):
/// measured on ARKit's template, 0.4–0.6 mm depending on how the gap is
/// measured; the lids do not touch.
pub const APPLE_BLINK_GAP: f64 = 0.0005;

/// Which generic template: how its eyeBlink shapes end.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TemplateVariant {
    /// Each upper-lid vertex meets its lower-lid partner exactly (the
    /// simulator's template, in every session it makes).
    #[default]
    ExactBlink,
    /// As Apple's: the lids stop [`APPLE_BLINK_GAP`] apart along the whole
    /// lid, each short of the meeting point by its share of the travel.
    AppleLike,
}

impl TemplateVariant {
    /// Both variants, the default first.
    pub const ALL: [TemplateVariant; 2] = [TemplateVariant::ExactBlink, TemplateVariant::AppleLike];

    /// The gap between the lids at eyeBlink = 1 (m).
    pub fn blink_gap(self) -> f64 {
        match self {
            TemplateVariant::ExactBlink => 0.0,
            TemplateVariant::AppleLike => APPLE_BLINK_GAP,
        }
    }

    /// The generic face of this variant as a linear model.
    pub fn model(self) -> FaceModel {
        let mask = face_mask();
        let neutral: Vec<DVec3> = mask.neutral.iter().map(|p| p.as_dvec3()).collect();
        let mut specs = generic_specs();
        for spec in &mut specs {
            if let Special::Blink { gap, .. } = &mut spec.special {
                *gap = self.blink_gap();
            }
        }
        let mut model = FaceModel::build(mask, neutral, &specs, DMat3::IDENTITY, GENERIC_JAW);
        model.nonlinear = None;
        model
    }

    /// This variant's template as the phone reports it: neutral and each
    /// shape at weight one.
    pub fn template(self) -> Template {
        let model = self.model();
        Template {
            neutral: to_f32(&model.neutral),
            shapes: Blendshape::ALL.map(|s| to_f32(&model.shape(s))),
        }
    }
}

/// The generic face as a linear model (the default variant).
pub fn generic_model() -> FaceModel {
    TemplateVariant::ExactBlink.model()
}

/// Converts positions to the session's single precision.
pub fn to_f32(points: &[DVec3]) -> Vec<Vec3> {
    points.iter().map(|p| p.as_vec3()).collect()
}

/// The template as the phone reports it: neutral and each shape at weight
/// one (the default variant).
pub fn generic_template() -> Template {
    TemplateVariant::ExactBlink.template()
}
