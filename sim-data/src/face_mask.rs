//! The face mask: a stand-in for ARKit's face geometry.
//!
//! ARKit's mask has 1,220 vertices and 2,304 triangles, one connected surface
//! with four boundary loops (the outline, two eye holes, the mouth slit). This
//! module builds a mesh of exactly that size and kind, deterministically:
//!
//! 1. In a flat parameter plane `(u, v)` (metres, `u` = x, `v` = y) it lays
//!    out the four loops: an egg-shaped outline 14.5 cm wide and 18 cm tall,
//!    two almond eye holes with 9 upper and 9 lower lid vertices between the
//!    corners, and a mouth opening with 11 upper and 11 lower lip vertices
//!    between the corners. That is 76 + 20 + 20 + 24 = 140 boundary vertices.
//! 2. It scatters 1,080 interior points with a spacing of about 3.3 mm at the
//!    eyes and mouth growing to 6.5 mm at the rim, relaxes them, and
//!    triangulates with a constrained Delaunay triangulation (`spade`).
//!    Euler's formula for a surface with four boundary loops, `V − F/2 − B/2 =
//!    χ = −2`, then gives `F = 2·1220 − 140 + 4 = 2304` triangles.
//! 3. It lifts the plane to a face-shaped surface (nose, brows, eye sockets,
//!    cheekbones, lips, chin) and closes the mouth opening so the upper and
//!    lower lip rows lie 0.2 mm apart: distinct vertices that touch.
//!
//! Coordinates follow ARKit's face anchor: +x towards the person's left, +y
//! up, +z out of the face. Index 0 of every `[_; 2]` landmark is the person's
//! left side (+x).

use glam::Vec3;
use likeness::Topology;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};
use std::sync::OnceLock;

/// Vertices of the outline loop.
pub const OUTLINE_VERTICES: usize = 76;
/// Lid vertices strictly between the two eye corners, per lid.
pub const LID_VERTICES: usize = 9;
/// Lip vertices strictly between the two mouth corners, per lip row.
pub const LIP_VERTICES: usize = 11;
/// Total vertex count, as ARKit's mask.
pub const VERTEX_COUNT: usize = 1220;

/// Centre of the mouth opening in the parameter plane (m).
pub const MOUTH_CENTRE: [f64; 2] = [0.0, -0.047];
/// Half the mouth width, corner to centre (m): mouths are about 5 cm wide.
pub const MOUTH_HALF_WIDTH: f64 = 0.025;
/// Half the height of the mouth opening in the parameter plane only (m);
/// the lifted surface closes it to [`LIP_GAP`].
pub const MOUTH_PARAM_HALF_GAP: f64 = 0.0035;
/// Gap between the lip rows of the relaxed neutral face at the centre (m).
pub const LIP_GAP: f64 = 0.0002;
/// Centre of the left eye opening (m); the right is mirrored. Eyes are about
/// 6.5 cm apart (interpupillary distance, adult mean 6.3 cm).
pub const EYE_CENTRE: [f64; 2] = [0.0325, 0.028];
/// Half the eye-opening width, corner to centre (m): palpebral fissures are
/// about 2.9 cm long.
pub const EYE_HALF_WIDTH: f64 = 0.0145;
/// Height of the upper lid above the eye centre line (m); with the lower lid
/// the opening is about 1 cm high, the adult palpebral fissure height.
pub const UPPER_LID_HEIGHT: f64 = 0.0055;
/// Depth of the lower lid below the eye centre line (m).
pub const LOWER_LID_HEIGHT: f64 = 0.0045;

/// Named vertices of the mask.
#[derive(Clone, Debug)]
pub struct Landmarks {
    /// Inner (nasal) eye corner, `[left, right]`.
    pub eye_inner: [u32; 2],
    /// Outer (temporal) eye corner.
    pub eye_outer: [u32; 2],
    /// Upper lid loop from inner to outer corner, corners excluded.
    pub upper_lid: [Vec<u32>; 2],
    /// Lower lid loop from inner to outer corner, corners excluded; vertex k
    /// sits straight below `upper_lid[_][k]`.
    pub lower_lid: [Vec<u32>; 2],
    /// Mouth corners, `[left, right]`.
    pub lip_corners: [u32; 2],
    /// Upper lip row from the right corner to the left, corners excluded.
    pub upper_lip: Vec<u32>,
    /// Lower lip row, same order; vertex k sits straight below `upper_lip[k]`.
    pub lower_lip: Vec<u32>,
    /// Tip of the nose (the most forward vertex).
    pub nose_tip: u32,
    /// Lowest point of the chin on the outline.
    pub chin: u32,
    /// The outline loop.
    pub outline: Vec<u32>,
}

