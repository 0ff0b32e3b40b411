//! The generalized winding number of a triangle mesh at a point (Jacobson,
//! Kavan & Sorkine-Hornung 2013, "Robust inside-outside segmentation using
//! generalized winding numbers", ACM TOG 32(4)): the solid angle the mesh
//! subtends at the point, over 4π,
//!
//! ```text
//! w(p) = Σ_t Ω_t(p) / 4π,
//! tan(Ω_t / 2) = a · (b × c) / (|a||b||c| + (a·b)|c| + (b·c)|a| + (c·a)|b|)
//! ```
//!
//! with `a, b, c` the triangle's corners less `p` (Van Oosterom & Strackee
//! 1983). For a closed mesh facing outwards it is 1 inside and 0 outside;
//! for an open one (an eyeball shell without its back, as MakeHuman's) it
//! still rises above ½ just inside the surface and falls below ½ beside
//! the opening, where the closest triangle's side says nothing.

use glam::DVec3;

/// The signed solid angle triangle `(a, b, c)` subtends at `p` (module
/// docs), positive where `p` sees its back (the side its normal leaves).
pub fn solid_angle(p: DVec3, [a, b, c]: [DVec3; 3]) -> f64 {
    let (a, b, c) = (a - p, b - p, c - p);
    let (la, lb, lc) = (a.length(), b.length(), c.length());
    let det = a.dot(b.cross(c));
    let den = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    2.0 * det.atan2(den)
}

/// The generalized winding number at `p` of the triangles `corners`
/// (module docs).
pub fn winding_number<'a>(corners: impl IntoIterator<Item = &'a [DVec3; 3]>, p: DVec3) -> f64 {
    corners.into_iter().map(|t| solid_angle(p, *t)).sum::<f64>() / (4.0 * std::f64::consts::PI)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An octahedron of radius one about the origin, faces outwards,
    /// without the faces listed in `open`.
    fn octahedron(open: &[usize]) -> Vec<[DVec3; 3]> {
        let (x, y, z) = (DVec3::X, DVec3::Y, DVec3::Z);
        let faces = [
            [x, y, z],
            [y, -x, z],
            [-x, -y, z],
            [-y, x, z],
            [y, x, -z],
            [-x, y, -z],
            [-y, -x, -z],
            [x, -y, -z],
        ];
        faces
            .iter()
            .enumerate()
            .filter(|(i, _)| !open.contains(i))
            .map(|(_, f)| *f)
            .collect()
    }

    #[test]
    fn a_closed_mesh_winds_once_inside_and_not_outside() {
        let mesh = octahedron(&[]);
        for p in [DVec3::ZERO, DVec3::new(0.2, -0.1, 0.3)] {
            assert!((winding_number(&mesh, p) - 1.0).abs() < 1e-12, "{p}");
        }
        for p in [DVec3::new(2.0, 0.0, 0.0), DVec3::new(0.5, 0.5, 0.5)] {
            assert!(winding_number(&mesh, p).abs() < 1e-12, "{p}");
        }
        // A single face seen from its back: an eighth of the sphere at the centre.
        assert!(
            (solid_angle(DVec3::ZERO, mesh[0]) / (4.0 * std::f64::consts::PI) - 0.125).abs()
                < 1e-12
        );
    }

    #[test]
    fn an_open_shell_is_inside_near_its_surface_and_outside_by_its_opening() {
        // The back half's faces gone: a bowl opening towards −z.
        let bowl = octahedron(&[4, 5, 6, 7]);
        assert!(winding_number(&bowl, DVec3::new(0.1, 0.1, 0.7)) > 0.5);
        assert!(winding_number(&bowl, DVec3::new(0.1, 0.1, -0.3)) < 0.5);
        // In front of it, outside: it turns its outer side to the point.
        assert!(winding_number(&bowl, DVec3::new(0.0, 0.0, 1.5)) < 0.0);
    }
}
