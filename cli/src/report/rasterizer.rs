//! A small software rasterizer for the report's faces: triangle meshes
//! seen from the front (orthographic), hidden surfaces removed by a
//! z-buffer, Gouraud-shaded with one Lambert light, each vertex in its own
//! colour, rendered at twice the size and averaged down.
//!
//! Coordinates are ARKit's face coordinates (metres): +x to the person's
//! left, which is the picture's right; +y up; +z out of the face towards
//! the viewer.

use super::image::Image;
use glam::{DVec2, DVec3};

/// The picture's background.
pub const BACKGROUND: [u8; 3] = [255, 255, 255];

/// Light that reaches every surface.
const AMBIENT: f64 = 0.32;

/// Light from the one lamp, at most.
const DIFFUSE: f64 = 0.68;

/// Towards the lamp: above, left of and in front of the face.
const LIGHT: DVec3 = DVec3::new(-0.35, 0.45, 1.0);

/// Each pixel is the mean of this many samples along each side.
const SUPERSAMPLING: u32 = 2;

/// Which part of the face plane a picture shows: `width × height` pixels,
/// `centre` (x, y in metres) in its middle, `metres_per_pixel` apart.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrontView {
    /// Picture width in pixels.
    pub width: u32,
    /// Picture height in pixels.
    pub height: u32,
    /// The point of the face plane in the picture's centre.
    pub centre: DVec2,
    /// The size of one pixel in metres.
    pub metres_per_pixel: f64,
}

impl FrontView {
    /// The view of `width × height` pixels in which `points` (seen from the
    /// front) fill the picture but for a `margin` (a share of the larger
    /// extent) on every side.
    pub fn framing(points: &[DVec3], width: u32, height: u32, margin: f64) -> FrontView {
        let (lo, hi) = points.iter().fold(
            (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(p.truncate()), hi.max(p.truncate())),
        );
        let (lo, hi) = if lo.x <= hi.x {
            (lo, hi)
        } else {
            (DVec2::ZERO, DVec2::ZERO)
        };
        let extent = (hi - lo).max(DVec2::splat(1e-6)) * (1.0 + 2.0 * margin);
        let metres_per_pixel =
            (extent.x / f64::from(width.max(1))).max(extent.y / f64::from(height.max(1)));
        FrontView {
            width,
            height,
            centre: (lo + hi) / 2.0,
            metres_per_pixel,
        }
    }

    /// Where `p` lands in a picture `scale` times this size: pixel
    /// coordinates (x right, y down) and depth (larger is nearer).
    fn project(&self, p: DVec3, scale: f64) -> DVec3 {
        let d = (p.truncate() - self.centre) / self.metres_per_pixel * scale;
        DVec3::new(
            f64::from(self.width) * scale / 2.0 + d.x,
            f64::from(self.height) * scale / 2.0 - d.y,
            p.z,
        )
    }
}

/// A triangle mesh to draw: positions, triangles as indices into them,
/// and one colour per vertex.
#[derive(Clone, Copy, Debug)]
pub struct Mesh<'a> {
    /// Vertex positions (metres, face coordinates).
    pub positions: &'a [DVec3],
    /// Triangles, indices into `positions`.
    pub triangles: &'a [[u32; 3]],
    /// One sRGB colour per vertex.
    pub colours: &'a [[u8; 3]],
}

