//! Dihedral angles: the angle between the normals of two triangles that
//! share an edge. A surface that bends smoothly changes it a little at
//! every edge; a crease changes it sharply along one row of edges, which
//! is how the avatar stage tells a crease from a new shape.

use glam::DVec3;
use std::collections::HashMap;

/// The interior edges of `triangles`: for every edge that exactly two
/// triangles share, its ends (the smaller first) and the indices of the
/// two triangles (the smaller first), in the order of the edges' ends, so
/// the same mesh always gives the same list. An edge of one triangle (a
/// border) or of three or more (non-manifold) has no dihedral angle and
/// is left out.
pub fn triangle_pairs(triangles: &[[u32; 3]]) -> Vec<((u32, u32), [usize; 2])> {
    let mut sides: HashMap<(u32, u32), Vec<usize>> = HashMap::new();
    for (k, t) in triangles.iter().enumerate() {
        for i in 0..3 {
            let (a, b) = (t[i], t[(i + 1) % 3]);
            if a != b {
                sides.entry((a.min(b), a.max(b))).or_default().push(k);
            }
        }
    }
    let mut pairs: Vec<((u32, u32), [usize; 2])> = sides
        .into_iter()
        .filter(|(_, k)| k.len() == 2)
        .map(|(e, k)| (e, [k[0].min(k[1]), k[0].max(k[1])]))
        .collect();
    pairs.sort_unstable();
    pairs
}

/// The dihedral angle (radians) between triangles `s` and `t` with their
/// corners at `at(v)`: 0 where they lie flat, π where folded onto each
/// other; 0 where either is degenerate.
pub fn dihedral(at: impl Fn(u32) -> DVec3, s: [u32; 3], t: [u32; 3]) -> f64 {
    let normal = |t: [u32; 3]| {
        let [a, b, c] = t.map(&at);
        (b - a).cross(c - a)
    };
    let (m, n) = (normal(s), normal(t));
    if m.length_squared() == 0.0 || n.length_squared() == 0.0 {
        return 0.0;
    }
    m.angle_between(n)
}

/// The interior edges of a mesh ([`triangle_pairs`]) with their dihedral
/// angles at rest, to measure how displacements change them.
#[derive(Clone, Debug)]
pub struct Hinges {
    triangles: Vec<[u32; 3]>,
    /// Each hinge's edge (its ends, the smaller first).
    edges: Vec<(u32, u32)>,
    pairs: Vec<[usize; 2]>,
    at_rest: Vec<f64>,
    /// Each triangle's unit normal at rest (zero where degenerate).
    normals: Vec<DVec3>,
}

impl Hinges {
    /// The hinges of `triangles` with corners at `rest`.
    pub fn new(rest: &[DVec3], triangles: &[[u32; 3]]) -> Hinges {
        let (edges, pairs): (Vec<(u32, u32)>, Vec<[usize; 2]>) =
            triangle_pairs(triangles).into_iter().unzip();
        let at = |v: u32| rest[v as usize];
        let at_rest = pairs
            .iter()
            .map(|&[s, t]| dihedral(at, triangles[s], triangles[t]))
            .collect();
        Hinges {
            normals: triangles.iter().map(|t| unit_normal(at, *t)).collect(),
            triangles: triangles.to_vec(),
            edges,
            pairs,
            at_rest,
        }
    }

    /// The triangles.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// The pairs of triangles ([`triangle_pairs`]).
    pub fn pairs(&self) -> &[[usize; 2]] {
        &self.pairs
    }

    /// Each pair's shared edge (its ends, the smaller first), in the
    /// order of [`Hinges::pairs`].
    pub fn edges(&self) -> &[(u32, u32)] {
        &self.edges
    }

    /// How much displacement `d` (one per vertex) changes each pair's
    /// dihedral angle, in radians, as an absolute value; 0, without
    /// measuring, where no corner of either triangle moves (most of a
    /// head in most shapes).
    pub fn changes(&self, rest: &[DVec3], d: &[DVec3]) -> Vec<f64> {
        let moved = |v: u32| rest[v as usize] + d[v as usize];
        let still = |t: [u32; 3]| t.iter().all(|&v| d[v as usize] == DVec3::ZERO);
        self.pairs
            .iter()
            .zip(&self.at_rest)
            .map(|(&[s, t], before)| {
                let (s, t) = (self.triangles[s], self.triangles[t]);
                if still(s) && still(t) {
                    0.0
                } else {
                    (dihedral(moved, s, t) - before).abs()
                }
            })
            .collect()
    }

    /// The largest dihedral change `changes` (one per pair) at each
    /// triangle's three edges (0 for a triangle with no pair).
    pub fn largest_at_triangles(&self, changes: &[f64]) -> Vec<f64> {
        let mut largest = vec![0.0_f64; self.triangles.len()];
        for (pair, change) in self.pairs.iter().zip(changes) {
            for &t in pair {
                largest[t] = largest[t].max(*change);
            }
        }
        largest
    }

