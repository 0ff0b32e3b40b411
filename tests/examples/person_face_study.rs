//! The checks of the person's face on the default avatar
//! (`tests/tests/person_face.rs`), printed for any subjects: the committed
//! ones (1–4) are read, others simulated from their seed.
//!
//! ```text
//! cargo run --release -p likeness-tests --example person_face_study -- 1 2 3 4 10 11
//! ```
//!
//! For each subject: the time of the whole avatar step and of taking the
//! face, then every figure of [`FaceChecks`]. The stock avatar's own
//! self-intersections and teeth in front come first, as the baseline.

use glam::DVec3;
use likeness::avatar::glb::read_avatar_bytes;
use likeness::avatar::personal_avatar::{AvatarShapes, PersonInput, RestFace, personal_avatar};
use likeness::avatar::registration::find_face;
use likeness::personalize::{Method, personalize};
use likeness_tests::face_checks::{
    FaceChecks, face_checks, self_intersections, teeth_and_gums, teeth_in_front,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let bytes = likeness_sim::default_avatar::default_avatar_glb()?;
    let glb = read_avatar_bytes(&bytes, "default avatar")?;
    let teeth = teeth_and_gums(&glb.avatar);
    let stock: Vec<DVec3> = glb
        .avatar
        .positions()
        .iter()
        .map(|p| p.as_dvec3())
        .collect();
    let skin = glb.avatar.part_triangles(&[0]);
    let session = likeness_tests::committed::read(1)?;
    let rig = session.template.blendshapes()?;
    let found = find_face(&glb.avatar, &session.topology, &rig)?;
    println!(
        "stock avatar: {} self-intersecting triangle pairs, {} teeth vertices in front of the lips",
        self_intersections(&stock, &skin),
        teeth_in_front(&stock, &found, &session.topology, &teeth)
    );

    for arg in std::env::args().skip(1) {
        let seed: u64 = arg.parse()?;
        let session = if (1..=4).contains(&seed) {
            likeness_tests::committed::read(seed)?
        } else {
            likeness_sim::capture_session::simulate_session(seed)
        };
        let rig = session.template.blendshapes()?;
        let person = personalize(&session, Method::DEFAULT)?.shapes;
        let input = PersonInput {
            mask: &session.topology,
            rig: &rig,
            personalized: &person,
        };
        let started = std::time::Instant::now();
        let made = personal_avatar(
            &glb,
            &input,
            None,
            AvatarShapes::Personalized,
            RestFace::Person,
            &mut |_| true,
        )?;
        let seconds = started.elapsed().as_secs_f64();
        let taking = made.taken_face.as_ref().map_or(0.0, |t| t.seconds);
        let c: FaceChecks = face_checks(&glb.avatar, &session.topology, &made, &person, &teeth);
        println!("subject {seed}: {seconds:.2} s (taking the face {taking:.3} s)\n  {c:?}");
    }
    Ok(())
}
