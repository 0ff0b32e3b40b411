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
/// meshes' morph targets, with one global topology over all of them.
///
/// Made only by [`Avatar::new`], which checks that every part fits its mesh
/// and itself; its parts are read through [`Avatar::parts`] and change
/// only by taking the avatar apart ([`Avatar::into_parts`]) and checking
/// it again.
#[derive(Clone, Debug, PartialEq)]
pub struct Avatar {
    meshes: Vec<AvatarMesh>,
    parts: Vec<AvatarPart>,
    /// Offset of each part's first vertex in the concatenated vertex list,
    /// and the total at the end.
    offsets: Vec<usize>,
    /// Every part's triangles in global vertex indices, part after part.
    triangles: Vec<[u32; 3]>,
    /// Offset of each part's first triangle in `triangles`, and the total
    /// at the end.
    triangle_offsets: Vec<usize>,
}

/// Why parts do not make an avatar: the first part (index into the parts
/// given) that breaks a rule, and the rule.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum InvalidAvatar {
    /// A part names a mesh past the end of the meshes.
    #[error("part {part}: mesh {mesh}, but there are {meshes} meshes")]
    Mesh {
        /// The part.
        part: usize,
        /// The mesh it names.
        mesh: usize,
        /// Meshes given.
        meshes: usize,
    },
    /// A triangle names a vertex past the part's end, or one vertex twice.
    #[error("part {part} triangle {triangle}: {what}")]
    Triangle {
        /// The part.
        part: usize,
        /// The triangle within the part.
        triangle: usize,
        /// What is wrong.
        what: String,
    },
    /// A part has not one displacement list per target of its mesh.
    #[error("part {part}: {found} targets, its mesh has {expected}")]
    TargetCount {
        /// The part.
        part: usize,
        /// Targets the part has.
        found: usize,
        /// Targets its mesh names.
        expected: usize,
    },
    /// A target does not displace every vertex of its part once.
    #[error("part {part} target {target}: {found} displacements for {expected} vertices")]
    TargetLength {
        /// The part.
        part: usize,
        /// The target.
        target: usize,
        /// Displacements given.
        found: usize,
        /// Vertices of the part.
        expected: usize,
    },
    /// A rest position or a displacement is NaN or infinite.
    #[error("part {part} {what} vertex {vertex}: not finite")]
    NotFinite {
        /// The part.
        part: usize,
        /// `position` or `target N`.
        what: String,
        /// The vertex within the part.
        vertex: usize,
    },
    /// The parts hold more vertices than a `u32` index reaches.
    #[error("{0} vertices: more than a 32-bit index reaches")]
    TooManyVertices(usize),
}

impl Avatar {
    /// The avatar of `meshes` and `parts`, checked: every part names one of
    /// the meshes and has one displacement list per target of it, each as
    /// long as its positions; every triangle names three distinct vertices
    /// of its part; every position and displacement is finite; the
    /// vertices all together fit `u32` indices.
    pub fn new(meshes: Vec<AvatarMesh>, parts: Vec<AvatarPart>) -> Result<Avatar, InvalidAvatar> {
        for (k, part) in parts.iter().enumerate() {
            check_part(k, part, &meshes)?;
        }
        let mut offsets = Vec::with_capacity(parts.len() + 1);
        let mut at = 0;
        for part in &parts {
            offsets.push(at);
            at += part.positions.len();
        }
        offsets.push(at);
        if u32::try_from(at).is_err() {
            return Err(InvalidAvatar::TooManyVertices(at));
        }
        let mut triangles = Vec::with_capacity(parts.iter().map(|p| p.triangles.len()).sum());
        let mut triangle_offsets = Vec::with_capacity(parts.len() + 1);
        for (part, &o) in parts.iter().zip(&offsets) {
            triangle_offsets.push(triangles.len());
            triangles.extend(part.triangles.iter().map(|t| t.map(|v| v + o as u32)));
        }
        triangle_offsets.push(triangles.len());
        Ok(Avatar {
            meshes,
            parts,
            offsets,
            triangles,
            triangle_offsets,
        })
    }

    /// The meshes, in the file's order.
    pub fn meshes(&self) -> &[AvatarMesh] {
        &self.meshes
    }

