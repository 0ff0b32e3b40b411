//! The face region of the default avatar's skin: the simulator's mask
//! resampled on the avatar's own, finer triangulation, so that every face
//! vertex lies exactly on the mask's neutral surface at a known point.
//!
//! 1. The mask's four boundary loops (outline, two eye holes, mouth slit)
//!    are subdivided in the parameter plane into pieces of at most
//!    [`FACE_SPACING`]; every such point lies on one mask edge.
//! 2. A hexagonal grid of spacing [`FACE_SPACING`] fills the domain, keeping
//!    0.6 spacings clear of the boundary.
//! 3. The vermilion border's two curves ([`super::lips::border_lines`]) are
//!    sampled at the same spacing, where they lie in the domain, and grid
//!    points within 0.6 spacings of them dropped.
//! 4. A constrained Delaunay triangulation (`spade`) of the points, with the
//!    loops and the border lines as constraints, keeps the triangles inside
//!    the domain and runs edges along the border, so the lips' material
//!    ends on it ([`FaceRegion::on_the_lips`]).
//! 5. Each point `p` is located in a mask triangle `t = (i, j, k)` with
//!    barycentric coordinates `b`, and placed at `x = b₀ x_i + b₁ x_j + b₂ x_k`
//!    (the mask's neutral positions, in `f64`).

use super::lips::{border_lines, on_the_lips};
use crate::face_mask::{FaceMask, face_mask, inside};
use glam::DVec3;
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

/// Grid spacing of the face region in the parameter plane (m): 1.7 mm gives
/// about 7,000 face vertices, six times the mask's density, so the avatar's
/// face is clearly its own resolution.
pub const FACE_SPACING: f64 = 0.0017;

/// Where an avatar vertex lies on the mask: a mask triangle and the
/// barycentric coordinates of the point in it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MaskPoint {
    /// Index of the mask triangle (into the mask's topology triangles).
    pub triangle: u32,
    /// Barycentric coordinates with respect to that triangle's vertices.
    pub barycentric: [f64; 3],
}

/// The resampled face region.
#[derive(Clone, Debug)]
pub struct FaceRegion {
    /// Parameter-plane point of each face vertex (m).
    pub uv: Vec<[f64; 2]>,
    /// Where each vertex lies on the mask.
    pub on_mask: Vec<MaskPoint>,
    /// Neutral position of each vertex (m).
    pub positions: Vec<DVec3>,
    /// Triangles, counter-clockwise seen from the front (+z).
    pub triangles: Vec<[u32; 3]>,
    /// The outline loop's vertices in order (indices into this region).
    pub rim: Vec<u32>,
    /// Whether each outline vertex is one of the mask's (else it lies on a
    /// mask edge between the neighbouring such vertices).
    pub rim_anchor: Vec<bool>,
    /// Whether each triangle is on the red of the lips (its centroid within
    /// the vermilion border, [`super::lips::on_the_lips`]).
    pub on_the_lips: Vec<bool>,
    /// The eye holes' rims `[left, right]`: the lids' edges, in order.
    pub eye_rims: [Vec<u32>; 2],
}

/// The mask's boundary loops as vertex lists: left eye, right eye, mouth,
/// outline. Each is a closed loop in order.
pub fn mask_loops(mask: &FaceMask) -> [Vec<u32>; 4] {
    let lm = &mask.landmarks;
    let eye = |s: usize| {
        let mut l = vec![lm.eye_inner[s]];
        l.extend(&lm.upper_lid[s]);
        l.push(lm.eye_outer[s]);
        l.extend(lm.lower_lid[s].iter().rev());
        l
    };
    let mut mouth = vec![lm.lip_corners[1]];
    mouth.extend(&lm.upper_lip);
    mouth.push(lm.lip_corners[0]);
    mouth.extend(lm.lower_lip.iter().rev());
    [eye(0), eye(1), mouth, lm.outline.clone()]
}

