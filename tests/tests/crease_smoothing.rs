//! Creases finer than the mask, smoothed out of the person's motion
//! (`partial_transfer::crease_smoothing`), on a person whose own capture
//! folds the brow: seed 4 of the simulator, on the default avatar's stock
//! face. Before the smoothing, that person's browDownLeft folded 60
//! triangles over the left lid (limit 50), a flap the check warned of.

use likeness::Blendshape;
use likeness::avatar::glb::read::{GlbAvatar, read_avatar_bytes};
use likeness::avatar::implant_check::Fault;
use likeness::avatar::personal_avatar::{AvatarShapes, PersonInput, RestFace, personal_avatar};
use likeness::personalize::{Method, personalize};
use likeness_sim::{SAMPLE_GEOMETRY_WINDOW, SimulationOptions, simulate_session_with};

fn default_glb() -> GlbAvatar {
    let bytes = likeness_sim::default_avatar::default_avatar_glb().expect("builds");
    read_avatar_bytes(&bytes, "default avatar").expect("reads")
}

/// The brow comes down and takes the lid with it: no shape passes a
/// limit (browDownLeft's flap gone: without the smoothing it folds 60
/// triangles, limit 50), and the blinks still close.
#[test]
fn a_brow_the_person_folds_comes_down_without_a_flap() {
    let options = SimulationOptions {
        geometry_window: Some(SAMPLE_GEOMETRY_WINDOW),
        ..SimulationOptions::default()
    };
    let session = simulate_session_with(4, options, &mut |_, _| {});
    let rig = session
        .template
        .blendshapes()
        .expect("the template's shapes");
    let personalized = personalize(&session, Method::DEFAULT)
        .expect("personalizes")
        .shapes;
    let input = PersonInput {
        mask: &session.topology,
        rig: &rig,
        personalized: &personalized,
    };
    let glb = default_glb();
    let made = personal_avatar(
        &glb,
        &input,
        None,
        AvatarShapes::Personalized,
        RestFace::Stock,
        &mut |_| true,
    )
    .expect("an avatar");
    let faults: Vec<&Fault> = made.faults().collect();
    assert!(faults.is_empty(), "{faults:?}");
    let implanted = made.implanted.as_ref().expect("personalized");
    eprintln!(
        "creased edges over the 52 shapes: {} found, {} left",
        implanted.creases_found, implanted.creases_left
    );
    assert!(implanted.creases_found > 0);
    // The lids a blink closes are held while the creases around them are
    // smoothed: the eyes still close (the check's blink rule passed above),
    // and the shape still moves the brow down.
    let brow = &implanted.shapes[Blendshape::BrowDownLeft.index()];
    let lowest = brow.iter().map(|d| d.y).fold(0.0_f32, f32::min);
    assert!(lowest < -0.004, "browDownLeft lowers the brow: {lowest} m");
}
