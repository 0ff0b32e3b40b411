//! Which triangles of a mesh are seen from one direction: the surface a
//! depth camera facing the mesh would measure. The TrueDepth camera sees a
//! face from the front, so the ARKit mask is the front-visible skin: teeth
//! behind closed lips, the mouth's lining, the inside of the nostrils and
//! the back of an eye socket are never part of it, and registering the
//! mask onto them is always wrong.
//!
//! An orthographic depth buffer along the direction `d` (towards the
//! viewer) with square pixels of side `pixel`: each triangle is
//! rasterized (pixel centres inside its projection, depth `p · d`
//! interpolated), and each pixel keeps the largest depth. A triangle is
//! visible when one of its corners or its centroid lies within one pixel
//! of depth of the front-most surface at its pixel: small triangles, which
//! no pixel centre falls in, and triangles seen edge-on count too.

use glam::{DVec2, DVec3};

/// Most pixels along a side of the buffer: `pixel` is enlarged to keep
/// the buffer at most this many pixels square.
pub const MAX_PIXELS_PER_SIDE: usize = 2048;

/// Whether each triangle of `triangles` over `positions` is seen from
/// direction `towards_viewer` (module docs); degenerate directions see
/// nothing.
pub fn visible_from(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    towards_viewer: DVec3,
    pixel: f64,
) -> Vec<bool> {
    let d = towards_viewer.normalize_or_zero();
    if d == DVec3::ZERO || pixel.is_nan() || pixel <= 0.0 || triangles.is_empty() {
        return vec![false; triangles.len()];
    }
    let u = d.any_orthonormal_vector();
    let v = d.cross(u);
    let project = |p: DVec3| (DVec2::new(p.dot(u), p.dot(v)), p.dot(d));
    let corners = |t: &[u32; 3]| t.map(|i| positions.get(i as usize).copied().unwrap_or_default());
    let (lo, hi) = triangles.iter().flat_map(corners).fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| {
            let (q, _) = project(p);
            (lo.min(q), hi.max(q))
        },
    );
    let span = hi - lo;
    let pixel = pixel.max(span.max_element() / MAX_PIXELS_PER_SIDE as f64);
    let width = (span.x / pixel) as usize + 1;
    let height = (span.y / pixel) as usize + 1;
    let cell = |q: DVec2| {
        let c = ((q - lo) / pixel).floor();
        (
            c.x.clamp(0.0, (width - 1) as f64) as usize,
            c.y.clamp(0.0, (height - 1) as f64) as usize,
        )
    };
    let mut depth = vec![f64::NEG_INFINITY; width * height];
    for t in triangles {
        let [a, b, c] = corners(t).map(project);
        let area = cross(b.0 - a.0, c.0 - a.0);
        let (min, max) = (a.0.min(b.0).min(c.0), a.0.max(b.0).max(c.0));
        let (x0, y0) = cell(min);
        let (x1, y1) = cell(max);
        for y in y0..=y1 {
            for x in x0..=x1 {
                let q = lo + (DVec2::new(x as f64, y as f64) + 0.5) * pixel;
                if area == 0.0 {
                    continue;
                }
                let wa = cross(b.0 - q, c.0 - q) / area;
                let wb = cross(c.0 - q, a.0 - q) / area;
                let wc = 1.0 - wa - wb;
                if wa >= 0.0 && wb >= 0.0 && wc >= 0.0 {
                    let z = wa * a.1 + wb * b.1 + wc * c.1;
                    let slot = &mut depth[y * width + x];
                    *slot = slot.max(z);
                }
            }
        }
        // Corners and centroid too, for triangles smaller than a pixel.
        let centroid = ((a.0 + b.0 + c.0) / 3.0, (a.1 + b.1 + c.1) / 3.0);
        for (q, z) in [a, b, c, centroid] {
            let (x, y) = cell(q);
            let slot = &mut depth[y * width + x];
            *slot = slot.max(z);
        }
    }
    triangles
        .iter()
        .map(|t| {
            let [a, b, c] = corners(t).map(project);
            let centroid = ((a.0 + b.0 + c.0) / 3.0, (a.1 + b.1 + c.1) / 3.0);
            [a, b, c, centroid].iter().any(|(q, z)| {
                let (x, y) = cell(*q);
                *z >= depth[y * width + x] - pixel
            })
        })
        .collect()
}

/// The z component of the 2-D cross product.
fn cross(a: DVec2, b: DVec2) -> f64 {
    a.x * b.y - a.y * b.x
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two parallel unit squares facing +z, at z = 0 and z = −1, and a
    /// small square off to the side at z = −1.
    #[test]
    fn a_surface_behind_another_is_hidden_and_one_beside_it_is_not() {
        let square = |x: f64, z: f64| {
            [
                DVec3::new(x, 0.0, z),
                DVec3::new(x + 1.0, 0.0, z),
                DVec3::new(x + 1.0, 1.0, z),
                DVec3::new(x, 1.0, z),
            ]
        };
        let positions: Vec<DVec3> =
            [square(0.0, 0.0), square(0.0, -1.0), square(2.0, -1.0)].concat();
        let triangles: Vec<[u32; 3]> = (0..3u32)
            .flat_map(|s| [[4 * s, 4 * s + 1, 4 * s + 2], [4 * s, 4 * s + 2, 4 * s + 3]])
            .collect();
        let seen = visible_from(&positions, &triangles, DVec3::Z, 0.05);
        assert_eq!(seen, vec![true, true, false, false, true, true]);
        // From behind, the back square hides the front one.
        let seen = visible_from(&positions, &triangles, -DVec3::Z, 0.05);
        assert_eq!(seen, vec![false, false, true, true, true, true]);
    }
}
