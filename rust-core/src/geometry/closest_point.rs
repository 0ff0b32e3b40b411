//! Closest points on a triangle mesh: the query behind ICP, non-rigid
//! registration and the correspondence map `M` of §3.3.
//!
//! The triangles are binned into a uniform grid of cubic cells over their
//! bounding box (about [`TRIANGLES_PER_CELL`] triangles per occupied cell on
//! a surface), each triangle into every cell its bounding box overlaps. A
//! query visits the cells in growing shells around the query point's cell
//! and stops once the next shell is farther than the best distance found:
//! the answer is exact, not approximate. Each triangle carries a bounding
//! sphere, so a triangle that cannot beat the best found so far is skipped
//! without the exact test. Point-to-triangle distance follows
//! Ericson, *Real-Time Collision Detection* (2005), §5.1.5: the closest
//! point lies in one of the triangle's seven Voronoi regions (three
//! vertices, three edges, the face), found from the signs of a few dot
//! products.

use glam::DVec3;

/// Target average of triangles per grid cell.
pub const TRIANGLES_PER_CELL: f64 = 4.0;

/// The closest point of a mesh to a query point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClosestPoint {
    /// Index of the triangle it lies on.
    pub triangle: usize,
    /// Its barycentric coordinates in that triangle (sum 1, each in [0, 1]).
    pub barycentric: [f64; 3],
    /// The point itself.
    pub point: DVec3,
    /// Its distance from the query.
    pub distance: f64,
}

/// A triangle mesh binned for closest-point queries.
#[derive(Clone, Debug)]
pub struct TriangleGrid {
    triangles: Vec<[u32; 3]>,
    /// Each triangle's corners (only the triangles' own vertices are
    /// kept, however many `positions` the grid was built over).
    corners: Vec<[DVec3; 3]>,
    /// Each triangle's bounding sphere: its centroid and the largest
    /// distance of a corner from it.
    spheres: Vec<(DVec3, f64)>,
    origin: DVec3,
    cell: f64,
    dims: [usize; 3],
    /// Cell `c`'s triangles are `items[starts[c]..starts[c + 1]]`.
    starts: Vec<usize>,
    items: Vec<u32>,
}

impl TriangleGrid {
    /// Bins `triangles` over `positions`. Triangles with an index past
    /// `positions` are left out (the caller's topology check reports them).
    pub fn new(positions: &[DVec3], triangles: &[[u32; 3]]) -> TriangleGrid {
        let n = positions.len();
        let triangles: Vec<[u32; 3]> = triangles
            .iter()
            .copied()
            .filter(|t| t.iter().all(|&i| (i as usize) < n))
            .collect();
        let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        for t in &triangles {
            for &i in t {
                lo = lo.min(positions[i as usize]);
                hi = hi.max(positions[i as usize]);
            }
        }
        if triangles.is_empty() {
            (lo, hi) = (DVec3::ZERO, DVec3::ZERO);
        }
        let extent = (hi - lo).max(DVec3::splat(1e-12));
        // A surface of area ~ the box's largest faces: cells of side `cell`
        // hold about `tri / (area / cell²)` triangles each.
        let area = extent.x * extent.y + extent.y * extent.z + extent.z * extent.x;
        let count = triangles.len().max(1) as f64;
        let cell = (TRIANGLES_PER_CELL * area / count)
            .sqrt()
            .max(extent.max_element() / 256.0);
        let dims =
            [extent.x, extent.y, extent.z].map(|e| ((e / cell).floor() as usize + 1).min(256));
        let cells = dims[0] * dims[1] * dims[2];
        let corners: Vec<[DVec3; 3]> = triangles
            .iter()
            .map(|t| t.map(|i| positions[i as usize]))
            .collect();
        let spheres = corners
            .iter()
            .map(|corners| {
                let centre = (corners[0] + corners[1] + corners[2]) / 3.0;
                let radius = corners
                    .iter()
                    .map(|c| (*c - centre).length())
                    .fold(0.0, f64::max);
                (centre, radius)
            })
            .collect();
        let mut grid = TriangleGrid {
            triangles,
            corners,
            spheres,
            origin: lo,
            cell,
            dims,
            starts: vec![0; cells + 1],
            items: Vec::new(),
        };
        // Two passes: count, then fill (a CSR layout, no per-cell vectors).
        let ranges: Vec<([usize; 3], [usize; 3])> =
            grid.corners.iter().map(|c| grid.cell_range(c)).collect();
        let mut counts = vec![0usize; cells + 1];
        for (a, b) in &ranges {
            for z in a[2]..=b[2] {
                for y in a[1]..=b[1] {
                    for x in a[0]..=b[0] {
                        counts[grid.index([x, y, z]) + 1] += 1;
                    }
                }
            }
        }
        for c in 0..cells {
            counts[c + 1] += counts[c];
        }
        let mut fill = counts.clone();
        let mut items = vec![0u32; counts[cells]];
        for (t, (a, b)) in ranges.iter().enumerate() {
            for z in a[2]..=b[2] {
                for y in a[1]..=b[1] {
                    for x in a[0]..=b[0] {
                        let c = grid.index([x, y, z]);
                        items[fill[c]] = t as u32;
                        fill[c] += 1;
                    }
                }
            }
        }
        grid.starts = counts;
        grid.items = items;
        grid
    }

