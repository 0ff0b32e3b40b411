//! Shapes the geometry's tests are built on (tests only).

use glam::DVec3;

/// A UV sphere of radius 1 (`rings` × `segments`, fans at both
/// poles, faces outwards): the crowded poles a uniform grid chokes on.
pub fn uv_sphere(rings: usize, segments: usize) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let mut positions = vec![DVec3::Z, -DVec3::Z];
    for r in 1..rings {
        let theta = std::f64::consts::PI * r as f64 / rings as f64;
        for s in 0..segments {
            let phi = std::f64::consts::TAU * s as f64 / segments as f64;
            positions.push(DVec3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            ));
        }
    }
    let at = |r: usize, s: usize| (2 + (r - 1) * segments + s % segments) as u32;
    let mut triangles = Vec::new();
    for s in 0..segments {
        triangles.push([0, at(1, s), at(1, s + 1)]);
        triangles.push([1, at(rings - 1, s + 1), at(rings - 1, s)]);
        for r in 1..rings - 1 {
            triangles.push([at(r, s), at(r + 1, s), at(r + 1, s + 1)]);
            triangles.push([at(r, s), at(r + 1, s + 1), at(r, s + 1)]);
        }
    }
    (positions, triangles)
}
