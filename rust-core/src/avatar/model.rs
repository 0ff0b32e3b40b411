//! The avatar as the rest of the pipeline sees it: triangle meshes in world
//! space with their morph targets, grouped as the glTF file groups them.
//!
//! A glTF mesh holds one or more primitives that share one list of morph
//! targets (the spec requires every primitive of a mesh to have the same
//! number of targets), so an [`AvatarMesh`] owns the target names and each
//! [`AvatarPart`] (one primitive as placed by one node) owns the
//! displacements of those targets on its own vertices.

use glam::{DVec3, Vec3};

/// One triangle primitive of the avatar, placed in world space.
#[derive(Clone, Debug, PartialEq)]
pub struct AvatarPart {
    /// Name for reports: the node's name, else the mesh's, else `mesh N`.
    pub name: String,
    /// Index of the [`AvatarMesh`] (in [`Avatar::meshes`]) this part belongs to.
    pub mesh: usize,
    /// Index of the primitive within its glTF mesh.
    pub primitive: usize,
    /// Rest positions in world space (node transforms applied), in the
    /// file's units.
    pub positions: Vec<Vec3>,
    /// Triangles as indices into `positions`.
    pub triangles: Vec<[u32; 3]>,
    /// World-space displacement of every vertex under each morph target of
    /// the mesh, in the mesh's target order: `targets[t][v]`. Every entry
    /// has `positions.len()` displacements.
    pub targets: Vec<Vec<Vec3>>,
}

/// One glTF mesh: its name and the names of its morph targets, shared by
/// its parts.
#[derive(Clone, Debug, PartialEq)]
pub struct AvatarMesh {
    /// The mesh's name in the file, if it has one.
    pub name: Option<String>,
    /// Each morph target's name as read (see `target_names` for where names
    /// come from); unnamed targets are `target N`.
    pub target_names: Vec<String>,
}

/// An avatar: every triangle primitive of the file in world space, and its
/// meshes' morph targets.
#[derive(Clone, Debug, PartialEq)]
pub struct Avatar {
    /// The meshes, in the file's order.
    pub meshes: Vec<AvatarMesh>,
    /// The parts, grouped by mesh in the file's order.
    pub parts: Vec<AvatarPart>,
}

impl Avatar {
    /// Total number of vertices over all parts.
    pub fn vertex_count(&self) -> usize {
        self.parts.iter().map(|p| p.positions.len()).sum()
    }

    /// Offset of each part's first vertex in the avatar's concatenated
    /// vertex list ([`Avatar::positions`]), and the total at the end.
    pub fn vertex_offsets(&self) -> Vec<usize> {
        let mut offsets = Vec::with_capacity(self.parts.len() + 1);
        let mut at = 0;
        for part in &self.parts {
            offsets.push(at);
            at += part.positions.len();
        }
        offsets.push(at);
        offsets
    }

    /// Every part's rest positions, concatenated in part order.
    pub fn positions(&self) -> Vec<Vec3> {
        self.parts
            .iter()
            .flat_map(|p| p.positions.iter().copied())
            .collect()
    }

    /// Every part's triangles, concatenated, as indices into
    /// [`Avatar::positions`].
    pub fn triangles(&self) -> Vec<[u32; 3]> {
        let offsets = self.vertex_offsets();
        self.parts
            .iter()
            .zip(&offsets)
            .flat_map(|(p, &o)| p.triangles.iter().map(move |t| t.map(|i| i + o as u32)))
            .collect()
    }

    /// The triangles of the parts `parts` (indices into `self.parts`; those
    /// out of range are skipped), as indices into [`Avatar::positions`].
    pub fn triangles_of(&self, parts: &[usize]) -> Vec<[u32; 3]> {
        let offsets = self.vertex_offsets();
        parts
            .iter()
            .filter_map(|&i| Some((self.parts.get(i)?, offsets[i] as u32)))
            .flat_map(|(part, o)| part.triangles.iter().map(move |t| t.map(|v| v + o)))
            .collect()
    }

    /// The triangles (indices into [`Avatar::positions`]) all of whose
    /// corners are among `vertices` (increasing).
    pub fn triangles_within(&self, vertices: &[u32]) -> Vec<[u32; 3]> {
        self.triangles()
            .into_iter()
            .filter(|t| t.iter().all(|v| vertices.binary_search(v).is_ok()))
            .collect()
    }

