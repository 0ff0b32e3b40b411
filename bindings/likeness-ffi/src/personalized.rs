//! The person's personalized face: posed live (the mirror view), as a GLB
//! mask, and implanted into an avatar.

use crate::error::LikenessError;
use crate::progress::{ProgressListener, cancelled, report};
use crate::types::{AvatarResult, flat_f64};
use likeness::Blendshapes;
use likeness::avatar::avatar_summary::avatar_summary;
use likeness::avatar::glb::read_avatar_bytes;
use likeness::avatar::personal_avatar::{
    AvatarShapes, PersonInput, RestFace, mask_glb, personal_avatar, retarget_map_json,
};
use likeness::geometry::Topology;
use likeness::personalize::Personalized;
use likeness::session::Session;
use std::path::Path;
use std::sync::Arc;

/// The name the default avatar goes by in messages and in the retarget
/// map (as `likeness avatar` names it).
const DEFAULT_AVATAR: &str = "default avatar";

/// The name an avatar given as bytes goes by in messages.
pub(crate) const GIVEN_AVATAR: &str = "avatar.glb";

/// Whose face an avatar has at rest (`RestFace` in the core).
#[derive(Clone, Copy, Debug, PartialEq, Eq, uniffi::Enum)]
pub enum RestFaceChoice {
    /// The avatar's own face.
    Stock,
    /// The person's face, from the neutral they scanned.
    Person,
}

impl From<RestFaceChoice> for RestFace {
    fn from(choice: RestFaceChoice) -> RestFace {
        match choice {
            RestFaceChoice::Stock => RestFace::Stock,
            RestFaceChoice::Person => RestFace::Person,
        }
    }
}

/// A session's personalized blendshapes, with what the avatar step needs.
#[derive(uniffi::Object)]
pub struct PersonalizedFace {
    /// The mask's triangles (the session's).
    topology: Topology,
    /// The session's generic template, where the face search starts.
    rig: Blendshapes,
    personalized: Personalized,
}

impl PersonalizedFace {
    /// `personalized` from `session`.
    pub(crate) fn new(
        session: &Session,
        personalized: Personalized,
    ) -> Result<PersonalizedFace, LikenessError> {
        let rig = session
            .template
            .blendshapes()
            .map_err(|e| LikenessError::Personalization {
                message: format!("template: {e}"),
            })?;
        Ok(PersonalizedFace {
            topology: session.topology.clone(),
            rig,
            personalized,
        })
    }
}

#[uniffi::export]
impl PersonalizedFace {
    /// The method that made the shapes.
    pub fn method(&self) -> String {
        self.personalized.method.name().to_string()
    }

    /// The mask's triangles, three vertex indices each.
    pub fn triangles(&self) -> Result<Vec<u32>, LikenessError> {
        Ok(self
            .topology
            .triangles()
            .iter()
            .flatten()
            .copied()
            .collect())
    }

    /// The mask's vertices (xyz flattened) at 52 live ARKit weights
    /// (`arkitNames()` order): `B₀ + Σ w_j B_j`.
    pub fn pose(&self, weights: Vec<f32>) -> Result<Vec<f32>, LikenessError> {
        let w = crate::types::weights("weights", &weights)?;
        Ok(flat_f64(&self.personalized.shapes.reconstruct(&w)))
    }

    /// The personalized mask alone as GLB bytes (the neutral and 52 ARKit
    /// targets, ARKit's face coordinates, metres).
    pub fn mask_glb(&self) -> Result<Vec<u8>, LikenessError> {
        Ok(mask_glb(
            &self.topology,
            &self.personalized.shapes,
            Path::new("mask.glb"),
        )?)
    }

    /// The person's shapes implanted into `avatar_glb` (a GLB with
    /// ARKit-named morph targets; `None` for the project's default avatar);
    /// `rest_face` says whose face it has at rest (`None`: the person's on
    /// the default avatar, the avatar's own on one the user brings, as
    /// `likeness avatar` decides); `listener` hears the steps and may
    /// cancel.
    pub fn avatar(
        &self,
        avatar_glb: Option<Vec<u8>>,
        rest_face: Option<RestFaceChoice>,
        listener: Option<Arc<dyn ProgressListener>>,
    ) -> Result<AvatarResult, LikenessError> {
        let listener = listener.as_ref();
        if cancelled(listener) {
            return Err(LikenessError::Cancelled);
        }
        let face = RestFace::chosen(avatar_glb.is_none(), rest_face.map(RestFace::from));
        let glb = match avatar_glb {
            Some(bytes) => read_avatar_bytes(&bytes, GIVEN_AVATAR)?,
            None => read_avatar_bytes(likeness_assets::DEFAULT_AVATAR_GLB, DEFAULT_AVATAR)?,
        };
        let person = PersonInput {
            mask: &self.topology,
            rig: &self.rig,
            personalized: &self.personalized.shapes,
        };
        let mut progress = |step: likeness::avatar::personal_avatar::AvatarStep| {
            report(listener, step.name(), step.done_before())
        };
        let made = personal_avatar(
            &glb,
            &person,
            None,
            AvatarShapes::Personalized,
            face,
            &mut progress,
        )?;
        report(listener, "done", 1.0);
        Ok(AvatarResult {
            retarget_map_json: retarget_map_json(&glb, &made.retargeting),
            summary: avatar_summary(&glb, &made),
            warnings: made.warnings.iter().map(|w| w.to_string()).collect(),
            rest_face: if made.taken_face.is_some() {
                RestFaceChoice::Person
            } else {
                RestFaceChoice::Stock
            },
            glb: made.glb,
        })
    }
}
