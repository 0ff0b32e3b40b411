//! The face found on an avatar, checked against it: what
//! [`super::find_face()`] found as plain data ([`FoundFace`], what the
//! cache stores) and the same checked against the avatar and the mask it is
//! for ([`FaceRegistration`], what the later steps take), with the parts'
//! roles read off it.

use super::correspondence::CorrespondenceMap;
use super::lip_sides::LipSides;
use super::part_roles::PartRole;
use super::similarity::Similarity;
use crate::arkit::Blendshape;
use crate::avatar::model::Avatar;
use glam::DVec3;
use serde::{Deserialize, Serialize};

/// What the search for a face found, as plain data: [`FaceRegistration::new`]
/// checks it against the avatar and the mask it is for.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FoundFace {
    /// Mask (metres, ARKit's face coordinates) → avatar (its units).
    pub similarity: Similarity,
    /// The mask's vertices registered onto the avatar (avatar units).
    pub mask_on_avatar: Vec<DVec3>,
    /// `M`.
    pub map: CorrespondenceMap,
    /// Mean and largest distance of the registered mask's vertices from
    /// the avatar's skin (mm, mask scale).
    pub residual_mean_mm: f64,
    /// See `residual_mean_mm`.
    pub residual_max_mm: f64,
    /// ICP iterations run.
    pub icp_iterations: usize,
    /// The avatar's optional features that disagreed with the mask's and
    /// were left out of the placement ([`super::feature_fit`]), with how
    /// far each lay from its partner (share of the eye distance).
    pub features_left_out: Vec<(Blendshape, f64)>,
    /// Each part's role ([`super::part_roles`]), in [`Avatar::parts`]
    /// order.
    pub roles: Vec<PartRole>,
    /// Each eyeball found ([`super::eyeballs`]): its avatar vertices,
    /// increasing, in whatever parts they are.
    pub eyeballs: Vec<Vec<u32>>,
    /// Share of the mask's vertices that ended on the avatar's skin.
    pub coverage: f64,
    /// Stiffness stages and closest-point steps of the non-rigid fit.
    pub nonrigid_steps: (usize, usize),
    /// Time the registration took (s).
    pub seconds: f64,
}

/// The face found on an avatar, checked against it: every index it holds
/// names a part, a vertex or a mask triangle that exists. Read its data
/// through [`FoundFace`]'s fields (it dereferences to it).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(transparent)]
pub struct FaceRegistration(FoundFace);

/// Why a [`FoundFace`] does not fit the avatar or the mask it is used
/// with (a cache file from elsewhere, a mistake in a test).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum InvalidRegistration {
    /// Not one role per part of the avatar.
    #[error("{found} part roles for an avatar of {expected} parts")]
    Roles {
        /// Roles given.
        found: usize,
        /// Parts of the avatar.
        expected: usize,
    },
    /// Not one registered position per mask vertex.
    #[error("{found} registered mask vertices for a mask of {expected}")]
    MaskSize {
        /// Positions given.
        found: usize,
        /// Vertices of the mask.
        expected: usize,
    },
    /// A number that must be finite is not, or the scale is not positive.
    #[error("{0} is not finite (or the scale not positive)")]
    NotFinite(&'static str),
    /// An avatar vertex index past the avatar's end, or a list that must
    /// increase does not.
    #[error("{what}: vertex {vertex} is past the avatar's {vertices} or out of order")]
    Vertex {
        /// `eyeball N` or `face region`.
        what: String,
        /// The vertex.
        vertex: u32,
        /// Vertices of the avatar.
        vertices: usize,
    },
    /// A mask triangle, or a vertex of one, out of range.
    #[error("the map's mask triangle {0} is out of range")]
    MaskTriangle(usize),
}

