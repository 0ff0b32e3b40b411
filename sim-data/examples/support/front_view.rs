//! A front view of an avatar as a PNG, for looking at the test avatars:
//! orthographic along −z (the face's front in ARKit's frame), a z-buffer,
//! flat Lambert shading in each primitive's material colour.

use glam::Vec3;
use likeness::avatar::glb::GlbAvatar;

/// Renders `avatar` (its world space mapped to metres, +Y up, face to +z
/// by `to_y_up`) into a PNG `width` pixels wide.
pub fn front_view_png(avatar: &GlbAvatar, to_y_up: impl Fn(Vec3) -> Vec3, width: usize) -> Vec<u8> {
    let parts: Vec<Vec<Vec3>> = avatar
        .avatar
        .parts()
        .iter()
        .map(|p| p.positions.iter().map(|&v| to_y_up(v)).collect())
        .collect();
    let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
    for v in parts.iter().flatten() {
        lo = lo.min(*v);
        hi = hi.max(*v);
    }
    let margin = 0.05 * (hi - lo).max_element();
    let scale = (width as f32) / (hi.x - lo.x + 2.0 * margin);
    let height = ((hi.y - lo.y + 2.0 * margin) * scale).ceil() as usize;
    let to_px = |v: Vec3| {
        Vec3::new(
            (v.x - lo.x + margin) * scale,
            (hi.y + margin - v.y) * scale,
            v.z,
        )
    };
    let mut depth = vec![f32::MIN; width * height];
    let mut rgb = vec![40u8; width * height * 3];
    let light = Vec3::new(0.3, 0.5, 1.0).normalize();
    let json = avatar.json();
    for (part, world) in avatar.avatar.parts().iter().zip(&parts) {
        let material = &json["meshes"][part.mesh]["primitives"][part.primitive]["material"];
        let colour = material
            .as_u64()
            .and_then(|m| {
                json["materials"][m as usize]["pbrMetallicRoughness"]["baseColorFactor"].as_array()
            })
            .map_or([0.6, 0.6, 0.6], |c| {
                [0, 1, 2].map(|i| c[i].as_f64().unwrap_or(0.6) as f32)
            });
        for t in &part.triangles {
            let [a, b, c] = t.map(|i| world[i as usize]);
            let n = (b - a).cross(c - a).normalize_or_zero();
            let shade = 0.25 + 0.75 * n.dot(light).abs();
            let [pa, pb, pc] = [a, b, c].map(to_px);
            let x0 = pa.x.min(pb.x).min(pc.x).floor().max(0.0) as usize;
            let x1 = (pa.x.max(pb.x).max(pc.x).ceil() as usize).min(width - 1);
            let y0 = pa.y.min(pb.y).min(pc.y).floor().max(0.0) as usize;
            let y1 = (pa.y.max(pb.y).max(pc.y).ceil() as usize).min(height - 1);
            let area = (pb.x - pa.x) * (pc.y - pa.y) - (pc.x - pa.x) * (pb.y - pa.y);
            if area.abs() < 1e-12 {
                continue;
            }
            for y in y0..=y1 {
                for x in x0..=x1 {
                    let (px, py) = (x as f32 + 0.5, y as f32 + 0.5);
                    let w0 = ((pb.x - px) * (pc.y - py) - (pc.x - px) * (pb.y - py)) / area;
                    let w1 = ((pc.x - px) * (pa.y - py) - (pa.x - px) * (pc.y - py)) / area;
                    let w2 = 1.0 - w0 - w1;
                    if w0 < 0.0 || w1 < 0.0 || w2 < 0.0 {
                        continue;
                    }
                    let z = w0 * pa.z + w1 * pb.z + w2 * pc.z;
                    let k = y * width + x;
                    if z > depth[k] {
                        depth[k] = z;
                        for (i, c) in colour.iter().enumerate() {
                            rgb[3 * k + i] =
                                (255.0 * (c * shade).clamp(0.0, 1.0).powf(1.0 / 2.2)) as u8;
                        }
                    }
                }
            }
        }
    }
    let mut out = Vec::new();
    let mut encoder = png::Encoder::new(&mut out, width as u32, height as u32);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header().expect("PNG header");
    writer.write_image_data(&rgb).expect("PNG data");
    drop(writer);
    out
}
