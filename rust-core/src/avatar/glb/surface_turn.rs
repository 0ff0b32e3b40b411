//! How a surface's normals turn when it moves: for a new rest written back
//! (`new_rest.rs`) and for each morph target's `NORMAL` deltas (glTF 2.0,
//! "Morph Targets": the engine adds the weighted deltas to the normal and
//! renormalizes, so a target that bends the surface shades as it bends).
//!
//! The surface's smooth normal at a vertex is the area-weighted normal
//! ([`vertex_normals`]) with the vertices that share a
//! position welded, so the two sides of a UV seam turn alike. Vertex `v`
//! turns by the shortest rotation `q_v` taking its smooth normal before to
//! its smooth normal after; the artist's own normal `n` is turned by it,
//! not replaced, so a hard edge or a deliberately bent normal keeps its
//! character. In a primitive's own space, with `L` the linear part of the
//! node placing it, a normal `n` becomes `Lᵀ q_v (L⁻ᵀ n)`, normalized.

use crate::personalize::blendshape_fit::in_parallel_ranges;
use glam::{Mat3, Quat, Vec3};
use std::collections::HashMap;

/// Area-weighted vertex normals: the sum of `(b − a) × (c − a)` over the
/// triangles around each vertex, normalized, so each face weighs by twice
/// its area (pmp-library's vertex normal); +Y for a vertex on no triangle
/// (glTF requires unit normals); a triangle with an index past
/// `positions` is skipped.
pub fn vertex_normals(positions: &[Vec3], triangles: &[[u32; 3]]) -> Vec<Vec3> {
    let mut sum = vec![Vec3::ZERO; positions.len()];
    for t in triangles {
        let [Some(&a), Some(&b), Some(&c)] = t.map(|i| positions.get(i as usize)) else {
            continue; // an index past the end: no face to weigh
        };
        let n = (b - a).cross(c - a);
        for &i in t {
            sum[i as usize] += n;
        }
    }
    sum.into_iter()
        .map(|n| n.try_normalize().unwrap_or(Vec3::Y))
        .collect()
}

/// A surface's triangles with the vertices that share a rest position
/// welded, and its smooth normals at rest.
pub struct WeldedSurface {
    /// Every vertex's first vertex with the same rest position.
    welded: Vec<u32>,
    /// The triangles over the welded vertices (those with an index past
    /// the vertices dropped).
    triangles: Vec<[u32; 3]>,
    /// Smooth normals at rest, per welded vertex.
    before: Vec<Vec3>,
}

impl WeldedSurface {
    /// Welds `rest` (bitwise equal positions) and takes its normals.
    pub fn new(rest: &[Vec3], triangles: &[[u32; 3]]) -> WeldedSurface {
        let mut first: HashMap<[u32; 3], u32> = HashMap::new();
        let welded: Vec<u32> = rest
            .iter()
            .enumerate()
            .map(|(i, p)| {
                *first
                    .entry(p.to_array().map(f32::to_bits))
                    .or_insert(i as u32)
            })
            .collect();
        let triangles: Vec<[u32; 3]> = triangles
            .iter()
            .filter(|t| t.iter().all(|&v| (v as usize) < welded.len()))
            .map(|t| t.map(|v| welded[v as usize]))
            .collect();
        let before = vertex_normals(rest, &triangles);
        WeldedSurface {
            welded,
            triangles,
            before,
        }
    }

    /// The rotation `q_v` per vertex taking its smooth normal at rest to
    /// its smooth normal on `moved` (one position per vertex); the
    /// identity where that normal did not change, exactly.
    pub fn turns(&self, moved: &[Vec3]) -> Vec<Quat> {
        let after = vertex_normals(moved, &self.triangles);
        self.welded
            .iter()
            .map(|&w| {
                let (b, a) = (self.before[w as usize], after[w as usize]);
                match a == b {
                    true => Quat::IDENTITY,
                    false => Quat::from_rotation_arc(b, a),
                }
            })
            .collect()
    }
}

/// A primitive's linear placement `L` (the linear part of the node placing
/// it), with `Lᵀ` and `L⁻ᵀ` worked out once for all its normals.
pub struct Placed {
    transpose: Mat3,
    inverse_transpose: Mat3,
}

impl Placed {
    /// The placement by `linear`.
    pub fn new(linear: Mat3) -> Placed {
        Placed {
            transpose: linear.transpose(),
            inverse_transpose: linear.inverse().transpose(),
        }
    }

    /// Normal `n` (the primitive's own space) turned by the world rotation
    /// `q`: `Lᵀ q (L⁻ᵀ n)`, normalized; `n` itself where `q` is the
    /// identity or the result degenerate.
    pub fn turned(&self, n: Vec3, q: Quat) -> Vec3 {
        if q == Quat::IDENTITY {
            return n;
        }
        (self.transpose * (q * (self.inverse_transpose * n)))
            .try_normalize()
            .unwrap_or(n)
    }
}

