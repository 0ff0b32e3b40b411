//! Boundary edges and loops of a triangle mesh, and the virtual triangles
//! that close the eye holes of an ARKit-like face mask.
//!
//! ARKit's face mask is a disc with three holes: the outline, two eyes and
//! the mouth. Deformation transfer only sees triangles, so a blink transferred
//! through the open eye hole does not know that the upper lid must meet the
//! lower one. Following Saito (2013, cited in the paper's §3.2), the eye holes
//! are spanned by *virtual triangles* from the upper to the lower lid; they
//! collapse when the source eye closes, and the transfer then closes the
//! target eye too.
//!
//! Coordinates are ARKit's face-anchor space: +x towards the person's left,
//! +y up, +z out of the face, metres.

use crate::geometry::topology::{GeometryError, Topology};
use glam::{DVec3, Vec3};
use std::collections::{HashMap, HashSet};

/// What makes a mesh's boundary unusable.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum BoundaryError {
    /// More than two triangles share an edge.
    #[error("edge ({a}, {b}) is used by {count} triangles; a surface edge has at most 2")]
    NonManifoldEdge {
        /// One end of the edge (the smaller index).
        a: u32,
        /// The other end.
        b: u32,
        /// Number of triangles using it.
        count: usize,
    },
    /// Two triangles traverse their shared edge in the same direction.
    #[error(
        "edge ({a}, {b}) runs the same way in both its triangles: they are not consistently oriented"
    )]
    InconsistentOrientation {
        /// Start of the edge in both triangles.
        a: u32,
        /// End of the edge in both triangles.
        b: u32,
    },
    /// Two boundary loops touch at a vertex, so they cannot be told apart.
    #[error("vertex {vertex} is on the boundary twice: two boundary loops touch there")]
    NonManifoldVertex {
        /// The vertex.
        vertex: u32,
    },
}

/// Whether barycentric point `b` of triangle `t` lies on a vertex or an
/// edge of a mesh's `boundary` (edges as `(min, max)`, [`boundary_edges`],
/// and their `vertices`): a closest point on an edge or a corner has an
/// exact zero coordinate, so only rounding (10⁻⁹) is allowed for.
pub fn on_boundary(
    t: [u32; 3],
    b: [f64; 3],
    boundary: &HashSet<(u32, u32)>,
    vertices: &HashSet<u32>,
) -> bool {
    const ON: f64 = 1e-9;
    (0..3).any(|k| {
        let (i, j) = (t[(k + 1) % 3], t[(k + 2) % 3]);
        (b[k] >= 1.0 - ON && vertices.contains(&t[k]))
            || (b[k] <= ON && boundary.contains(&(i.min(j), i.max(j))))
    })
}

/// The edges used by exactly one triangle, `(min, max)`.
pub fn boundary_edges(triangles: &[[u32; 3]]) -> HashSet<(u32, u32)> {
    let mut count: HashMap<(u32, u32), usize> = HashMap::new();
    for t in triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            *count.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    count
        .into_iter()
        .filter(|(_, c)| *c == 1)
        .map(|(e, _)| e)
        .collect()
}

