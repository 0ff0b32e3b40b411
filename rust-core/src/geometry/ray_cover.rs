//! Whether rays cast along one direction are covered by a set of
//! triangles: Möller & Trumbore (1997) for each ray against each triangle
//! whose shadow along the direction falls where the ray starts.
//!
//! The triangles are binned by the bounding boxes of their projections
//! onto the plane across the direction, in square cells about a mean
//! triangle's size, so a ray meets only the few triangles in its own
//! cell: an eyeball's front, seen past the lids of a head, is a few
//! hundred rays among a few thousand triangles. The cells are a dense
//! grid over the projections' extent, each cell's triangles one slice of
//! one array (building a hash map of cells took longer than the rays
//! when a few thousand rays met twenty thousand triangles, once per
//! shape).

use glam::DVec3;

/// A line counts as parallel to a triangle's plane where the volume
/// spanned by its direction and two of the triangle's edges is below this
/// share of the product of their lengths (dimensionless, so the same in
/// any unit: rounding, not geometry).
pub const PARALLEL: f64 = 1e-12;

/// Möller–Trumbore: whether the ray `o + s d`, `s > 0`, crosses triangle
/// `abc`.
pub fn ray_hits(o: DVec3, d: DVec3, abc: [DVec3; 3]) -> bool {
    ray_distance(o, d, abc).is_some()
}

/// Möller–Trumbore: the `s > 0` at which the ray `o + s d` crosses
/// triangle `abc`, if it does.
pub fn ray_distance(o: DVec3, d: DVec3, abc: [DVec3; 3]) -> Option<f64> {
    line_crossing(o, d, abc).filter(|s| *s > 0.0)
}

/// Möller–Trumbore: the `s` (of either sign) at which the line `o + s d`
/// crosses triangle `abc`, if it does.
pub fn line_crossing(o: DVec3, d: DVec3, [a, b, c]: [DVec3; 3]) -> Option<f64> {
    let (e1, e2) = (b - a, c - a);
    let p = d.cross(e2);
    let det = e1.dot(p);
    // Parallel (within rounding) to the triangle's plane: `det` is the
    // volume of the three vectors, compared with the product of their
    // lengths, so the test is the same in any unit.
    if det.abs() <= PARALLEL * d.length() * e1.length() * e2.length() {
        return None;
    }
    let t = o - a;
    let u = t.dot(p) / det;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = t.cross(e1);
    let v = d.dot(q) / det;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    Some(e2.dot(q) / det)
}

/// Triangles binned across one direction, for rays cast along it.
pub struct RayCover {
    /// The direction the rays go (unit).
    direction: DVec3,
    /// Two unit vectors across it.
    across: [DVec3; 2],
    /// The side of a cell.
    cell: f64,
    /// The first cell's key along each of `across`.
    origin: [i64; 2],
    /// Cells along each of `across`.
    size: [i64; 2],
    /// The triangles.
    triangles: Vec<[DVec3; 3]>,
    /// Cell `c`'s triangles (those whose projection's box meets it) are
    /// `binned[starts[c]..starts[c + 1]]`, cells row by row.
    starts: Vec<usize>,
    /// See `starts`.
    binned: Vec<usize>,
    /// Triangles too large to bin, tested for every ray.
    large: Vec<usize>,
}

/// The most cells one triangle is binned into: a triangle larger than
/// this many mean triangles is tested for every ray.
pub const MAX_CELLS: i64 = 1024;

/// The most cells the grid holds per triangle binned (plus a fixed
/// 4,096): triangles strewn far apart get larger cells, not a grid
/// larger than the mesh.
const CELLS_PER_TRIANGLE: f64 = 16.0;

