//! Closed eyes stay closed on the avatar: where the person's lids meet in a
//! shape, the avatar's lids are made to meet too.
//!
//! The avatar's lid margins are the rims of its eye openings, which lie on
//! the mask's boundary; `M` leaves them out (a boundary point has no
//! surface around it to map), so steps 1 and 2 set them only by
//! continuation, and a blink that closes on the mask stays up to a
//! millimetre open on the avatar. This module finds the margins and the
//! shapes that close them; [`super::adjacent_step::AdjacentStep`] closes
//! them with the least bending of its correction.
//!
//! - **The openings.** The boundary loops of the avatar's face parts; an
//!   eye's opening is the loop whose centroid lies nearest the registered
//!   mask's eye hole (within the hole's width). Where the lids fold inwards
//!   from their edges (a margin with thickness runs from the edge to the
//!   loop), the lids' edges are the vertices nearest the mask's rim
//!   instead ([`FOLDED_LIDS`]), unless fewer than half as many as the rim
//!   has lie on it: then the rim does not follow this avatar's lids (ARKit's
//!   eye holes are wider than the default avatar's openings), and the loop
//!   is the lids' edge. It is split at its corners,
//!   the loop vertices farthest apart along the face's left–right axis (the
//!   registration's rotation of the mask's `x`), into an upper and a lower
//!   lid (the chain higher along the rotated `y`).
//! - **When an eye closes.** On the person's mask (its eye holes split
//!   into lids on the template's neutral, as the personalization split
//!   them), in shape `j`, with
//!   `O = max over upper-lid vertices of the distance to the lower lid's
//!   polyline`: the eye closes when `O_j ≤ f · O_0`, `f` =
//!   [`CONTACT_FRACTION`], the rule the mask's own transfer uses.
//! - **The contacts.** Each upper-lid vertex `u` strictly between the
//!   corners is paired with its closest point on the lower lid's polyline
//!   in the shape, `(1 − t) x_a + t x_b`, and the step imposes
//!   `x'_u = (1 − t) x'_a + t x'_b`.
//! - **Closing.** Each step's unknowns `z` (the face step's displacement,
//!   step 2's correction) minimize a quadratic energy with a factored
//!   matrix `K`; the contacts, rows `G` with present gaps `e`, are met by
//!   the change of least energy `ΔzᵀKΔz` ([`least_energy_closing`]).

use crate::arkit::{Blendshape, Blendshapes};
use crate::avatar::registration::FaceRegistration;
use crate::geometry::deformation_transfer::CONTACT_FRACTION;
use crate::geometry::mesh_boundary::{EyeHole, boundary_loops, eye_holes};
use crate::geometry::{Topology, closest_point::closest_on_segment};
use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::Llt;
use faer::{Mat, Side};
use glam::{DVec3, Vec3};

/// One eye opening of the avatar: its lids as avatar vertices, from corner
/// to corner, both corners in both.
#[derive(Clone, Debug, PartialEq)]
pub struct EyeOpening {
    /// Upper lid.
    pub upper: Vec<u32>,
    /// Lower lid, from the same corner as `upper`.
    pub lower: Vec<u32>,
    /// How far open the eye is at rest ([`opening`]): no lid vertex is
    /// paired farther than this.
    pub rest_opening: f64,
}

/// One contact: avatar vertex `vertex` is put on the segment `a`–`b` at
/// `t` (`0` at `a`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LidContact {
    /// The upper-lid vertex.
    pub vertex: u32,
    /// The lower lid's segment.
    pub a: u32,
    /// See `a`.
    pub b: u32,
    /// Where on it.
    pub t: f64,
}