impl FaceRegistration {
    /// `found`, checked against `avatar` and a mask of `mask_vertices`
    /// vertices: one role per part; one registered position per mask
    /// vertex, all finite, as the similarity; eyeballs and the face region
    /// of increasing avatar vertices; the map's triangles on the mask and
    /// its points on its triangles.
    pub fn new(
        found: FoundFace,
        avatar: &Avatar,
        mask_vertices: usize,
    ) -> Result<FaceRegistration, InvalidRegistration> {
        let parts = avatar.parts().len();
        if found.roles.len() != parts {
            return Err(InvalidRegistration::Roles {
                found: found.roles.len(),
                expected: parts,
            });
        }
        if found.mask_on_avatar.len() != mask_vertices {
            return Err(InvalidRegistration::MaskSize {
                found: found.mask_on_avatar.len(),
                expected: mask_vertices,
            });
        }
        let s = found.similarity;
        let finite = s.scale.is_finite() && s.rotation.is_finite() && s.translation.is_finite();
        if !(finite && s.scale > 0.0) {
            return Err(InvalidRegistration::NotFinite("the similarity"));
        }
        if found.mask_on_avatar.iter().any(|p| !p.is_finite()) {
            return Err(InvalidRegistration::NotFinite("the registered mask"));
        }
        let vertices = avatar.vertex_count();
        let increasing = |what: String, list: &mut dyn Iterator<Item = u32>| {
            let mut last: Option<u32> = None;
            for v in list {
                if v as usize >= vertices || last.is_some_and(|l| l >= v) {
                    return Err(InvalidRegistration::Vertex {
                        what,
                        vertex: v,
                        vertices,
                    });
                }
                last = Some(v);
            }
            Ok(())
        };
        for (k, eyeball) in found.eyeballs.iter().enumerate() {
            increasing(format!("eyeball {k}"), &mut eyeball.iter().copied())?;
        }
        increasing(
            "face region".into(),
            &mut found.map.face.iter().map(|f| f.vertex),
        )?;
        let map = &found.map;
        if let Some(t) = map
            .mask_triangles
            .iter()
            .position(|t| t.iter().any(|&v| v as usize >= mask_vertices))
        {
            return Err(InvalidRegistration::MaskTriangle(t));
        }
        if let Some(f) = map.face.iter().find(|f| {
            f.triangle as usize >= map.mask_triangles.len()
                || f.barycentric.iter().any(|b| !b.is_finite())
        }) {
            return Err(InvalidRegistration::MaskTriangle(f.triangle as usize));
        }
        Ok(FaceRegistration(found))
    }

    /// The registered mask's lips ([`LipSides`]), for keeping each lip's
    /// motion on its own side of the mouth's slit.
    pub fn lip_sides(&self) -> LipSides {
        LipSides::of_mask(&self.mask_on_avatar, &self.map.mask_triangles)
    }

    /// The lips (bits of `lips`, this registration's [`LipSides`]; 0 off
    /// the lips) of each of the avatar's `n` vertices: those of the mask
    /// triangle the map `M` takes it to.
    pub fn vertex_lips(&self, lips: &LipSides, n: usize) -> Vec<u8> {
        let mut labels = vec![0u8; n];
        for f in &self.map.face {
            if let (Some(l), Some(t)) = (
                labels.get_mut(f.vertex as usize),
                self.map.mask_triangles.get(f.triangle as usize),
            ) {
                *l = lips.lips_of(*t);
            }
        }
        labels
    }

    /// The parts of role `role`, increasing.
    pub fn parts_with(&self, role: PartRole) -> Vec<usize> {
        (0..self.roles.len())
            .filter(|&i| self.roles[i] == role)
            .collect()
    }

    /// The parts the face region was taken from: the skin.
    pub fn face_parts(&self) -> Vec<usize> {
        self.parts_with(PartRole::Skin)
    }

    /// The parts taken wholly for eyeballs.
    pub fn eyeball_parts(&self) -> Vec<usize> {
        self.parts_with(PartRole::Eyeball)
    }

    /// The same registration with the mask's registered vertices moved by
    /// `by` (one displacement per mask vertex; the person's face taken on
    /// the avatar moves the skin under them), checked again.
    pub fn with_mask_moved(
        &self,
        avatar: &Avatar,
        by: impl Fn(usize) -> DVec3,
    ) -> Result<FaceRegistration, InvalidRegistration> {
        let mut found = self.0.clone();
        for (i, p) in found.mask_on_avatar.iter_mut().enumerate() {
            *p += by(i);
        }
        let n = found.mask_on_avatar.len();
        FaceRegistration::new(found, avatar, n)
    }

    /// The data, to store or to change and check again.
    pub fn into_found(self) -> FoundFace {
        self.0
    }
}

impl std::ops::Deref for FaceRegistration {
    type Target = FoundFace;

    fn deref(&self) -> &FoundFace {
        &self.0
    }
}
