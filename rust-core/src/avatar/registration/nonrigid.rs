//! Non-rigid registration of the mask onto the avatar's face surface:
//! optimal-step non-rigid ICP (Amberg, Romdhani & Vetter 2007, "Optimal
//! step nonrigid ICP algorithms for surface registration", CVPR), with the
//! blendshape features as landmarks. It stands in for the paper's
//! non-rigid registration \[1\] (Achenbach et al. 2017).
//!
//! Every mask vertex `i` carries an affine map `X_i` (a 4 × 3 matrix);
//! with `v_i = [x_i, y_i, z_i, 1]` its position after ICP, the registered
//! vertex is `v_i X_i`. Each step minimizes, for a stiffness α,
//!
//! ```text
//! E(X) = α Σ_{(i,j) ∈ edges} ‖G (X_i − X_j)‖²_F        (stiffness)
//!      + Σ_i w_i ‖v_i X_i − c_i‖²                      (closest points)
//!      + β Σ_l ‖Σ_i a_li v_i X_i − f_l‖²               (landmarks)
//! ```
//!
//! with `G = diag(1, 1, 1, γ)`, `c_i` the closest compatible avatar point
//! of the current vertex (on a triangle whose normal is within
//! [`MIN_NORMAL_DOT`] in cosine of the mask's vertex normal, within
//! [`SEARCH_RADIUS`]: a lid does not latch onto the eyeball behind it nor
//! a lip onto the teeth or the mouth's lining), `w_i ∈ {0, 1}` the pairs
//! kept (within [`TRIM`] medians, or within [`TRIM_FLOOR`] whatever the
//! median), and landmark `l` the mask's feature `Σ_i a_li x_i` (motion
//! weighted, [`super::features`]) held at the avatar's feature `f_l`. The
//! landmark term couples its vertices densely; each step replaces it by
//! per-vertex pulls towards the feature's remaining offset
//! (`landmark_pulls`), so the system's pattern is the mask's edges plus
//! one 4 × 4 block per vertex, the same in every step: it is analysed
//! once (where each entry goes, and the symbolic factorization), and each
//! step only sums its values into place and runs one sparse numeric
//! `4n × 4n` Cholesky. The closest-point searches of a step are
//! independent and run over the cores.
//!
//! Coordinates are normalized by the placed mask's centre and RMS radius
//! first, so α, β and γ are unit-free and mean the same on a centimetre
//! and a metre avatar. Following Amberg et al., for each stiffness the
//! closest points are updated until the mask stops moving (RMS motion
//! below [`CONVERGED`], at most [`MAX_STEPS_PER_STAGE`] updates); then α
//! is lowered ([`STIFFNESS_FACTOR`]) down to [`MIN_STIFFNESS`]. Every
//! stage runs, even on a mask that already lies on the surface: the
//! landmarks, which two rigs never place quite alike, must fade before
//! the fit ends (a stage whose mask does not move costs one step). The
//! landmarks weigh in proportion to α² (β = [`LANDMARK_WEIGHT`] · α² /
//! [`INITIAL_STIFFNESS`]): they bring eyes to eyes and mouth to mouth
//! while the mask is stiff and have faded when the fit gets fine.

use crate::geometry::closest_point::TriangleTree;
use crate::geometry::sparse_cholesky::{FactorWork, FixedPattern};
use crate::personalize::blendshape_fit::in_parallel_map;
use faer::Mat;
use faer::sparse::Triplet;
use glam::DVec3;

/// α of the first, stiffest stage.
pub const INITIAL_STIFFNESS: f64 = 50.0;

/// Each stage's α is this share of the previous one's.
pub const STIFFNESS_FACTOR: f64 = 0.4;

/// The suplest stage's α: below it the mask would follow the avatar's
/// triangles rather than its surface.
pub const MIN_STIFFNESS: f64 = 0.05;

/// γ: weight of the translation column against the linear part in the
/// stiffness term (normalized coordinates, so 1 as in Amberg et al.).
pub const GAMMA: f64 = 1.0;

/// β / α at the first stage: the landmarks' weight relative to the
/// stiffness, which falls with α (β = [`LANDMARK_WEIGHT`] · α² /
/// [`INITIAL_STIFFNESS`]), so the landmarks have faded by the suple
/// stages and leave the fine fit to the surface.
pub const LANDMARK_WEIGHT: f64 = 0.1;

