//! Where the default scene places each mesh (glTF 2.0 spec, "Nodes and Hierarchy",
//! "Transformations").
//!
//! A node's local transform is its `matrix` (column-major) or `T · R · S`
//! from `translation`, `rotation` (a unit quaternion x, y, z, w) and
//! `scale`; its world transform is its parent's world transform times its
//! local one. Points go through the whole matrix; a displacement (a morph
//! target's) only through its linear part, and back to the mesh's own
//! space through that part's inverse.
//!
//! A skinned mesh ignores its node's transform (spec, "Skins"): its vertices are
//! placed by the joints, `Σ wⱼ · Gⱼ · IBMⱼ · v` (`Gⱼ` the joint's world
//! transform, `IBMⱼ` its inverse bind matrix). In the pose the file was
//! exported in, every `Gⱼ · IBMⱼ` is the same matrix (the identity when the
//! armature sits at the origin), so a skinned mesh is placed by
//! `G₀ · IBM₀` of its first joint; a file saved in another pose than its
//! bind pose is read in its bind pose this way only approximately.

use super::GlbError;
use super::accessor::Source;
use glam::{Mat3, Mat4};

/// One placement of a glTF mesh: the node that places it and the node's
/// world transform (for a skinned mesh, its bind placement).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// Index of the node in the file.
    pub node: usize,
    /// Index of the glTF mesh.
    pub mesh: usize,
    /// Mesh space to world space.
    pub world: Mat4,
}

impl Placement {
    /// The linear part of [`Placement::world`]: how displacements move.
    pub fn linear(&self) -> Mat3 {
        Mat3::from_mat4(self.world)
    }
}

fn local(node: &gltf::Node) -> Mat4 {
    Mat4::from_cols_array_2d(&node.transform().matrix())
}

/// Every node's world transform, each computed once from its parent's (a
/// node with two parents, which the spec forbids, takes the first; a cycle
/// is cut where it closes).
fn world_transforms(document: &gltf::Document) -> Vec<Mat4> {
    let nodes: Vec<gltf::Node> = document.nodes().collect();
    let mut parent = vec![None; nodes.len()];
    for node in &nodes {
        for child in node.children() {
            parent[child.index()].get_or_insert(node.index());
        }
    }
    let mut world: Vec<Option<Mat4>> = vec![None; nodes.len()];
    let mut on_path = vec![false; nodes.len()];
    for start in 0..nodes.len() {
        // Walk up to a known ancestor (or the root), then back down.
        let mut path = Vec::new();
        let mut at = Some(start);
        while let Some(i) = at.filter(|&i| world[i].is_none() && !on_path[i]) {
            on_path[i] = true;
            path.push(i);
            at = parent[i];
        }
        let mut m = at.and_then(|i| world[i]).unwrap_or(Mat4::IDENTITY);
        for &i in path.iter().rev() {
            m *= local(&nodes[i]);
            world[i] = Some(m);
        }
    }
    world
        .into_iter()
        .map(|m| m.unwrap_or(Mat4::IDENTITY))
        .collect()
}

/// The placements of meshes by the default scene (or the first scene), in
/// depth-first node order; each node visited once.
pub(crate) fn placements(
    document: &gltf::Document,
    source: &Source,
) -> Result<Vec<Placement>, GlbError> {
    let Some(scene) = document
        .default_scene()
        .or_else(|| document.scenes().next())
    else {
        return Ok(Vec::new());
    };
    let worlds = world_transforms(document);
    let mut seen = vec![false; worlds.len()];
    let mut stack: Vec<gltf::Node> = scene.nodes().collect();
    stack.reverse();
    let mut out = Vec::new();
    while let Some(node) = stack.pop() {
        if std::mem::replace(&mut seen[node.index()], true) {
            continue;
        }
        if let Some(mesh) = node.mesh() {
            let world = match node.skin() {
                Some(skin) => bind_placement(&skin, &worlds, source)?,
                None => worlds[node.index()],
            };
            if Mat3::from_mat4(world).determinant().abs() < 1e-12 || !world.is_finite() {
                return Err(GlbError::Invalid {
                    file: source.file.to_path_buf(),
                    what: format!("node {}: transform not invertible", node.index()),
                });
            }
            out.push(Placement {
                node: node.index(),
                mesh: mesh.index(),
                world,
            });
        }
        let mut children: Vec<gltf::Node> = node.children().collect();
        children.reverse();
        stack.extend(children);
    }
    Ok(out)
}

/// `G₀ · IBM₀` of a skin's first joint (identity without joints).
fn bind_placement(skin: &gltf::Skin, worlds: &[Mat4], source: &Source) -> Result<Mat4, GlbError> {
    let Some(joint) = skin.joints().next() else {
        return Ok(Mat4::IDENTITY);
    };
    let ibm = match skin.inverse_bind_matrices() {
        Some(accessor) => source
            .mat4(&accessor)?
            .first()
            .copied()
            .unwrap_or(Mat4::IDENTITY),
        None => Mat4::IDENTITY,
    };
    Ok(worlds[joint.index()] * ibm)
}
