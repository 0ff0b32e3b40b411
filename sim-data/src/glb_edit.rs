//! Editing a GLB the core wrote (`likeness::avatar::glb::new_avatar_glb`):
//! its JSON and binary chunks apart, accessors appended, node hierarchies
//! and skins added, and the chunks put back together.
//!
//! The core's writer places every mesh by a node of its own at the origin
//! with no skin, as the default avatar needs; the test avatars need what
//! users' files have besides (glTF 2.0 spec, "Nodes and Hierarchy",
//! "Skins"). Only files this crate wrote are edited, so a malformed input
//! is a bug and panics.

use glam::{Mat4, Quat, Vec3};
use serde_json::{Value, json};

/// `ARRAY_BUFFER`: a buffer view of vertex attributes.
const ARRAY_BUFFER: u32 = 34962;
/// Component types.
const FLOAT: u32 = 5126;
const UNSIGNED_SHORT: u32 = 5123;

/// A GLB as its JSON document and its binary chunk.
#[derive(Clone, Debug)]
pub struct Glb {
    /// The JSON chunk.
    pub json: Value,
    /// The binary chunk (buffer 0), unpadded.
    pub bin: Vec<u8>,
}

fn u32_at(bytes: &[u8], at: usize) -> usize {
    u32::from_le_bytes(bytes[at..at + 4].try_into().expect("4 bytes")) as usize
}

impl Glb {
    /// Splits a GLB of one JSON and at most one binary chunk.
    pub fn parse(bytes: &[u8]) -> Glb {
        assert_eq!(&bytes[..4], b"glTF", "not a GLB");
        let json_len = u32_at(bytes, 12);
        let json = serde_json::from_slice(&bytes[20..20 + json_len]).expect("GLB JSON");
        let mut bin = Vec::new();
        let at = 20 + json_len;
        if bytes.len() > at + 8 {
            let bin_len = u32_at(bytes, at);
            bin = bytes[at + 8..at + 8 + bin_len].to_vec();
        }
        let mut glb = Glb { json, bin };
        if let Some(len) = glb.json["buffers"][0]["byteLength"].as_u64() {
            glb.bin.truncate(len as usize);
        }
        glb
    }

