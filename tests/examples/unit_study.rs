//! The same avatar in other units gives the same shapes? Subject `SEED`
//! (default 1) implanted into an avatar (`AVATAR=path.glb`, default: the
//! default avatar) and into it wrapped in a parent node that scales by
//! `SCALE` (default 100) and turns by `DEGREES` about +X (default 90: +Y
//! up to +Z up); the registrations, the retargetings, the implants and the
//! shapes compared in the first one's frame.
//!
//! `cargo run --release -p likeness-tests --example unit_study`

use likeness::Blendshape;
use likeness::avatar::glb::read::read_avatar_bytes;
use likeness::avatar::personal_avatar::PersonalAvatar;
use likeness_tests::units::{Wrapping, shape_difference};

fn env_or<T: std::str::FromStr>(name: &str, default: T) -> T {
    std::env::var(name).map_or(default, |s| s.parse().ok().expect(name))
}

fn main() {
    let seed: u64 = env_or("SEED", 1);
    let wrapping = Wrapping {
        scale: env_or("SCALE", 100.0),
        degrees: env_or("DEGREES", 90.0),
    };
    let bytes = match std::env::var("AVATAR") {
        Ok(path) => std::fs::read(path).expect("reads"),
        Err(_) => likeness_sim::default_avatar::default_avatar_glb().expect("writes"),
    };
    let plain = read_avatar_bytes(&bytes, "plain").expect("reads");
    let wrapped = read_avatar_bytes(&wrapping.wrap(&bytes), "wrapped").expect("reads");
    let a = likeness_tests::committed::personal_avatar_of(seed, &plain).expect("plain");
    let b = likeness_tests::committed::personal_avatar_of(seed, &wrapped).expect("wrapped");
    for (name, made) in [("plain", &a), ("wrapped", &b)] {
        describe(name, made);
    }
    let mm = a.registration.similarity.scale * 1e-3;
    let mask = a
        .registration
        .mask_on_avatar
        .iter()
        .zip(&b.registration.mask_on_avatar)
        .map(|(p, q)| (*p - wrapping.unwrap(*q)).length())
        .fold(0.0, f64::max);
    eprintln!("registered mask differs by up to {:.4} mm", mask / mm);
    let weights = a
        .retargeting
        .weights
        .iter()
        .flatten()
        .zip(b.retargeting.weights.iter().flatten())
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    eprintln!("retargeting weights differ by up to {weights:.4}");
    let shapes = |m: &PersonalAvatar| m.implanted.as_ref().expect("implanted").shapes.clone();
    let d = shape_difference(&shapes(&a), &shapes(&b), wrapping);
    for (shape, share) in Blendshape::ALL.iter().zip(&d.per_shape) {
        if *share > 1e-3 {
            eprintln!("{:>22}: {:.3}% of its motion", shape.name(), 100.0 * share);
        }
    }
    println!(
        "seed {seed}: RMS difference {:.4}% of the motion, largest {:.4} mm (mask scale) in {}",
        100.0 * d.rms_share,
        d.largest.0 / mm,
        Blendshape::ALL[d.largest.1].name()
    );
}

/// One line on the registration and the implant.
fn describe(name: &str, made: &PersonalAvatar) {
    let r = &made.registration;
    let i = made.implanted.as_ref().expect("implanted");
    eprintln!(
        "{name}: residual {:.4} mm, coverage {:.4}, ICP iterations {}, face vertices {}, creases {} -> {}",
        r.residual_mean_mm,
        r.coverage,
        r.icp_iterations,
        i.face_vertices,
        i.creases_found,
        i.creases_left
    );
}
