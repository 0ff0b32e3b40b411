//! Lids with thickness: from each eye hole's rim (the lids' edges) the
//! skin turns inwards and runs back to the eyeball, as the lid margin and
//! the conjunctiva do, so that between lid and eye one sees skin, not the
//! socket behind the globe (the opening, 29 mm across, is wider than the
//! 24 mm globe, and its inner corner stands 14 mm off it).
//!
//! For a rim vertex at `p`, with `c` the eye's centre and `d` the unit
//! direction of `p − c`, the margin's inner edge is at
//! `q(p) = c + min((r(d) + LID_CLEARANCE) / cos(θ/2), |p − c| − MIN_DEPTH) · d`:
//! - `r(d)` is the farthest the eye's surface reaches along `d` over the
//!   gazes it turns to ([`super::eyes::farthest_reach`]): the globe where
//!   the cornea never passes, clear of the cornea where it does;
//! - `θ` is the widest angle any shape turns the direction of any rim
//!   vertex through: a blendshape moves a vertex along a straight chord,
//!   which dips `cos(θ/2)` towards the centre half way, so the inner edge
//!   stays clear at every weight, not only at the ends. One `θ` for the
//!   whole rim, so that where the lids' edges meet in a shape their inner
//!   edges meet too;
//! - [`MIN_DEPTH`] keeps every margin deep enough to have area.
//!
//! The margin is one band of triangles from the rim to its inner edge.
//! Every shape moves the inner edge by the same rule from the moved rim.

use super::LID_CLEARANCE;
use super::eyes::farthest_reach;
use glam::{DMat3, DVec3};

/// The least depth of a margin, from the lid's edge to its inner edge (m):
/// the eyes sit this much further back than the lids alone would allow
/// (`super::eye_depth`), so every margin has room; a margin of no depth
/// has triangles of no area, whose normals turn at random (dark notches
/// above a half-closed lid in Blender).
pub const MIN_DEPTH: f64 = 0.0008;

/// The margin of one eye: new vertices (numbered from `first`), their
/// triangles, and their displacement under each shape.
pub struct Margin {
    /// Rest positions of the inner edge's vertices, one per rim vertex.
    pub positions: Vec<DVec3>,
    /// Triangles over the rim's and the new vertices (skin indices), facing
    /// as the skin around them does.
    pub triangles: Vec<[u32; 3]>,
    /// `[shape][new vertex]`.
    pub targets: Vec<Vec<DVec3>>,
}

/// The margin inside the rim `rim` (skin vertices in order, at
/// `positions`, moved by `targets[shape][vertex]`) of the eye at `centre`
/// turning by `gazes`; `skin` is the skin's triangles (to face the same
/// way) and `first` the index the new vertices start at.
pub fn margin(
    rim: &[u32],
    positions: &[DVec3],
    targets: &[Vec<DVec3>],
    skin: &[[u32; 3]],
    (centre, gazes): (DVec3, &[DMat3]),
    first: u32,
) -> Margin {
    let sweep = rim
        .iter()
        .map(|&v| {
            let p = positions[v as usize] - centre;
            let turn = |s: &Vec<DVec3>| p.angle_between(p + s[v as usize]);
            targets.iter().map(turn).fold(0.0, f64::max)
        })
        .fold(0.0, f64::max);
    let inner = |p: DVec3| {
        let d = (p - centre).normalize();
        let clear = (farthest_reach(d, gazes) + LID_CLEARANCE) / (0.5 * sweep).cos();
        centre + clear.min((p - centre).length() - MIN_DEPTH) * d
    };
    let mut out = Margin {
        positions: Vec::with_capacity(rim.len()),
        triangles: Vec::with_capacity(2 * rim.len()),
        targets: vec![Vec::with_capacity(rim.len()); targets.len()],
    };
    for &v in rim {
        let p = positions[v as usize];
        let at_rest = inner(p);
        out.positions.push(at_rest);
        for (moved, shape) in out.targets.iter_mut().zip(targets) {
            moved.push(inner(p + shape[v as usize]) - at_rest);
        }
    }
    // The skin's triangle on rim edge (a, b) runs a → b or b → a; the
    // margin runs it the other way, so both face alike.
    let forward = |a: u32, b: u32| {
        skin.iter()
            .any(|t| (0..3).any(|k| t[k] == a && t[(k + 1) % 3] == b))
    };
    let n = rim.len();
    for k in 0..n {
        let (a, b) = (rim[k], rim[(k + 1) % n]);
        let (a1, b1) = (first + k as u32, first + ((k + 1) % n) as u32);
        if forward(a, b) {
            out.triangles.extend([[b, a, a1], [b, a1, b1]]);
        } else {
            out.triangles.extend([[a, b, b1], [a, b1, a1]]);
        }
    }
    out
}