    /// The GLB's bytes: the JSON chunk padded with spaces, the binary
    /// chunk with zeros (spec, "GLB File Format Specification").
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut json = self.json.clone();
        json["buffers"] = json!([{ "byteLength": self.bin.len() }]);
        let mut text = serde_json::to_vec(&json).expect("JSON");
        text.resize(text.len().next_multiple_of(4), b' ');
        let mut bin = self.bin.clone();
        bin.resize(bin.len().next_multiple_of(4), 0);
        let total = 12 + 8 + text.len() + 8 + bin.len();
        let mut out = Vec::with_capacity(total);
        out.extend_from_slice(b"glTF");
        out.extend_from_slice(&2u32.to_le_bytes());
        out.extend_from_slice(&(total as u32).to_le_bytes());
        out.extend_from_slice(&(text.len() as u32).to_le_bytes());
        out.extend_from_slice(b"JSON");
        out.extend_from_slice(&text);
        out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(&bin);
        out
    }

    /// Appends `bytes` as a buffer view (4-byte aligned) and `accessor`
    /// over it; the accessor's index. Vertex attributes' views carry the
    /// `ARRAY_BUFFER` target, other data (matrices) none.
    pub fn push_accessor(&mut self, bytes: &[u8], mut accessor: Value, vertex: bool) -> usize {
        self.bin.resize(self.bin.len().next_multiple_of(4), 0);
        let mut view =
            json!({ "buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len() });
        if vertex {
            view["target"] = json!(ARRAY_BUFFER);
        }
        self.bin.extend_from_slice(bytes);
        let views = self.json["bufferViews"].as_array_mut().expect("views");
        views.push(view);
        accessor["bufferView"] = json!(views.len() - 1);
        let accessors = self.json["accessors"].as_array_mut().expect("accessors");
        accessors.push(accessor);
        accessors.len() - 1
    }

    /// Appends `bytes` as a buffer view (4-byte aligned) with no target
    /// (an image's); the view's index.
    pub fn push_view(&mut self, bytes: &[u8]) -> usize {
        self.bin.resize(self.bin.len().next_multiple_of(4), 0);
        let view = json!({ "buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len() });
        self.bin.extend_from_slice(bytes);
        let views = self.json["bufferViews"].as_array_mut().expect("views");
        views.push(view);
        views.len() - 1
    }

    /// Adds `JOINTS_0` (unsigned short) and `WEIGHTS_0` (float) to
    /// primitive `primitive` of mesh `mesh`.
    pub fn skin_primitive(
        &mut self,
        mesh: usize,
        primitive: usize,
        joints: &[[u16; 4]],
        weights: &[[f32; 4]],
    ) {
        let j: Vec<u8> = joints
            .iter()
            .flatten()
            .flat_map(|x| x.to_le_bytes())
            .collect();
        let w: Vec<u8> = weights
            .iter()
            .flatten()
            .flat_map(|x| x.to_le_bytes())
            .collect();
        let n = joints.len();
        let ja = self.push_accessor(
            &j,
            json!({ "componentType": UNSIGNED_SHORT, "count": n, "type": "VEC4" }),
            true,
        );
        let wa = self.push_accessor(
            &w,
            json!({ "componentType": FLOAT, "count": n, "type": "VEC4" }),
            true,
        );
        let attributes = &mut self.json["meshes"][mesh]["primitives"][primitive]["attributes"];
        attributes["JOINTS_0"] = json!(ja);
        attributes["WEIGHTS_0"] = json!(wa);
    }

    /// Appends a node; its index.
    pub fn push_node(&mut self, node: Value) -> usize {
        let nodes = self.json["nodes"].as_array_mut().expect("nodes");
        nodes.push(node);
        nodes.len() - 1
    }

    /// Makes `nodes` the default scene's root nodes.
    pub fn set_scene_roots(&mut self, nodes: &[usize]) {
        self.json["scenes"] = json!([{ "nodes": nodes }]);
        self.json["scene"] = json!(0);
    }

    /// Adds a skeleton of `joints` (nodes in the given order, each parent
    /// before its children) and a skin over all of them whose inverse bind
    /// matrices are the inverses of the joints' world transforms at rest
    /// (the bind pose is the pose written); the skeleton's root node and
    /// the skin's index.
    pub fn push_skeleton(&mut self, joints: &[Joint]) -> (usize, usize) {
        let first = self.json["nodes"].as_array().map_or(0, Vec::len);
        let worlds = joint_worlds(joints);
        for (k, j) in joints.iter().enumerate() {
            let children: Vec<usize> = (0..joints.len())
                .filter(|&c| joints[c].parent == Some(k))
                .map(|c| first + c)
                .collect();
            let mut node = json!({
                "name": j.name,
                "translation": j.translation.to_array(),
            });
            if j.rotation != Quat::IDENTITY {
                node["rotation"] = json!(j.rotation.to_array());
            }
            if !children.is_empty() {
                node["children"] = json!(children);
            }
            self.push_node(node);
        }
        let ibm: Vec<u8> = worlds
            .iter()
            .flat_map(|w| w.inverse().to_cols_array())
            .flat_map(f32::to_le_bytes)
            .collect();
        let accessor = self.push_accessor(
            &ibm,
            json!({ "componentType": FLOAT, "count": joints.len(), "type": "MAT4" }),
            false,
        );
        let mut skins = self.json["skins"].as_array().cloned().unwrap_or_default();
        skins.push(json!({
            "joints": (first..first + joints.len()).collect::<Vec<_>>(),
            "inverseBindMatrices": accessor,
            "skeleton": first,
        }));
        let skin = skins.len() - 1;
        self.json["skins"] = Value::Array(skins);
        (first, skin)
    }
}

/// One joint of a skeleton: a node with a translation and a rotation
/// relative to its parent.
#[derive(Clone, Debug)]
pub struct Joint {
    /// The node's name.
    pub name: &'static str,
    /// Index of the parent in the joint list (`None` for the root).
    pub parent: Option<usize>,
    /// Translation relative to the parent (m).
    pub translation: Vec3,
    /// Rotation relative to the parent.
    pub rotation: Quat,
}

impl Joint {
    /// A joint without rotation.
    pub fn at(name: &'static str, parent: Option<usize>, translation: Vec3) -> Joint {
        Joint {
            name,
            parent,
            translation,
            rotation: Quat::IDENTITY,
        }
    }
}

/// World transforms of `joints` at rest.
pub fn joint_worlds(joints: &[Joint]) -> Vec<Mat4> {
    let mut worlds: Vec<Mat4> = Vec::new();
    for j in joints {
        let local = Mat4::from_rotation_translation(j.rotation, j.translation);
        worlds.push(j.parent.map_or(local, |p| worlds[p] * local));
    }
    worlds
}