/// The avatar's eye openings matching the mask's two eye holes (module
/// docs): `positions` the avatar at rest, `triangles` its face parts',
/// `mask_on_avatar` the registered mask, `holes` the mask's eye holes,
/// `right` and `up` the face's axes in avatar space: each found opening
/// with the index of its hole. An eye whose opening cannot be found is
/// left out.
pub fn eye_openings(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    mask_on_avatar: &[DVec3],
    holes: &[EyeHole],
    right: DVec3,
    up: DVec3,
) -> Vec<(usize, EyeOpening)> {
    let Ok(topology) = Topology::new(positions.len(), triangles.to_vec()) else {
        return Vec::new();
    };
    let Ok(loops) = boundary_loops(&topology) else {
        return Vec::new();
    };
    let centroid = |vs: &mut dyn Iterator<Item = DVec3>| {
        let (sum, n) = vs.fold((DVec3::ZERO, 0usize), |(s, n), p| (s + p, n + 1));
        sum / n.max(1) as f64
    };
    holes
        .iter()
        .enumerate()
        .filter_map(|(h, hole)| {
            let rim: Vec<DVec3> = hole
                .upper
                .iter()
                .chain(&hole.lower)
                .filter_map(|&v| mask_on_avatar.get(v as usize).copied())
                .collect();
            let centre = centroid(&mut rim.iter().copied());
            let width = rim
                .iter()
                .map(|p| (*p - centre).dot(right).abs())
                .fold(0.0, f64::max);
            let best = loops
                .iter()
                .map(|l| {
                    let c = centroid(&mut l.iter().map(|&v| positions[v as usize]));
                    ((c - centre).length(), l)
                })
                .min_by(|a, b| a.0.total_cmp(&b.0))?;
            if best.0 > width {
                return None;
            }
            let edge = lid_edge(
                best.1,
                positions,
                triangles,
                &rim_loop(hole, mask_on_avatar),
                width,
            );
            let opening = split_opening(&edge, positions, right, up)?;
            Some((h, opening))
        })
        .collect()
}

/// The registered mask's eye hole as a closed polyline on the avatar: the
/// upper lid from corner to corner, then the lower lid back.
fn rim_loop(hole: &EyeHole, mask_on_avatar: &[DVec3]) -> Vec<DVec3> {
    let lower = hole.lower.iter().rev();
    (hole.upper.iter().chain(lower))
        .filter_map(|&v| mask_on_avatar.get(v as usize).copied())
        .collect()
}

/// Share of the hole's half width beyond which an opening's loop is not on
/// the mask's rim: the lids fold inwards from their edges.
pub const FOLDED_LIDS: f64 = 0.1;

/// Share of the hole's half width within which a vertex is on the mask's
/// rim.
pub const ON_RIM: f64 = 0.01;

/// The lids' edges of an opening whose boundary loop is `lp`: the loop
/// itself where it lies on the mask's rim `rim` (mean distance at most
/// [`FOLDED_LIDS`] × `half_width`); else, where the lids fold inwards from
/// their edges to the loop (a margin with thickness), the face parts'
/// vertices within [`ON_RIM`] × `half_width` of the rim, in the rim's
/// order (of their closest points along it).
fn lid_edge(
    lp: &[u32],
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    rim: &[DVec3],
    half_width: f64,
) -> Vec<u32> {
    let n = rim.len();
    if n < 2 {
        return lp.to_vec();
    }
    // A point's distance to the rim and where its closest point lies along
    // it (arc length from the first rim point).
    let mut along = vec![0.0; n + 1];
    for k in 0..n {
        along[k + 1] = along[k] + rim[k].distance(rim[(k + 1) % n]);
    }
    let place = |p: DVec3| {
        (0..n)
            .map(|k| {
                let (c, t) = closest_on_segment(p, rim[k], rim[(k + 1) % n]);
                (c.distance(p), along[k] + t * (along[k + 1] - along[k]))
            })
            .fold((f64::INFINITY, 0.0), |a, b| if b.0 < a.0 { b } else { a })
    };
    let mean = lp
        .iter()
        .map(|&v| place(positions[v as usize]).0)
        .sum::<f64>()
        / lp.len().max(1) as f64;
    if mean <= FOLDED_LIDS * half_width {
        return lp.to_vec();
    }
    let mut used: Vec<u32> = triangles.iter().flatten().copied().collect();
    used.sort_unstable();
    used.dedup();
    let mut on_rim: Vec<(f64, u32)> = used
        .into_iter()
        .filter_map(|v| {
            let (d, s) = place(positions[v as usize]);
            (d <= ON_RIM * half_width).then_some((s, v))
        })
        .collect();
    // Too few vertices on the rim to draw the lids by: the rim does not
    // follow this avatar's lids (ARKit's eye holes are wider than the
    // default avatar's openings, and 4 of its vertices lay within reach),
    // and the opening's own loop is the best edge there is.
    if on_rim.len() < n / 2 {
        return lp.to_vec();
    }
    on_rim.sort_by(|a, b| a.0.total_cmp(&b.0));
    on_rim.into_iter().map(|(_, v)| v).collect()
}

