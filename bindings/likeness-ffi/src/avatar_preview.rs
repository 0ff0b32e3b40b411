//! The person's avatar moving with their live weights (the result screen's
//! preview): the core's [`AvatarPose`] over an avatar GLB.

use crate::error::LikenessError;
use crate::personalized::GIVEN_AVATAR;
use crate::types::flat;
use likeness::avatar::avatar_pose::AvatarPose;
use likeness::avatar::glb::read_avatar_bytes;
use std::sync::Arc;

/// The centre and radius of what a preview should show.
#[derive(Clone, Debug, PartialEq, uniffi::Record)]
pub struct PreviewFocus {
    /// Centre, x.
    pub x: f32,
    /// Centre, y.
    pub y: f32,
    /// Centre, z.
    pub z: f32,
    /// Half the diagonal of the box around it.
    pub radius: f32,
}

/// An avatar GLB (for example `AvatarResult.glb`) ready to be posed by ARKit
/// weights, every mesh of it as one triangle list in world space.
#[derive(uniffi::Object)]
pub struct AvatarPreview {
    pose: AvatarPose,
}

#[uniffi::export]
impl AvatarPreview {
    /// Reads `glb`; its ARKit-named morph targets are what `pose` drives.
    #[uniffi::constructor]
    pub fn new(glb: Vec<u8>) -> Result<Arc<Self>, LikenessError> {
        let avatar = read_avatar_bytes(&glb, GIVEN_AVATAR)?;
        Ok(Arc::new(AvatarPreview {
            pose: AvatarPose::new(&avatar.avatar),
        }))
    }

    /// Every mesh's triangles, three indices each into `pose`'s vertices.
    pub fn triangles(&self) -> Vec<u32> {
        self.pose.triangles().iter().flatten().copied().collect()
    }

    /// Where to point a camera: the centre and radius of the part of the
    /// avatar that its ARKit shapes move (its face), in the file's units.
    pub fn focus(&self) -> PreviewFocus {
        let (centre, radius) = self.pose.focus();
        PreviewFocus {
            x: centre.x,
            y: centre.y,
            z: centre.z,
            radius,
        }
    }

    /// How many of ARKit's 52 shapes the avatar has.
    pub fn shapes_found(&self) -> u32 {
        crate::types::count(self.pose.arkit_targets().found())
    }

    /// Every vertex (xyz flattened, the file's units) at 52 live ARKit
    /// weights (`arkitNames()` order): the rest mesh plus each weight times
    /// the avatar's blendshape of that name.
    pub fn pose(&self, weights: Vec<f32>) -> Result<Vec<f32>, LikenessError> {
        let w = crate::types::weights("weights", &weights)?;
        Ok(flat(&self.pose.pose(&w)))
    }
}