/// Pairs farther than this many median distances are dropped.
pub const TRIM: f64 = 3.0;

/// The trimming limit never falls below this share of the mask's RMS
/// radius (about 2 mm on a human face): pairs closer than that are kept
/// whatever the median.
pub const TRIM_FLOOR: f64 = 0.1;

/// Compatible points are sought within this share of the mask's RMS
/// radius (as in [`super::rigid_icp::SEARCH_RADIUS`]).
pub const SEARCH_RADIUS: f64 = super::rigid_icp::SEARCH_RADIUS;

/// Smallest cosine between the mask's and the avatar's normals for a pair
/// to be kept (60°).
pub const MIN_NORMAL_DOT: f64 = 0.5;

/// A stage ends when the mask's vertices moved less than this share of
/// its RMS radius in a step (RMS over the vertices; about 0.1 mm on a
/// human face, below what the next, suppler stage changes).
pub const CONVERGED: f64 = 2e-3;

/// Most closest-point updates in one stage: the next stage goes on from
/// where this one stopped, so a stage need not converge fully (it bounds
/// the time on an avatar whose surface keeps the mask sliding).
pub const MAX_STEPS_PER_STAGE: usize = 4;

/// One landmark: a combination of mask vertices (index, weight; weights
/// summing to one) and the avatar point it is held at.
#[derive(Clone, Debug, PartialEq)]
pub struct Landmark {
    /// The mask's feature as a combination of its vertices.
    pub mask: Vec<(usize, f64)>,
    /// The avatar's feature (avatar units).
    pub target: DVec3,
    /// Disagreements up to this distance (avatar units) are not pulled
    /// on: two rigs never place a feature quite alike (their vertices
    /// sample the motion differently), and a landmark that insists on the
    /// last fraction of a millimetre would slide a mask that already lies
    /// right.
    pub slack: f64,
    /// Held at the first stage's weight through every stage instead of
    /// fading with the stiffness: for a feature that every rig places
    /// alike (module docs).
    pub held: bool,
}

/// The registered mask and how well it fits.
#[derive(Clone, Debug, PartialEq)]
pub struct NonRigidResult {
    /// The mask's vertices on the avatar (avatar units).
    pub positions: Vec<DVec3>,
    /// Each vertex's distance to the avatar surface at the end.
    pub distances: Vec<f64>,
    /// Whether each vertex's pair was kept at the end (close, facing the
    /// same way): the region both surfaces cover.
    pub kept: Vec<bool>,
    /// Stages (stiffnesses) run.
    pub stages: usize,
    /// Closest-point updates run in all.
    pub steps: usize,
    /// The last stage's α.
    pub final_stiffness: f64,
}

/// Deforms `start` (the mask placed by ICP; `triangles` its topology) onto
/// the surface in `target` (module docs). `None` if a system cannot be
/// factored.
pub fn register_nonrigid(
    start: &[DVec3],
    triangles: &[[u32; 3]],
    target: &TriangleTree,
    landmarks: &[Landmark],
) -> Option<NonRigidResult> {
    let n = start.len();
    if n == 0 {
        return None;
    }
    let system = StepSystem::new(n, unique_edges(triangles, n))?;
    // The factor's storage, reused by every step.
    let mut work = system.pattern.work(3);
    let centre = start.iter().sum::<DVec3>() / n as f64;
    let radius = (start
        .iter()
        .map(|p| (*p - centre).length_squared())
        .sum::<f64>()
        / n as f64)
        .sqrt()
        .max(f64::MIN_POSITIVE);
    let to_local = |p: DVec3| (p - centre) / radius;
    let local: Vec<DVec3> = start.iter().map(|p| to_local(*p)).collect();
    let landmarks: Vec<Landmark> = landmarks
        .iter()
        .filter(|l| l.mask.iter().all(|(i, _)| *i < n) && l.target.is_finite())
        .map(|l| Landmark {
            mask: l.mask.clone(),
            target: to_local(l.target),
            slack: l.slack / radius,
            held: l.held,
        })
        .collect();
    let mut x = local.clone();
    let mut alpha = INITIAL_STIFFNESS;
    let (mut stages, mut steps) = (0, 0);
    let mut pairs = closest_pairs(&x, triangles, target, centre, radius);
    loop {
        stages += 1;
        for _ in 0..MAX_STEPS_PER_STAGE {
            steps += 1;
            let next = solve_step((&system, &mut work), &local, &x, &pairs, &landmarks, alpha)?;
            // RMS motion (Amberg et al.'s ‖X − X_old‖): a few vertices
            // trading one compatible point for another must not keep a
            // converged mask stepping.
            let motion = (next
                .iter()
                .zip(&x)
                .map(|(a, b)| (*a - *b).length_squared())
                .sum::<f64>()
                / n as f64)
                .sqrt();
            x = next;
            pairs = closest_pairs(&x, triangles, target, centre, radius);
            if motion < CONVERGED {
                break;
            }
        }
        if alpha * STIFFNESS_FACTOR < MIN_STIFFNESS {
            break;
        }
        alpha *= STIFFNESS_FACTOR;
    }
    Some(NonRigidResult {
        positions: x.iter().map(|p| centre + *p * radius).collect(),
        distances: pairs.iter().map(|p| p.distance * radius).collect(),
        kept: pairs.iter().map(|p| p.weight > 0.0).collect(),
        stages,
        steps,
        final_stiffness: alpha,
    })
}

