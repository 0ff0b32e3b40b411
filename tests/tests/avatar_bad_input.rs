//! `personal_avatar` on avatars that lack something:
//! no eyes or teeth (the steps are skipped and said so), targets that move
//! nothing, a face that cannot be found; each a warning or a typed error,
//! never a panic. (A session whose personalization fails is refused by
//! `likeness avatar` before any file is written: `cli/tests/avatar.rs`.)

use likeness::avatar::glb::{
    GlbAvatar, NewGlbOptions, check_avatar, new_avatar_glb, read_avatar_bytes,
};
use likeness::avatar::personal_avatar::{
    AvatarError, AvatarShapes, AvatarStep, AvatarWarning, PersonInput, RestFace, personal_avatar,
};
use likeness::avatar::{Avatar, AvatarPart};
use likeness::{Blendshape, Blendshapes};
use likeness_sim::default_avatar::default_avatar;
use likeness_sim::face_mask::face_mask;
use likeness_sim::template::generic_template;
use std::path::Path;

/// `avatar` through a GLB and back, as a user's file arrives.
fn as_glb(avatar: &Avatar, name: &str) -> GlbAvatar {
    let bytes = new_avatar_glb(avatar, &NewGlbOptions::default(), Path::new(name)).expect("writes");
    read_avatar_bytes(&bytes, name).expect("reads back")
}

fn run(glb: &GlbAvatar) -> Result<likeness::avatar::personal_avatar::PersonalAvatar, AvatarError> {
    let mask = face_mask();
    let rig: Blendshapes = generic_template().blendshapes().expect("a template");
    let person = PersonInput {
        mask: &mask.topology,
        rig: &rig,
        personalized: &rig,
    };
    personal_avatar(
        glb,
        &person,
        None,
        AvatarShapes::Personalized,
        RestFace::Stock,
        &mut |_| true,
    )
}

/// The default avatar with only its head mesh: no eyeballs, teeth, gums
/// or tongue.
fn head_only() -> Avatar {
    let edit = |meshes: &mut Vec<_>, parts: &mut Vec<AvatarPart>| {
        parts.retain(|p| p.mesh == 0);
        meshes.truncate(1);
    };
    default_avatar().avatar.clone().edited(edit).unwrap()
}

#[test]
fn an_avatar_without_eyes_or_teeth_is_made_and_says_what_it_skipped() {
    let glb = as_glb(&head_only(), "head-only.glb");
    let made = run(&glb).expect("an avatar without eyes is still an avatar");
    assert!(
        made.warnings.contains(&AvatarWarning::NoEyeballs),
        "{:?}",
        made.warnings
    );
    assert!(
        made.warnings.contains(&AvatarWarning::NoTeeth),
        "{:?}",
        made.warnings
    );
    let implanted = made.implanted.as_ref().expect("implanted");
    assert_eq!(implanted.lids_repaired, 0);
    let back = read_avatar_bytes(&made.glb, "out.glb").expect("the GLB reads");
    assert_eq!(check_avatar(&back).expect("an avatar").found(), 52);
    // The full avatar has both: no such warning there.
    let full = run(&as_glb(&default_avatar().avatar, "default.glb")).expect("made");
    assert!(
        !full
            .warnings
            .iter()
            .any(|w| matches!(w, AvatarWarning::NoEyeballs | AvatarWarning::NoTeeth)),
        "{:?}",
        full.warnings
    );
}

#[test]
fn targets_that_move_nothing_are_named_and_an_avatar_of_only_such_is_refused() {
    let puff = Blendshape::CheekPuff.index();
    let avatar = head_only()
        .edited(|_, parts| {
            for part in parts {
                part.targets[puff].fill(glam::Vec3::ZERO);
            }
        })
        .unwrap();
    let made = run(&as_glb(&avatar, "still-cheeks.glb")).expect("made");
    assert!(
        made.warnings
            .contains(&AvatarWarning::StillTargets(vec!["cheekPuff".to_string()])),
        "{:?}",
        made.warnings
    );

    let avatar = avatar
        .edited(|_, parts| {
            for target in parts.iter_mut().flat_map(|p| &mut p.targets) {
                target.fill(glam::Vec3::ZERO);
            }
        })
        .unwrap();
    let err = run(&as_glb(&avatar, "still.glb")).expect_err("nothing moves");
    assert!(
        matches!(err, AvatarError::StillAvatar { targets: 52, .. }),
        "{err}"
    );
    assert!(err.to_string().contains("still.glb"), "{err}");
}

#[test]
fn an_avatar_whose_face_cannot_be_found_is_a_typed_error_naming_the_file() {
    // The blinks move the mouth and the jaw moves the eyes: no face has
    // its features there.
    let (blink, jaw) = (
        Blendshape::EyeBlinkLeft.index(),
        Blendshape::MouthSmileLeft.index(),
    );
    let avatar = head_only()
        .edited(|_, parts| {
            for part in parts {
                part.targets.swap(blink, jaw);
            }
        })
        .unwrap();
    let err = run(&as_glb(&avatar, "no-face.glb")).expect_err("no face");
    assert!(matches!(err, AvatarError::Registration { .. }), "{err}");
    assert!(err.to_string().contains("no-face.glb"), "{err}");
}

#[test]
fn cancelling_stops_before_the_step_asked() {
    let glb = as_glb(&head_only(), "head-only.glb");
    let mask = face_mask();
    let rig: Blendshapes = generic_template().blendshapes().expect("a template");
    let person = PersonInput {
        mask: &mask.topology,
        rig: &rig,
        personalized: &rig,
    };
    let mut seen = Vec::new();
    let err = personal_avatar(
        &glb,
        &person,
        None,
        AvatarShapes::Personalized,
        RestFace::Stock,
        &mut |s| {
            seen.push(s);
            s != AvatarStep::Implanting
        },
    )
    .expect_err("cancelled");
    assert!(
        matches!(err, AvatarError::Cancelled(AvatarStep::Implanting)),
        "{err}"
    );
    assert_eq!(
        seen,
        [
            AvatarStep::Checking,
            AvatarStep::FindingFace,
            AvatarStep::Retargeting,
            AvatarStep::Implanting
        ]
    );
}
