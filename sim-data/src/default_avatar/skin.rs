//! The skin (face region and head sharing the outline) with its 52 shapes,
//! at any resolution: the default avatar's at [`super::face::FACE_SPACING`] and
//! [`super::head::HEAD_SPACING`], the low-poly test avatar's coarser
//! (`avatar_variants::low_poly`). Resampling the mask and continuing the
//! template past the outline at another spacing gives the same surface and
//! the same motion on other vertices.

use super::face::{FaceRegion, face_region_with};
use super::head::head_region_with;
use super::{mouth_opening, shapes};
use crate::face_mask::face_mask;
use crate::template::{generic_model, generic_template};
use glam::DVec3;

/// The skin and its shapes.
#[derive(Clone, Debug)]
pub struct Skin {
    /// The face region; its vertices are the skin's first ones.
    pub face: FaceRegion,
    /// Face vertices, then the head's own (m).
    pub positions: Vec<DVec3>,
    /// Triangles over `positions`, outward-facing; those of the red of the
    /// lips last, from `lips_from` on.
    pub triangles: Vec<[u32; 3]>,
    /// Index of the first triangle on the red of the lips.
    pub lips_from: usize,
    /// The 52 shapes in Apple's order, one delta per skin vertex.
    pub targets: Vec<Vec<DVec3>>,
    /// The 52 shapes on the face region only (`targets` restricted to its
    /// vertices).
    pub face_targets: Vec<Vec<DVec3>>,
    /// Skin vertices of the cut through neck and shoulders, in order.
    pub neck_bottom: Vec<u32>,
}

/// The skin with the face sampled `face_spacing` apart and the head
/// `head_spacing` apart (m).
pub fn skin(face_spacing: f64, head_spacing: f64) -> Skin {
    let mask = face_mask();
    let tris = mask.topology.triangles();
    let face = face_region_with(face_spacing);
    let rim: Vec<DVec3> = face
        .rim
        .iter()
        .map(|&v| face.positions[v as usize])
        .collect();
    let head = head_region_with(&rim, &face.rim_anchor, head_spacing);
    let nf = face.positions.len() as u32;
    let nr = rim.len() as u32;
    let remap = |i: u32| {
        if i < nr {
            face.rim[i as usize]
        } else {
            nf + i - nr
        }
    };
    let mut positions = face.positions.clone();
    positions.extend(&head.positions);
    // The face's triangles but the lips', the head's, then the lips' (a
    // material of their own: the last triangles, from `lips_from` on).
    let face_where = |lips: bool| {
        let marked = face.triangles.iter().zip(&face.on_the_lips);
        marked.filter(move |(_, l)| **l == lips).map(|(t, _)| *t)
    };
    let mut triangles: Vec<[u32; 3]> = face_where(false).collect();
    triangles.extend(head.triangles.iter().map(|t| t.map(remap)));
    let lips_from = triangles.len();
    triangles.extend(face_where(true));
    let template = generic_template();
    let mut face_targets = shapes::face_targets(&face.on_mask, &template, tris);
    mouth_opening::round(
        &mut face_targets,
        &face.on_mask,
        &mouth_opening::on_mask(),
        tris,
    );
    let jaw = generic_model().jaw_weights;
    let rim_jaw: Vec<f64> = face
        .rim
        .iter()
        .map(|&v| {
            let m = face.on_mask[v as usize];
            let t = tris[m.triangle as usize];
            (0..3).map(|k| m.barycentric[k] * jaw[t[k] as usize]).sum()
        })
        .collect();
    let rim_deltas: Vec<Vec<DVec3>> = face_targets
        .iter()
        .map(|t| face.rim.iter().map(|&v| t[v as usize]).collect())
        .collect();
    let head_t = shapes::head_targets(&head.positions, &rim, &rim_deltas, &rim_jaw);
    let targets = face_targets
        .iter()
        .zip(&head_t)
        .map(|(f, h)| f.iter().chain(h).copied().collect())
        .collect();
    let neck_bottom = head.bottom.iter().map(|&i| remap(i)).collect();
    Skin {
        face,
        positions,
        triangles,
        lips_from,
        targets,
        face_targets,
        neck_bottom,
    }
}
