//! The face a person is simulated on: the simulator's own mask, or ARKit's
//! own mesh ([`crate::arkit_face`]).
//!
//! A basis is a mask (topology, parameter plane, neutral, landmarks), the
//! template the phone reports for it, where the jaw's joint sits on it, and
//! what its template does beyond the simulator's generic model.
//!
//! **A person on ARKit's mesh** is the simulator's person with ARKit's face
//! as the generic one. Identity (proportions and bumps) acts on ARKit's
//! neutral through the carried `(u, v)`; each shape is the person's own
//! field (style, asymmetry, idiosyncrasy, as on the simulator's mask) plus
//! what ARKit's template does beyond the simulator's generic field of that
//! shape on the same vertices (`offset_j = T_j − G_j`, scaled with the
//! person's proportions). So the person departs from ARKit's template by as
//! much as a simulated person departs from the simulator's. Three shapes
//! take no offset, because they are physics rather than an artist's rig:
//! - eyeBlink: a person's lids always meet (ARKit's template stops them
//!   about 0.5 mm apart);
//! - jawOpen: the person's mandible turns about their condyles
//!   ([`crate::shape_spec::JawJoint`], placed on ARKit's face by the
//!   registration's similarity);
//! - mouthClose: it closes the lips against that jaw.

use crate::arkit_face::ArkitFace;
use crate::face_mask::{FaceMask, face_mask};
use crate::face_model::SparseField;
use crate::shape_spec::{GENERIC_JAW, JawJoint};
use crate::template::generic_template;
use likeness::Template;

/// Which face people are simulated on.
#[derive(Clone, Copy, Debug, Default)]
pub enum FaceBasis {
    /// The simulator's own mask and template (every committed session).
    #[default]
    Simulator,
    /// ARKit's own mesh and template.
    Arkit(&'static ArkitFace),
}

impl FaceBasis {
    /// The mask people are simulated on.
    pub fn mask(self) -> &'static FaceMask {
        match self {
            FaceBasis::Simulator => face_mask(),
            FaceBasis::Arkit(face) => &face.mask,
        }
    }

    /// The template the phone reports on this basis.
    pub fn template(self) -> Template {
        match self {
            FaceBasis::Simulator => generic_template(),
            FaceBasis::Arkit(face) => face.template.clone(),
        }
    }

    /// The generic jaw joint placed on this basis's face.
    pub fn jaw(self) -> JawJoint {
        match self {
            FaceBasis::Simulator => GENERIC_JAW,
            FaceBasis::Arkit(face) => face.jaw,
        }
    }

    /// What the basis's template does beyond the simulator's generic field
    /// of each shape (`T_j − G_j`, Apple's order); `None` on the
    /// simulator's own mask, where they are the same.
    pub fn offsets(self) -> Option<&'static [SparseField]> {
        match self {
            FaceBasis::Simulator => None,
            FaceBasis::Arkit(face) => Some(&face.offsets),
        }
    }

    /// A short name for messages: `simulator` or `arkit`.
    pub fn name(self) -> &'static str {
        match self {
            FaceBasis::Simulator => "simulator",
            FaceBasis::Arkit(_) => "arkit",
        }
    }
}