/// The boundary loops of `topology`.
///
/// A boundary edge is an edge used by exactly one triangle. Each is taken in
/// the direction its triangle traverses it (`a → b` for a triangle
/// `(…, a, b, …)` in cyclic order), and the edges are chained head to tail
/// into closed loops. The loops are therefore oriented consistently with the
/// triangles: walking along a loop, the mesh is on the left when seen from
/// the triangles' front. For a face mask whose triangles are counter-clockwise
/// seen from +z, the outline runs counter-clockwise and every hole clockwise.
///
/// Each loop lists its vertices once, starting from its smallest index; loops
/// are sorted by that vertex. A closed mesh has no loops. Edges used by more
/// than two triangles, inconsistently oriented neighbours, and loops touching
/// at a vertex are errors.
pub fn boundary_loops(topology: &Topology) -> Result<Vec<Vec<u32>>, BoundaryError> {
    // Per undirected edge {a < b}: how many triangles use it, and the
    // direction of its first use.
    struct EdgeUse {
        count: usize,
        from: u32,
        to: u32,
    }
    // Indexing: `k < 3` on a triangle, and every vertex (and so `visited`'s
    // index) comes from the checked `topology`.
    let mut edges: HashMap<(u32, u32), EdgeUse> = HashMap::new();
    for tri in topology.triangles() {
        for k in 0..3 {
            let (from, to) = (tri[k], tri[(k + 1) % 3]);
            let key = (from.min(to), from.max(to));
            let entry = edges.entry(key).or_insert(EdgeUse { count: 0, from, to });
            entry.count += 1;
            if entry.count == 2 && entry.from == from {
                return Err(BoundaryError::InconsistentOrientation { a: from, b: to });
            }
            if entry.count > 2 {
                return Err(BoundaryError::NonManifoldEdge {
                    a: key.0,
                    b: key.1,
                    count: entry.count,
                });
            }
        }
    }

    // Successor of each boundary vertex along its loop.
    let mut next: HashMap<u32, u32> = HashMap::new();
    for edge in edges.values().filter(|e| e.count == 1) {
        if next.insert(edge.from, edge.to).is_some() {
            return Err(BoundaryError::NonManifoldVertex { vertex: edge.from });
        }
    }
    let mut starts: Vec<u32> = next.keys().copied().collect();
    starts.sort_unstable();

    let mut visited = vec![false; topology.vertex_count()];
    let mut loops = Vec::new();
    for start in starts {
        if visited[start as usize] {
            continue;
        }
        let mut boundary = Vec::new();
        let mut v = start;
        loop {
            visited[v as usize] = true;
            boundary.push(v);
            // Every boundary vertex has a successor: with consistently
            // oriented triangles each vertex has as many incoming as
            // outgoing boundary edges, and at most one outgoing.
            v = match next.get(&v) {
                Some(&w) => w,
                None => return Err(BoundaryError::NonManifoldVertex { vertex: v }),
            };
            if v == start {
                break;
            }
            if visited[v as usize] {
                return Err(BoundaryError::NonManifoldVertex { vertex: v });
            }
        }
        loops.push(boundary);
    }
    Ok(loops)
}

/// One eye hole of a face mask, split at its corners, and its virtual
/// triangles.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct EyeHole {
    /// Upper lid from the corner with the smallest x to the corner with the
    /// largest x, both corners included.
    pub upper: Vec<u32>,
    /// Lower lid between the same corners, in the same direction.
    pub lower: Vec<u32>,
    /// Virtual triangles filling the hole: `upper.len() + lower.len() − 4`
    /// of them (the hole's loop length minus two), each with at least one
    /// vertex strictly inside each lid.
    pub triangles: Vec<[u32; 3]>,
}

/// Why the eye holes of a mesh cannot be found.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum EyeHoleError {
    /// The neutral positions do not fit the topology.
    #[error(transparent)]
    Geometry(#[from] GeometryError),
    /// The boundary is not a set of disjoint loops.
    #[error(transparent)]
    Boundary(#[from] BoundaryError),
    /// Not the four loops of a face mask.
    #[error(
        "expected 4 boundary loops (outline, two eyes, mouth), found {found} (lengths {lengths:?})"
    )]
    LoopCount {
        /// Number of boundary loops found.
        found: usize,
        /// Their vertex counts.
        lengths: Vec<usize>,
    },
    /// An eye loop has no vertex strictly between its corners on one lid.
    #[error(
        "the {side} eye hole has {upper} upper-lid and {lower} lower-lid vertices between its corners; each lid needs at least one"
    )]
    EyeTooSmall {
        /// `"left"` (+x) or `"right"` (−x).
        side: &'static str,
        /// Upper-lid vertices strictly between the corners.
        upper: usize,
        /// Lower-lid vertices strictly between the corners.
        lower: usize,
    },
}