/// Splits a loop at its corners (extremes along `right`) into an upper and
/// a lower lid, both from the corner at smaller `right`.
fn split_opening(lp: &[u32], positions: &[DVec3], right: DVec3, up: DVec3) -> Option<EyeOpening> {
    let n = lp.len();
    if n < 4 {
        return None;
    }
    let along = |i: usize| positions[lp[i] as usize].dot(right);
    let first = (0..n).min_by(|a, b| along(*a).total_cmp(&along(*b)))?;
    let last = (0..n).max_by(|a, b| along(*a).total_cmp(&along(*b)))?;
    let chain = |step: usize| -> Vec<u32> {
        let mut out = vec![lp[first]];
        let mut i = first;
        while i != last {
            i = (i + step) % n;
            out.push(lp[i]);
        }
        out
    };
    let (one, other) = (chain(1), chain(n - 1));
    let height = |c: &[u32]| {
        c.iter()
            .map(|&v| positions[v as usize].dot(up))
            .sum::<f64>()
            / c.len() as f64
    };
    let (upper, lower) = if height(&one) >= height(&other) {
        (one, other)
    } else {
        (other, one)
    };
    let rest_opening = opening(&upper, &lower, |v| positions[v as usize]);
    (upper.len() >= 3 && lower.len() >= 3).then_some(EyeOpening {
        upper,
        lower,
        rest_opening,
    })
}

/// The mask's eye holes (`triangles`), split at their corners on
/// `neutral`, or none if the mask has not the four boundary loops of a face
/// mask. Split on the template's neutral, the lids are those the
/// personalization closed the person's blinks by: a corner is the eye
/// loop's vertex of smallest or largest x, and at ARKit's outer corner
/// three vertices lie within a few hundredths of a millimetre of each
/// other's x, so a person's own neutral can pick another of them, whose
/// lid then seems to stay 17% open in a blink that closed.
pub fn mask_eye_holes(triangles: &[[u32; 3]], neutral: &[DVec3]) -> Vec<EyeHole> {
    let Ok(mask) = Topology::new(neutral.len(), triangles.to_vec()) else {
        return Vec::new();
    };
    let neutral: Vec<Vec3> = neutral.iter().map(|p| p.as_vec3()).collect();
    eye_holes(&mask, &neutral).map_or(Vec::new(), |h| h.to_vec())
}

/// How far open an eye is: the largest distance from an upper-lid vertex to
/// the lower lid's polyline (module docs, `O`); `at(v)` gives a vertex's
/// position.
pub fn opening(upper: &[u32], lower: &[u32], at: impl Fn(u32) -> DVec3) -> f64 {
    upper
        .iter()
        .map(|&u| {
            let p = at(u);
            lower
                .windows(2)
                .map(|w| (closest_on_segment(p, at(w[0]), at(w[1])).0 - p).length())
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max)
}

/// Whether the person's eye `hole` closes in a shape (module docs):
/// `rest` and `shape` the mask's positions.
pub fn closes(hole: &EyeHole, rest: &[DVec3], shape: &[DVec3]) -> bool {
    fn at(p: &[DVec3]) -> impl Fn(u32) -> DVec3 + '_ {
        move |v| p.get(v as usize).copied().unwrap_or(DVec3::ZERO)
    }
    let o0 = opening(&hole.upper, &hole.lower, at(rest));
    let oj = opening(&hole.upper, &hole.lower, at(shape));
    o0 > 0.0 && oj <= CONTACT_FRACTION * o0
}

/// The contacts that close `opening` in a shape whose positions `at(v)`
/// gives (module docs; `None` where a position is not known: such vertices
/// are left out): one per upper-lid vertex strictly between the corners
/// that comes within the eye's rest opening of the lower lid.
pub fn contacts(opening: &EyeOpening, at: impl Fn(u32) -> Option<DVec3>) -> Vec<LidContact> {
    let inner = &opening.upper[1..opening.upper.len().saturating_sub(1)];
    inner
        .iter()
        .filter_map(|&u| {
            let p = at(u)?;
            opening
                .lower
                .windows(2)
                .filter_map(|w| {
                    let (q, t) = closest_on_segment(p, at(w[0])?, at(w[1])?);
                    Some(((q - p).length(), w[0], w[1], t))
                })
                .min_by(|x, y| x.0.total_cmp(&y.0))
                .filter(|(gap, ..)| *gap <= opening.rest_opening)
                .map(|(_, a, b, t)| LidContact { vertex: u, a, b, t })
        })
        .collect()
}

