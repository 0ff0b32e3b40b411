//! Issue 21's figures for one or more avatars: the committed subjects'
//! shapes implanted into each, and what a user would see wrong, measured
//! against the avatar's own shapes ([`likeness_tests::avatar_quality`]):
//!
//!     cargo run --release -p likeness-tests --example avatar_study -- [--round-trip] [AVATAR.glb …]
//!
//! With no avatar it studies the default avatar. Each avatar also gets the
//! round trip (its own shapes, seen through the registration, as the
//! person); `--round-trip` studies only that. Per avatar and subject
//! it prints whether the face was found (coverage, residual, time), the
//! most torn edges in a shape, how much of each eyeball a blink leaves
//! seen (the avatar's own blink, then the person's), the deepest lid
//! inside an eyeball where the avatar's own shape keeps out, and the
//! GLB's size.

use likeness::avatar::glb::read::{GlbAvatar, read_avatar, read_avatar_bytes};
use likeness_tests::avatar_quality::{figures, round_trip, summary};
use std::path::PathBuf;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let only_round_trip = args.iter().any(|a| a == "--round-trip");
    let paths: Vec<PathBuf> = args
        .iter()
        .filter(|a| *a != "--round-trip")
        .map(PathBuf::from)
        .collect();
    let avatars: Vec<GlbAvatar> = if paths.is_empty() {
        let bytes = likeness_sim::default_avatar::default_avatar_glb().expect("builds");
        vec![read_avatar_bytes(&bytes, "default avatar").expect("reads")]
    } else {
        paths
            .iter()
            .map(|p| read_avatar(p).expect("reads"))
            .collect()
    };
    for glb in &avatars {
        if !only_round_trip {
            for subject in 1..=4 {
                study(glb, subject);
            }
        }
        study_round_trip(glb);
    }
}

fn study(glb: &GlbAvatar, subject: u64) {
    let name = glb.file.display();
    let made = match likeness_tests::committed::personal_avatar_of(subject, glb) {
        Ok(m) => m,
        Err(e) => {
            println!("{name} subject-{subject}: refused: {e}");
            return;
        }
    };
    let found = &made.registration;
    let implanted = made.implanted.as_ref().expect("personalized");
    let f = figures(&glb.avatar, found, implanted);
    println!(
        "{name} subject-{subject}: {}; {} rigid pieces; warnings: {:?}; GLB {:.2} MB",
        summary(found, &f),
        implanted.rigid_pieces.len(),
        made.warnings,
        made.glb.len() as f64 / 1e6,
    );
}

fn study_round_trip(glb: &GlbAvatar) {
    let name = glb.file.display();
    let made = match likeness_tests::committed::round_trip_of(glb) {
        Ok(m) => m,
        Err(e) => {
            println!("{name} round trip: refused: {e}");
            return;
        }
    };
    let implanted = made.implanted.as_ref().expect("personalized");
    let r = round_trip(&glb.avatar, &made.registration, implanted);
    let blinks: String = r
        .blinks
        .iter()
        .map(|(b, own, got)| {
            format!(
                " {b} {:.1}% seen own, {:.1}% round trip;",
                100.0 * own,
                100.0 * got
            )
        })
        .collect();
    println!(
        "{name} round trip: face RMSE at most {:.2}% of the shape's largest motion ({}), \
         worst vertex {:.1}% ({}, vertex {} of part {}, face region: {});{blinks} GLB {:.2} MB",
        100.0 * r.face_rmse_share.0,
        r.face_rmse_share.1,
        100.0 * r.vertex_share.0,
        r.vertex_share.1,
        r.worst_vertex,
        part_of(&glb.avatar, r.worst_vertex),
        made.registration
            .map
            .face
            .iter()
            .any(|f| f.vertex == r.worst_vertex),
        made.glb.len() as f64 / 1e6,
    );
}

/// The name of the part holding avatar vertex `v`.
fn part_of(avatar: &likeness::avatar::Avatar, v: u32) -> String {
    let offsets = avatar.vertex_offsets();
    (0..avatar.parts().len())
        .find(|&i| (offsets[i]..offsets[i + 1]).contains(&(v as usize)))
        .map_or("?".into(), |i| avatar.parts()[i].name.clone())
}