impl RayCover {
    /// Bins `triangles` for rays along `direction` (any length but zero;
    /// a zero direction covers nothing).
    pub fn new(triangles: Vec<[DVec3; 3]>, direction: DVec3) -> RayCover {
        let direction = direction.normalize_or_zero();
        let (u, v) = direction.any_orthonormal_pair();
        let mean_size = triangles
            .iter()
            .map(|[a, b, c]| ((b - a).length() + (c - b).length() + (a - c).length()) / 3.0)
            .filter(|s| s.is_finite())
            .sum::<f64>()
            / triangles.len().max(1) as f64;
        let mut cover = RayCover {
            direction,
            across: [u, v],
            cell: mean_size.max(f64::MIN_POSITIVE),
            origin: [0, 0],
            size: [0, 0],
            triangles: Vec::new(),
            starts: vec![0],
            binned: Vec::new(),
            large: Vec::new(),
        };
        if direction == DVec3::ZERO {
            return cover;
        }
        // The projections' extent, and cells no more than the grid allows.
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in triangles.iter().flatten() {
            for k in 0..2 {
                let x = p.dot(cover.across[k]);
                if x.is_finite() {
                    lo[k] = lo[k].min(x);
                    hi[k] = hi[k].max(x);
                }
            }
        }
        if lo[0] > hi[0] || lo[1] > hi[1] {
            cover.large = (0..triangles.len()).collect();
            cover.triangles = triangles;
            return cover;
        }
        let most = CELLS_PER_TRIANGLE * triangles.len() as f64 + 4096.0;
        let area = ((hi[0] - lo[0]) / cover.cell + 1.0) * ((hi[1] - lo[1]) / cover.cell + 1.0);
        if area > most {
            cover.cell *= (area / most).sqrt();
        }
        cover.origin = [0, 1].map(|k| cover.key_along(lo[k]));
        cover.size = [0, 1].map(|k| cover.key_along(hi[k]) - cover.origin[k] + 1);
        // Each triangle's cells, counted, then filled in (rows of cells).
        let spans: Vec<Option<[[i64; 2]; 2]>> = triangles
            .iter()
            .map(|t| {
                let keys = t.map(|p| cover.key(p));
                let lo = [0, 1].map(|k| keys.iter().map(|c| c[k]).min().unwrap_or(0));
                let hi = [0, 1].map(|k| keys.iter().map(|c| c[k]).max().unwrap_or(0));
                // A triangle spanning more than [`MAX_CELLS`] cells, far
                // larger than the rest, is tested for every ray instead.
                let cells = (hi[0] - lo[0] + 1).saturating_mul(hi[1] - lo[1] + 1);
                (cells <= MAX_CELLS).then_some([lo, hi])
            })
            .collect();
        let cells = (cover.size[0] * cover.size[1]) as usize;
        let mut counts = vec![0usize; cells + 1];
        for span in spans.iter().flatten() {
            cover.each_cell(*span, |c| counts[c + 1] += 1);
        }
        for c in 0..cells {
            counts[c + 1] += counts[c];
        }
        let mut next = counts.clone();
        let mut binned = vec![0; counts[cells]];
        for (i, span) in spans.iter().enumerate() {
            match span {
                Some(span) => cover.each_cell(*span, |c| {
                    binned[next[c]] = i;
                    next[c] += 1;
                }),
                None => cover.large.push(i),
            }
        }
        cover.binned = binned;
        cover.starts = counts;
        cover.triangles = triangles;
        cover
    }

    /// Calls `f` with the index of every cell of the grid within the keys
    /// `[lo, hi]`.
    fn each_cell(&self, [lo, hi]: [[i64; 2]; 2], mut f: impl FnMut(usize)) {
        for x in lo[0].max(self.origin[0])..=hi[0].min(self.origin[0] + self.size[0] - 1) {
            for y in lo[1].max(self.origin[1])..=hi[1].min(self.origin[1] + self.size[1] - 1) {
                let (i, j) = (x - self.origin[0], y - self.origin[1]);
                f((i * self.size[1] + j) as usize);
            }
        }
    }

    /// The key of a coordinate along one of `across`.
    fn key_along(&self, x: f64) -> i64 {
        (x / self.cell).floor().clamp(-1e9, 1e9) as i64
    }

    /// The cell a point projects into.
    fn key(&self, p: DVec3) -> [i64; 2] {
        self.across.map(|a| self.key_along(p.dot(a)))
    }

    /// The triangles binned into the cell `o` projects into.
    fn binned_at(&self, o: DVec3) -> &[usize] {
        let [x, y] = self.key(o);
        let (i, j) = (x - self.origin[0], y - self.origin[1]);
        if i < 0 || j < 0 || i >= self.size[0] || j >= self.size[1] {
            return &[];
        }
        let c = (i * self.size[1] + j) as usize;
        &self.binned[self.starts[c]..self.starts[c + 1]]
    }

    /// Whether the ray from `o` along the direction crosses a triangle.
    pub fn covers(&self, o: DVec3) -> bool {
        let hits = |i: &usize| ray_hits(o, self.direction, self.triangles[*i]);
        self.binned_at(o).iter().any(hits) || self.large.iter().any(hits)
    }

    /// Every triangle the line through `o` along the direction crosses
    /// (its index in the list given to [`RayCover::new`]) and where:
    /// `s` in `o + s d`, negative behind `o`.
    pub fn line_crossings(&self, o: DVec3) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.binned_at(o)
            .iter()
            .chain(&self.large)
            .filter_map(move |&i| Some((i, line_crossing(o, self.direction, self.triangles[i])?)))
    }

    /// Triangle `i` as given to [`RayCover::new`].
    pub fn triangle(&self, i: usize) -> [DVec3; 3] {
        self.triangles[i]
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
    fn a_line_crosses_the_triangles_before_and_behind_it() {
        let mut triangles = square(4);
        let far: Vec<[DVec3; 3]> = square(4)
            .iter()
            .map(|t| t.map(|p| p + DVec3::Z * 2.0))
            .collect();
        triangles.extend(far);
        let cover = RayCover::new(triangles, DVec3::Z);
        let mut found: Vec<_> = cover.line_crossings(DVec3::new(0.3, 0.6, 1.5)).collect();
        found.sort_by(|a, b| a.1.total_cmp(&b.1));
        assert_eq!(found.len(), 2, "{found:?}");
        assert!(found[0].0 < 32 && (found[0].1 + 0.5).abs() < 1e-12);
        assert!(found[1].0 >= 32 && (found[1].1 - 1.5).abs() < 1e-12);
        assert_eq!(cover.triangle(found[1].0)[0].z, 3.0);
        assert_eq!(cover.line_crossings(DVec3::new(3.3, 0.6, 1.5)).count(), 0);
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
