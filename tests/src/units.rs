//! The same avatar in other units and axes: a GLB wrapped in a parent node
//! that scales it and turns +Y up into +Z up (as a Blender or 3ds Max
//! export in centimetres without the glTF axis conversion places a head),
//! and how far apart two sets of shapes are once the wrapping is undone.

use glam::{DQuat, DVec3, Quat};
use likeness_sim::glb_edit::Glb;
use serde_json::json;

/// A parent node's transform: a uniform scale, then a turn about +X.
#[derive(Clone, Copy, Debug)]
pub struct Wrapping {
    /// Uniform scale (100: metres to centimetres).
    pub scale: f64,
    /// Turn about +X in degrees (90: +Y up to +Z up).
    pub degrees: f64,
}

impl Wrapping {
    /// Metres to centimetres, +Y up to +Z up.
    pub const CM_Z_UP: Wrapping = Wrapping {
        scale: 100.0,
        degrees: 90.0,
    };

    /// `bytes` (a GLB with one scene) with every root of its scene made a
    /// child of one new root node carrying this transform.
    pub fn wrap(&self, bytes: &[u8]) -> Vec<u8> {
        let mut glb = Glb::parse(bytes);
        let roots = glb.json["scenes"][0]["nodes"].clone();
        let turn = Quat::from_rotation_x((self.degrees as f32).to_radians());
        let s = self.scale as f32;
        let root = glb.push_node(json!({
            "name": "Units",
            "rotation": turn.to_array(),
            "scale": [s, s, s],
            "children": roots,
        }));
        glb.set_scene_roots(&[root]);
        glb.to_bytes()
    }

    /// A displacement of the wrapped avatar (world space) in the
    /// unwrapped one's world space.
    pub fn unwrap(&self, d: DVec3) -> DVec3 {
        DQuat::from_rotation_x(-self.degrees.to_radians()) * d / self.scale
    }
}

/// How far shapes made on a wrapped avatar are from those made on it
/// unwrapped.
#[derive(Clone, Debug)]
pub struct ShapeDifference {
    /// RMS difference over all shapes and vertices, as a share of the RMS
    /// motion.
    pub rms_share: f64,
    /// The largest difference of one vertex in one shape (unwrapped
    /// units), and the shape's index.
    pub largest: (f64, usize),
    /// Each shape's RMS difference as a share of its RMS motion.
    pub per_shape: Vec<f64>,
}

/// `plain` against `wrapped` (each shape's displacement of every vertex),
/// the latter unwrapped by `wrapping`.
pub fn shape_difference(
    plain: &[Vec<glam::Vec3>],
    wrapped: &[Vec<glam::Vec3>],
    wrapping: Wrapping,
) -> ShapeDifference {
    let (mut diff2, mut motion2, mut largest) = (0.0, 0.0, (0.0f64, 0usize));
    let mut per_shape = Vec::new();
    for (k, (x, y)) in plain.iter().zip(wrapped).enumerate() {
        let (mut d2, mut m2) = (0.0, 0.0);
        for (p, q) in x.iter().zip(y) {
            let p = p.as_dvec3();
            let d = (p - wrapping.unwrap(q.as_dvec3())).length();
            d2 += d * d;
            m2 += p.length_squared();
            if d > largest.0 {
                largest = (d, k);
            }
        }
        per_shape.push((d2 / m2.max(f64::MIN_POSITIVE)).sqrt());
        diff2 += d2;
        motion2 += m2;
    }
    ShapeDifference {
        rms_share: (diff2 / motion2.max(f64::MIN_POSITIVE)).sqrt(),
        largest,
        per_shape,
    }
}
