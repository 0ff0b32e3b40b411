//! Closest points on a triangle mesh: the query behind ICP, non-rigid
//! registration and the correspondence map `M` of §3.3.
//!
//! The triangles are kept in a bounding-volume hierarchy: a binary tree
//! of axis-aligned boxes, each node's box holding its triangles, split at
//! the median of the triangles' centroids along the longest axis of their
//! spread until a leaf holds at most [`LEAF_TRIANGLES`] (the
//! "median-split" build of Wald, Boulos & Shirley, *Ray Tracing
//! Deformable Scenes Using Dynamic Bounding Volume Hierarchies*, 2007,
//! §3). A query descends nearer child first and skips every node whose
//! box is farther than the best distance found so far, so the answer is
//! exact, not approximate, and costs about `log n` boxes wherever the
//! triangles crowd (the fan at a sphere's pole, a dense face on a coarse
//! body), which a uniform grid does not. Point-to-triangle distance
//! follows Ericson, *Real-Time Collision Detection* (2005), §5.1.5: the
//! closest point lies in one of the triangle's seven Voronoi regions
//! (three vertices, three edges, the face), found from the signs of a few
//! dot products.
//!
//! Of triangles at the same distance the one listed first is the answer,
//! whatever the tree's shape.

use glam::DVec3;

/// Most triangles in a leaf of the tree.
pub const LEAF_TRIANGLES: usize = 4;

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

/// One node of the tree: its box and either its two children (at
/// `first` and `first + 1`, `count == 0`) or its triangles (`count` of
/// them from `first` in the tree's order).
#[derive(Clone, Copy, Debug)]
struct Node {
    lo: DVec3,
    hi: DVec3,
    first: u32,
    count: u32,
}

impl Node {
    /// The distance from `p` to the node's box (0 inside).
    fn distance(&self, p: DVec3) -> f64 {
        (self.lo - p).max(p - self.hi).max(DVec3::ZERO).length()
    }
}

/// A triangle mesh kept in a bounding-volume hierarchy for closest-point
/// queries (module docs).
#[derive(Clone, Debug)]
pub struct TriangleTree {
    triangles: Vec<[u32; 3]>,
    /// Each triangle's corners (only the triangles' own vertices are
    /// kept, however many `positions` the tree was built over).
    corners: Vec<[DVec3; 3]>,
    /// Each triangle's unit normal (zero for a degenerate one).
    normals: Vec<DVec3>,
    /// The triangles in the tree's order: a leaf's are contiguous.
    order: Vec<u32>,
    /// The root first; children in adjacent pairs.
    nodes: Vec<Node>,
}

/// Deepest a tree can be: each split halves the triangles, so 2⁶⁴ would
/// be needed to pass it.
const MAX_DEPTH: usize = 64;

impl TriangleTree {
    /// Builds the tree of `triangles` over `positions`. Triangles with an
    /// index past `positions` are left out (the caller's topology check
    /// reports them).
    pub fn new(positions: &[DVec3], triangles: &[[u32; 3]]) -> TriangleTree {
        let n = positions.len();
        let triangles: Vec<[u32; 3]> = triangles
            .iter()
            .copied()
            .filter(|t| t.iter().all(|&i| (i as usize) < n))
            .collect();
        let corners: Vec<[DVec3; 3]> = triangles
            .iter()
            .map(|t| t.map(|i| positions[i as usize]))
            .collect();
        let centroids: Vec<DVec3> = corners
            .iter()
            .map(|[a, b, c]| (*a + *b + *c) / 3.0)
            .collect();
        let mut tree = TriangleTree {
            order: (0..triangles.len() as u32).collect(),
            normals: corners.iter().map(unit_normal).collect(),
            triangles,
            corners,
            nodes: Vec::new(),
        };
        if !tree.triangles.is_empty() {
            tree.split(&centroids);
            tree.fit_boxes();
        }
        tree
    }

    /// The same triangles over `positions` (the same vertices moved, as a
    /// shape moves them), in the same tree with its boxes fitted anew (a
    /// "refit", Wald et al. 2007, §4): exact still, and as quick as long
    /// as the motion is mostly rigid, as an eyeball's is.
    ///
    /// Triangles with an index past `positions` are left out, and the tree
    /// built anew, if any are.
    pub fn moved_to(&self, positions: &[DVec3]) -> TriangleTree {
        let n = positions.len();
        if self
            .triangles
            .iter()
            .any(|t| t.iter().any(|&i| i as usize >= n))
        {
            return TriangleTree::new(positions, &self.triangles);
        }
        let corners: Vec<[DVec3; 3]> = self
            .triangles
            .iter()
            .map(|t| t.map(|i| positions[i as usize]))
            .collect();
        let mut tree = TriangleTree {
            triangles: self.triangles.clone(),
            normals: corners.iter().map(unit_normal).collect(),
            corners,
            order: self.order.clone(),
            nodes: self.nodes.clone(),
        };
        tree.fit_boxes();
        tree
    }