/// The two eye holes of an ARKit-like face mask, `[left, right]` (the
/// person's left is +x), with their virtual triangles.
///
/// The mask must have exactly four boundary loops ([`boundary_loops`]). In
/// the neutral positions, the *outline* is the loop with the largest extent
/// (diagonal of its bounding box in the x–y plane); of the other three, the
/// *mouth* is the one whose centroid is lowest in y, and the remaining two are
/// the eyes, the left one at larger x.
///
/// Each eye loop is split at its *corners*, the loop vertices with the
/// smallest and the largest x, into two chains from corner to corner; the
/// *upper* lid is the chain whose inner vertices have the larger mean y. The
/// chains `u₀ … u_p` and `l₀ … l_q` (`u₀ = l₀`, `u_p = l_q` the corners) are
/// zipped into a strip: the first triangle is `(u₀, u₁, l₁)`, then from the
/// current diagonal `uᵢ–lⱼ` the strip advances along the chain whose new
/// diagonal (`‖u_{i+1} − lⱼ‖` or `‖uᵢ − l_{j+1}‖`) is shorter, as long as
/// both stay strictly inside their lids, and ends with
/// `(u_{p−1}, u_p, l_{q−1})`. That is `(p − 1) + (q − 1)` triangles, the
/// loop length minus two, and each joins the upper lid to the lower lid.
///
/// Every triangle is oriented to traverse the hole's boundary edges opposite
/// to the mesh triangles beside them, so the mesh plus its virtual triangles
/// is consistently oriented; for a mask facing +z their normals face +z.
pub fn eye_holes(topology: &Topology, neutral: &[Vec3]) -> Result<[EyeHole; 2], EyeHoleError> {
    // Indexing: `neutral` has one point per vertex of the checked topology
    // (checked here), and there are exactly four loops, so three inner ones.
    topology.check_positions("neutral", neutral)?;
    let pos = |v: u32| neutral[v as usize].as_dvec3();
    let loops = boundary_loops(topology)?;
    if loops.len() != 4 {
        return Err(EyeHoleError::LoopCount {
            found: loops.len(),
            lengths: loops.iter().map(Vec::len).collect(),
        });
    }
    let extent = |l: &[u32]| {
        let (lo, hi) = l.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), &v| (lo.min(pos(v)), hi.max(pos(v))),
        );
        (hi - lo).truncate().length()
    };
    let centroid = |l: &[u32]| l.iter().map(|&v| pos(v)).sum::<DVec3>() / l.len() as f64;

    let mut inner: Vec<&Vec<u32>> = loops.iter().collect();
    inner.sort_by(|a, b| extent(a).total_cmp(&extent(b)));
    inner.pop(); // the outline
    inner.sort_by(|a, b| centroid(a).y.total_cmp(&centroid(b).y));
    let (left, right) = if centroid(inner[1]).x >= centroid(inner[2]).x {
        (inner[1], inner[2])
    } else {
        (inner[2], inner[1])
    };
    Ok([
        fill_eye(left, &pos, "left")?,
        fill_eye(right, &pos, "right")?,
    ])
}

/// The virtual triangles of both eye holes, left eye first: see
/// [`eye_holes`].
pub fn eye_hole_triangles(
    topology: &Topology,
    neutral: &[Vec3],
) -> Result<Vec<[u32; 3]>, EyeHoleError> {
    let [left, right] = eye_holes(topology, neutral)?;
    Ok(left.triangles.into_iter().chain(right.triangles).collect())
}