/// Eigenvalues of `G Y` below this fraction of its largest are taken as
/// zero (contacts that repeat others).
pub const RANK_TOLERANCE: f64 = 1e-10;

/// Why a closed eye's lids could not be made to meet: the contacts'
/// small dense system `G Y` ([`least_energy_closing`]) had no
/// eigendecomposition (a NaN in the shapes reaches it).
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("the {contacts} lid contacts' system has no eigendecomposition")]
pub struct LidClosingError {
    /// Contacts in the system.
    pub contacts: usize,
}

/// The change `Δz` of least `ΔzᵀKΔz` that closes `contacts` (module docs):
/// with `G` the contacts' rows on the unknowns and `e` their present gaps,
///
/// ```text
/// Δz = −Y (G Y)⁻¹ e,   Y = K⁻¹ Gᵀ,
/// ```
///
/// one solve with the factored `K` (`llt`, `unknowns` × `unknowns`) per
/// contact and a small dense eigendecomposition (`(G Y)⁻¹` its
/// pseudo-inverse where contacts repeat one another). `index(v)` is avatar
/// vertex `v`'s unknown (`None`: fixed), `at(v)` its present position. A
/// contact of fixed vertices only, or with a position unknown, is left
/// out; with no contact left the change is empty.
pub fn least_energy_closing(
    llt: &Llt<usize, f64>,
    unknowns: usize,
    index: impl Fn(u32) -> Option<usize>,
    at: impl Fn(u32) -> Option<DVec3>,
    contacts: &[LidContact],
) -> Result<Vec<(usize, DVec3)>, LidClosingError> {
    let mut rows: Vec<Vec<(usize, f64)>> = Vec::new();
    let mut gaps: Vec<DVec3> = Vec::new();
    for c in contacts {
        let (Some(xu), Some(xa), Some(xb)) = (at(c.vertex), at(c.a), at(c.b)) else {
            continue;
        };
        let row: Vec<(usize, f64)> = [(c.vertex, 1.0), (c.a, -(1.0 - c.t)), (c.b, -c.t)]
            .into_iter()
            .filter(|(_, w)| *w != 0.0)
            .filter_map(|(v, w)| Some((index(v)?, w)))
            .collect();
        if row.is_empty() {
            continue;
        }
        rows.push(row);
        gaps.push(xu - xa * (1.0 - c.t) - xb * c.t);
    }
    let k = rows.len();
    if k == 0 {
        return Ok(Vec::new());
    }
    // Indexing: every row entry is an unknown below `unknowns`.
    let mut y = Mat::<f64>::zeros(unknowns, k);
    for (r, row) in rows.iter().enumerate() {
        for &(i, w) in row {
            y[(i, r)] += w;
        }
    }
    llt.solve_in_place(&mut y);
    let s = Mat::<f64>::from_fn(k, k, |r, c| {
        rows[r].iter().map(|&(i, w)| w * y[(i, c)]).sum()
    });
    // `G Y` is singular where contacts repeat one another (two fixed lid
    // vertices paired with one free segment): its pseudo-inverse, over the
    // eigenvalues above a relative `RANK_TOLERANCE`, meets what can be met
    // and moves nothing along the repeated directions.
    let eigen = s
        .self_adjoint_eigen(Side::Lower)
        .map_err(|_| LidClosingError { contacts: k })?;
    let (values, vectors) = (eigen.S(), eigen.U());
    let largest = (0..k).map(|i| values[i].abs()).fold(0.0, f64::max);
    let e = Mat::<f64>::from_fn(k, 3, |r, axis| gaps[r][axis]);
    let mut projected = vectors.transpose() * &e;
    for i in 0..k {
        let scale = if values[i] > RANK_TOLERANCE * largest {
            1.0 / values[i]
        } else {
            0.0
        };
        for axis in 0..3 {
            projected[(i, axis)] *= scale;
        }
    }
    let lambda = vectors * &projected;
    let change = &y * &lambda;
    Ok((0..unknowns)
        .map(|i| {
            (
                i,
                -DVec3::new(change[(i, 0)], change[(i, 1)], change[(i, 2)]),
            )
        })
        .filter(|(_, d)| *d != DVec3::ZERO)
        .collect())
}