/// A mask vertex's closest avatar point (normalized coordinates), its
/// distance and whether the pair is kept.
#[derive(Clone, Copy, Debug)]
struct Pair {
    point: DVec3,
    distance: f64,
    weight: f64,
}

/// The closest avatar point of every current vertex `x` (normalized by
/// `centre` and `radius`), trimmed by distance and normals (module docs).
fn closest_pairs(
    x: &[DVec3],
    triangles: &[[u32; 3]],
    target: &TriangleTree,
    centre: DVec3,
    radius: f64,
) -> Vec<Pair> {
    let normals = vertex_normals(x, triangles);
    let pair = |i: usize| {
        let (p, normal) = (x[i], normals[i]);
        let reach = SEARCH_RADIUS * radius;
        match target.closest_facing(centre + p * radius, normal, MIN_NORMAL_DOT, reach) {
            Some(c) => Pair {
                point: (c.point - centre) / radius,
                distance: c.distance / radius,
                weight: 1.0,
            },
            None => Pair {
                point: p,
                distance: f64::INFINITY,
                weight: 0.0,
            },
        }
    };
    // The searches are independent: over the cores.
    let mut pairs: Vec<Pair> = in_parallel_map(x.len(), pair);
    let mut kept: Vec<f64> = pairs
        .iter()
        .filter(|p| p.weight > 0.0 && p.distance.is_finite())
        .map(|p| p.distance)
        .collect();
    kept.sort_by(f64::total_cmp);
    let median = kept.get(kept.len() / 2).copied().unwrap_or(0.0);
    // The limit follows the median down while the mask is far, but never
    // below a fixed share of the face's size: a fit that improves must
    // not drop the pairs it has not reached yet.
    let limit = (TRIM * median).max(TRIM_FLOOR);
    for p in &mut pairs {
        if !(p.distance.is_finite() && p.distance <= limit) {
            p.weight = 0.0;
        }
    }
    pairs
}

/// Area-weighted vertex normals of `x` with `triangles`.
pub fn vertex_normals(x: &[DVec3], triangles: &[[u32; 3]]) -> Vec<DVec3> {
    let mut normals = vec![DVec3::ZERO; x.len()];
    for t in triangles {
        let [a, b, c] = t.map(|i| i as usize);
        if a >= x.len() || b >= x.len() || c >= x.len() {
            continue;
        }
        let n = (x[b] - x[a]).cross(x[c] - x[a]);
        for v in [a, b, c] {
            normals[v] += n;
        }
    }
    normals.iter().map(|n| n.normalize_or_zero()).collect()
}

/// Each undirected edge of `triangles` once, `(i, j)` with `i < j < n`.
fn unique_edges(triangles: &[[u32; 3]], n: usize) -> Vec<(usize, usize)> {
    let mut edges: Vec<(usize, usize)> = triangles
        .iter()
        .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
        .map(|(a, b)| (a.min(b) as usize, a.max(b) as usize))
        .filter(|(a, b)| a != b && *b < n)
        .collect();
    edges.sort_unstable();
    edges.dedup();
    edges
}