/// Barycentric coordinates of `p` in the triangle `(a, b, c)` of the plane.
pub fn barycentric(p: [f64; 2], a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> [f64; 3] {
    let det = (b[1] - c[1]) * (a[0] - c[0]) + (c[0] - b[0]) * (a[1] - c[1]);
    let l0 = ((b[1] - c[1]) * (p[0] - c[0]) + (c[0] - b[0]) * (p[1] - c[1])) / det;
    let l1 = ((c[1] - a[1]) * (p[0] - c[0]) + (a[0] - c[0]) * (p[1] - c[1])) / det;
    [l0, l1, 1.0 - l0 - l1]
}

/// The position of a mask point on the mask's neutral surface.
pub fn mask_position(mask: &FaceMask, m: &MaskPoint) -> DVec3 {
    let t = mask.topology.triangles()[m.triangle as usize];
    (0..3)
        .map(|k| m.barycentric[k] * mask.neutral[t[k] as usize].as_dvec3())
        .sum()
}

/// Locates `p` in the mask: the triangle whose smallest barycentric
/// coordinate is largest (exactly the containing triangle when `p` is in
/// the domain). Candidates come from a bucket grid of triangle boxes.
struct Locator {
    origin: [f64; 2],
    cell: f64,
    dims: [usize; 2],
    buckets: Vec<Vec<u32>>,
}

impl Locator {
    fn new(mask: &FaceMask) -> Locator {
        let (cell, origin) = (0.006, [-0.09, -0.12]);
        let dims = [32, 36];
        let mut buckets = vec![Vec::new(); dims[0] * dims[1]];
        for (ti, t) in mask.topology.triangles().iter().enumerate() {
            let pts = t.map(|i| mask.uv[i as usize]);
            let lo = [0, 1].map(|d| pts.iter().map(|p| p[d]).fold(f64::MAX, f64::min));
            let hi = [0, 1].map(|d| pts.iter().map(|p| p[d]).fold(f64::MIN, f64::max));
            let c0 = [0, 1].map(|d| (((lo[d] - origin[d]) / cell).floor().max(0.0)) as usize);
            let c1 = [0, 1].map(|d| (((hi[d] - origin[d]) / cell) as usize).min(dims[d] - 1));
            for x in c0[0]..=c1[0] {
                for y in c0[1]..=c1[1] {
                    buckets[y * dims[0] + x].push(ti as u32);
                }
            }
        }
        Locator {
            origin,
            cell,
            dims,
            buckets,
        }
    }

    fn locate(&self, mask: &FaceMask, p: [f64; 2]) -> Option<MaskPoint> {
        let c = [0, 1].map(|d| ((p[d] - self.origin[d]) / self.cell).floor());
        if c[0] < 0.0 || c[1] < 0.0 {
            return None;
        }
        let [x, y] = c.map(|v| v as usize);
        let bucket = self
            .buckets
            .get(y * self.dims[0] + x.min(self.dims[0] - 1))?;
        let tris = mask.topology.triangles();
        bucket
            .iter()
            .map(|&ti| {
                let t = tris[ti as usize].map(|i| mask.uv[i as usize]);
                (ti, barycentric(p, t[0], t[1], t[2]))
            })
            .max_by(|a, b| min3(a.1).total_cmp(&min3(b.1)))
            .filter(|(_, b)| min3(*b) > -1e-9)
            .map(|(triangle, b)| MaskPoint {
                triangle,
                barycentric: b.map(|v| v.max(0.0) / b.iter().map(|w| w.max(0.0)).sum::<f64>()),
            })
    }
}

fn min3(b: [f64; 3]) -> f64 {
    b[0].min(b[1]).min(b[2])
}

/// The mask triangle holding boundary edge `(a, b)` and the barycentric
/// coordinates of the point `(1 − t) a + t b` in it.
fn on_edge(mask: &FaceMask, a: u32, b: u32, t: f64) -> Option<MaskPoint> {
    let tris = mask.topology.triangles();
    let ti = tris
        .iter()
        .position(|tr| tr.contains(&a) && tr.contains(&b))?;
    let barycentric = tris[ti].map(|v| {
        if v == a {
            1.0 - t
        } else if v == b {
            t
        } else {
            0.0
        }
    });
    Some(MaskPoint {
        triangle: ti as u32,
        barycentric,
    })
}

/// Builds the face region of the skin at [`FACE_SPACING`].
pub fn face_region() -> FaceRegion {
    face_region_with(FACE_SPACING)
}

/// Builds the face region with grid and boundary spacing `spacing` (m): the
/// default avatar's is [`FACE_SPACING`]; the low-poly test avatar's coarser.
pub fn face_region_with(spacing: f64) -> FaceRegion {
    let mask = face_mask();
    let loops = mask_loops(mask);
    let mut uv: Vec<[f64; 2]> = Vec::new();
    let mut on_mask: Vec<MaskPoint> = Vec::new();
    let mut loop_ranges = Vec::new();
    let mut anchors = Vec::new();
    for l in &loops {
        let start = uv.len();
        for k in 0..l.len() {
            let (a, b) = (l[k], l[(k + 1) % l.len()]);
            let (pa, pb) = (mask.uv[a as usize], mask.uv[b as usize]);
            let len = ((pa[0] - pb[0]).powi(2) + (pa[1] - pb[1]).powi(2)).sqrt();
            let pieces = (len / spacing).ceil().max(1.0) as usize;
            for s in 0..pieces {
                let t = s as f64 / pieces as f64;
                if let Some(m) = on_edge(mask, a, b, t) {
                    uv.push([0, 1].map(|d| pa[d] + t * (pb[d] - pa[d])));
                    on_mask.push(m);
                    anchors.push(s == 0);
                }
            }
        }
        loop_ranges.push(start..uv.len());
    }
    let polygons: Vec<Vec<[f64; 2]>> = loop_ranges.iter().map(|r| uv[r.clone()].to_vec()).collect();
    let in_domain =
        |p: [f64; 2]| inside(&polygons[3], p) && !polygons[..3].iter().any(|h| inside(h, p));
    let locator = Locator::new(mask);
    let h = spacing;
    // The vermilion border, in runs of points clear of the loops.
    let clear = |p: [f64; 2], of: &[[f64; 2]]| of.iter().all(|b| dist2(*b, p) >= (0.6 * h).powi(2));
    let loops_only = uv.clone();
    let mut lines = Vec::new();
    for line in border_lines(h) {
        let mut run = uv.len();
        for p in line {
            let located = (in_domain(p) && clear(p, &loops_only))
                .then(|| locator.locate(mask, p))
                .flatten();
            match located {
                Some(m) => {
                    uv.push(p);
                    on_mask.push(m);
                }
                None => {
                    if uv.len() - run >= 2 {
                        lines.push(run..uv.len());
                    }
                    run = uv.len();
                }
            }
        }
        if uv.len() - run >= 2 {
            lines.push(run..uv.len());
        }
    }
    let boundary = uv.clone();
    let rows = (0.2 / (h * 0.866)) as i64;
    for r in 0..rows {
        let v = -0.11 + r as f64 * h * 0.866;
        let shift = if r % 2 == 0 { 0.0 } else { 0.5 * h };
        for c in 0..(0.16 / h) as i64 {
            let p = [-0.08 + shift + c as f64 * h, v];
            if !in_domain(p) || boundary.iter().any(|b| dist2(*b, p) < (0.6 * h).powi(2)) {
                continue;
            }
            if let Some(m) = locator.locate(mask, p) {
                uv.push(p);
                on_mask.push(m);
            }
        }
    }
    let triangles = triangulate(&uv, &loop_ranges, &lines);
    let centroid =
        |t: &[u32; 3]| [0, 1].map(|d| t.iter().map(|&i| uv[i as usize][d]).sum::<f64>() / 3.0);
    let on_the_lips = triangles.iter().map(|t| on_the_lips(centroid(t))).collect();
    let positions = on_mask.iter().map(|m| mask_position(mask, m)).collect();
    let rim = loop_ranges[3].clone().map(|i| i as u32).collect();
    let rim_anchor = anchors[loop_ranges[3].clone()].to_vec();
    let eye_rims = [0, 1].map(|s| loop_ranges[s].clone().map(|i| i as u32).collect());
    FaceRegion {
        uv,
        on_mask,
        positions,
        triangles,
        rim,
        rim_anchor,
        on_the_lips,
        eye_rims,
    }
}

fn dist2(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)
}