    /// The cosine of the angle by which displacement `d` turns each
    /// triangle's normal; `None` for a triangle degenerate at rest or
    /// moved. Computed once per displacement, it serves
    /// [`Hinges::turned`] and [`Hinges::changes_beyond`].
    pub fn turn_cosines(&self, rest: &[DVec3], d: &[DVec3]) -> Vec<Option<f64>> {
        let moved = |v: u32| rest[v as usize] + d[v as usize];
        self.triangles
            .iter()
            .zip(&self.normals)
            .map(|(t, before)| {
                if *before == DVec3::ZERO {
                    return None;
                }
                // A triangle no corner of which moves does not turn (most
                // of a head in most shapes): no normal to compute.
                if t.iter().all(|&v| d[v as usize] == DVec3::ZERO) {
                    return Some(1.0);
                }
                let after = unit_normal(moved, *t);
                (after != DVec3::ZERO).then(|| after.dot(*before))
            })
            .collect()
    }

    /// Whether each triangle turns by more than `angle` (radians), from
    /// its turn's cosine ([`Hinges::turn_cosines`]); a triangle degenerate
    /// at rest or moved is not turned (as in the avatar's checks).
    pub fn turned(cosines: &[Option<f64>], angle: f64) -> Vec<bool> {
        let least = angle.cos();
        cosines
            .iter()
            .map(|c| c.is_some_and(|c| c < least))
            .collect()
    }

    /// How much displacement `d` changes each pair's dihedral angle
    /// (radians, absolute), measured only where it can exceed `angle`,
    /// given the triangles' turns under `d` (`cosines`,
    /// [`Hinges::turn_cosines`]): a dihedral angle changes by at most the
    /// sum of the turns of its two triangles' normals, so a pair whose
    /// triangles both turn by at most `angle / 2` is given 0 unmeasured.
    /// Compared with `angle`, the same as [`Hinges::changes`].
    pub fn changes_beyond(
        &self,
        rest: &[DVec3],
        d: &[DVec3],
        cosines: &[Option<f64>],
        angle: f64,
    ) -> Vec<f64> {
        let moved = |v: u32| rest[v as usize] + d[v as usize];
        let least = (angle / 2.0).cos();
        let turns_little: Vec<bool> = cosines
            .iter()
            .map(|c| c.is_some_and(|c| c >= least))
            .collect();
        self.pairs
            .iter()
            .zip(&self.at_rest)
            .map(|(&[s, t], before)| {
                if turns_little[s] && turns_little[t] {
                    return 0.0;
                }
                let (s, t) = (self.triangles[s], self.triangles[t]);
                (dihedral(moved, s, t) - before).abs()
            })
            .collect()
    }
}

/// Triangle `t`'s unit normal, corners at `at(v)`; zero where degenerate.
fn unit_normal(at: impl Fn(u32) -> DVec3, t: [u32; 3]) -> DVec3 {
    let [a, b, c] = t.map(at);
    (b - a).cross(c - a).normalize_or_zero()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    /// Two triangles on the edge 0–1, a third on the edge 1–2 alone.
    fn hinge() -> (Vec<DVec3>, Vec<[u32; 3]>) {
        let positions = vec![
            DVec3::ZERO,
            DVec3::X,
            DVec3::new(0.5, 1.0, 0.0),
            DVec3::new(0.5, -1.0, 0.0),
            DVec3::new(1.5, 1.0, 0.0),
        ];
        (positions, vec![[0, 1, 2], [1, 0, 3], [1, 4, 2]])
    }

    #[test]
    fn only_edges_of_two_triangles_pair_them() {
        let (_, triangles) = hinge();
        // 0–1 is shared by triangles 0 and 1, 1–2 by 0 and 2; the rest
        // are borders.
        assert_eq!(
            triangle_pairs(&triangles),
            vec![((0, 1), [0, 1]), ((1, 2), [0, 2])]
        );
    }

    #[test]
    fn lifting_a_wing_by_a_right_angle_changes_only_its_hinge() {
        let (rest, triangles) = hinge();
        let hinges = Hinges::new(&rest, &triangles);
        // Vertex 3 swung up about the edge 0–1, to stand upright.
        let mut d = vec![DVec3::ZERO; rest.len()];
        d[3] = DVec3::new(0.0, 1.0, 1.0);
        let changes = hinges.changes(&rest, &d);
        assert!((changes[0] - FRAC_PI_2).abs() < 1e-12, "{changes:?}");
        assert!(changes[1].abs() < 1e-12, "{changes:?}");
        let cosines = hinges.turn_cosines(&rest, &d);
        let bent = |angle: f64| -> Vec<bool> {
            let changes = hinges.changes_beyond(&rest, &d, &cosines, angle);
            changes.iter().map(|c| *c > angle).collect()
        };
        assert_eq!(bent(1.5), vec![true, false]);
        assert_eq!(bent(1.6), vec![false, false]);
        assert_eq!(hinges.edges(), &[(0, 1), (1, 2)]);
        // Only the wing turns, by a right angle.
        assert_eq!(Hinges::turned(&cosines, 1.5), vec![false, true, false]);
        assert_eq!(Hinges::turned(&cosines, 1.6), vec![false, false, false]);
        let flat = |v: u32| rest[v as usize];
        assert_eq!(dihedral(flat, [0, 0, 1], [0, 1, 2]), 0.0, "degenerate");
    }
}