/// `[x, y, z, 1]`.
fn homogeneous(p: DVec3) -> [f64; 4] {
    [p.x, p.y, p.z, 1.0]
}

/// The per-step system's fixed sparsity (stiffness edges and every
/// vertex's diagonal block), analysed once: only the values change from
/// step to step.
struct StepSystem {
    pattern: FixedPattern,
    edges: Vec<(usize, usize)>,
}

impl StepSystem {
    fn new(n: usize, edges: Vec<(usize, usize)>) -> Option<StepSystem> {
        let entries = step_entries(n, &edges, 1.0, &vec![[0.0; 10]; n]);
        let pattern = FixedPattern::new(4 * n, &entries).ok()?;
        Some(StepSystem { pattern, edges })
    }
}

/// The lower triangle of the step's matrix: α G² per edge (stiffness)
/// and, per vertex, the 10 lower entries of its 4 × 4 diagonal block
/// (`blocks`, the data terms), always all present so the pattern never
/// changes.
fn step_entries(
    n: usize,
    edges: &[(usize, usize)],
    alpha: f64,
    blocks: &[[f64; 10]],
) -> Vec<Triplet<usize, usize, f64>> {
    let g2 = [1.0, 1.0, 1.0, GAMMA * GAMMA];
    let mut entries = Vec::with_capacity(10 * n + 12 * edges.len());
    // Stiffness: α ‖G (X_i − X_j)‖² adds α G² to blocks (i,i), (j,j) and
    // −α G² to (i,j), (j,i).
    for &(i, j) in edges {
        for (k, g) in g2.iter().enumerate() {
            entries.push(Triplet::new(4 * i + k, 4 * i + k, alpha * g));
            entries.push(Triplet::new(4 * j + k, 4 * j + k, alpha * g));
            entries.push(Triplet::new(4 * j + k, 4 * i + k, -alpha * g));
        }
    }
    for (i, block) in blocks.iter().enumerate() {
        let mut e = 0;
        for r in 0..4 {
            for c in 0..=r {
                entries.push(Triplet::new(4 * i + r, 4 * i + c, block[e]));
                e += 1;
            }
        }
    }
    entries
}

/// Where each landmark vertex is pulled this step: the landmark's term
/// `β ‖Σ_i a_i v_i X_i − f‖²` couples all its vertices densely, so it is
/// replaced by `Σ_i β a_i ‖v_i X_i − (x_i + f − F)‖²`, with `x_i` the
/// vertex's current position and `F = Σ_i a_i x_i` the feature's: every
/// vertex is asked to move by the feature's remaining offset. The two
/// agree when the feature's vertices move together, and repeated steps
/// bring `F` to `f` the same way. The offset is shortened by the
/// landmark's slack (zero within it). Returns (vertex, weight share,
/// target, held).
fn landmark_pulls(landmarks: &[Landmark], x: &[DVec3]) -> Vec<(usize, f64, DVec3, bool)> {
    let mut pulls = Vec::new();
    for l in landmarks {
        let feature: DVec3 = l.mask.iter().map(|&(i, a)| x[i] * a).sum();
        let gap = l.target - feature;
        let beyond = gap.length() - l.slack;
        if l.held && beyond <= 0.0 {
            // Within its slack a held landmark takes no part: held where
            // it is through the supple stages, it would pin the lids while
            // the rest of the mask settles.
            continue;
        }
        let offset = gap * (beyond.max(0.0) / gap.length().max(f64::MIN_POSITIVE));
        pulls.extend(l.mask.iter().map(|&(i, a)| (i, a, x[i] + offset, l.held)));
    }
    pulls
}

