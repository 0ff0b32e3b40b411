//! Writes the default avatar as OBJ files, neutral and under a few shapes,
//! for `tools/render_avatar.py`:
//!
//!     cargo run --release -p likeness-sim --example dump_avatar -- OUT_DIR
//!
//! One file per pose, one `o` group per part, named after the part.

use likeness_sim::default_avatar::default_avatar;
use std::fmt::Write as _;
use std::time::Instant;

fn main() -> std::io::Result<()> {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "avatar-obj".into());
    std::fs::create_dir_all(&out)?;
    let start = Instant::now();
    let dflt = default_avatar();
    let avatar = &dflt.avatar;
    eprintln!("built in {:.3} s", start.elapsed().as_secs_f64());
    for p in avatar.parts() {
        eprintln!(
            "{}: {} vertices, {} triangles",
            p.name,
            p.positions.len(),
            p.triangles.len()
        );
    }
    eprintln!(
        "total {} vertices, face {}",
        avatar.vertex_count(),
        default_avatar().true_correspondence.len()
    );
    let poses: Vec<(&str, Vec<(&str, f32)>)> = vec![
        ("neutral", vec![]),
        ("jawOpen", vec![("jawOpen", 1.0)]),
        ("eyeBlinkLeft", vec![("eyeBlinkLeft", 1.0)]),
        (
            "eyeLookOutLeft",
            vec![("eyeLookOutLeft", 1.0), ("eyeLookInRight", 1.0)],
        ),
        ("mouthSmileLeft", vec![("mouthSmileLeft", 1.0)]),
        ("tongueOut", vec![("tongueOut", 1.0), ("jawOpen", 0.5)]),
        ("cheekPuff", vec![("cheekPuff", 1.0)]),
    ];
    for (pose, weights) in poses {
        let mut text = String::new();
        let mut base = 1;
        for part in avatar.parts() {
            let names = &avatar.meshes()[part.mesh].target_names;
            let mut pos = part.positions.clone();
            for (name, w) in &weights {
                if let Some(t) = names.iter().position(|n| n == name) {
                    for (p, d) in pos.iter_mut().zip(&part.targets[t]) {
                        *p += *w * *d;
                    }
                }
            }
            let _ = writeln!(text, "o {}", part.name);
            for p in &pos {
                let _ = writeln!(text, "v {} {} {}", p.x, p.y, p.z);
            }
            // An eye's cornea (within 32° of its rest axis) goes to its own
            // group, `<eye>Iris`, so the renders show where it looks.
            let centre = match part.name.as_str() {
                "eyeLeft" => Some(dflt.eye_centres[0]),
                "eyeRight" => Some(dflt.eye_centres[1]),
                _ => None,
            };
            let is_iris = |t: &[u32; 3]| {
                centre.is_some_and(|c| {
                    let m = t
                        .iter()
                        .map(|&i| part.positions[i as usize])
                        .sum::<glam::Vec3>()
                        / 3.0;
                    (m - c).normalize().z > 32f32.to_radians().cos()
                })
            };
            for iris in [false, true] {
                if iris {
                    let _ = writeln!(text, "o {}Iris", part.name);
                }
                for t in part.triangles.iter().filter(|t| is_iris(t) == iris) {
                    let _ = writeln!(text, "f {} {} {}", t[0] + base, t[1] + base, t[2] + base);
                }
            }
            base += pos.len() as u32;
        }
        std::fs::write(format!("{out}/{pose}.obj"), text)?;
    }
    Ok(())
}