    /// The triangles, as given (less any with an out-of-range index).
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// The unit normal of triangle `t` (of [`TriangleGrid::triangles`]),
    /// zero for a degenerate or unknown triangle.
    pub fn triangle_normal(&self, t: usize) -> DVec3 {
        let Some(&[a, b, c]) = self.corners.get(t) else {
            return DVec3::ZERO;
        };
        (b - a).cross(c - a).normalize_or_zero()
    }

    /// The point of the mesh closest to `p`; `None` for a mesh without
    /// triangles.
    pub fn closest(&self, p: DVec3) -> Option<ClosestPoint> {
        self.closest_within(p, f64::INFINITY)
    }

    /// The point of the mesh closest to `p` if it is within `max_distance`.
    pub fn closest_within(&self, p: DVec3, max_distance: f64) -> Option<ClosestPoint> {
        self.closest_where(p, max_distance, |_| true)
    }

    /// The closest point of `p` among the triangles whose normal makes a
    /// cosine of at least `min_cosine` with `normal` (a compatible point,
    /// as in normal-compatible ICP: a vertex just inside a lip finds the
    /// lip's outer surface, not the mouth's lining behind it), if it is
    /// within `max_distance`.
    pub fn closest_facing(
        &self,
        p: DVec3,
        normal: DVec3,
        min_cosine: f64,
        max_distance: f64,
    ) -> Option<ClosestPoint> {
        self.closest_where(p, max_distance, |t| {
            self.triangle_normal(t).dot(normal) >= min_cosine
        })
    }

    /// The closest point of `p` within `max_distance` among the triangles
    /// `accept` takes: shells of cells outwards until the next shell is
    /// farther than the best found (module docs).
    pub fn closest_where(
        &self,
        p: DVec3,
        max_distance: f64,
        accept: impl Fn(usize) -> bool,
    ) -> Option<ClosestPoint> {
        // Every triangle lies within the grid's box.
        if self.triangles.is_empty() || self.outside_distance(p) > max_distance {
            return None;
        }
        let home = self.cell_of(p);
        let mut best: Option<ClosestPoint> = None;
        let max_shell = self.dims.iter().max().copied().unwrap_or(1);
        for shell in 0..=max_shell + 1 {
            let limit = best.map_or(max_distance, |b| b.distance.min(max_distance));
            if self.shell_distance(p, home, shell) > limit {
                break;
            }
            self.for_shell(home, shell, |t| {
                let limit = best.map_or(max_distance, |b| b.distance.min(max_distance));
                let (centre, radius) = self.spheres[t];
                if (p - centre).length() - radius > limit || !accept(t) {
                    return;
                }
                let c = self.closest_on_triangle(t, p);
                if c.distance <= max_distance && best.is_none_or(|b| c.distance < b.distance) {
                    best = Some(c);
                }
            });
        }
        best
    }

    /// A lower bound on the distance from `p` (whose cell, clamped onto
    /// the grid, is `home`) to any point of a cell of shell `shell`: such
    /// a point lies outside the box of the cells within `shell − 1` of
    /// `home`, so at least as far as `p` is from that box's nearest face
    /// (inside it), or from the grid's box (outside the grid).
    fn shell_distance(&self, p: DVec3, home: [usize; 3], shell: usize) -> f64 {
        if shell == 0 {
            return 0.0;
        }
        let inner = shell as f64 - 1.0;
        let q = (p - self.origin) / self.cell;
        let mut gap = f64::INFINITY;
        for (axis, v) in [q.x, q.y, q.z].into_iter().enumerate() {
            let h = home[axis] as f64;
            // Faces of the inner box that have cells beyond them.
            if h - inner > 0.0 {
                gap = gap.min(v - (h - inner));
            }
            if h + inner + 1.0 < self.dims[axis] as f64 {
                gap = gap.min(h + inner + 1.0 - v);
            }
        }
        (gap.max(0.0) * self.cell).max(self.outside_distance(p))
    }