/// One step: the affine maps minimizing `E` (module docs, landmarks as
/// in [`landmark_pulls`]) for the pairs `pairs` and stiffness `alpha`,
/// applied to the start `local`; `x` is the current mask. The system is
/// factored in `work`, kept from step to step.
fn solve_step(
    (system, work): (&StepSystem, &mut FactorWork),
    local: &[DVec3],
    x: &[DVec3],
    pairs: &[Pair],
    landmarks: &[Landmark],
    alpha: f64,
) -> Option<Vec<DVec3>> {
    let n = local.len();
    let mut blocks = vec![[0.0; 10]; n];
    let mut rhs = Mat::<f64>::zeros(4 * n, 3);
    // A tiny pull of every map towards the identity keeps the system
    // definite where nothing else holds it (a vertex without edges or
    // pairs, or the direction normal to a flat mask, which `v_i` spans
    // nowhere).
    let identity_weight = 1e-8 * alpha;
    for (i, block) in blocks.iter_mut().enumerate() {
        for k in 0..4 {
            block[k * (k + 1) / 2 + k] += identity_weight;
        }
        for k in 0..3 {
            rhs[(4 * i + k, k)] += identity_weight;
        }
    }
    let mut pull = |i: usize, weight: f64, target: DVec3, rhs: &mut Mat<f64>| {
        let v = homogeneous(local[i]);
        let mut e = 0;
        for r in 0..4 {
            for c in 0..=r {
                blocks[i][e] += weight * v[r] * v[c];
                e += 1;
            }
            for axis in 0..3 {
                rhs[(4 * i + r, axis)] += weight * v[r] * target[axis];
            }
        }
    };
    // Closest points: w ‖v_i X_i − c_i‖².
    for (i, pair) in pairs.iter().enumerate() {
        if pair.weight > 0.0 {
            pull(i, pair.weight, pair.point, &mut rhs);
        }
    }
    let fading = LANDMARK_WEIGHT * alpha * (alpha / INITIAL_STIFFNESS);
    let held = LANDMARK_WEIGHT * INITIAL_STIFFNESS;
    for (i, share, target, is_held) in landmark_pulls(landmarks, x) {
        let beta = if is_held { held } else { fading };
        pull(i, beta * share, target, &mut rhs);
    }
    let values: Vec<f64> = step_entries(n, &system.edges, alpha, &blocks)
        .iter()
        .map(|t| t.val)
        .collect();
    let mut llt = system.pattern.factor(&values, work).ok()?;
    llt.solve_in_place(rhs.as_mut());
    let out: Vec<DVec3> = local
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let v = homogeneous(*p);
            let mut q = DVec3::ZERO;
            for (r, vr) in v.iter().enumerate() {
                q += DVec3::new(
                    rhs[(4 * i + r, 0)],
                    rhs[(4 * i + r, 1)],
                    rhs[(4 * i + r, 2)],
                ) * *vr;
            }
            q
        })
        .collect();
    out.iter().all(|p| p.is_finite()).then_some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat grid, `k × k` vertices spaced `h`, at height `z`.
    fn grid(k: usize, h: f64, z: f64) -> (Vec<DVec3>, Vec<[u32; 3]>) {
        let mut p = Vec::new();
        for j in 0..k {
            for i in 0..k {
                p.push(DVec3::new(i as f64 * h, j as f64 * h, z));
            }
        }
        let mut t = Vec::new();
        for j in 0..k - 1 {
            for i in 0..k - 1 {
                let a = (j * k + i) as u32;
                let b = a + 1;
                let c = a + k as u32;
                t.push([a, b, c + 1]);
                t.push([a, c + 1, c]);
            }
        }
        (p, t)
    }

    #[test]
    fn a_flat_mask_lies_down_on_a_bump() {
        let (mask, triangles) = grid(15, 0.1, 0.0);
        // The target: the same grid, finer, with a smooth bump.
        let (mut surface, surface_triangles) = grid(43, 0.05, 0.0);
        for p in &mut surface {
            let r2 = (p.x - 0.7).powi(2) + (p.y - 0.7).powi(2);
            p.z = 0.2 * (-r2 / 0.08).exp();
        }
        let target = TriangleTree::new(&surface, &surface_triangles);
        let result = register_nonrigid(&mask, &triangles, &target, &[]).expect("solves");
        let mean = result.distances.iter().sum::<f64>() / result.distances.len() as f64;
        assert!(mean < 2e-3, "mean distance {mean}");
        assert!(result.stages > 1, "{} stages", result.stages);
        // The centre vertex rose onto the bump.
        let centre = result.positions[7 * 15 + 7];
        assert!((centre.z - 0.2).abs() < 0.02, "{centre}");
    }
}