    /// The parts, grouped by mesh in the file's order.
    pub fn parts(&self) -> &[AvatarPart] {
        &self.parts
    }

    /// The meshes and parts, to change and check again with
    /// [`Avatar::new`].
    pub fn into_parts(self) -> (Vec<AvatarMesh>, Vec<AvatarPart>) {
        (self.meshes, self.parts)
    }

    /// The avatar with every vertex's rest position moved by `by` (one
    /// displacement per vertex of [`Avatar::positions`], double precision),
    /// its targets kept; an error where a moved position is not finite.
    pub fn with_rest_moved(&self, by: &[DVec3]) -> Result<Avatar, InvalidAvatar> {
        let mut parts = self.parts.clone();
        for (k, part) in parts.iter_mut().enumerate() {
            let moved = by.get(self.offsets[k]..).unwrap_or_default();
            for (p, u) in part.positions.iter_mut().zip(moved) {
                *p += u.as_vec3();
            }
        }
        Avatar::new(self.meshes.clone(), parts)
    }

    /// The avatar with `edit` applied to its meshes and parts, checked
    /// again by [`Avatar::new`].
    pub fn edited(
        self,
        edit: impl FnOnce(&mut Vec<AvatarMesh>, &mut Vec<AvatarPart>),
    ) -> Result<Avatar, InvalidAvatar> {
        let (mut meshes, mut parts) = self.into_parts();
        edit(&mut meshes, &mut parts);
        Avatar::new(meshes, parts)
    }

    /// Total number of vertices over all parts.
    pub fn vertex_count(&self) -> usize {
        self.offsets[self.parts.len()]
    }

    /// Offset of each part's first vertex in the avatar's concatenated
    /// vertex list ([`Avatar::positions`]), and the total at the end.
    pub fn vertex_offsets(&self) -> &[usize] {
        &self.offsets
    }

