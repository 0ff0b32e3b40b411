//! The avatar stage for people simulated on either mask: the simulator's
//! own and ARKit's own mesh (`../shared/arkit-face/`), on each avatar.
//!
//! ```text
//! cargo run --release -p likeness-tests --example mask_study -- [SEEDS…]
//! ```
//!
//! For each avatar (the default, its generated variants, and ICT-FaceKit
//! and the MPFB body where `../shared/avatars/` has them), each mask and
//! each seed (default 1–5): the registration's time and residual, the
//! face match (own face, default avatar), the largest change at rest, the
//! most torn edges and folded triangles over the shapes, each blink's
//! eyeball seen (own, personalized), the deepest lid, and the checks'
//! warnings. `AVATARS=a,b` keeps only those avatars; `TAKE_FACE=1` takes
//! the person's face on every avatar (as `likeness avatar --take-face`),
//! not only on the default one.

use likeness::avatar::glb::{GlbAvatar, read_avatar, read_avatar_bytes};
use likeness::avatar::personal_avatar::{AvatarShapes, PersonInput, RestFace, personal_avatar};
use likeness::avatar::registration::find_face;
use likeness_sim::arkit_face::shared_arkit_face;
use likeness_sim::face_basis::FaceBasis;
use likeness_tests::arkit_people::{ArkitPerson, study_seeds};
use std::path::Path;

fn avatars() -> Result<Vec<(String, GlbAvatar)>, Box<dyn std::error::Error>> {
    let mut out = vec![(
        "default".to_string(),
        read_avatar_bytes(
            &likeness_sim::default_avatar::default_avatar_glb()?,
            "default",
        )?,
    )];
    let only: Option<String> = std::env::var("AVATARS").ok();
    for v in likeness_sim::avatar_variants::avatar_variants() {
        out.push((v.name.to_string(), read_avatar_bytes(&v.glb, v.name)?));
    }
    let shared = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/avatars");
    for name in ["ict-facekit", "mpfb-makehuman"] {
        let path = shared.join(format!("{name}.glb"));
        if path.exists() {
            out.push((name.to_string(), read_avatar(&path)?));
        }
    }
    if let Some(only) = only {
        out.retain(|(n, _)| only.split(',').any(|o| o == n));
    }
    Ok(out)
}

/// The most head triangles one shape folds, and that shape.
fn most_folded(
    made: &likeness::avatar::personal_avatar::PersonalAvatar,
    stock: &likeness::avatar::Avatar,
) -> (usize, likeness::Blendshape) {
    use likeness::avatar::implant_check::{folded_triangles, head_triangles, own_shape};
    let avatar = made.shaped(stock);
    let found = made.shaped_registration();
    let rest = avatar.positions();
    let triangles = head_triangles(avatar, found);
    let shapes = &made.implanted.as_ref().expect("personalized").shapes;
    likeness::Blendshape::ALL
        .iter()
        .map(|b| {
            let n = folded_triangles(
                &rest,
                &own_shape(avatar, *b),
                &shapes[b.index()],
                &triangles,
            )
            .len();
            (n, *b)
        })
        .max_by_key(|x| x.0)
        .expect("52 shapes")
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // TAKE_FACE=1: the person's face on every avatar, as `--take-face`.
    let asked_face = std::env::var("TAKE_FACE")
        .is_ok()
        .then_some(RestFace::Person);
    let seeds = study_seeds()?;
    let mut bases = vec![FaceBasis::Simulator];
    if let Some(face) = shared_arkit_face() {
        bases.push(FaceBasis::Arkit(face));
    }
    let mut people = Vec::new();
    for basis in &bases {
        for &seed in &seeds {
            let p = ArkitPerson::simulate(*basis, seed);
            people.push((*basis, seed, p.session, p.rig, p.personalized));
        }
    }
    for (name, glb) in avatars()? {
        for (basis, seed, session, rig, person) in &people {
            let (basis, seed) = (*basis, *seed);
            {
                let input = PersonInput {
                    mask: &session.topology,
                    rig,
                    personalized: person,
                };
                let started = std::time::Instant::now();
                let found = match find_face(&glb.avatar, &session.topology, rig) {
                    Ok(f) => f,
                    Err(e) => {
                        println!("{name} {} {seed}: registration refused: {e}", basis.name());
                        continue;
                    }
                };
                let registration_s = started.elapsed().as_secs_f64();
                let face = RestFace::chosen(name == "default", asked_face);
                let made = personal_avatar(
                    &glb,
                    &input,
                    Some(found.clone()),
                    AvatarShapes::Personalized,
                    face,
                    &mut |_| true,
                );
                let whole = started.elapsed().as_secs_f64();
                match made {
                    Err(e) => println!("{name} {} {seed}: refused: {e}", basis.name()),
                    Ok(made) => {
                        let shaped = made.shaped(&glb.avatar);
                        let f = likeness_tests::avatar_quality::figures(
                            shaped,
                            made.shaped_registration(),
                            made.implanted.as_ref().expect("personalized"),
                        );
                        let taken = made.taken_face.as_ref().map(|t| {
                            format!(
                                "face to the scan {:.3} mm mean, {:.2} mm p95 ({} points left out), largest change {:.1} mm; ",
                                t.surface_mean_mm, t.surface_p95_mm, t.points_left_out.len(), t.largest_mm
                            )
                        });
                        let folded = most_folded(&made, &glb.avatar);
                        println!(
                            "{name} {} {seed}: {:.2} s ({registration_s:.2} s registration, residual {:.3} mm); {}{}; most folded {folded:?}; warnings: {:?}",
                            basis.name(),
                            whole,
                            found.residual_mean_mm,
                            taken.unwrap_or_default(),
                            likeness_tests::avatar_quality::summary(made.shaped_registration(), &f),
                            made.warnings
                                .iter()
                                .map(|w| w.to_string())
                                .collect::<Vec<_>>(),
                        );
                    }
                }
            }
        }
    }
    Ok(())
}
