//! Issue 22: the person's own face on the default avatar
//! (`likeness::avatar::person_face`). The committed subjects' scanned
//! neutrals taken onto the default avatar's rest, and the checks of the
//! issue's point 2 on each ([`likeness_tests::face_checks`]): the new rest
//! through the scan, no strain seam at the face's border, no skin
//! through skin, no lid in an eyeball, closing blinks, no tooth in front
//! of the lips, the round trip, and two people who look different.

use glam::DVec3;
use likeness::Blendshape;
use likeness::avatar::glb::read::{GlbAvatar, read_avatar_bytes};
use likeness::avatar::personal_avatar::{PersonalAvatar, RestFace};
use likeness::personalize::{Method, personalize};
use likeness_tests::avatar_quality::round_trip;
use likeness_tests::bend::largest_bend;
use likeness_tests::committed::{personal_avatar_with, round_trip_with};
use likeness_tests::face_checks::{face_checks, self_intersections, teeth_and_gums};

/// The sharpest bend jawOpen may make at a skin edge beyond the face
/// (degrees). Model 2 of the simulator, whose chin swung straight back
/// into a neck rising right under it, made 38° there: a crease across the
/// throat in every render. ICT-FaceKit's own jawOpen bends its neck by
/// 8° at most.
const NECK_BEND_DEGREES: f64 = 25.0;

/// How much sharper than the avatar's own rig at the person's opening
/// (`A_j`, the retargeted jawOpen) the implanted jawOpen may bend the neck
/// (degrees). The bend grows with how far a person opens: fresh seed 102
/// opens 42 mm, is retargeted to the stock jawOpen at weight 1.2, and the
/// rig alone bends its neck 25.2°, the implant 32.0°.
const IMPLANT_NECK_DEGREES: f64 = 8.0;

fn default_glb() -> GlbAvatar {
    let bytes = likeness_sim::default_avatar::default_avatar_glb().expect("builds");
    read_avatar_bytes(&bytes, "default avatar").expect("reads")
}

/// The default avatar's teeth and gums (avatar vertex indices).
fn teeth(glb: &GlbAvatar) -> Vec<u32> {
    let teeth = teeth_and_gums(&glb.avatar);
    assert!(teeth.len() > 1000, "the default avatar's teeth and gums");
    teeth
}

fn taken(seed: u64, glb: &GlbAvatar) -> PersonalAvatar {
    personal_avatar_with(seed, glb, RestFace::Person).expect("makes the avatar")
}

/// Point 2 on committed subjects 1–4 (the same figures on fresh seeds come
/// from `cargo run --example
/// person_face_study`): the scanned neutral within 0.8 mm of the new
/// skin at every mask vertex on it (the skin is laid on the scan's
/// surface, `person_face::surface_fit`; the subjects measure 0.15–0.71 mm
/// at most), the face's border strained at most 1.5 times
/// its inside, no skin triangle through another (the stock avatar has
/// none either), no lid inside an eyeball at rest (0.01 mm) or in any
/// shape where the avatar's own keeps it out (0.05 mm), each blink
/// leaving at most 2% of its eyeball seen, and no tooth in front of the
/// lips.
#[test]
fn the_persons_face_passes_every_check_on_the_default_avatar() {
    let glb = default_glb();
    let teeth = teeth(&glb);
    let stock: Vec<DVec3> = glb
        .avatar
        .positions()
        .iter()
        .map(|p| p.as_dvec3())
        .collect();
    let skin = glb.avatar.part_triangles(&[0]);
    assert_eq!(self_intersections(&stock, &skin), 0, "the stock avatar");
    for seed in likeness_tests::committed::SEEDS {
        let session = likeness_tests::committed::read(seed).expect("reads");
        let person = personalize(&session, Method::DEFAULT)
            .expect("personalizes")
            .shapes;
        let made = taken(seed, &glb);
        let c = face_checks(&glb.avatar, &session.topology, &made, &person, &teeth);
        eprintln!("subject {seed}: {c:?}");
        assert!(c.fit_max_mm <= 0.8, "subject {seed}: {c:?}");
        assert!(
            c.border_strain <= 1.5 * c.inside_strain,
            "subject {seed}: {c:?}"
        );
        assert_eq!(c.self_intersections, 0, "subject {seed}: {c:?}");
        assert!(c.lid_in_eyeball_rest_mm <= 0.01, "subject {seed}: {c:?}");
        assert!(c.deepest_lid_mm.0 <= 0.05, "subject {seed}: {c:?}");
        assert_eq!(c.blinks.len(), 2, "subject {seed}: a blink per eye");
        assert!(
            c.blinks.iter().all(|b| b.1 <= 0.02),
            "subject {seed}: {c:?}"
        );
        assert_eq!(c.teeth_in_front, 0, "subject {seed}: {c:?}");
        let neck = c.neck_bend.expect("edges beyond the face");
        assert!(
            neck.degrees <= NECK_BEND_DEGREES,
            "subject {seed}: jawOpen bends the neck {neck:?}"
        );
        let rig = c.neck_bend_rig.expect("edges beyond the face");
        assert!(
            neck.degrees <= rig.degrees + IMPLANT_NECK_DEGREES,
            "subject {seed}: the implant bends the neck {neck:?}, the rig {rig:?}"
        );
    }
}