    /// Splits the triangles into the tree (module docs), from the root
    /// down: a node of more than [`LEAF_TRIANGLES`] is split at the median
    /// of its triangles' centroids along the axis they spread most on.
    /// Leaves the boxes to [`TriangleTree::fit_boxes`].
    fn split(&mut self, centroids: &[DVec3]) {
        let node = |first: usize, count: usize| Node {
            lo: DVec3::ZERO,
            hi: DVec3::ZERO,
            first: first as u32,
            count: count as u32,
        };
        self.nodes = vec![node(0, self.triangles.len())];
        let mut pending = vec![0];
        while let Some(at) = pending.pop() {
            let Node { first, count, .. } = self.nodes[at];
            let (first, count) = (first as usize, count as usize);
            if count <= LEAF_TRIANGLES {
                continue;
            }
            let range = &mut self.order[first..first + count];
            let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
            for &t in range.iter() {
                lo = lo.min(centroids[t as usize]);
                hi = hi.max(centroids[t as usize]);
            }
            let spread = hi - lo;
            let axis = if spread.x >= spread.y && spread.x >= spread.z {
                0
            } else if spread.y >= spread.z {
                1
            } else {
                2
            };
            let half = count / 2;
            range.select_nth_unstable_by(half, |&a, &b| {
                centroids[a as usize][axis].total_cmp(&centroids[b as usize][axis])
            });
            let children = self.nodes.len();
            self.nodes
                .extend([node(first, half), node(first + half, count - half)]);
            self.nodes[at].first = children as u32;
            self.nodes[at].count = 0;
            pending.extend([children, children + 1]);
        }
    }

    /// Each node's box: a leaf's round its triangles' corners, an inner
    /// node's round its children's (children come after their parent, so
    /// one pass from the back does it).
    fn fit_boxes(&mut self) {
        for at in (0..self.nodes.len()).rev() {
            let Node { first, count, .. } = self.nodes[at];
            let first = first as usize;
            let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
            if count == 0 {
                for child in &self.nodes[first..first + 2] {
                    lo = lo.min(child.lo);
                    hi = hi.max(child.hi);
                }
            } else {
                for &t in &self.order[first..first + count as usize] {
                    for c in self.corners[t as usize] {
                        lo = lo.min(c);
                        hi = hi.max(c);
                    }
                }
            }
            self.nodes[at].lo = lo;
            self.nodes[at].hi = hi;
        }
    }

    /// The triangles, as given (less any with an out-of-range index).
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Each triangle's corners, in [`TriangleTree::triangles`]' order.
    pub fn corners(&self) -> &[[DVec3; 3]] {
        &self.corners
    }