    fn closest_on_triangle(&self, t: usize, p: DVec3) -> ClosestPoint {
        let [a, b, c] = self.corners[t];
        let (point, barycentric) = closest_point_on_triangle(p, a, b, c);
        ClosestPoint {
            triangle: t,
            barycentric,
            point,
            distance: (point - p).length(),
        }
    }

    fn outside_distance(&self, p: DVec3) -> f64 {
        let hi = self.origin
            + DVec3::new(
                self.dims[0] as f64,
                self.dims[1] as f64,
                self.dims[2] as f64,
            ) * self.cell;
        let d = (self.origin - p).max(p - hi).max(DVec3::ZERO);
        d.length()
    }

    /// The cell holding `p`, clamped onto the grid.
    fn cell_of(&self, p: DVec3) -> [usize; 3] {
        let q = (p - self.origin) / self.cell;
        let mut out = [0; 3];
        for (axis, v) in [q.x, q.y, q.z].into_iter().enumerate() {
            let v = if v.is_finite() {
                v.floor().max(0.0)
            } else {
                0.0
            };
            out[axis] = (v as usize).min(self.dims[axis] - 1);
        }
        out
    }

    fn cell_range(&self, ps: &[DVec3; 3]) -> ([usize; 3], [usize; 3]) {
        let lo = ps[0].min(ps[1]).min(ps[2]);
        let hi = ps[0].max(ps[1]).max(ps[2]);
        (self.cell_of(lo), self.cell_of(hi))
    }

    fn index(&self, [x, y, z]: [usize; 3]) -> usize {
        (z * self.dims[1] + y) * self.dims[0] + x
    }

    /// Calls `visit` for each triangle in the cells at Chebyshev distance
    /// exactly `shell` from `home` (a triangle in several cells may be
    /// visited more than once).
    fn for_shell(&self, home: [usize; 3], shell: usize, mut visit: impl FnMut(usize)) {
        let s = shell as isize;
        let h = home.map(|v| v as isize);
        let d = self.dims.map(|v| v as isize);
        for z in (h[2] - s).max(0)..=(h[2] + s).min(d[2] - 1) {
            for y in (h[1] - s).max(0)..=(h[1] + s).min(d[1] - 1) {
                let on_face = (z - h[2]).abs() == s || (y - h[1]).abs() == s;
                // On the shell's faces every x; inside, only its two ends.
                let step = if on_face || s == 0 { 1 } else { 2 * s };
                let mut x = h[0] - s;
                while x <= h[0] + s {
                    if (0..d[0]).contains(&x) {
                        let c = self.index([x as usize, y as usize, z as usize]);
                        for &t in &self.items[self.starts[c]..self.starts[c + 1]] {
                            visit(t as usize);
                        }
                    }
                    x += step;
                }
            }
        }
    }
}