    /// The global vertex indices of part `part`: a range of
    /// [`Avatar::positions`].
    pub fn part_vertices(&self, part: usize) -> std::ops::Range<usize> {
        self.offsets[part]..self.offsets[part + 1]
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
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// The triangles of the parts `parts` (indices into
    /// [`Avatar::parts`]; those out of range are skipped), in that order,
    /// as indices into [`Avatar::positions`].
    pub fn part_triangles(&self, parts: &[usize]) -> Vec<[u32; 3]> {
        parts
            .iter()
            .filter(|&&i| i < self.parts.len())
            .flat_map(|&i| &self.triangles[self.triangle_offsets[i]..self.triangle_offsets[i + 1]])
            .copied()
            .collect()
    }

    /// The triangles (indices into [`Avatar::positions`]) all of whose
    /// corners are among `vertices` (increasing).
    pub fn triangles_within(&self, vertices: &[u32]) -> Vec<[u32; 3]> {
        self.triangles
            .iter()
            .filter(|t| t.iter().all(|v| vertices.binary_search(v).is_ok()))
            .copied()
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
}

#[cfg(test)]
impl Avatar {
    /// The smallest avatar, for tests: one mesh of one part `name` of one
    /// triangle `(0, x, y)`, no targets.
    pub(crate) fn one_triangle(name: &str) -> Avatar {
        let mesh = AvatarMesh {
            name: Some(name.into()),
            target_names: Vec::new(),
        };
        let part = AvatarPart {
            name: name.into(),
            mesh: 0,
            primitive: 0,
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            triangles: vec![[0, 1, 2]],
            targets: Vec::new(),
        };
        Avatar::new(vec![mesh], vec![part]).expect("one triangle is an avatar")
    }
}

/// Checks part `k` against the rules of [`Avatar::new`].
fn check_part(k: usize, part: &AvatarPart, meshes: &[AvatarMesh]) -> Result<(), InvalidAvatar> {
    let Some(mesh) = meshes.get(part.mesh) else {
        return Err(InvalidAvatar::Mesh {
            part: k,
            mesh: part.mesh,
            meshes: meshes.len(),
        });
    };
    let n = part.positions.len();
    for (triangle, t) in part.triangles.iter().enumerate() {
        let what = if let Some(v) = t.iter().find(|&&v| v as usize >= n) {
            format!("vertex {v} past the part's {n}")
        } else if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
            format!("vertex repeated in {t:?}")
        } else {
            continue;
        };
        return Err(InvalidAvatar::Triangle {
            part: k,
            triangle,
            what,
        });
    }
    if part.targets.len() != mesh.target_names.len() {
        return Err(InvalidAvatar::TargetCount {
            part: k,
            found: part.targets.len(),
            expected: mesh.target_names.len(),
        });
    }
    if let Some(vertex) = part.positions.iter().position(|p| !p.is_finite()) {
        return Err(InvalidAvatar::NotFinite {
            part: k,
            what: "position".into(),
            vertex,
        });
    }
    for (target, d) in part.targets.iter().enumerate() {
        if d.len() != n {
            return Err(InvalidAvatar::TargetLength {
                part: k,
                target,
                found: d.len(),
                expected: n,
            });
        }
        if let Some(vertex) = d.iter().position(|x| !x.is_finite()) {
            return Err(InvalidAvatar::NotFinite {
                part: k,
                what: format!("target {target}"),
                vertex,
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mesh() -> AvatarMesh {
        AvatarMesh {
            name: None,
            target_names: vec!["a".into()],
        }
    }

    fn triangle() -> AvatarPart {
        AvatarPart {
            name: "p".into(),
            mesh: 0,
            primitive: 0,
            positions: vec![Vec3::X, Vec3::Y, Vec3::Z],
            triangles: vec![[0, 1, 2]],
            targets: vec![vec![Vec3::ZERO; 3]],
        }
    }

    /// The error for two parts, the second changed by `edit`.
    fn broken(edit: fn(&mut AvatarPart)) -> InvalidAvatar {
        let mut part = triangle();
        edit(&mut part);
        Avatar::new(vec![mesh()], vec![triangle(), part]).unwrap_err()
    }

    #[test]
    fn a_part_that_does_not_fit_is_refused_naming_the_part_and_the_rule() {
        assert!(Avatar::new(vec![mesh()], vec![triangle(), triangle()]).is_ok());
        assert_eq!(
            broken(|p| p.mesh = 1),
            InvalidAvatar::Mesh {
                part: 1,
                mesh: 1,
                meshes: 1
            }
        );
        assert_eq!(
            broken(|p| p.triangles[0] = [0, 1, 3]).to_string(),
            "part 1 triangle 0: vertex 3 past the part's 3"
        );
        assert_eq!(
            broken(|p| p.triangles[0] = [0, 2, 2]).to_string(),
            "part 1 triangle 0: vertex repeated in [0, 2, 2]"
        );
        assert_eq!(
            broken(|p| p.targets.clear()),
            InvalidAvatar::TargetCount {
                part: 1,
                found: 0,
                expected: 1
            }
        );
        assert_eq!(
            broken(|p| p.targets[0].truncate(2)),
            InvalidAvatar::TargetLength {
                part: 1,
                target: 0,
                found: 2,
                expected: 3
            }
        );
        assert_eq!(
            broken(|p| p.positions[2].x = f32::NAN).to_string(),
            "part 1 position vertex 2: not finite"
        );
        assert_eq!(
            broken(|p| p.targets[0][1].y = f32::INFINITY).to_string(),
            "part 1 target 0 vertex 1: not finite"
        );
    }

    #[test]
    fn part_triangles_are_in_global_indices_in_the_order_asked() {
        let mut second = triangle();
        second.triangles.push([2, 1, 0]);
        let avatar = Avatar::new(vec![mesh()], vec![triangle(), second]).unwrap();
        assert_eq!(avatar.vertex_offsets(), &[0, 3, 6]);
        assert_eq!(
            avatar.part_triangles(&[1, 0, 7]),
            vec![[3, 4, 5], [5, 4, 3], [0, 1, 2]]
        );
        assert_eq!(avatar.triangles().len(), 3);
        let moved = avatar.with_rest_moved(&[DVec3::Z; 6]).unwrap();
        assert_eq!(moved.parts()[1].positions[0], Vec3::new(1.0, 0.0, 1.0));
        assert!(avatar.with_rest_moved(&[DVec3::NAN; 6]).is_err());
    }

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
        let avatar = Avatar::new(
            vec![
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
            vec![
                part(0, 1.0, vec![still.clone(), lift.clone()]),
                part(1, 2.0, vec![lift]),
            ],
        )
        .unwrap();
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
