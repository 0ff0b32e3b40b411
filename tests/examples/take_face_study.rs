//! Taking the person's face on the default avatar, whatever the crease
//! check would decide (`person_face::take_face` alone), for people
//! simulated on either mask: how far the scan lies from the new skin, how
//! many head edges the new rest creases (the check's rule,
//! `rest_check::REST_CREASE_ANGLE`), and how many of those crease by more
//! than the scan itself bends the mask there (the rule the shapes' crease
//! smoothing uses: the person's own bend plus 22.5°).
//!
//! ```text
//! cargo run --release -p likeness-tests --example take_face_study -- [SEEDS…]
//! ```
//!
//! The figures behind issue 41's point 3 (`docs/avatar.md`).

use glam::DVec3;
use likeness::avatar::Avatar;
use likeness::avatar::glb::read_avatar_bytes;
use likeness::avatar::implant_check::head_triangles;
use likeness::avatar::person_face::{TakenFace, take_face};
use likeness::avatar::registration::{FaceRegistration, find_face};
use likeness::avatar::rest_check::REST_CREASE_ANGLE;
use likeness::geometry::dihedral_angle::Hinges;
use likeness_sim::arkit_face::shared_arkit_face;
use likeness_sim::face_basis::FaceBasis;
use likeness_tests::arkit_people::{ArkitPerson, study_seeds};
use std::f64::consts::FRAC_PI_8;

/// For each avatar vertex, how much the scanned neutral bends the
/// registered mask at the mask triangle the map takes it to: the largest
/// change of a dihedral angle at the triangle's edges (radians).
fn scan_bend(avatar: &Avatar, found: &FaceRegistration, neutral: &[DVec3]) -> Vec<f64> {
    let s = found.similarity;
    let on_avatar = &found.mask_on_avatar;
    let change: Vec<DVec3> = neutral
        .iter()
        .zip(on_avatar)
        .map(|(p, m)| s.apply(*p) - *m)
        .collect();
    let hinges = Hinges::new(on_avatar, &found.map.mask_triangles);
    let at_triangle = hinges.largest_at_triangles(&hinges.changes(on_avatar, &change));
    let mut bend = vec![0.0; avatar.vertex_count()];
    for f in &found.map.face {
        bend[f.vertex as usize] = at_triangle[f.triangle as usize];
    }
    bend
}

/// The head edges the new rest creases, and those among them creased by
/// more than the scan bends the mask there plus 22.5°.
fn creases(
    avatar: &Avatar,
    found: &FaceRegistration,
    taken: &TakenFace,
    bend: &[f64],
) -> (usize, usize) {
    let rest: Vec<DVec3> = avatar.positions().iter().map(|p| p.as_dvec3()).collect();
    let hinges = Hinges::new(&rest, &head_triangles(avatar, found));
    let changes = hinges.changes(&rest, &taken.moved);
    let creased: Vec<usize> = (0..changes.len())
        .filter(|&k| changes[k] > REST_CREASE_ANGLE)
        .collect();
    let beyond = creased
        .iter()
        .filter(|&&k| {
            let allowed = hinges.pairs()[k]
                .iter()
                .flat_map(|&t| hinges.triangles()[t])
                .map(|v| bend[v as usize])
                .fold(0.0, f64::max);
            changes[k] > allowed + FRAC_PI_8
        })
        .count();
    (creased.len(), beyond)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let seeds = study_seeds()?;
    let glb = read_avatar_bytes(
        &likeness_sim::default_avatar::default_avatar_glb()?,
        "default",
    )?;
    let mut bases = vec![FaceBasis::Simulator];
    if let Some(face) = shared_arkit_face() {
        bases.push(FaceBasis::Arkit(face));
    }
    for basis in &bases {
        for &seed in &seeds {
            let person = ArkitPerson::simulate(*basis, seed);
            let (session, rig) = (&person.session, &person.rig);
            let neutral = person.personalized.neutral();
            let found = find_face(&glb.avatar, &session.topology, rig)?;
            let taken = take_face(&glb.avatar, &found, neutral)?;
            let bend = scan_bend(&glb.avatar, &found, neutral);
            let (creased, beyond) = creases(&glb.avatar, &found, &taken, &bend);
            println!(
                "{} {seed}: scan to skin {:.3} mm mean, {:.2} mm p95; points {:.3} mm mean, {:.2} mm max, {} left out; largest change {:.1} mm; {:.2} s; creased edges {creased}, {beyond} past the scan's own bend",
                basis.name(),
                taken.surface_mean_mm,
                taken.surface_p95_mm,
                taken.fit_mean_mm,
                taken.fit_max_mm,
                taken.points_left_out.len(),
                taken.largest_mm,
                taken.seconds,
            );
        }
    }
    Ok(())
}