/// The generic face mask: connectivity, parameter-plane coordinates and the
/// template's neutral positions.
#[derive(Clone, Debug)]
pub struct FaceMask {
    /// Triangles over [`VERTEX_COUNT`] vertices.
    pub topology: Topology,
    /// Each vertex's position in the flat parameter plane (m). Expression
    /// fields are defined over this plane, so they mean the same on every face.
    pub uv: Vec<[f64; 2]>,
    /// The template's neutral face (m).
    pub neutral: Vec<Vec3>,
    /// Named vertices.
    pub landmarks: Landmarks,
}

/// The mask, built once per process (it is deterministic).
pub fn face_mask() -> &'static FaceMask {
    static MASK: OnceLock<FaceMask> = OnceLock::new();
    MASK.get_or_init(build_face_mask)
}

/// Whether a parameter-plane point lies on the upper side of the mouth line
/// (1), the lower side (0), or in between beyond the corners.
pub fn lip_row_offset(u: f64) -> f64 {
    let s = u / MOUTH_HALF_WIDTH;
    if s.abs() >= 1.0 {
        0.0
    } else {
        MOUTH_PARAM_HALF_GAP * (1.0 - s * s)
    }
}

fn smoothstep(edge0: f64, edge1: f64, x: f64) -> f64 {
    let t = ((x - edge0) / (edge1 - edge0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

fn gauss(t: f64) -> f64 {
    (-t * t).exp()
}

/// The outline: an ellipse 14.5 × 18 cm, narrowed towards the chin.
fn outline_point(k: usize) -> [f64; 2] {
    let theta = std::f64::consts::TAU * k as f64 / OUTLINE_VERTICES as f64;
    let y = -0.01 + 0.09 * theta.cos();
    let narrowing = 1.0 - 0.30 * smoothstep(-0.03, -0.10, y);
    [0.0725 * theta.sin() * narrowing, y]
}

/// Corner-clustered stations `s ∈ (−1, 1)` for `n` points between corners.
fn stations(n: usize) -> impl Iterator<Item = f64> {
    (1..=n).map(move |k| -(std::f64::consts::PI * k as f64 / (n + 1) as f64).cos())
}

/// The four boundary loops in the parameter plane, in vertex order: left eye,
/// right eye, mouth, outline. Returns the points and the loops' index lists.
fn boundary_loops() -> (Vec<[f64; 2]>, Vec<Vec<usize>>) {
    let mut points = Vec::new();
    let mut loops = Vec::new();
    for side in [1.0, -1.0] {
        // inner corner, upper lid inner→outer, outer corner, lower lid outer→inner
        let (cx, cy) = (side * EYE_CENTRE[0], EYE_CENTRE[1]);
        let at = |s: f64, h: f64| [cx + side * s * EYE_HALF_WIDTH, cy + h];
        let start = points.len();
        points.push(at(-1.0, 0.0));
        for s in stations(LID_VERTICES) {
            points.push(at(s, UPPER_LID_HEIGHT * (1.0 - s * s).powf(0.8)));
        }
        points.push(at(1.0, 0.0015));
        let lower: Vec<_> = stations(LID_VERTICES)
            .map(|s| at(s, -LOWER_LID_HEIGHT * (1.0 - s * s)))
            .collect();
        points.extend(lower.into_iter().rev());
        loops.push((start..points.len()).collect());
    }
    let start = points.len();
    let [mx, my] = MOUTH_CENTRE;
    points.push([mx - MOUTH_HALF_WIDTH, my]);
    for s in stations(LIP_VERTICES) {
        let u = mx + s * MOUTH_HALF_WIDTH;
        points.push([u, my + lip_row_offset(u)]);
    }
    points.push([mx + MOUTH_HALF_WIDTH, my]);
    let lower: Vec<_> = stations(LIP_VERTICES)
        .map(|s| {
            let u = mx + s * MOUTH_HALF_WIDTH;
            [u, my - lip_row_offset(u)]
        })
        .collect();
    points.extend(lower.into_iter().rev());
    loops.push((start..points.len()).collect());
    let start = points.len();
    points.extend((0..OUTLINE_VERTICES).map(outline_point));
    loops.push((start..points.len()).collect());
    (points, loops)
}

/// Whether `p` is inside `polygon` (a closed loop of points, either
/// orientation), by the even-odd rule.
pub fn inside(polygon: &[[f64; 2]], p: [f64; 2]) -> bool {
    let mut inside = false;
    let mut j = polygon.len() - 1;
    for i in 0..polygon.len() {
        let (a, b) = (polygon[i], polygon[j]);
        if (a[1] > p[1]) != (b[1] > p[1])
            && p[0] < (b[0] - a[0]) * (p[1] - a[1]) / (b[1] - a[1]) + a[0]
        {
            inside = !inside;
        }
        j = i;
    }
    inside
}

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt()
}

/// Target edge length at `p`: 3.3 mm at the eyes and mouth, 6.5 mm far away.
fn spacing(p: [f64; 2]) -> f64 {
    let to_eye = dist([p[0].abs(), p[1]], EYE_CENTRE) - EYE_HALF_WIDTH * 0.8;
    let to_mouth = dist(p, MOUTH_CENTRE) - MOUTH_HALF_WIDTH * 0.8;
    let d = to_eye.min(to_mouth).max(0.0);
    0.0033 + (0.0065 - 0.0033) * smoothstep(0.0, 0.035, d)
}

/// A kept point and its clearance radius.
type KeptPoint = ([f64; 2], f64);

struct Domain {
    boundary: Vec<[f64; 2]>,
    polygons: Vec<Vec<[f64; 2]>>,
}

impl Domain {
    fn contains(&self, p: [f64; 2]) -> bool {
        let (holes, outline) = self.polygons.split_at(3);
        inside(&outline[0], p) && !holes.iter().any(|h| inside(h, p))
    }

    /// Each candidate's distance to the nearest boundary point.
    fn boundary_clearance(&self, candidates: &[[f64; 2]]) -> Vec<f64> {
        candidates
            .iter()
            .map(|p| {
                self.boundary
                    .iter()
                    .map(|b| dist(*b, *p))
                    .fold(f64::INFINITY, f64::min)
            })
            .collect()
    }

    /// Dart throwing with a variable radius scaled by `scale`: a candidate
    /// `p` is kept if it is farther than `0.75 r(p)` from the boundary and
    /// farther than `(r(p) + r(q))/2` from every kept `q`.
    ///
    /// Kept points are bucketed on a grid whose cells are wider than the
    /// largest clearance `0.0065 · scale`, so only the 3 × 3 cells around a
    /// candidate can hold a point too close to it; the result is the same
    /// as testing every kept point.
    fn scatter(&self, candidates: &[[f64; 2]], clearance: &[f64], scale: f64) -> Vec<[f64; 2]> {
        let cell = 0.0065 * scale * 1.001;
        let key = |p: [f64; 2]| ((p[0] / cell).floor() as i64, (p[1] / cell).floor() as i64);
        let mut grid: std::collections::HashMap<(i64, i64), Vec<KeptPoint>> =
            std::collections::HashMap::new();
        let mut accepted: Vec<[f64; 2]> = Vec::new();
        for (&p, &to_boundary) in candidates.iter().zip(clearance) {
            let r = spacing(p) * scale;
            if to_boundary <= 0.75 * r {
                continue;
            }
            let (cx, cy) = key(p);
            let clear = (-1..=1).all(|dx| {
                (-1..=1).all(|dy| {
                    grid.get(&(cx + dx, cy + dy))
                        .is_none_or(|near| near.iter().all(|(q, rq)| dist(*q, p) > 0.5 * (r + rq)))
                })
            });
            if clear {
                accepted.push(p);
                grid.entry((cx, cy))
                    .or_default()
                    .push((p, spacing(p) * scale));
            }
        }
        accepted
    }
}

fn triangulate(points: &[[f64; 2]], loops: &[Vec<usize>], domain: &Domain) -> Vec<[u32; 3]> {
    let mut cdt = ConstrainedDelaunayTriangulation::<Point2<f64>>::new();
    let mut handle_to_index = vec![usize::MAX; points.len()];
    let mut handles = Vec::with_capacity(points.len());
    for (i, p) in points.iter().enumerate() {
        let h = cdt
            .insert(Point2::new(p[0], p[1]))
            .expect("mask points are finite");
        handle_to_index[h.index()] = i;
        handles.push(h);
    }
    for l in loops {
        for k in 0..l.len() {
            cdt.add_constraint(handles[l[k]], handles[l[(k + 1) % l.len()]]);
        }
    }
    let mut triangles = Vec::new();
    for face in cdt.inner_faces() {
        let vs = face.vertices();
        let idx = vs.map(|v| handle_to_index[v.fix().index()]);
        let c = [0, 1].map(|d| idx.iter().map(|&i| points[i][d]).sum::<f64>() / 3.0);
        if domain.contains(c) {
            triangles.push(idx.map(|i| i as u32));
        }
    }
    let centroid =
        |t: &[u32; 3]| [0, 1].map(|d| t.iter().map(|&i| points[i as usize][d]).sum::<f64>());
    triangles.sort_by(|a, b| {
        let (ca, cb) = (centroid(a), centroid(b));
        (cb[1], ca[0]).partial_cmp(&(ca[1], cb[0])).expect("finite")
    });
    triangles
}

/// Neighbour lists from triangles.
fn neighbours(n: usize, triangles: &[[u32; 3]]) -> Vec<Vec<usize>> {
    let mut nb = vec![Vec::new(); n];
    for t in triangles {
        for k in 0..3 {
            let (a, b) = (t[k] as usize, t[(k + 1) % 3] as usize);
            if !nb[a].contains(&b) {
                nb[a].push(b);
                nb[b].push(a);
            }
        }
    }
    nb
}

fn build_face_mask() -> FaceMask {
    let (boundary, loops) = boundary_loops();
    let polygons = loops
        .iter()
        .map(|l| l.iter().map(|&i| boundary[i]).collect())
        .collect();
    let domain = Domain {
        boundary: boundary.clone(),
        polygons,
    };
    let interior_target = VERTEX_COUNT - boundary.len();
    // A fixed stream of candidate points; the radius scale is bisected so that
    // dart throwing keeps at least the target count, and extras are dropped.
    let mut rng = ChaCha8Rng::seed_from_u64(0x4d41534b); // "MASK"
    let candidates: Vec<[f64; 2]> = (0..40_000)
        .map(|_| {
            [
                rng.random_range(-0.075..0.075),
                rng.random_range(-0.102..0.082),
            ]
        })
        .filter(|p| domain.contains(*p))
        .collect();
    let clearance = domain.boundary_clearance(&candidates);
    let (mut lo, mut hi) = (0.5, 2.0);
    let mut best = domain.scatter(&candidates, &clearance, lo);
    for _ in 0..40 {
        let mid = 0.5 * (lo + hi);
        let pts = domain.scatter(&candidates, &clearance, mid);
        if pts.len() >= interior_target {
            lo = mid;
            best = pts;
        } else {
            hi = mid;
        }
    }
    best.truncate(interior_target);
    let mut points = boundary.clone();
    points.extend(best);
    // Damped umbrella smoothing of the interior, re-triangulating each time.
    for _ in 0..6 {
        let triangles = triangulate(&points, &loops, &domain);
        let nb = neighbours(points.len(), &triangles);
        let moved: Vec<[f64; 2]> = (0..points.len())
            .map(|i| {
                if i < boundary.len() || nb[i].is_empty() {
                    return points[i];
                }
                let m = [0, 1]
                    .map(|d| nb[i].iter().map(|&j| points[j][d]).sum::<f64>() / nb[i].len() as f64);
                let p = [0, 1].map(|d| 0.5 * points[i][d] + 0.5 * m[d]);
                if domain.contains(p) { p } else { points[i] }
            })
            .collect();
        points = moved;
    }
    // Interior vertices in reading order (top to bottom, right to left as seen).
    let mut interior: Vec<[f64; 2]> = points.split_off(boundary.len());
    interior.sort_by(|a, b| (b[1], a[0]).partial_cmp(&(a[1], b[0])).expect("finite"));
    points.extend(interior);
    let triangles = triangulate(&points, &loops, &domain);
    let topology = Topology::new(points.len(), triangles).expect("mask triangulation is valid");
    let neutral = points.iter().map(|p| lift(*p)).collect::<Vec<_>>();
    let landmarks = landmarks(&loops, &neutral);
    FaceMask {
        topology,
        uv: points,
        neutral,
        landmarks,
    }
}

/// Height of the face surface above the parameter plane (m): a curved base
/// with nose, brow ridge, eye sockets, cheekbones, lips and chin. Nose
/// projection about 2.5 cm and face depth to the rim about 3.5 cm follow
/// adult anthropometric norms (Farkas 1994).
fn height(u: f64, v: f64) -> f64 {
    let ax = u.abs();
    let base = 0.035 - u * u / (2.0 * 0.075) - (v + 0.01).powi(2) / (2.0 * 0.12);
    let nose_profile = if v > -0.012 {
        gauss((v + 0.012) / 0.03)
    } else {
        gauss((v + 0.012) / 0.008)
    };
    let nose = 0.026 * gauss(u / 0.0085) * nose_profile;
    let alae = 0.007 * gauss((ax - 0.012) / 0.006) * gauss((v + 0.018) / 0.006);
    let sockets = -0.007 * gauss(dist([ax, v], EYE_CENTRE) / 0.017);
    let brows = 0.004 * gauss((v - 0.046) / 0.008) * gauss((ax - 0.03) / 0.025);
    let cheeks = 0.008 * gauss((ax - 0.043) / 0.018) * gauss((v + 0.008) / 0.02);
    let lips = 0.007 * (-(u / 0.024).powi(4)).exp() * gauss((v - MOUTH_CENTRE[1]) / 0.009);
    let chin = 0.010 * gauss(u / 0.02) * gauss((v + 0.085) / 0.015);
    base + nose + alae + sockets + brows + cheeks + lips + chin
}

/// Lifts a parameter-plane point onto the face and closes the mouth opening.
fn lift(p: [f64; 2]) -> Vec3 {
    let [u, v] = p;
    let row = lip_row_offset(u);
    let s = u / MOUTH_HALF_WIDTH;
    let closure = if s.abs() < 1.0 {
        (MOUTH_PARAM_HALF_GAP - 0.5 * LIP_GAP) * (1.0 - s * s)
    } else {
        0.0
    };
    let dv = v - MOUTH_CENTRE[1];
    let falloff = |d: f64| {
        let t = (d / 0.012).clamp(0.0, 1.0);
        (1.0 - t * t).powi(3)
    };
    let y = if dv >= 0.0 {
        v - closure * falloff(dv - row)
    } else {
        v + closure * falloff(-dv - row)
    };
    Vec3::new(u as f32, y as f32, height(u, y) as f32)
}

fn landmarks(loops: &[Vec<usize>], neutral: &[Vec3]) -> Landmarks {
    let eye = |l: &Vec<usize>| {
        let upper: Vec<u32> = l[1..=LID_VERTICES].iter().map(|&i| i as u32).collect();
        let mut lower: Vec<u32> = l[LID_VERTICES + 2..].iter().map(|&i| i as u32).collect();
        lower.reverse();
        (l[0] as u32, l[LID_VERTICES + 1] as u32, upper, lower)
    };
    let (li, lo, lu, ll) = eye(&loops[0]);
    let (ri, ro, ru, rl) = eye(&loops[1]);
    let m = &loops[2];
    let upper_lip: Vec<u32> = m[1..=LIP_VERTICES].iter().map(|&i| i as u32).collect();
    let mut lower_lip: Vec<u32> = m[LIP_VERTICES + 2..].iter().map(|&i| i as u32).collect();
    lower_lip.reverse();
    let outline: Vec<u32> = loops[3].iter().map(|&i| i as u32).collect();
    let nose_tip = (0..neutral.len())
        .max_by(|&a, &b| neutral[a].z.total_cmp(&neutral[b].z))
        .expect("mask has vertices") as u32;
    let chin = *outline
        .iter()
        .min_by(|&&a, &&b| neutral[a as usize].y.total_cmp(&neutral[b as usize].y))
        .expect("outline has vertices");
    Landmarks {
        eye_inner: [li, ri],
        eye_outer: [lo, ro],
        upper_lid: [lu, ru],
        lower_lid: [ll, rl],
        lip_corners: [m[LIP_VERTICES + 1] as u32, m[0] as u32],
        upper_lip,
        lower_lip,
        nose_tip,
        chin,
        outline,
    }
}