/// A clean neck: the default avatar's own jawOpen bends no skin edge with
/// an end beyond the face's outline by more than [`NECK_BEND_DEGREES`]
/// (the person's, in the test above, neither).
#[test]
fn the_default_avatars_jaw_opens_without_creasing_the_neck() {
    let built = likeness_sim::default_avatar::default_avatar();
    let skin = &built.avatar.parts()[built.skin];
    // Beyond the face's outline: the head's vertices, not the lids'
    // margins (skin past the eye holes).
    let face = built.true_correspondence.len();
    let margins = &built.lid_margin_vertices;
    let head = |v: u32| v as usize >= face && !margins.contains(&(v as usize));
    let bend = largest_bend(
        &skin.positions,
        &skin.triangles,
        &skin.targets[Blendshape::JawOpen.index()],
        |a, b| {
            (head(a) || head(b))
                && !margins.contains(&(a as usize))
                && !margins.contains(&(b as usize))
        },
    )
    .expect("edges beyond the face");
    eprintln!("default avatar, jawOpen: sharpest bend beyond the face {bend:?}");
    assert!(bend.degrees <= NECK_BEND_DEGREES, "{bend:?}");
}

/// Simulated subject 10 keeps its lips closed at rest, the two copies of
/// each mouth corner sliding 0.03 mm against each other under the tied
/// bi-Laplacian alone: the nearly coplanar lip sheets crossed (2 pairs),
/// until touching vertices that move alike were made to move as one
/// (`rest_field::move_touching_as_one`).
#[test]
fn closed_lips_stay_closed_without_crossing() {
    let glb = default_glb();
    let session = likeness_sim::capture_session::simulate_session(10);
    let rig = session.template.blendshapes().expect("a template");
    let person = personalize(&session, Method::DEFAULT)
        .expect("personalizes")
        .shapes;
    let input = likeness::avatar::personal_avatar::PersonInput {
        mask: &session.topology,
        rig: &rig,
        personalized: &person,
    };
    let made = likeness::avatar::personal_avatar::personal_avatar(
        &glb,
        &input,
        None,
        likeness::avatar::personal_avatar::AvatarShapes::Personalized,
        RestFace::Person,
        &mut |_| true,
    )
    .expect("makes the avatar");
    let c = face_checks(&glb.avatar, &session.topology, &made, &person, &teeth(&glb));
    assert_eq!(c.self_intersections, 0, "{c:?}");
    assert!(c.fit_max_mm <= 0.8, "{c:?}");
}

