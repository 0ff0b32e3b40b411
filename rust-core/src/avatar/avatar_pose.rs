//! The avatar as an engine plays it: its rest mesh plus ARKit's 52 weights
//! times its own blendshapes, `x = x₀ + Σ_j w_j D_j` (the blendshape model
//! of the paper's Eq. (1), on the avatar). The phone's result screen shows
//! the person's avatar moving with their live weights this way.
//!
//! `D_j` is the sum of every morph target that carries ARKit shape `j`
//! ([`arkit_targets`]: a whole target on every mesh that has it, or both
//! halves of a split shape), over the avatar's parts concatenated in
//! [`Avatar::positions`] order. Each `D_j` is kept sparse (only the vertices
//! it moves), since most shapes move a small part of a whole head.

use super::target_names::arkit_targets;
use super::{ArkitTargets, Avatar};
use crate::arkit::{BLENDSHAPE_COUNT, Blendshape, Weights};
use crate::avatar::glb::write_new::vertex_normals;
use glam::Vec3;

/// One blendshape's displacement, on the vertices it moves only.
#[derive(Clone, Debug, Default, PartialEq)]
struct SparseShape {
    /// Vertex indices into the concatenated positions, ascending.
    vertices: Vec<u32>,
    /// The displacement of each of `vertices`.
    displacements: Vec<Vec3>,
}

/// An avatar ready to be posed by ARKit weights.
#[derive(Clone, Debug, PartialEq)]
pub struct AvatarPose {
    rest: Vec<Vec3>,
    triangles: Vec<[u32; 3]>,
    shapes: Vec<SparseShape>,
    found: ArkitTargets,
}

impl AvatarPose {
    /// The avatar's rest mesh and its 52 ARKit blendshapes `D_j` (zero for a
    /// shape it lacks).
    pub fn new(avatar: &Avatar) -> AvatarPose {
        let found = arkit_targets(avatar);
        let shapes = Blendshape::ALL
            .iter()
            .map(|&shape| {
                let field = avatar.summed_displacement(found.of(shape));
                let (vertices, displacements) = field
                    .iter()
                    .enumerate()
                    .filter(|(_, d)| **d != Vec3::ZERO)
                    .map(|(v, d)| (v as u32, *d))
                    .unzip();
                SparseShape {
                    vertices,
                    displacements,
                }
            })
            .collect();
        AvatarPose {
            rest: avatar.positions(),
            triangles: avatar.triangles().to_vec(),
            shapes,
            found,
        }
    }

    /// The rest positions of every part, concatenated.
    pub fn rest(&self) -> &[Vec3] {
        &self.rest
    }

    /// Every part's triangles, as indices into [`AvatarPose::rest`].
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Which of ARKit's shapes the avatar has, and on which targets.
    pub fn arkit_targets(&self) -> &ArkitTargets {
        &self.found
    }

    /// How many vertices shape `shape` moves.
    pub fn moved_vertices(&self, shape: Blendshape) -> usize {
        self.shapes[shape.index()].vertices.len()
    }