/// Renders `meshes` as `view` shows them on [`BACKGROUND`]: the nearest
/// surface at each pixel, shaded per vertex (both sides lit alike, since
/// face masks are open surfaces) and interpolated across each triangle.
pub fn render(meshes: &[Mesh<'_>], view: &FrontView) -> Image {
    let scale = f64::from(SUPERSAMPLING);
    let (w, h) = (view.width * SUPERSAMPLING, view.height * SUPERSAMPLING);
    let mut image = Image::filled(w, h, BACKGROUND);
    let mut depth = vec![f64::NEG_INFINITY; image.pixels.len()];
    for mesh in meshes {
        let shaded = shaded_colours(mesh);
        let screen: Vec<DVec3> = mesh
            .positions
            .iter()
            .map(|p| view.project(*p, scale))
            .collect();
        for t in mesh.triangles {
            let [a, b, c] = t.map(|i| i as usize);
            let (Some(pa), Some(pb), Some(pc)) = (screen.get(a), screen.get(b), screen.get(c))
            else {
                continue;
            };
            let colours = [shaded[a], shaded[b], shaded[c]];
            fill_triangle(&mut image, &mut depth, [*pa, *pb, *pc], colours);
        }
    }
    image.downsampled(SUPERSAMPLING)
}

/// Each vertex's colour lit by the lamp: `colour · (AMBIENT + DIFFUSE ·
/// |n · l|)` with `n` the area-weighted mean normal of its triangles.
fn shaded_colours(mesh: &Mesh<'_>) -> Vec<DVec3> {
    let mut normals = vec![DVec3::ZERO; mesh.positions.len()];
    for t in mesh.triangles {
        let [a, b, c] = t.map(|i| i as usize);
        let (Some(pa), Some(pb), Some(pc)) = (
            mesh.positions.get(a),
            mesh.positions.get(b),
            mesh.positions.get(c),
        ) else {
            continue;
        };
        let n = (*pb - *pa).cross(*pc - *pa);
        for i in [a, b, c] {
            normals[i] += n;
        }
    }
    let light = LIGHT.normalize();
    normals
        .iter()
        .enumerate()
        .map(|(i, n)| {
            let lit = AMBIENT + DIFFUSE * n.normalize_or_zero().dot(light).abs();
            let [r, g, b] = mesh.colours.get(i).copied().unwrap_or([128, 128, 128]);
            DVec3::new(f64::from(r), f64::from(g), f64::from(b)) * lit
        })
        .collect()
}

/// Twice the signed area of the triangle `a, b, p` in the picture plane.
fn edge(a: DVec3, b: DVec3, p: DVec2) -> f64 {
    (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x)
}

/// Draws one triangle (picture coordinates and depth) where it is nearer
/// than what is drawn, colours interpolated barycentrically.
fn fill_triangle(image: &mut Image, depth: &mut [f64], p: [DVec3; 3], colours: [DVec3; 3]) {
    let area = edge(p[0], p[1], p[2].truncate());
    if area.abs() < 1e-12 || !area.is_finite() {
        return;
    }
    let (w, h) = (f64::from(image.width), f64::from(image.height));
    let lo = p[0].min(p[1]).min(p[2]);
    let hi = p[0].max(p[1]).max(p[2]);
    if hi.x < 0.0 || hi.y < 0.0 || lo.x >= w || lo.y >= h {
        return;
    }
    let (x0, y0) = (lo.x.max(0.0) as u32, lo.y.max(0.0) as u32);
    let (x1, y1) = (
        (hi.x.min(w - 1.0)).max(0.0) as u32,
        (hi.y.min(h - 1.0)).max(0.0) as u32,
    );
    for y in y0..=y1 {
        for x in x0..=x1 {
            let q = DVec2::new(f64::from(x) + 0.5, f64::from(y) + 0.5);
            let b0 = edge(p[1], p[2], q) / area;
            let b1 = edge(p[2], p[0], q) / area;
            let b2 = 1.0 - b0 - b1;
            if b0 < 0.0 || b1 < 0.0 || b2 < 0.0 {
                continue;
            }
            let z = b0 * p[0].z + b1 * p[1].z + b2 * p[2].z;
            let i = (y * image.width + x) as usize;
            if z <= depth[i] {
                continue;
            }
            depth[i] = z;
            let c = colours[0] * b0 + colours[1] * b1 + colours[2] * b2;
            image.pixels[i] = [c.x, c.y, c.z].map(|v| v.round().clamp(0.0, 255.0) as u8);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(z: f64, size: f64) -> Vec<DVec3> {
        vec![
            DVec3::new(-size, -size, z),
            DVec3::new(size, -size, z),
            DVec3::new(size, size, z),
            DVec3::new(-size, size, z),
        ]
    }

    const QUAD: [[u32; 3]; 2] = [[0, 1, 2], [0, 2, 3]];

    #[test]
    fn the_nearer_surface_hides_the_farther() {
        let (near, far) = (square(0.01, 0.5), square(0.0, 1.0));
        let red = [[255, 0, 0]; 4];
        let blue = [[0, 0, 255]; 4];
        let view = FrontView::framing(&far, 20, 20, 0.0);
        // Drawn far last: the near square must still show in the middle.
        let image = render(
            &[
                Mesh {
                    positions: &near,
                    triangles: &QUAD,
                    colours: &red,
                },
                Mesh {
                    positions: &far,
                    triangles: &QUAD,
                    colours: &blue,
                },
            ],
            &view,
        );
        let centre = image.pixels[10 * 20 + 10];
        let corner = image.pixels[20 + 1];
        assert!(centre[0] > 200 && centre[2] == 0, "{centre:?}");
        assert!(corner[2] > 200 && corner[0] == 0, "{corner:?}");
    }

    #[test]
    fn a_face_turned_from_the_lamp_is_darker_and_background_stays() {
        let flat = square(0.0, 1.0);
        let tilted: Vec<DVec3> = flat
            .iter()
            .map(|p| DVec3::new(p.x, p.y, -0.9 * p.x))
            .collect();
        let white = [[255, 255, 255]; 4];
        let view = FrontView::framing(&flat, 10, 10, 0.5);
        let lum = |positions: &[DVec3]| {
            let image = render(
                &[Mesh {
                    positions,
                    triangles: &QUAD,
                    colours: &white,
                }],
                &view,
            );
            assert_eq!(image.pixels[0], BACKGROUND, "margin left empty");
            image.pixels[5 * 10 + 5][0]
        };
        // The lamp is to the left (−x): a surface whose normal leans right
        // (z falling with x) faces it less than the flat one does.
        assert!(lum(&tilted) + 40 < lum(&flat));
    }
}