/// The point of segment `a`–`b` closest to `p`, and its parameter `t ∈
/// [0, 1]` (`a + t (b − a)`); `a` for a segment of zero length.
pub fn closest_on_segment(p: DVec3, a: DVec3, b: DVec3) -> (DVec3, f64) {
    let ab = b - a;
    let length2 = ab.length_squared();
    let t = if length2 > 0.0 {
        ((p - a).dot(ab) / length2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + ab * t, t)
}

/// The point of triangle `abc` closest to `p` and its barycentric
/// coordinates (Ericson 2005, §5.1.5).
pub fn closest_point_on_triangle(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> (DVec3, [f64; 3]) {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return (a, [1.0, 0.0, 0.0]);
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return (b, [0.0, 1.0, 0.0]);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return (a + v * ab, [1.0 - v, v, 0.0]);
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return (c, [0.0, 0.0, 1.0]);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return (a + w * ac, [1.0 - w, 0.0, w]);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (b + w * (c - b), [0.0, 1.0 - w, w]);
    }
    let denom = va + vb + vc;
    if denom.abs() < f64::MIN_POSITIVE {
        // A degenerate triangle: its first vertex.
        return (a, [1.0, 0.0, 0.0]);
    }
    let (v, w) = (vb / denom, vc / denom);
    (a + ab * v + ac * w, [1.0 - v - w, v, w])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A bumpy grid surface of 2·20·20 triangles.
    fn surface() -> (Vec<DVec3>, Vec<[u32; 3]>) {
        let n = 21;
        let positions = (0..n * n)
            .map(|i| {
                let (x, y) = ((i % n) as f64 * 0.01, (i / n) as f64 * 0.01);
                DVec3::new(x, y, 0.02 * (x * 40.0).sin() * (y * 30.0).cos())
            })
            .collect();
        let mut triangles = Vec::new();
        for y in 0..n - 1 {
            for x in 0..n - 1 {
                let i = (y * n + x) as u32;
                triangles.push([i, i + 1, i + n as u32]);
                triangles.push([i + 1, i + n as u32 + 1, i + n as u32]);
            }
        }
        (positions, triangles)
    }

    #[test]
    fn the_grid_finds_what_brute_force_finds() {
        let (positions, triangles) = surface();
        let grid = TriangleGrid::new(&positions, &triangles);
        for k in 0..200 {
            let f = k as f64;
            let p = DVec3::new(
                (f * 0.37).sin() * 0.3 + 0.1,
                (f * 0.73).cos() * 0.3 + 0.1,
                (f * 1.1).sin() * 0.1,
            );
            let found = grid.closest(p).expect("a mesh");
            let brute = (0..triangles.len())
                .map(|t| grid.closest_on_triangle(t, p).distance)
                .fold(f64::INFINITY, f64::min);
            assert!(
                (found.distance - brute).abs() < 1e-12,
                "{p}: {} vs {brute}",
                found.distance
            );
            let [a, b, c] = triangles[found.triangle].map(|i| positions[i as usize]);
            let [u, v, w] = found.barycentric;
            assert!((a * u + b * v + c * w - found.point).length() < 1e-12);
        }
        assert!(
            grid.closest_within(DVec3::new(0.1, 0.1, 1.0), 0.5)
                .is_none()
        );
    }

    #[test]
    fn a_grid_over_a_few_of_many_vertices_answers_in_the_given_indices() {
        let (positions, triangles) = surface();
        // The same surface after 100 vertices no triangle uses.
        let mut padded = vec![DVec3::splat(50.0); 100];
        padded.extend(&positions);
        let shifted: Vec<[u32; 3]> = triangles.iter().map(|t| t.map(|i| i + 100)).collect();
        let grid = TriangleGrid::new(&positions, &triangles);
        let padded_grid = TriangleGrid::new(&padded, &shifted);
        assert_eq!(padded_grid.triangles(), &shifted[..]);
        for p in [DVec3::new(0.1, 0.2, 0.05), DVec3::new(-2.0, 0.1, 0.0)] {
            let (a, b) = (grid.closest(p), padded_grid.closest(p));
            let (a, b) = (a.expect("a mesh"), b.expect("a mesh"));
            assert_eq!((a.triangle, a.point), (b.triangle, b.point));
            assert_eq!(
                grid.triangle_normal(a.triangle),
                padded_grid.triangle_normal(b.triangle)
            );
        }
        // The surface spans x in [0, 0.2]: a point 0.3 beyond its box is
        // found within 0.31, and not within 0.29.
        let beyond = DVec3::new(0.5, 0.1, 0.0);
        let found = grid.closest_within(beyond, 0.31).expect("within reach");
        assert!((found.distance - 0.3).abs() < 0.01, "{}", found.distance);
        assert!(grid.closest_within(beyond, 0.29).is_none());
    }

    #[test]
    fn voronoi_regions_of_one_triangle() {
        let (a, b, c) = (DVec3::ZERO, DVec3::X, DVec3::Y);
        assert_eq!(
            closest_point_on_triangle(DVec3::new(-1.0, -1.0, 0.0), a, b, c).1,
            [1.0, 0.0, 0.0]
        );
        let (p, w) = closest_point_on_triangle(DVec3::new(0.25, 0.25, 3.0), a, b, c);
        assert!((p - DVec3::new(0.25, 0.25, 0.0)).length() < 1e-15);
        assert!((w[0] - 0.5).abs() < 1e-15);
        let (p, _) = closest_point_on_triangle(DVec3::new(1.0, 1.0, 0.0), a, b, c);
        assert!((p - DVec3::new(0.5, 0.5, 0.0)).length() < 1e-15);
    }
}
