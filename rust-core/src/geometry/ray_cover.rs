//! Whether rays cast along one direction are covered by a set of
//! triangles: Möller & Trumbore (1997) for each ray against each triangle
//! whose shadow along the direction falls where the ray starts.
//!
//! The triangles are binned by the bounding boxes of their projections
//! onto the plane across the direction, in square cells about a mean
//! triangle's size, so a ray meets only the few triangles in its own
//! cell: an eyeball's front, seen past the lids of a head, is a few
//! hundred rays among a few thousand triangles.

use glam::DVec3;
use std::collections::HashMap;

/// Möller–Trumbore: whether the ray `o + s d`, `s > 0`, crosses triangle
/// `abc`.
pub fn ray_hits(o: DVec3, d: DVec3, [a, b, c]: [DVec3; 3]) -> bool {
    let (e1, e2) = (b - a, c - a);
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-18 {
        return false;
    }
    let t = o - a;
    let u = t.dot(p) / det;
    if !(0.0..=1.0).contains(&u) {
        return false;
    }
    let q = t.cross(e1);
    let v = d.dot(q) / det;
    if v < 0.0 || u + v > 1.0 {
        return false;
    }
    e2.dot(q) / det > 0.0
}

/// Triangles binned across one direction, for rays cast along it.
pub struct RayCover {
    /// The direction the rays go (unit).
    direction: DVec3,
    /// Two unit vectors across it.
    across: [DVec3; 2],
    /// The side of a cell.
    cell: f64,
    /// The triangles.
    triangles: Vec<[DVec3; 3]>,
    /// For each cell, the triangles whose projection's box meets it.
    cells: HashMap<[i64; 2], Vec<usize>>,
    /// Triangles too large to bin, tested for every ray.
    large: Vec<usize>,
}

/// The most cells one triangle is binned into: a triangle larger than
/// this many mean triangles is tested for every ray.
pub const MAX_CELLS: i64 = 1024;

impl RayCover {
    /// Bins `triangles` for rays along `direction` (any length but zero;
    /// a zero direction covers nothing).
    pub fn new(triangles: Vec<[DVec3; 3]>, direction: DVec3) -> RayCover {
        let direction = direction.normalize_or_zero();
        let (u, v) = direction.any_orthonormal_pair();
        let mean_size = triangles
            .iter()
            .map(|[a, b, c]| ((b - a).length() + (c - b).length() + (a - c).length()) / 3.0)
            .sum::<f64>()
            / triangles.len().max(1) as f64;
        let cell = mean_size.max(f64::MIN_POSITIVE);
        let mut cover = RayCover {
            direction,
            across: [u, v],
            cell,
            triangles: Vec::new(),
            cells: HashMap::new(),
            large: Vec::new(),
        };
        if direction == DVec3::ZERO {
            return cover;
        }
        for (i, t) in triangles.iter().enumerate() {
            let keys = t.map(|p| cover.key(p));
            let lo = [0, 1].map(|k| keys.iter().map(|c| c[k]).min().unwrap_or(0));
            let hi = [0, 1].map(|k| keys.iter().map(|c| c[k]).max().unwrap_or(0));
            // A triangle spanning more than [`MAX_CELLS`] cells, far larger
            // than the rest, is tested for every ray instead.
            let spans = (hi[0] - lo[0] + 1).saturating_mul(hi[1] - lo[1] + 1);
            if spans > MAX_CELLS {
                cover.large.push(i);
                continue;
            }
            for x in lo[0]..=hi[0] {
                for y in lo[1]..=hi[1] {
                    cover.cells.entry([x, y]).or_default().push(i);
                }
            }
        }
        cover.triangles = triangles;
        cover
    }

    /// The cell a point projects into.
    fn key(&self, p: DVec3) -> [i64; 2] {
        self.across
            .map(|a| (p.dot(a) / self.cell).floor().clamp(-1e9, 1e9) as i64)
    }

    /// Whether the ray from `o` along the direction crosses a triangle.
    pub fn covers(&self, o: DVec3) -> bool {
        let hits = |i: &usize| ray_hits(o, self.direction, self.triangles[*i]);
        self.cells
            .get(&self.key(o))
            .is_some_and(|list| list.iter().any(hits))
            || self.large.iter().any(hits)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit square of two triangles in the plane z = 1, split finely
    /// enough that a ray meets several cells' worth of neighbours.
    fn square(n: usize) -> Vec<[DVec3; 3]> {
        let s = 1.0 / n as f64;
        let mut out = Vec::new();
        for i in 0..n {
            for j in 0..n {
                let p =
                    |a: usize, b: usize| DVec3::new((i + a) as f64 * s, (j + b) as f64 * s, 1.0);
                out.push([p(0, 0), p(1, 0), p(1, 1)]);
                out.push([p(0, 0), p(1, 1), p(0, 1)]);
            }
        }
        out
    }

    #[test]
    fn a_ray_is_covered_exactly_where_a_triangle_lies_ahead_of_it() {
        let triangles = square(8);
        let cover = RayCover::new(triangles.clone(), DVec3::Z);
        for k in 0..200 {
            // Points over and around the square, before and beyond it.
            let x = -0.25 + 1.5 * ((k * 37) % 200) as f64 / 200.0;
            let y = -0.25 + 1.5 * ((k * 91) % 200) as f64 / 200.0;
            for z in [0.0, 2.0] {
                let o = DVec3::new(x, y, z);
                let brute = triangles.iter().any(|t| ray_hits(o, DVec3::Z, *t));
                assert_eq!(cover.covers(o), brute, "at {o}");
                assert_eq!(
                    brute,
                    z == 0.0 && (0.0..=1.0).contains(&x) && (0.0..=1.0).contains(&y)
                );
            }
        }
    }

    #[test]
    fn a_tilted_direction_and_a_zero_one() {
        let triangles = square(4);
        let d = DVec3::new(0.3, -0.2, 1.0);
        let cover = RayCover::new(triangles.clone(), d);
        let o = DVec3::new(0.5, 0.5, 0.0) - d * 0.5;
        assert!(cover.covers(o));
        assert!(!cover.covers(o + DVec3::new(3.0, 0.0, 0.0)));
        assert!(!RayCover::new(triangles, DVec3::ZERO).covers(o));
    }

    #[test]
    fn a_huge_triangle_among_small_ones_still_covers() {
        let mut triangles = square(8);
        triangles.push([
            DVec3::new(-1e4, -1e4, 3.0),
            DVec3::new(1e4, -1e4, 3.0),
            DVec3::new(0.0, 1e4, 3.0),
        ]);
        let cover = RayCover::new(triangles, DVec3::Z);
        assert!(cover.covers(DVec3::new(50.0, 20.0, 2.0)));
        assert!(!cover.covers(DVec3::new(50.0, 20.0, 4.0)));
    }
}
