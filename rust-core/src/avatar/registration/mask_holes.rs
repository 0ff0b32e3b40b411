//! The registered mask's boundary and its holes: the outline, the two
//! eyes' openings and the mouth's slit, told apart by their extent (the
//! diagonal of their bounding box, so in any unit and orientation).
//!
//! The rims come back as ordered sets: callers sum positions over them,
//! and a sum in a hash's order would differ in its last bits from run to
//! run.

use glam::DVec3;
use std::collections::{BTreeSet, HashMap, HashSet};

/// The vertices on the rims of the mask's holes (the eyes, the mouth): the
/// boundary's connected pieces but the one of the largest extent, the
/// outline.
pub fn hole_rims(mask: &[DVec3], boundary: &HashSet<(u32, u32)>) -> BTreeSet<u32> {
    let mut pieces = boundary_pieces(mask, boundary);
    pieces.pop();
    pieces.into_iter().flatten().collect()
}

/// The boundary's connected pieces (vertex lists), by increasing extent
/// (the diagonal of their bounding box): the outline last. Each piece is
/// walked from its smallest vertex, so the result does not depend on a
/// hash's order.
fn boundary_pieces(mask: &[DVec3], boundary: &HashSet<(u32, u32)>) -> Vec<Vec<u32>> {
    let mut next: HashMap<u32, Vec<u32>> = HashMap::new();
    for &(a, b) in boundary {
        next.entry(a).or_default().push(b);
        next.entry(b).or_default().push(a);
    }
    let mut starts: Vec<u32> = next.keys().copied().collect();
    starts.sort_unstable();
    let mut seen: HashSet<u32> = HashSet::new();
    let mut pieces: Vec<Vec<u32>> = Vec::new();
    for start in starts {
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
pub fn mouth_rim(mask: &[DVec3], boundary: &HashSet<(u32, u32)>) -> BTreeSet<u32> {
    let mut pieces = boundary_pieces(mask, boundary);
    pieces.pop();
    pieces.pop().unwrap_or_default().into_iter().collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A loop of `n` vertices from `first` on a circle of `radius` around
    /// `centre`: its positions and its edges.
    fn ring(first: u32, n: u32, centre: DVec3, radius: f64) -> (Vec<DVec3>, Vec<(u32, u32)>) {
        let at = |k: u32| {
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            centre + radius * DVec3::new(a.cos(), a.sin(), 0.0)
        };
        let edges = (0..n)
            .map(|k| {
                let (a, b) = (first + k, first + (k + 1) % n);
                (a.min(b), a.max(b))
            })
            .collect();
        ((0..n).map(at).collect(), edges)
    }

    #[test]
    fn the_mouth_is_the_larger_hole_and_its_rim_comes_in_increasing_order() {
        // An outline of radius 90, a mouth slit of 25 and two eyes of 14,
        // numbered so that the mouth's vertices lie between the eyes'.
        let mut mask = Vec::new();
        let mut boundary = HashSet::new();
        for (n, centre, radius) in [
            (40, DVec3::ZERO, 90.0),
            (12, DVec3::new(-30.0, 30.0, 0.0), 14.0),
            (16, DVec3::new(0.0, -40.0, 0.0), 25.0),
            (12, DVec3::new(30.0, 30.0, 0.0), 14.0),
        ] {
            let (positions, edges) = ring(mask.len() as u32, n, centre, radius);
            mask.extend(positions);
            boundary.extend(edges);
        }
        let mouth: Vec<u32> = mouth_rim(&mask, &boundary).into_iter().collect();
        assert_eq!(mouth, (52..68).collect::<Vec<u32>>());
        let rims: Vec<u32> = hole_rims(&mask, &boundary).into_iter().collect();
        assert_eq!(rims, (40..80).collect::<Vec<u32>>());
    }
}
