//! ICP with scale (Zinßer, Schmidt & Niemann 2005, "Point set registration
//! with integrated scale estimation", PRIP; the paper's \[52\]): the ARKit
//! mask's vertices are moved by a similarity onto the avatar's surface.
//!
//! Each iteration pairs every transformed mask vertex `x_i` with its
//! closest compatible point `c_i` on the avatar (normal `n_i`, that of the
//! triangle it lies on, within [`MIN_NORMAL_DOT`] in cosine of the mask's
//! vertex normal turned by the current rotation; within [`SEARCH_RADIUS`]) and drops the pairs farther than [`TRIM`] times the median pair
//! distance (the mask's rim reaching past an avatar's hairline, or the eye
//! holes facing the eyeballs; pairs closer than [`KEEP_WITHIN`] of the
//! mask's radius are always kept, so a mask that already lies on the
//! surface is not trimmed at random). Compatible normals matter where the
//! mask starts a little inside the avatar: the plain closest point of a
//! vertex behind the lips is the mouth's lining, which faces the other
//! way and would pull the mask further in.
//!
//! The first [`POINT_TO_POINT_ITERATIONS`] iterations refit the similarity
//! from the original mask to the kept closest points
//! ([`fit_similarity`], robust from far away). Point-to-point ICP then
//! converges only linearly while the mask slides along the surface, so the
//! following iterations minimize the point-to-plane distance instead
//! (Chen & Medioni 1992), linearized in a small similarity update about the
//! kept points' centroid `x̄` (with `y_i = x_i − x̄`):
//!
//! ```text
//! min_{ω, τ, σ} Σ_i ( n_i·(x_i − c_i) + ω·(y_i × n_i) + n_i·τ + σ n_i·y_i )²,
//! x ↦ x̄ + τ + (1 + σ) R(ω) (x − x̄),
//! ```
//!
//! `R(ω)` the rotation by angle `‖ω‖` about `ω` (Rodrigues). It stops when
//! a point-to-plane iteration moves the mask's vertices by less than
//! [`TOLERANCE`] of the mask's size (RMS), or after [`MAX_ITERATIONS`]
//! (on a face of other proportions the compatible pairs keep changing a
//! little and ICP would creep on; the non-rigid step takes over from
//! there).

use super::similarity::{Similarity, fit_similarity};
use crate::geometry::closest_point::TriangleTree;
use crate::personalize::blendshape_fit::in_parallel_map;
use faer::Mat;
use faer::linalg::solvers::Solve;
use glam::{DMat3, DVec3};

/// Pairs farther than this many median distances are dropped.
pub const TRIM: f64 = 2.5;

/// Smallest cosine between the mask's and the avatar's normals for a pair
/// to be kept (60°, as in the non-rigid step).
pub const MIN_NORMAL_DOT: f64 = 0.5;

/// Compatible points are sought within this share of the mask's RMS
/// radius (about 1.5 cm on a human face); a vertex with none that near
/// takes no part in the iteration.
pub const SEARCH_RADIUS: f64 = 0.25;

/// Pairs closer than this share of the mask's RMS radius are always kept.
pub const KEEP_WITHIN: f64 = 1e-3;

/// Point-to-point iterations before the point-to-plane ones.
pub const POINT_TO_POINT_ITERATIONS: usize = 10;

/// RMS motion of the mask in one iteration, relative to the mask's RMS
/// radius, below which ICP stops (about 6 µm on a human face), judged on
/// the point-to-plane iterations only.
pub const TOLERANCE: f64 = 1e-4;

/// Most iterations.
pub const MAX_ITERATIONS: usize = 30;

/// The rigs' features weigh this share of the surface's kept pairs,
/// together. Closest points alone let the mask shrink onto a face larger
/// than the simulator's (on ICT-FaceKit they settled at a scale 23% below
/// the features' and put the mask's eyes 20 mm from the avatar's); the
/// features hold eyes to eyes and mouth to mouth, and the surface decides
/// what they do not.
pub const FEATURE_SHARE: f64 = 1.0;

/// What ICP reached.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IcpResult {
    /// The similarity from mask to avatar.
    pub similarity: Similarity,
    /// RMS distance of the kept pairs at the end (avatar units).
    pub rms: f64,
    /// Iterations run.
    pub iterations: usize,
}

/// One closest-point pair: the point, its triangle's normal, the distance.
type Pair = (DVec3, DVec3, f64);