/// A normal delta shorter than this is written as zero: it turns the normal
/// by under 0.06° and changes a Lambertian `n·l` by under 0.001, a quarter
/// of one step of an 8-bit colour, so no engine shows it; dropping it
/// keeps the targets sparse where a shape barely bends the surface.
pub const NEGLIGIBLE_NORMAL_DELTA: f32 = 1e-3;

/// Each morph target's `NORMAL` deltas, one list per displacement list in
/// `displacements` (the targets split over the machine's cores): at each
/// vertex, its normal `n` (primitive space) turned as the surface turns
/// under the target, minus `n`; zero wherever that is under
/// [`NEGLIGIBLE_NORMAL_DELTA`] (sparse where the target is).
pub fn all_normal_deltas(
    surface: &WeldedSurface,
    rest: &[Vec3],
    displacements: &[&[Vec3]],
    normals: &[Vec3],
    linear: Mat3,
) -> Vec<Vec<Vec3>> {
    let placed = Placed::new(linear);
    let chunks = in_parallel_ranges(displacements.len(), |range| {
        displacements[range]
            .iter()
            .map(|d| deltas(surface, rest, d, normals, &placed))
            .collect::<Vec<_>>()
    });
    match chunks.into_iter().collect::<Option<Vec<_>>>() {
        Some(chunks) => chunks.into_iter().flatten().collect(),
        // A thread panicked: work them out again here, so the panic
        // surfaces on the caller's thread rather than as missing data.
        None => (displacements.iter())
            .map(|d| deltas(surface, rest, d, normals, &placed))
            .collect(),
    }
}

/// One target's deltas ([`all_normal_deltas`]).
fn deltas(
    surface: &WeldedSurface,
    rest: &[Vec3],
    displacement: &[Vec3],
    normals: &[Vec3],
    placed: &Placed,
) -> Vec<Vec3> {
    if displacement.iter().all(|d| *d == Vec3::ZERO) {
        return vec![Vec3::ZERO; normals.len()];
    }
    let moved: Vec<Vec3> = rest
        .iter()
        .zip(displacement)
        .map(|(p, d)| *p + *d)
        .collect();
    surface
        .turns(&moved)
        .iter()
        .zip(normals)
        .map(|(q, n)| placed.turned(*n, *q) - *n)
        .map(|d| match d.length() < NEGLIGIBLE_NORMAL_DELTA {
            true => Vec3::ZERO,
            false => d,
        })
        .collect()
}

/// Two triangles of the unit square in z = 0, the corner at x = 1, y = 0
/// split in two (vertices 1 and 4, a UV seam): the fixture of this
/// module's tests and of [`super::new_rest`]'s.
#[cfg(test)]
pub(super) fn seam_square() -> (Vec<Vec3>, [[u32; 3]; 2]) {
    let rest = vec![
        Vec3::ZERO,
        Vec3::X,
        Vec3::Y,
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::X,
    ];
    (rest, [[0, 1, 2], [4, 3, 2]])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bend_turns_the_normals_around_it_and_both_sides_of_a_seam_alike() {
        let (rest, triangles) = seam_square();
        let surface = WeldedSurface::new(&rest, &triangles);
        let normals = vec![Vec3::Z; rest.len()];
        let one = |d: &[Vec3]| {
            all_normal_deltas(&surface, &rest, &[d], &normals, Mat3::IDENTITY).remove(0)
        };
        let none = one(&[Vec3::ZERO; 5]);
        assert!(none.iter().all(|d| *d == Vec3::ZERO));
        // Lift the far corner: both triangles tilt; the corner opposite the
        // lift (0) is on the first triangle only, which stays flat.
        let mut lift = vec![Vec3::ZERO; 5];
        lift[3].z = 0.5;
        let deltas = one(&lift);
        assert_eq!(deltas[0], Vec3::ZERO, "its only triangle did not turn");
        assert_eq!(deltas[1], deltas[4], "both halves of the seam turn alike");
        assert!(deltas[3].length() > 0.1, "the lifted corner turns");
        for (d, n) in deltas.iter().zip(&normals) {
            assert!(
                ((*n + *d).length() - 1.0).abs() < 1e-5,
                "rest plus delta is unit"
            );
        }
        // Vertex 3's normal is the second triangle's: −(0.5, 0.5, −1)/√1.5
        // up to sign, so n + δ is the tilted triangle's normal.
        let tilted = Vec3::new(-0.5, -0.5, 1.0).normalize();
        assert!((normals[3] + deltas[3] - tilted).length() < 1e-5);
    }

    #[test]
    fn normals_in_a_scaled_primitive_turn_in_its_own_space() {
        // A primitive scaled 2x along x: its own-space normal of a surface
        // tilted in world space is found through L⁻ᵀ and back through Lᵀ.
        let linear = Mat3::from_diagonal(Vec3::new(2.0, 1.0, 1.0));
        let q = Quat::from_rotation_y(0.3);
        let n = Vec3::Z;
        let placed = Placed::new(linear);
        let turned = placed.turned(n, q);
        let world = q * Vec3::Z;
        let expected = (linear.transpose() * world).normalize();
        assert!((turned - expected).length() < 1e-6);
        assert_eq!(placed.turned(n, Quat::IDENTITY), n);
    }
}