/// Constrained Delaunay triangulation of `points` with each range of
/// `loops` a closed constraint loop and each range of `lines` an open
/// polyline of constraint edges; keeps the triangles inside an odd number
/// of loops (a breadth-first walk from the convex hull counting the loop
/// edges crossed, not the lines'), counter-clockwise. The walk, not a test
/// of each triangle's centroid, decides, so slivers between nearly
/// collinear loop points fall on the right side.
pub fn triangulate(
    points: &[[f64; 2]],
    loops: &[std::ops::Range<usize>],
    lines: &[std::ops::Range<usize>],
) -> Vec<[u32; 3]> {
    let mut cdt = ConstrainedDelaunayTriangulation::<Point2<f64>>::new();
    let mut handle_to_index = Vec::new();
    let mut handles = Vec::with_capacity(points.len());
    for (i, p) in points.iter().enumerate() {
        let h = cdt.insert(Point2::new(p[0], p[1])).ok();
        if let Some(h) = h {
            if handle_to_index.len() <= h.index() {
                handle_to_index.resize(h.index() + 1, usize::MAX);
            }
            handle_to_index[h.index()] = i;
        }
        handles.push(h);
    }
    for r in loops {
        let n = r.len();
        for k in 0..n {
            let (a, b) = (handles[r.start + k], handles[r.start + (k + 1) % n]);
            if let (Some(a), Some(b)) = (a, b) {
                if a != b && cdt.can_add_constraint(a, b) {
                    cdt.add_constraint(a, b);
                }
            }
        }
    }
    let mut on_lines = std::collections::HashSet::new();
    for r in lines {
        for k in r.start..r.end - 1 {
            if let (Some(a), Some(b)) = (handles[k], handles[k + 1]) {
                if a != b && cdt.can_add_constraint(a, b) {
                    cdt.add_constraint(a, b);
                    on_lines.insert((a.index().min(b.index()), a.index().max(b.index())));
                }
            }
        }
    }
    let crosses_loop = |e: spade::handles::DirectedEdgeHandle<'_, _, _, _, _>| {
        let [a, b] = e.vertices().map(|v| v.fix().index());
        cdt.is_constraint_edge(e.as_undirected().fix()) && !on_lines.contains(&(a.min(b), a.max(b)))
    };
    let mut depth = vec![usize::MAX; cdt.num_all_faces()];
    let mut queue = std::collections::VecDeque::new();
    for e in cdt.convex_hull() {
        if let Some(f) = e.rev().face().as_inner() {
            let d = usize::from(crosses_loop(e));
            if d < depth[f.fix().index()] {
                depth[f.fix().index()] = d;
                queue.push_back(f.fix());
            }
        }
    }
    while let Some(f) = queue.pop_front() {
        let face = cdt.face(f);
        let d = depth[f.index()];
        for e in face.adjacent_edges() {
            let Some(g) = e.rev().face().as_inner() else {
                continue;
            };
            let next = d + usize::from(crosses_loop(e));
            if next < depth[g.fix().index()] {
                depth[g.fix().index()] = next;
                queue.push_back(g.fix());
            }
        }
    }
    cdt.inner_faces()
        .filter(|f| depth[f.fix().index()] % 2 == 1)
        .map(|face| {
            face.vertices()
                .map(|v| handle_to_index[v.fix().index()] as u32)
        })
        .collect()
}