    /// The avatar's morph targets as `(mesh, target)` pairs, in mesh order.
    pub fn target_ids(&self) -> Vec<(usize, usize)> {
        self.meshes
            .iter()
            .enumerate()
            .flat_map(|(m, mesh)| (0..mesh.target_names.len()).map(move |t| (m, t)))
            .collect()
    }

    /// The displacement of every avatar vertex (concatenated, as
    /// [`Avatar::positions`]) under target `t` of mesh `mesh`: zero on the
    /// parts of other meshes.
    pub fn target_displacement(&self, mesh: usize, t: usize) -> Vec<Vec3> {
        let mut out = Vec::with_capacity(self.vertex_count());
        for part in &self.parts {
            match part.targets.get(t).filter(|_| part.mesh == mesh) {
                Some(d) => out.extend_from_slice(d),
                None => out.extend(std::iter::repeat_n(Vec3::ZERO, part.positions.len())),
            }
        }
        out
    }

    /// The displacement of every avatar vertex (as [`Avatar::positions`])
    /// under each target that moves some vertex, in double precision, in
    /// [`Avatar::target_ids`] order; a target that moves nothing is left
    /// out (every piece of the avatar is still, and so rigid, under it).
    pub fn moving_target_displacements(&self) -> Vec<Vec<DVec3>> {
        self.target_ids()
            .into_iter()
            .filter(|&(m, t)| {
                self.parts.iter().any(|part| {
                    part.mesh == m
                        && part
                            .targets
                            .get(t)
                            .is_some_and(|d| d.iter().any(|x| *x != Vec3::ZERO))
                })
            })
            .map(|(m, t)| {
                self.target_displacement(m, t)
                    .iter()
                    .map(|d| d.as_dvec3())
                    .collect()
            })
            .collect()
    }

    /// The summed displacement of every avatar vertex under the targets
    /// `targets` (`(mesh, target)` pairs): one blendshape spread over
    /// several meshes, or a shape split into halves.
    pub fn summed_displacement(&self, targets: &[(usize, usize)]) -> Vec<Vec3> {
        let mut out = vec![Vec3::ZERO; self.vertex_count()];
        for &(mesh, t) in targets {
            for (o, d) in out.iter_mut().zip(self.target_displacement(mesh, t)) {
                *o += d;
            }
        }
        out
    }

    /// The summed displacement of every target named exactly `name`, on
    /// whichever meshes have one.
    pub fn named_displacement(&self, name: &str) -> Vec<Vec3> {
        let targets: Vec<(usize, usize)> = self
            .target_ids()
            .into_iter()
            .filter(|&(m, t)| self.meshes[m].target_names[t] == name)
            .collect();
        self.summed_displacement(&targets)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_targets_that_move_something_are_given_in_double_precision() {
        let part = |mesh: usize, x: f32, targets: Vec<Vec<Vec3>>| AvatarPart {
            name: format!("part {mesh}"),
            mesh,
            primitive: 0,
            positions: vec![Vec3::X * x, Vec3::Y, Vec3::Z],
            triangles: vec![[0, 1, 2]],
            targets,
        };
        let still = vec![Vec3::ZERO; 3];
        let lift = vec![Vec3::ZERO, Vec3::ZERO, Vec3::Y * 0.5];
        let avatar = Avatar {
            meshes: vec![
                AvatarMesh {
                    name: None,
                    target_names: vec!["a".into(), "b".into()],
                },
                AvatarMesh {
                    name: None,
                    target_names: vec!["a".into()],
                },
            ],
            // Mesh 0's "a" moves nothing, its "b" lifts a vertex; mesh
            // 1's "a" lifts one too.
            parts: vec![
                part(0, 1.0, vec![still.clone(), lift.clone()]),
                part(1, 2.0, vec![lift]),
            ],
        };
        let moving = avatar.moving_target_displacements();
        assert_eq!(moving.len(), 2);
        let lifted = |v: usize| {
            let mut d = vec![DVec3::ZERO; 6];
            d[v] = DVec3::Y * 0.5;
            d
        };
        assert_eq!(moving[0], lifted(2), "mesh 0's b");
        assert_eq!(moving[1], lifted(5), "mesh 1's a");
    }
}
