//! The registered mask's boundary and its holes: the outline, the two
//! eyes' openings and the mouth's slit, told apart by their extent (the
//! diagonal of their bounding box, so in any unit and orientation).

use glam::DVec3;
use std::collections::{HashMap, HashSet};

/// The vertices on the rims of the mask's holes (the eyes, the mouth): the
/// boundary's connected pieces but the one of the largest extent, the
/// outline.
pub fn hole_rims(mask: &[DVec3], boundary: &HashSet<(u32, u32)>) -> HashSet<u32> {
    let mut pieces = boundary_pieces(mask, boundary);
    pieces.pop();
    pieces.into_iter().flatten().collect()
}

/// The boundary's connected pieces (vertex lists), by increasing extent
/// (the diagonal of their bounding box): the outline last.
fn boundary_pieces(mask: &[DVec3], boundary: &HashSet<(u32, u32)>) -> Vec<Vec<u32>> {
    let mut next: HashMap<u32, Vec<u32>> = HashMap::new();
    for &(a, b) in boundary {
        next.entry(a).or_default().push(b);
        next.entry(b).or_default().push(a);
    }
    let mut seen: HashSet<u32> = HashSet::new();
    let mut pieces: Vec<Vec<u32>> = Vec::new();
    for &start in next.keys() {
        if !seen.insert(start) {
            continue;
        }
        let mut piece = vec![start];
        let mut k = 0;
        while k < piece.len() {
            for &n in &next[&piece[k]] {
                if seen.insert(n) {
                    piece.push(n);
                }
            }
            k += 1;
        }
        pieces.push(piece);
    }
    let extent = |piece: &[u32]| {
        let at = |v: u32| mask.get(v as usize).copied().unwrap_or_default();
        let (lo, hi) = piece.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), &v| (lo.min(at(v)), hi.max(at(v))),
        );
        (hi - lo).length()
    };
    pieces.sort_by(|a, b| extent(a).total_cmp(&extent(b)));
    pieces
}

/// The vertices of the mouth's slit: of the mask's holes (ARKit's mask has
/// three: the eyes and the mouth), the one of the largest extent (the
/// lips span about 50 mm, an eye's opening about 28).
pub fn mouth_rim(mask: &[DVec3], boundary: &HashSet<(u32, u32)>) -> HashSet<u32> {
    let mut pieces = boundary_pieces(mask, boundary);
    pieces.pop();
    pieces.pop().unwrap_or_default().into_iter().collect()
}

/// The edges used by exactly one triangle, `(min, max)`.
pub fn boundary_edges(triangles: &[[u32; 3]]) -> HashSet<(u32, u32)> {
    let mut count: HashMap<(u32, u32), usize> = HashMap::new();
    for t in triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            *count.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    count
        .into_iter()
        .filter(|(_, c)| *c == 1)
        .map(|(e, _)| e)
        .collect()
}