/// Splits one eye loop at its corners and zips the lids (see [`eye_holes`]).
fn fill_eye(
    eye: &[u32],
    pos: &impl Fn(u32) -> DVec3,
    side: &'static str,
) -> Result<EyeHole, EyeHoleError> {
    // Indexing: every loop position is `< n` (`first`, `last` and the
    // chains are taken modulo `n`); past the length check each chain has at
    // least three positions, and the zip keeps `i ≤ p − 1`, `j ≤ q − 1`.
    let n = eye.len();
    let by_x = |a: &usize, b: &usize| pos(eye[*a]).x.total_cmp(&pos(eye[*b]).x);
    // Loop positions of the corners (first of equals, so the result is
    // deterministic).
    let first = (0..n).min_by(by_x).unwrap_or(0);
    let last = (0..n).rev().max_by(by_x).unwrap_or(0);
    // The two chains as loop positions from `first` to `last`.
    let forward: Vec<usize> = (0..n)
        .map(|k| (first + k) % n)
        .take_while(|&p| p != last)
        .chain([last])
        .collect();
    let backward: Vec<usize> = (0..n)
        .map(|k| (first + n - k) % n)
        .take_while(|&p| p != last)
        .chain([last])
        .collect();
    // A chain has at least its last corner; when every vertex of the loop
    // has the same x the two corners coincide, both chains are that one
    // vertex, and the length check below rejects the eye.
    let mean_inner_y = |chain: &[usize]| {
        let inner = chain.get(1..chain.len().saturating_sub(1)).unwrap_or(&[]);
        inner.iter().map(|&p| pos(eye[p]).y).sum::<f64>() / inner.len().max(1) as f64
    };
    let (upper, lower) = if mean_inner_y(&forward) >= mean_inner_y(&backward) {
        (forward, backward)
    } else {
        (backward, forward)
    };
    if upper.len() < 3 || lower.len() < 3 {
        return Err(EyeHoleError::EyeTooSmall {
            side,
            upper: upper.len().saturating_sub(2),
            lower: lower.len().saturating_sub(2),
        });
    }

    // Zip: triangles as triples of loop positions.
    let (p, q) = (upper.len() - 1, lower.len() - 1);
    let dist = |i: usize, j: usize| pos(eye[upper[i]]).distance(pos(eye[lower[j]]));
    let mut strip = vec![[upper[0], upper[1], lower[1]]];
    let (mut i, mut j) = (1, 1);
    while i < p - 1 || j < q - 1 {
        let advance_upper = j == q - 1 || (i < p - 1 && dist(i + 1, j) <= dist(i, j + 1));
        if advance_upper {
            strip.push([upper[i], upper[i + 1], lower[j]]);
            i += 1;
        } else {
            strip.push([upper[i], lower[j + 1], lower[j]]);
            j += 1;
        }
    }
    strip.push([upper[p - 1], upper[p], lower[q - 1]]);

    // Orientation: the loop runs a → b along the mesh's own half-edges, so
    // the filling must run against it. A triangle on loop positions
    // x < y < z follows the loop's cyclic order as (x, y, z); reverse it.
    let triangles = strip
        .into_iter()
        .map(|mut t| {
            t.sort_unstable();
            [eye[t[2]], eye[t[1]], eye[t[0]]]
        })
        .collect();
    Ok(EyeHole {
        upper: upper.iter().map(|&p| eye[p]).collect(),
        lower: lower.iter().map(|&p| eye[p]).collect(),
        triangles,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_support::*;

    fn normal(p: &[Vec3], t: [u32; 3]) -> Vec3 {
        let [a, b, c] = t.map(|v| p[v as usize]);
        (b - a).cross(c - a)
    }

    #[test]
    fn loops_of_a_grid_with_holes_are_closed_and_oriented() {
        let (topo, p, _) = face_grid();
        let loops = boundary_loops(&topo).unwrap();
        let mut lengths: Vec<usize> = loops.iter().map(Vec::len).collect();
        lengths.sort_unstable();
        // Eyes: 6 × 2 cells → 16; mouth: 9 × 1 → 20; outline 2 · (21 + 16).
        assert_eq!(lengths, [16, 16, 20, 74]);
        for l in &loops {
            // Signed area in x–y: positive (counter-clockwise) only for the outline.
            let area: f32 = (0..l.len())
                .map(|k| {
                    let (a, b) = (p[l[k] as usize], p[l[(k + 1) % l.len()] as usize]);
                    a.x * b.y - b.x * a.y
                })
                .sum();
            assert_eq!(area > 0.0, l.len() == 74, "loop of {} vertices", l.len());
        }
    }

    #[test]
    fn eye_holes_are_zipped_from_upper_to_lower_lid() {
        let (topo, p, index) = face_grid();
        let eyes = eye_holes(&topo, &p).unwrap();
        let mut virtual_triangles = Vec::new();
        for (eye, hole) in eyes.iter().zip(EYES) {
            let (i0, i1, j0, j1) = hole;
            let v = |i: usize, j: usize| index[j * FACE_NX + i].unwrap();
            // Corners are the pushed-out middle vertices.
            let mid = (j0 + j1) / 2;
            assert_eq!(eye.upper[0], v(i0, mid));
            assert_eq!(*eye.upper.last().unwrap(), v(i1, mid));
            assert_eq!(eye.lower[0], v(i0, mid));
            let top: Vec<u32> = (i0..=i1).map(|i| v(i, j1)).collect();
            let bottom: Vec<u32> = (i0..=i1).map(|i| v(i, j0)).collect();
            assert_eq!(eye.upper[1..eye.upper.len() - 1], top[..]);
            assert_eq!(eye.lower[1..eye.lower.len() - 1], bottom[..]);

            let (u, l) = (eye.upper.len(), eye.lower.len());
            assert_eq!(eye.triangles.len(), (u - 1) + (l - 1) - 2);
            assert_eq!(eye.triangles.len(), 14);
            let inner_upper = &eye.upper[1..u - 1];
            let inner_lower = &eye.lower[1..l - 1];
            for t in &eye.triangles {
                assert!(t.iter().any(|v| inner_upper.contains(v)), "{t:?}");
                assert!(t.iter().any(|v| inner_lower.contains(v)), "{t:?}");
                assert!(normal(&p, *t).z > 0.0, "{t:?} faces −z");
            }
            virtual_triangles.extend(&eye.triangles);
        }
        assert_eq!(eye_hole_triangles(&topo, &p).unwrap(), virtual_triangles);

        // The mesh plus its virtual triangles is consistently oriented, and
        // only the outline and the mouth remain open.
        let closed = Topology::new(
            topo.vertex_count(),
            topo.triangles()
                .iter()
                .chain(&virtual_triangles)
                .copied()
                .collect(),
        )
        .unwrap();
        let mut lengths: Vec<usize> = boundary_loops(&closed)
            .unwrap()
            .iter()
            .map(Vec::len)
            .collect();
        lengths.sort_unstable();
        assert_eq!(lengths, [20, 74]);
    }

    #[test]
    fn meshes_without_two_eyes_and_a_mouth_are_typed_errors() {
        let (topo, p, _) = grid_with_holes(6, 5, &[], |_, _| Vec3::ZERO);
        let err = eye_holes(&topo, &p).unwrap_err();
        assert_eq!(
            err,
            EyeHoleError::LoopCount {
                found: 1,
                lengths: vec![18]
            }
        );
        let (topo, p, _) = grid_with_holes(12, 8, &[(2, 4, 4, 6), (7, 9, 4, 6)], |_, _| Vec3::ZERO);
        let err = eye_holes(&topo, &p).unwrap_err().to_string();
        assert!(err.starts_with("expected 4 boundary loops"), "{err}");
        assert!(err.contains("found 3"), "{err}");

        let (topo, mut p, _) = face_grid();
        p[3].z = f32::NAN;
        assert!(matches!(
            eye_holes(&topo, &p),
            Err(EyeHoleError::Geometry(GeometryError::NotFinite {
                vertex: 3,
                ..
            }))
        ));
    }

    #[test]
    fn an_eye_without_a_lower_lid_is_an_error() {
        // One-cell eyes whose top edge is narrower than the bottom one: the
        // corners (smallest and largest x) are the bottom two vertices, so
        // the lower lid has no vertex between them.
        let eyes = [(13, 14, 10, 11), (4, 5, 10, 11)];
        let (topo, p, _) = grid_with_holes(22, 17, &[eyes[0], eyes[1], MOUTH], |i, j| {
            let inwards = if j == 11 && (i == 4 || i == 13) {
                0.2 * CELL
            } else if j == 11 && (i == 5 || i == 14) {
                -0.2 * CELL
            } else {
                0.0
            };
            Vec3::new(inwards, 0.0, 0.0)
        });
        let err = eye_holes(&topo, &p).unwrap_err();
        assert_eq!(
            err,
            EyeHoleError::EyeTooSmall {
                side: "left",
                upper: 2,
                lower: 0
            }
        );
    }

    #[test]
    fn hostile_masks_are_errors_not_panics() {
        let loop_count = |topo: &Topology, p: &[Vec3]| match eye_holes(topo, p) {
            Err(EyeHoleError::LoopCount { found, .. }) => found,
            other => panic!("expected a loop count error, got {other:?}"),
        };
        let too_small = |topo: &Topology, p: &[Vec3]| {
            assert!(
                matches!(eye_holes(topo, p), Err(EyeHoleError::EyeTooSmall { .. })),
                "{:?}",
                eye_holes(topo, p)
            );
        };
        // The face's topology with every vertex at one point, or with the
        // eyes squashed onto a vertical line: an eye loop whose smallest and
        // largest x are the same vertex has no lids.
        let (topo, p, _) = face_grid();
        too_small(&topo, &vec![Vec3::ZERO; p.len()]);
        let squashed: Vec<Vec3> = p.iter().map(|q| Vec3::new(0.0, q.y, q.z)).collect();
        too_small(&topo, &squashed);
        // A single hole, a closed fan, two disjoint triangles.
        let (topo, p, _) = grid_with_holes(8, 6, &[(2, 4, 2, 4)], |_, _| Vec3::ZERO);
        assert_eq!(loop_count(&topo, &p), 2);
        let fan = Topology::new(7, (0..6).map(|k| [0, 1 + k, 1 + (k + 1) % 6]).collect()).unwrap();
        assert_eq!(loop_count(&fan, &[Vec3::X; 7]), 1);
        let two = Topology::new(6, vec![[0, 1, 2], [3, 4, 5]]).unwrap();
        assert_eq!(loop_count(&two, &[Vec3::ZERO; 6]), 2);
        // Four disjoint triangles: four loops, but every "eye" has three
        // vertices, at distinct points or all at one.
        let four =
            Topology::new(12, (0..4).map(|t| [3 * t, 3 * t + 1, 3 * t + 2]).collect()).unwrap();
        let spread: Vec<Vec3> = (0..12)
            .map(|v| Vec3::new((v % 3) as f32, (v / 3) as f32, 0.0))
            .collect();
        too_small(&four, &spread);
        too_small(&four, &[Vec3::ZERO; 12]);
        // Two holes touching at a corner: the boundary is not a set of loops.
        let (topo, p, _) = grid_with_holes(8, 8, &[(2, 3, 2, 3), (3, 4, 3, 4)], |_, _| Vec3::ZERO);
        assert!(matches!(
            eye_holes(&topo, &p),
            Err(EyeHoleError::Boundary(
                BoundaryError::NonManifoldVertex { .. }
            ))
        ));
        // Positions that do not fit the topology.
        let (topo, p, _) = face_grid();
        assert!(matches!(
            eye_holes(&topo, &p[1..]),
            Err(EyeHoleError::Geometry(GeometryError::VertexCount { .. }))
        ));
    }

    #[test]
    fn inconsistent_and_non_manifold_meshes_are_rejected() {
        let flipped = Topology::new(4, vec![[0, 1, 2], [1, 2, 3]]).unwrap();
        assert_eq!(
            boundary_loops(&flipped),
            Err(BoundaryError::InconsistentOrientation { a: 1, b: 2 })
        );
        let fin = Topology::new(5, vec![[0, 1, 2], [1, 0, 3], [0, 1, 4]]).unwrap();
        assert!(matches!(
            boundary_loops(&fin),
            Err(BoundaryError::InconsistentOrientation { .. }
                | BoundaryError::NonManifoldEdge { .. })
        ));
        let bowtie = Topology::new(5, vec![[0, 1, 2], [0, 3, 4]]).unwrap();
        assert_eq!(
            boundary_loops(&bowtie),
            Err(BoundaryError::NonManifoldVertex { vertex: 0 })
        );
        let tetrahedron =
            Topology::new(4, vec![[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]]).unwrap();
        assert_eq!(boundary_loops(&tetrahedron), Ok(vec![]));
    }
}