    /// Where to look: the centre and half-diagonal of the bounding box of
    /// the rest vertices that some ARKit shape moves (the face, whatever the
    /// avatar's units and placement), or of every vertex if none moves.
    pub fn focus(&self) -> (Vec3, f32) {
        let mut moved = vec![false; self.rest.len()];
        for shape in &self.shapes {
            for &v in &shape.vertices {
                moved[v as usize] = true;
            }
        }
        let any = moved.contains(&true);
        let (lo, hi) = self
            .rest
            .iter()
            .zip(&moved)
            .filter(|(_, m)| **m || !any)
            .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), (p, _)| {
                (lo.min(*p), hi.max(*p))
            });
        match lo.cmple(hi).all() {
            true => ((lo + hi) / 2.0, (hi - lo).length() / 2.0),
            false => (Vec3::ZERO, 0.0),
        }
    }

    /// Shape `shape`'s displacement `D_j` at every vertex, zero where it
    /// moves none (the dense form an engine's morph target takes).
    pub fn displacement(&self, shape: Blendshape) -> Vec<Vec3> {
        let mut out = vec![Vec3::ZERO; self.rest.len()];
        let sparse = &self.shapes[shape.index()];
        for (&v, d) in sparse.vertices.iter().zip(&sparse.displacements) {
            out[v as usize] = *d;
        }
        out
    }

    /// The rest mesh's area-weighted vertex normals
    /// ([`vertex_normals`]).
    pub fn rest_normals(&self) -> Vec<Vec3> {
        vertex_normals(&self.rest, &self.triangles)
    }

    /// How shape `shape` at weight one changes each vertex normal: the
    /// normals of `x₀ + D_j` minus `rest_normals` (the rest's,
    /// [`AvatarPose::rest_normals`], computed once by the caller for all
    /// 52), so an engine that adds weighted normal deltas and renormalizes
    /// (SceneKit's additive morpher, glTF's morph targets) shades the shape
    /// as it bends.
    pub fn normal_change(&self, shape: Blendshape, rest_normals: &[Vec3]) -> Vec<Vec3> {
        if self.shapes[shape.index()].vertices.is_empty() {
            return vec![Vec3::ZERO; self.rest.len()];
        }
        let posed: Vec<Vec3> = (self.rest.iter())
            .zip(self.displacement(shape))
            .map(|(x, d)| *x + d)
            .collect();
        vertex_normals(&posed, &self.triangles)
            .iter()
            .zip(rest_normals)
            .map(|(n, r)| *n - *r)
            .collect()
    }

    /// `x₀ + Σ_j w_j D_j` at `weights` (ARKit's order), every part
    /// concatenated.
    pub fn pose(&self, weights: &Weights) -> Vec<Vec3> {
        let mut out = self.rest.clone();
        for (shape, sparse) in (0..BLENDSHAPE_COUNT).zip(&self.shapes) {
            let w = weights.0[shape];
            if w == 0.0 {
                continue;
            }
            for (&v, d) in sparse.vertices.iter().zip(&sparse.displacements) {
                out[v as usize] += w * *d;
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::avatar::{AvatarMesh, AvatarPart};

    /// Two meshes: a head of two vertices with `jawOpen` and split brow
    /// halves, and a tooth of one vertex with its own `jawOpen`.
    fn avatar() -> Avatar {
        let head = AvatarPart {
            name: "head".into(),
            mesh: 0,
            primitive: 0,
            positions: vec![Vec3::ZERO, Vec3::X, Vec3::Y],
            triangles: vec![[0, 1, 2]],
            targets: vec![
                vec![Vec3::ZERO, Vec3::new(0.0, -1.0, 0.0), Vec3::ZERO],
                vec![Vec3::ZERO, Vec3::ZERO, Vec3::new(0.0, 0.0, 0.5)],
                vec![Vec3::new(0.0, 0.0, 0.25), Vec3::ZERO, Vec3::ZERO],
            ],
        };
        let tooth = AvatarPart {
            name: "tooth".into(),
            mesh: 1,
            primitive: 0,
            positions: vec![Vec3::splat(2.0), Vec3::splat(3.0), Vec3::splat(4.0)],
            triangles: vec![[0, 1, 2]],
            targets: vec![vec![Vec3::ZERO, Vec3::ZERO, Vec3::new(0.0, -2.0, 0.0)]],
        };
        Avatar::new(
            vec![
                AvatarMesh {
                    name: Some("head".into()),
                    target_names: vec![
                        "jawOpen".into(),
                        "browInnerUp_L".into(),
                        "browInnerUp_R".into(),
                    ],
                },
                AvatarMesh {
                    name: Some("tooth".into()),
                    target_names: vec!["jawOpen".into()],
                },
            ],
            vec![head, tooth],
        )
        .unwrap()
    }

    #[test]
    fn rest_weights_give_the_rest_mesh() {
        let pose = AvatarPose::new(&avatar());
        assert_eq!(pose.pose(&Weights::default()), pose.rest());
        assert_eq!(pose.triangles(), &[[0, 1, 2], [3, 4, 5]]);
    }

    #[test]
    fn one_shape_moves_every_mesh_that_carries_it() {
        let pose = AvatarPose::new(&avatar());
        let mut w = Weights::default();
        w.set(Blendshape::JawOpen, 0.5);
        let posed = pose.pose(&w);
        assert_eq!(posed[1], Vec3::new(1.0, -0.5, 0.0));
        assert_eq!(posed[5], Vec3::new(4.0, 3.0, 4.0));
        assert_eq!(posed[0], Vec3::ZERO);
        assert_eq!(pose.moved_vertices(Blendshape::JawOpen), 2);
    }

    #[test]
    fn split_halves_are_one_shape_and_weights_add() {
        let pose = AvatarPose::new(&avatar());
        let mut w = Weights::default();
        w.set(Blendshape::BrowInnerUp, 1.0);
        w.set(Blendshape::JawOpen, 1.0);
        let posed = pose.pose(&w);
        assert_eq!(posed[0], Vec3::new(0.0, 0.0, 0.25));
        assert_eq!(posed[1], Vec3::new(1.0, -1.0, 0.0));
        assert_eq!(posed[2], Vec3::new(0.0, 1.0, 0.5));
        assert_eq!(pose.moved_vertices(Blendshape::EyeBlinkLeft), 0);
        assert_eq!(pose.arkit_targets().found(), 2);
    }

    #[test]
    fn the_focus_is_on_what_the_shapes_move() {
        let pose = AvatarPose::new(&avatar());
        // Moved: head vertices 0, 1, 2 (the unit triangle) and tooth vertex 5.
        let (centre, radius) = pose.focus();
        assert_eq!(centre, Vec3::splat(2.0));
        assert!((radius - Vec3::splat(4.0).length() / 2.0).abs() < 1e-6);
        let still = Avatar::new(
            vec![AvatarMesh {
                name: None,
                target_names: vec![],
            }],
            vec![AvatarPart {
                mesh: 0,
                targets: vec![],
                ..avatar().parts()[1].clone()
            }],
        )
        .unwrap();
        let (centre, _) = AvatarPose::new(&still).focus();
        assert_eq!(centre, Vec3::splat(3.0));
    }
}
