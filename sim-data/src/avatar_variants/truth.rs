//! What a correct reader must find in each test avatar, known by
//! construction.

use glam::Vec3;
use likeness::avatar::Avatar;
use std::ops::Range;

/// The world's vertical axis as the file has it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UpAxis {
    /// +Y up (glTF's convention, ARKit's face-anchor space).
    Y,
    /// +Z up (Blender, 3ds Max and CAD exports without the conversion).
    Z,
}

/// Something of an avatar that a reader must find as one piece: a whole
/// part, or a loose piece of a part (eyeballs in the head's primitive).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Piece {
    /// The part it lies in.
    pub part: usize,
    /// Its vertices, indices into the part's.
    pub vertices: Range<usize>,
}

impl Piece {
    /// The whole of part `k`.
    pub fn whole(avatar: &Avatar, k: usize) -> Piece {
        Piece {
            part: k,
            vertices: 0..avatar.parts()[k].positions.len(),
        }
    }

    /// Whether it is the whole of its part in `avatar`.
    pub fn is_whole(&self, avatar: &Avatar) -> bool {
        self.vertices == (0..avatar.parts()[self.part].positions.len())
    }

    /// Its vertices as indices into `avatar`'s concatenated vertices.
    pub fn avatar_vertices(&self, avatar: &Avatar) -> Range<usize> {
        let o = avatar.vertex_offsets()[self.part];
        o + self.vertices.start..o + self.vertices.end
    }
}

/// What a reader must find in a test avatar. Part indices are those of
/// `likeness::avatar::glb::read_avatar_bytes(..).avatar.parts()` (parts
/// grouped by mesh in file order, each mesh placed once).
#[derive(Clone, Debug, PartialEq)]
pub struct VariantTruth {
    /// glTF meshes in the file.
    pub meshes: usize,
    /// Parts the reader returns (one per primitive, each mesh placed once).
    pub parts: usize,
    /// The part holding the face's skin.
    pub head_part: usize,
    /// Vertices of that part.
    pub head_vertices: usize,
    /// Of those, the face region's (inside the face's outline): the part's
    /// first `face_vertices` vertices.
    pub face_vertices: usize,
    /// The eyeballs, `[left, right]` (the person's left: +x in ARKit
    /// space).
    pub eyeballs: [Piece; 2],
    /// Whether the eyeballs are turned by bones (skinned to eye joints)
    /// rather than by eyeLook targets.
    pub eyes_bone_driven: bool,
    /// Whether some eyeLook* target moves an eyeball.
    pub eye_look_moves_eyeballs: bool,
    /// Whether upper and lower teeth and gums are one primitive.
    pub teeth_share_mesh_with_gums: bool,
    /// The teeth (the upper teeth where they are split), if there are
    /// teeth.
    pub teeth: Option<Piece>,
    /// Vertices of `teeth` that jawOpen moves (rigidly, about the
    /// hinge): the lower row's.
    pub jaw_moved_vertices: usize,
    /// Whether some mesh is skinned.
    pub skinned: bool,
    /// Whether some inverse bind matrix is not the identity.
    pub non_identity_bind_pose: bool,
    /// Metres per unit of the file's world space (after node transforms).
    pub unit_to_metres: f32,
    /// The world's up axis.
    pub up: UpAxis,
    /// Bounding box `[min, max]` of every part's rest positions in world
    /// space, in the file's units: what the reader finds after applying
    /// node transforms and bind placements.
    pub world_bounds: [Vec3; 2],
    /// Distinct ARKit shapes among the targets (52 for every variant).
    pub arkit_targets: usize,
    /// Names of the targets that are not ARKit's, in file order.
    pub extra_targets: Vec<&'static str>,
    /// Names of the meshes that have no morph targets.
    pub meshes_without_targets: Vec<&'static str>,
    /// Distance between the eyeball centres (m).
    pub eye_distance: f32,
}
