//! The round trip: an avatar's own 52 shapes, seen through
//! the registration (each mask vertex takes the avatar's displacement
//! where it lies on the skin, `likeness::avatar::own_shapes`), given to
//! the pipeline as the person, must come back as the avatar's own
//! targets. On the default avatar, every generated variant
//! (`likeness_sim::avatar_variants`) and, where
//! `../shared/avatars/ict-facekit.glb` is present, a real avatar nobody
//! here made. Measures in `likeness_tests::avatar_quality::round_trip`.

use likeness::avatar::glb::read::{GlbAvatar, read_avatar_bytes};
use likeness_sim::avatar_variants::avatar_variants;
use likeness_tests::avatar_quality::round_trip;

/// Per shape, the face's RMSE at most 3% of that shape's largest own
/// motion, no vertex of the avatar more than 10% of it away, and each
/// blink leaving as much of its eyeball seen as the avatar's own (within
/// half a percentage point).
fn assert_gives_back_its_own_shapes(glb: &GlbAvatar) {
    let name = glb.file.display().to_string();
    let made =
        likeness_tests::committed::round_trip_of(glb).unwrap_or_else(|e| panic!("{name}: {e}"));
    let implanted = made.implanted.as_ref().expect("personalized");
    let r = round_trip(&glb.avatar, &made.registration, implanted);
    eprintln!(
        "{name}: face RMSE at most {:.2}% ({}), worst vertex {:.2}% ({}, vertex {}), blinks {:?}",
        100.0 * r.face_rmse_share.0,
        r.face_rmse_share.1,
        100.0 * r.vertex_share.0,
        r.vertex_share.1,
        r.worst_vertex,
        r.blinks
    );
    assert!(
        r.face_rmse_share.0 <= 0.03,
        "{name}: {}'s face RMSE is {:.1}% of its largest motion",
        r.face_rmse_share.1,
        100.0 * r.face_rmse_share.0
    );
    assert!(
        r.vertex_share.0 <= 0.10,
        "{name}: in {}, vertex {} is {:.1}% of the shape's largest motion away",
        r.vertex_share.1,
        r.worst_vertex,
        100.0 * r.vertex_share.0
    );
    assert_eq!(r.blinks.len(), 2, "{name}: a blink per eyeball");
    for (b, own, got) in &r.blinks {
        assert!(
            *got <= own + 0.005,
            "{name}: {b} leaves {:.1}% of the eyeball seen, its own {:.1}%",
            100.0 * got,
            100.0 * own
        );
    }
}

#[test]
fn the_default_avatar_and_every_variant_give_back_their_own_shapes() {
    let default = likeness_sim::default_avatar::default_avatar_glb().expect("builds");
    assert_gives_back_its_own_shapes(
        &read_avatar_bytes(&default, "default avatar").expect("reads"),
    );
    for variant in avatar_variants() {
        let glb = read_avatar_bytes(&variant.glb, variant.name).expect("reads");
        assert_gives_back_its_own_shapes(&glb);
    }
}

/// On ICT-FaceKit and the MPFB/MakeHuman body (measured only, never
/// committed; skipped where absent).
#[test]
fn real_avatars_nobody_here_made_give_back_their_own_shapes() {
    for glb in likeness_tests::shared_avatars::shared_avatars() {
        assert_gives_back_its_own_shapes(&glb);
    }
}
