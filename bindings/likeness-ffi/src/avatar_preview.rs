//! The person's avatar moving with their live weights (the result screen's
//! preview): the core's [`AvatarPose`] over an avatar GLB.

use crate::error::LikenessError;
use crate::personalized::GIVEN_AVATAR;
use crate::types::{flat, packed};
use likeness::arkit::Blendshape;
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

/// The avatar as one morphable mesh ([`AvatarPreview::morph_mesh`]).
#[derive(Clone, Debug, PartialEq, uniffi::Record)]
pub struct PreviewMesh {
    /// Rest vertices, `f32` x, y, z after x, y, z (12 bytes a vertex).
    pub positions: Vec<u8>,
    /// Rest normals, packed as `positions`.
    pub normals: Vec<u8>,
    /// Triangles, `u32` vertex indices, three a triangle.
    pub triangles: Vec<u8>,
    /// One per ARKit shape in `arkitNames()` order: every vertex's
    /// displacement at weight one, packed as `positions`; empty for a shape
    /// the avatar lacks.
    pub position_targets: Vec<Vec<u8>>,
    /// One per ARKit shape, as `position_targets`: how each vertex normal
    /// changes at weight one.
    pub normal_targets: Vec<Vec<u8>>,
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
    pub fn triangles(&self) -> Result<Vec<u32>, LikenessError> {
        Ok(self.pose.triangles().iter().flatten().copied().collect())
    }

    /// Where to point a camera: the centre and radius of the part of the
    /// avatar that its ARKit shapes move (its face), in the file's units.
    pub fn focus(&self) -> Result<PreviewFocus, LikenessError> {
        let (centre, radius) = self.pose.focus();
        Ok(PreviewFocus {
            x: centre.x,
            y: centre.y,
            z: centre.z,
            radius,
        })
    }

    /// The whole avatar as one mesh with its 52 ARKit shapes as morph
    /// targets, for an engine to play (SceneKit's `SCNMorpher` in additive
    /// mode): called once, after which a frame sets only the 52 weights and
    /// nothing crosses the boundary. Everything is packed as
    /// little-endian 32-bit values.
    pub fn morph_mesh(&self) -> Result<PreviewMesh, LikenessError> {
        let found = self.pose.arkit_targets();
        let rest_normals = self.pose.rest_normals();
        // A shape the avatar lacks crosses as an empty target.
        let (mut position_targets, mut normal_targets) = (Vec::new(), Vec::new());
        for shape in Blendshape::ALL {
            let has = !found.of(shape).is_empty();
            position_targets.push(match has {
                true => packed(&self.pose.displacement(shape)),
                false => Vec::new(),
            });
            normal_targets.push(match has {
                true => packed(&self.pose.normal_change(shape, &rest_normals)),
                false => Vec::new(),
            });
        }
        Ok(PreviewMesh {
            positions: packed(self.pose.rest()),
            normals: packed(&rest_normals),
            triangles: self
                .pose
                .triangles()
                .iter()
                .flatten()
                .flat_map(|i| i.to_le_bytes())
                .collect(),
            position_targets,
            normal_targets,
        })
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