/// Rounds of pairing and closing per shape: each round pairs the lid
/// vertices with the lower lid as the previous round left it (a pair can
/// slide along the lid as it closes).
pub const ROUNDS: usize = 3;

/// For each of the 52 shapes, the avatar's eye openings the person closes
/// in it (module docs).
pub struct ClosingEyes {
    per_shape: Vec<Vec<EyeOpening>>,
    /// The mask's eye holes (indices into [`mask_eye_holes`]) whose
    /// opening was found on the avatar.
    found: Vec<usize>,
}

impl ClosingEyes {
    /// Finds the openings of the avatar (`positions` at rest, its face
    /// parts' `triangles`) and which of the person's shapes
    /// (`personalized`) close the mask's eye `holes` ([`mask_eye_holes`]).
    /// Nothing closes on a mask without a face mask's eye holes or an
    /// avatar without matching openings.
    pub fn new(
        positions: &[DVec3],
        triangles: &[[u32; 3]],
        registration: &FaceRegistration,
        personalized: &Blendshapes,
        holes: &[EyeHole],
    ) -> ClosingEyes {
        let rest = personalized.neutral();
        let rotation = registration.similarity.rotation;
        let openings = eye_openings(
            positions,
            triangles,
            &registration.mask_on_avatar,
            holes,
            rotation * DVec3::X,
            rotation * DVec3::Y,
        );
        let per_shape = Blendshape::ALL
            .iter()
            .map(|&b| {
                let shape: Vec<DVec3> = rest
                    .iter()
                    .zip(personalized.delta(b))
                    .map(|(p, q)| *p + *q)
                    .collect();
                openings
                    .iter()
                    .filter(|(h, _)| closes(&holes[*h], rest, &shape))
                    .map(|(_, o)| o.clone())
                    .collect()
            })
            .collect();
        let found = openings.iter().map(|(h, _)| *h).collect();
        ClosingEyes { per_shape, found }
    }

    /// The mask's eye holes (indices into [`mask_eye_holes`]) whose opening
    /// was found on the avatar: their lids are closed by contacts.
    pub fn found(&self) -> &[usize] {
        &self.found
    }

    /// (Shape, eye) pairs that close.
    pub fn count(&self) -> usize {
        self.per_shape.iter().map(Vec::len).sum()
    }

    /// The openings shape `j` (Apple's order) closes.
    pub fn of(&self, j: usize) -> &[EyeOpening] {
        self.per_shape.get(j).map_or(&[], Vec::as_slice)
    }

    /// Marks in `held` (one per avatar vertex) the lid vertices of the
    /// openings shape `j` (Apple's order) closes.
    pub fn hold(&self, j: usize, held: &mut [bool]) {
        for opening in self.of(j) {
            for &v in opening.upper.iter().chain(&opening.lower) {
                if let Some(h) = held.get_mut(v as usize) {
                    *h = true;
                }
            }
        }
    }

    /// Closes, in every shape's `data[j]`, the eyes it closes: [`ROUNDS`]
    /// times, pairs from `at(j, data, v)` (`None`: not known there), then
    /// `close(j, data, contacts)`. Stops at the first `close` that fails.
    pub fn close_all<D>(
        &self,
        data: &mut [D],
        at: impl Fn(usize, &D, u32) -> Option<DVec3>,
        close: impl Fn(usize, &mut D, &[LidContact]) -> Result<(), LidClosingError>,
    ) -> Result<(), LidClosingError> {
        for (j, d) in data.iter_mut().enumerate() {
            let openings = self.of(j);
            if openings.is_empty() {
                continue;
            }
            for _ in 0..ROUNDS {
                let contacts: Vec<LidContact> = openings
                    .iter()
                    .flat_map(|o| contacts(o, |v| at(j, d, v)))
                    .collect();
                close(j, d, &contacts)?;
            }
        }
        Ok(())
    }
}
