//! The avatar step of `likeness demo`: the person's shapes on the default
//! avatar, written to the current folder, and a picture of the faces.

use crate::CliResult;
use crate::avatar::default_glb;
use likeness::Session;
use likeness::avatar::person_face::take_face;
use likeness::avatar::personal_avatar::{AvatarShapes, PersonInput, RestFace, personal_avatar};
use likeness::avatar::rest_check::{rest_creases, scan_bend};
use likeness::io::atomic_write::write_atomically;
use likeness::personalize::{Method, personalize};
use std::path::Path;
use std::time::Instant;

/// Where `likeness demo` writes the person's avatar: in the current folder.
pub const DEMO_AVATAR: &str = "likeness-demo-avatar.glb";

/// Where `likeness demo` writes its preview of the faces: the default
/// avatar's stock face, the person's and another person's, side by side.
pub const DEMO_FACES: &str = "likeness-demo-faces.png";

/// The avatar step of `likeness demo`: the session's personalized shapes
/// (`method`) implanted into the default avatar wearing the person's face,
/// summarized, and written to [`DEMO_AVATAR`] in the current folder; then
/// the preview [`DEMO_FACES`]: the default avatar's stock face, the
/// person's (`name`) and `other`'s (a second person, `other_name`) side by
/// side, each taken from their own neutral scan.
pub fn demo_avatar(
    session: &Session,
    name: &str,
    other: &Session,
    other_name: &str,
    method: Method,
) -> CliResult {
    let started = Instant::now();
    let personalized = personalize(session, method)?;
    let glb = default_glb()?;
    let rig = session.template.blendshapes()?;
    let person = PersonInput {
        mask: &session.topology,
        rig: &rig,
        personalized: &personalized.shapes,
    };
    let made = personal_avatar(
        &glb,
        &person,
        None,
        AvatarShapes::Personalized,
        RestFace::Person,
        &mut |_| true,
    )?;
    for warning in &made.warnings {
        eprintln!("warning: {warning}");
    }
    let (registration, implanted) = (&made.registration, &made.implanted);
    println!(
        "Default avatar: {} vertices in {} meshes; face found on {} of them, registration residual mean {:.3} mm, max {:.3} mm ({:.2} s)",
        glb.avatar.vertex_count(),
        glb.avatar.meshes().len(),
        registration.map.face.len(),
        registration.residual_mean_mm,
        registration.residual_max_mm,
        registration.seconds
    );
    let out = Path::new(DEMO_AVATAR);
    write_atomically(out, &made.glb).map_err(|e| format!("{}: {e}", out.display()))?;
    let absolute = std::fs::canonicalize(out).unwrap_or_else(|_| out.to_path_buf());
    if let Some(implanted) = implanted {
        println!(
            "The person's 52 shapes ({method}) implanted: {} face vertices, {} next to them; {:.2} s in all",
            implanted.face_vertices,
            implanted.adjacent_vertices,
            started.elapsed().as_secs_f64()
        );
    }
    println!(
        "Wrote {} ({:.1} MB): open it in Blender (File → Import → glTF) and try its 52 shape keys.",
        absolute.display(),
        made.glb.len() as f64 / 1e6
    );
    let other_neutral = personalize(other, method)?.shapes;
    let other_face = take_face(&glb.avatar, registration, other_neutral.neutral())?;
    // The product's own rule: a face that would crease the skin is not
    // taken, and the picture says so rather than show it.
    let bend = scan_bend(&glb.avatar, registration, other_neutral.neutral());
    let other_creases = rest_creases(&glb.avatar, registration, &other_face.moved, &bend);
    if let Some(creases) = &other_creases {
        eprintln!("warning: {other_name}: {creases}");
    }
    let mouth_parts: Vec<usize> = implanted.as_ref().map_or(Vec::new(), |i| {
        i.rigid_parts
            .iter()
            .copied()
            .filter(|p| !registration.eyeball_parts().contains(p))
            .collect()
    });
    let faces = [
        ("stock face", &glb.avatar),
        (name, made.shaped(&glb.avatar)),
        (
            other_name,
            match other_creases {
                None => &other_face.avatar,
                Some(_) => &glb.avatar,
            },
        ),
    ];
    let out = Path::new(DEMO_FACES);
    let (w, h) = crate::avatar_preview::write_faces(
        &glb.avatar,
        registration,
        &mouth_parts,
        &crate::avatar_preview::vertex_colours(&glb),
        &faces,
        out,
    )
    .map_err(|e| format!("{}: {e}", out.display()))?;
    let kept: Vec<&str> = [
        (name, made.taken_face.is_none()),
        (other_name, other_creases.is_some()),
    ]
    .iter()
    .filter(|(_, kept)| *kept)
    .map(|(n, _)| *n)
    .collect();
    let kept = match kept.is_empty() {
        true => String::new(),
        false => format!(
            " (the stock face for {}: taking the scan would crease the skin)",
            kept.join(" and ")
        ),
    };
    println!(
        "Wrote {} ({w} × {h}): the default avatar's stock face, then {name}'s and {other_name}'s, each from their own neutral scan{kept}, from the front and the side.",
        out.display()
    );
    Ok(())
}