/// Two people, two faces: subjects 1 and 2's rests differ by more than a
/// millimetre on average over the face region and by more than 5 mm
/// somewhere (measured: 4.9 mm and 12.2 mm; against the stock face 2.9 and 4.0 mm, 8.6 and 12.8 mm), and each differs from the
/// stock face by as much.
#[test]
fn two_people_give_two_visibly_different_avatars() {
    let glb = default_glb();
    let (one, two) = (taken(1, &glb), taken(2, &glb));
    let rest = |m: &PersonalAvatar| m.shaped(&glb.avatar).positions();
    let stock = glb.avatar.positions();
    let face: Vec<usize> = one
        .registration
        .map
        .face
        .iter()
        .map(|f| f.vertex as usize)
        .collect();
    let apart = |a: &[glam::Vec3], b: &[glam::Vec3]| {
        let d: Vec<f64> = face
            .iter()
            .map(|&v| f64::from((a[v] - b[v]).length()) * 1e3)
            .collect();
        let mean = d.iter().sum::<f64>() / d.len() as f64;
        (mean, d.iter().copied().fold(0.0, f64::max))
    };
    let (r1, r2) = (rest(&one), rest(&two));
    for (what, (mean, max)) in [
        ("subject 1 against 2", apart(&r1, &r2)),
        ("subject 1 against the stock face", apart(&r1, &stock)),
        ("subject 2 against the stock face", apart(&r2, &stock)),
    ] {
        eprintln!("{what}: mean {mean:.2} mm, largest {max:.2} mm");
        assert!(mean > 1.0 && max > 5.0, "{what}: {mean:.2} / {max:.2} mm");
    }
}

/// The round trip with the face taken: the avatar's own face (the
/// registered mask) taken onto its rest changes the rest by under 0.3 mm,
/// and its own 52 shapes still come back (the round trip's tolerances).
/// The skin keeps its height over the mask's triangles
/// (`person_face::surface_fit`), not its slide along them, where it lies
/// over an edge of the mask: 0.26 mm at most on the default avatar, 0.33
/// mm with no height kept (the skin flattened onto the mask), under 0.1 mm
/// while the registration's points were met exactly.
#[test]
fn taking_the_avatars_own_face_changes_nothing() {
    let glb = default_glb();
    let made = round_trip_with(&glb, RestFace::Person).expect("makes the avatar");
    let taken = made.taken_face.as_ref().expect("the face was taken");
    eprintln!(
        "own face taken: rest moved by up to {:.3} mm, fit {:.4} mm",
        taken.largest_mm, taken.fit_max_mm
    );
    assert!(taken.largest_mm < 0.3, "{taken:?}");
    let implanted = made.implanted.as_ref().expect("personalized");
    let r = round_trip(
        made.shaped(&glb.avatar),
        made.shaped_registration(),
        implanted,
    );
    eprintln!("{r:?}");
    assert!(r.face_rmse_share.0 <= 0.03, "{r:?}");
    assert!(r.vertex_share.0 <= 0.10, "{r:?}");
}

/// The GLB written carries the new rest: read back, its positions are the
/// person's face, not the stock one.
#[test]
fn the_written_glb_carries_the_persons_face() {
    let glb = default_glb();
    let made = taken(2, &glb);
    let back = read_avatar_bytes(&made.glb, "written").expect("reads back");
    let want = made.shaped(&glb.avatar).positions();
    let got = back.avatar.positions();
    assert_eq!(got.len(), want.len());
    let worst = got
        .iter()
        .zip(&want)
        .map(|(a, b)| (*a - *b).length())
        .fold(0.0, f32::max);
    assert!(worst < 1e-6, "{worst}");
    let moved = got
        .iter()
        .zip(glb.avatar.positions())
        .filter(|(a, b)| (**a - *b).length() > 1e-4)
        .count();
    assert!(moved > 5000, "{moved} vertices moved");
}