    /// The unit normal of triangle `t` (of [`TriangleTree::triangles`]),
    /// zero for a degenerate or unknown triangle.
    pub fn triangle_normal(&self, t: usize) -> DVec3 {
        self.normals.get(t).copied().unwrap_or(DVec3::ZERO)
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
    /// `accept` takes: the tree descended nearer box first, every box
    /// farther than the best found skipped (module docs).
    pub fn closest_where(
        &self,
        p: DVec3,
        max_distance: f64,
        accept: impl Fn(usize) -> bool,
    ) -> Option<ClosestPoint> {
        if self.nodes.is_empty() || max_distance.is_nan() || max_distance < 0.0 {
            return None;
        }
        // The best distance so far (or the limit), and what it was found
        // on.
        let mut limit = max_distance;
        let mut best: Option<ClosestPoint> = None;
        let mut stack = [0u32; MAX_DEPTH + 1];
        let mut depth = usize::from(self.nodes[0].distance(p) <= limit);
        while depth > 0 {
            depth -= 1;
            let node = self.nodes[stack[depth] as usize];
            if node.distance(p) > limit {
                continue;
            }
            let first = node.first as usize;
            if node.count > 0 {
                for &t in &self.order[first..first + node.count as usize] {
                    let t = t as usize;
                    if !accept(t) {
                        continue;
                    }
                    let c = self.closest_on_triangle(t, p);
                    let better = match best {
                        None => c.distance <= limit,
                        Some(b) => c.distance < limit || (c.distance == limit && t < b.triangle),
                    };
                    if better {
                        limit = c.distance;
                        best = Some(c);
                    }
                }
                continue;
            }
            // The nearer child goes on top of the stack, so it is searched
            // first.
            let (a, b) = (first, first + 1);
            let (da, db) = (self.nodes[a].distance(p), self.nodes[b].distance(p));
            let ((near, d_near), (far, d_far)) = if da <= db {
                ((a, da), (b, db))
            } else {
                ((b, db), (a, da))
            };
            for (child, d) in [(far, d_far), (near, d_near)] {
                if d <= limit && depth < stack.len() {
                    stack[depth] = child as u32;
                    depth += 1;
                }
            }
        }
        best
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
}

/// The unit normal of triangle `abc` (counter-clockwise seen from the
/// side it points to), zero for a degenerate one.
fn unit_normal([a, b, c]: &[DVec3; 3]) -> DVec3 {
    (*b - *a).cross(*c - *a).normalize_or_zero()
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
    use crate::geometry::test_shapes::uv_sphere;

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
    fn the_tree_finds_what_brute_force_finds() {
        let (positions, triangles) = surface();
        let grid = TriangleTree::new(&positions, &triangles);
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
    fn a_tree_over_a_few_of_many_vertices_answers_in_the_given_indices() {
        let (positions, triangles) = surface();
        // The same surface after 100 vertices no triangle uses.
        let mut padded = vec![DVec3::splat(50.0); 100];
        padded.extend(&positions);
        let shifted: Vec<[u32; 3]> = triangles.iter().map(|t| t.map(|i| i + 100)).collect();
        let grid = TriangleTree::new(&positions, &triangles);
        let padded_grid = TriangleTree::new(&padded, &shifted);
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
    fn inside_and_outside_a_sphere_with_crowded_poles_as_brute_force() {
        let (positions, triangles) = uv_sphere(40, 48);
        let tree = TriangleTree::new(&positions, &triangles);
        for k in 0..300 {
            let f = k as f64;
            // Points from the centre to twice the radius, many near the
            // poles.
            let direction = DVec3::new((f * 0.37).sin() * 0.3, (f * 0.91).cos() * 0.3, 1.0)
                .normalize()
                * if k % 2 == 0 { 1.0 } else { -1.0 };
            let p = direction * (f * 0.013).rem_euclid(2.0);
            let found = tree.closest(p).expect("a mesh");
            let brute = (0..triangles.len())
                .map(|t| (tree.closest_on_triangle(t, p).distance, t))
                .fold((f64::INFINITY, 0), |a, b| if b.0 < a.0 { b } else { a });
            assert_eq!(found.distance, brute.0, "{p}");
            // Of equally near triangles, the first listed.
            assert_eq!(found.triangle, brute.1, "{p}");
            // Inside is on the inner side of the closest triangle.
            let inside = (p - found.point).dot(tree.triangle_normal(found.triangle)) < 0.0;
            assert_eq!(inside, p.length() < 0.99, "{p}");
            let facing = tree.closest_facing(p, DVec3::Z, 0.5, 0.5);
            let brute_facing = (0..triangles.len())
                .filter(|&t| tree.triangle_normal(t).dot(DVec3::Z) >= 0.5)
                .map(|t| tree.closest_on_triangle(t, p).distance)
                .fold(f64::INFINITY, f64::min);
            match facing {
                Some(c) => assert_eq!(c.distance, brute_facing),
                None => assert!(brute_facing > 0.5, "{p}"),
            }
        }
    }

    #[test]
    fn a_tree_moved_with_its_mesh_answers_as_one_built_anew() {
        let (positions, triangles) = uv_sphere(24, 32);
        let tree = TriangleTree::new(&positions, &triangles);
        // Turned 0.6 rad about a slanted axis, stretched and shifted.
        let turn = glam::DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 0.5).normalize(), 0.6);
        let moved: Vec<DVec3> = positions
            .iter()
            .map(|&p| turn * p * DVec3::new(1.0, 1.2, 0.9) + DVec3::new(3.0, -1.0, 0.5))
            .collect();
        let (refit, anew) = (tree.moved_to(&moved), TriangleTree::new(&moved, &triangles));
        for k in 0..100 {
            let f = k as f64;
            let p = DVec3::new(
                3.0 + (f * 0.7).sin(),
                -1.0 + (f * 0.3).cos(),
                0.5 + (f * 0.11).sin(),
            );
            let (a, b) = (
                refit.closest(p).expect("a mesh"),
                anew.closest(p).expect("a mesh"),
            );
            assert_eq!((a.triangle, a.distance), (b.triangle, b.distance), "{p}");
        }
        // Fewer positions than the triangles use: the out-of-range ones
        // are left out, as a new tree would.
        let few = tree.moved_to(&moved[..100]);
        assert_eq!(
            few.triangles(),
            TriangleTree::new(&moved[..100], &triangles).triangles()
        );
    }

    #[test]
    fn an_empty_mesh_and_bad_limits_find_nothing() {
        let (positions, triangles) = surface();
        assert!(
            TriangleTree::new(&positions, &[])
                .closest(DVec3::ZERO)
                .is_none()
        );
        let tree = TriangleTree::new(&positions, &triangles);
        assert!(tree.closest_within(DVec3::ZERO, f64::NAN).is_none());
        assert!(tree.closest_within(DVec3::ZERO, -1.0).is_none());
        assert!(tree.closest(DVec3::NAN).is_none());
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