/// Refines `initial` (mask → avatar) by ICP with scale against the
/// surface in `target` (module docs); `normals` are the mask's vertex
/// normals; `features` pairs of mask and avatar points (the rigs'
/// features) that weigh as much, together, as the surface's pairs
/// ([`FEATURE_SHARE`]) and pull only beyond `feature_slack` (mask units).
pub fn icp_with_scale(
    mask: &[DVec3],
    normals: &[DVec3],
    target: &TriangleTree,
    initial: Similarity,
    features: &[(DVec3, DVec3)],
    feature_slack: f64,
) -> IcpResult {
    let n = mask.len().max(1) as f64;
    let centre = mask.iter().sum::<DVec3>() / n;
    let radius = (mask
        .iter()
        .map(|p| (*p - centre).length_squared())
        .sum::<f64>()
        / n)
        .sqrt();
    let mut current = initial;
    let mut result = IcpResult {
        similarity: current,
        rms: f64::INFINITY,
        iterations: 0,
    };
    for iteration in 1..=MAX_ITERATIONS {
        let moved: Vec<DVec3> = mask.iter().map(|p| current.apply(*p)).collect();
        let reach = SEARCH_RADIUS * radius * current.scale;
        let pair = |i: usize| {
            let x = moved[i];
            target
                .closest_facing(x, current.rotation * normals[i], MIN_NORMAL_DOT, reach)
                .map_or((x, DVec3::ZERO, f64::INFINITY), |c| {
                    (c.point, target.triangle_normal(c.triangle), c.distance)
                })
        };
        // The searches are independent: over the cores.
        let pairs: Vec<Pair> = in_parallel_map(moved.len().min(normals.len()), pair);
        let floor = KEEP_WITHIN * radius * current.scale;
        let distances: Vec<f64> = pairs.iter().map(|p| p.2).collect();
        let weights = trimmed_weights(&distances, floor);
        let kept: f64 = weights.iter().sum();
        let rms = (pairs
            .iter()
            .zip(&weights)
            .filter(|(_, w)| **w > 0.0)
            .map(|(p, w)| w * p.2 * p.2)
            .sum::<f64>()
            / kept.max(1.0))
        .sqrt();
        result = IcpResult {
            similarity: current,
            rms,
            iterations: iteration,
        };
        // Each feature pulls towards its avatar point only by what is
        // left beyond the slack.
        let feature_weight = FEATURE_SHARE * kept / features.len().max(1) as f64;
        // (A feature within its slack takes no part: held where it is, it
        // would only brake the surface's fit.)
        let feature_targets: Vec<(DVec3, DVec3, f64)> = features
            .iter()
            .map(|(p, q)| {
                let x = current.apply(*p);
                let gap = x - *q;
                let beyond = gap.length() - feature_slack * current.scale;
                match beyond > 0.0 {
                    true => (x, x - gap * (beyond / gap.length()), feature_weight),
                    false => (x, x, 0.0),
                }
            })
            .collect();
        let next = if iteration <= POINT_TO_POINT_ITERATIONS {
            let (mut from, mut to, mut w) = (mask.to_vec(), Vec::new(), weights.clone());
            to.extend(pairs.iter().map(|p| p.0));
            from.extend(features.iter().map(|f| f.0));
            to.extend(feature_targets.iter().map(|f| f.1));
            w.extend(feature_targets.iter().map(|f| f.2));
            fit_similarity(&from, &to, &w)
        } else {
            // A feature pulls along all three axes: three planes through
            // its target.
            let (mut moved, mut pairs, mut w) = (moved.clone(), pairs, weights.clone());
            for (x, target, weight) in &feature_targets {
                for axis in [DVec3::X, DVec3::Y, DVec3::Z] {
                    moved.push(*x);
                    pairs.push((*target, axis, 0.0));
                    w.push(*weight);
                }
            }
            point_to_plane_step(&moved, &pairs, &w).map(|step| step.after(&current))
        };
        let Some(next) = next else {
            break;
        };
        let motion = (mask
            .iter()
            .map(|p| (next.apply(*p) - current.apply(*p)).length_squared())
            .sum::<f64>()
            / n)
            .sqrt();
        current = next;
        result.similarity = current;
        // Point-to-point steps are short while the mask slides along the
        // surface: only a point-to-plane step's smallness means converged.
        if iteration > POINT_TO_POINT_ITERATIONS && motion <= TOLERANCE * radius * current.scale {
            break;
        }
    }
    result
}

/// The linearized point-to-plane similarity update (module docs) as a
/// similarity of the avatar's space; `None` if its system is singular.
fn point_to_plane_step(moved: &[DVec3], pairs: &[Pair], weights: &[f64]) -> Option<Similarity> {
    let kept: f64 = weights.iter().sum();
    if kept < 7.0 {
        return None;
    }
    let centroid = moved
        .iter()
        .zip(weights)
        .map(|(x, w)| *x * *w)
        .sum::<DVec3>()
        / kept;
    let mut a = Mat::<f64>::zeros(7, 7);
    let mut b = Mat::<f64>::zeros(7, 1);
    for ((x, (c, normal, _)), w) in moved.iter().zip(pairs).zip(weights) {
        if *w == 0.0 {
            continue;
        }
        let y = *x - centroid;
        let yn = y.cross(*normal);
        let j = [
            yn.x,
            yn.y,
            yn.z,
            normal.x,
            normal.y,
            normal.z,
            normal.dot(y),
        ];
        let r = normal.dot(*x - *c);
        for row in 0..7 {
            b[(row, 0)] -= w * j[row] * r;
            for col in 0..7 {
                a[(row, col)] += w * j[row] * j[col];
            }
        }
    }
    let x = a.partial_piv_lu().solve(&b);
    let u: Vec<f64> = (0..7).map(|i| x[(i, 0)]).collect();
    if u.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let omega = DVec3::new(u[0], u[1], u[2]);
    let tau = DVec3::new(u[3], u[4], u[5]);
    let scale = 1.0 + u[6];
    let rotation = if omega.length() > 0.0 {
        DMat3::from_axis_angle(omega.normalize(), omega.length())
    } else {
        DMat3::IDENTITY
    };
    (scale > 0.0).then(|| Similarity {
        scale,
        rotation,
        translation: centroid + tau - scale * (rotation * centroid),
    })
}

/// 1 for distances within [`TRIM`] medians or within `floor` (and
/// finite), else 0.
pub fn trimmed_weights(distances: &[f64], floor: f64) -> Vec<f64> {
    let mut sorted: Vec<f64> = distances
        .iter()
        .copied()
        .filter(|d| d.is_finite())
        .collect();
    if sorted.is_empty() {
        return vec![0.0; distances.len()];
    }
    sorted.sort_by(f64::total_cmp);
    let median = sorted[sorted.len() / 2];
    let limit = (TRIM * median).max(floor);
    distances
        .iter()
        .map(|d| {
            if d.is_finite() && *d <= limit {
                1.0
            } else {
                0.0
            }
        })
        .collect()
}
