//! Writes every generated test avatar as `OUTDIR/NAME.glb`, and with
//! `--png` a front view `OUTDIR/NAME.png` of each as the core's reader
//! places it (world space mapped to metres, +Y up).
//!
//!     cargo run --release -p likeness-sim --example write_avatar_variants -- OUTDIR [--png]

#[path = "support/front_view.rs"]
mod front_view;

use glam::Vec3;
use likeness::avatar::glb::read_avatar_bytes;
use likeness_sim::avatar_variants::{UpAxis, avatar_variants};
use std::path::PathBuf;
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(out) = args
        .iter()
        .find(|a| !a.starts_with("--"))
        .map(PathBuf::from)
    else {
        eprintln!("usage: write_avatar_variants OUTDIR [--png]");
        std::process::exit(2);
    };
    let png = args.iter().any(|a| a == "--png");
    std::fs::create_dir_all(&out).expect("create OUTDIR");
    let start = Instant::now();
    let variants = avatar_variants();
    println!(
        "built {} variants in {:.2} s",
        variants.len(),
        start.elapsed().as_secs_f64()
    );
    for v in &variants {
        let file = out.join(format!("{}.glb", v.name));
        std::fs::write(&file, &v.glb).expect("write GLB");
        println!(
            "{} ({:.1} MB): {} meshes, head {} vertices ({} face) — {}",
            file.display(),
            v.glb.len() as f64 / 1e6,
            v.truth.meshes,
            v.truth.head_vertices,
            v.truth.face_vertices,
            v.description
        );
        let read = read_avatar_bytes(&v.glb, v.name).expect("the core reads every variant");
        println!(
            "    {} vertices in {} parts",
            read.avatar.vertex_count(),
            read.avatar.parts().len()
        );
        if png {
            let t = &v.truth;
            let to_y_up = |p: Vec3| {
                let q = p * t.unit_to_metres;
                match t.up {
                    UpAxis::Y => q,
                    UpAxis::Z => Vec3::new(q.x, q.z, -q.y),
                }
            };
            let image = front_view::front_view_png(&read, to_y_up, 600);
            std::fs::write(out.join(format!("{}.png", v.name)), image).expect("write PNG");
        }
    }
}
