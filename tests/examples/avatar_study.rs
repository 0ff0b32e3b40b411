//! Issue 21's figures for one or more avatars: the committed subjects'
//! shapes implanted into each, and what a user would see wrong, measured
//! against the avatar's own shapes ([`likeness_tests::avatar_quality`]):
//!
//!     cargo run --release -p likeness-tests --example avatar_study -- [AVATAR.glb …]
//!
//! With no argument it studies the default avatar. Per avatar and subject
//! it prints whether the face was found (coverage, residual, time), the
//! most torn edges in a shape, how much of each eyeball a blink leaves
//! seen (the avatar's own blink, then the person's), the deepest lid
//! inside an eyeball where the avatar's own shape keeps out, and the
//! GLB's size.

use likeness::avatar::glb::read::{GlbAvatar, read_avatar, read_avatar_bytes};
use likeness_tests::avatar_quality::{figures, summary};
use std::path::PathBuf;

fn main() {
    let paths: Vec<PathBuf> = std::env::args().skip(1).map(PathBuf::from).collect();
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
        for subject in 1..=4 {
            study(glb, subject);
        }
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
