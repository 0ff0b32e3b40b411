//! The same avatar in any units and axes gives the same shapes: committed
//! subject 1 implanted into an avatar and into it wrapped in a parent node
//! that turns metres into centimetres and +Y up into +Z up
//! (`likeness_tests::units`). On the default avatar this holds; on the
//! MPFB body and ICT-FaceKit it does not yet (`docs/avatar.md`, "subject
//! 1's shapes on an avatar and on it wrapped").

use likeness::avatar::glb::read::{GlbAvatar, read_avatar_bytes};
use likeness_tests::units::{ShapeDifference, Wrapping, shape_difference};

/// The shapes' RMS difference may be this share of their motion.
const SAME_WITHIN: f64 = 1e-3;

/// Subject 1's shapes on `bytes` and on it wrapped, compared.
fn difference(bytes: &[u8], name: &str) -> ShapeDifference {
    let wrapping = Wrapping::CM_Z_UP;
    let shapes = |glb: &GlbAvatar| {
        likeness_tests::committed::personal_avatar_of(1, glb)
            .unwrap_or_else(|e| panic!("{name}: {e}"))
            .implanted
            .expect("implanted")
            .shapes
    };
    let plain = read_avatar_bytes(bytes, name).expect("reads");
    let wrapped = read_avatar_bytes(&wrapping.wrap(bytes), name).expect("reads");
    let d = shape_difference(&shapes(&plain), &shapes(&wrapped), wrapping);
    eprintln!(
        "{name}: RMS difference {:.4}% of the motion, largest {:.3e} in shape {}",
        100.0 * d.rms_share,
        d.largest.0,
        d.largest.1
    );
    d
}

/// Measured: 0.004% of the motion, at most 0.02 mm (0.001% scaled by
/// 0.01 or by 1,000 without the turn).
#[test]
fn the_default_avatar_in_centimetres_and_z_up_gives_the_same_shapes() {
    let glb = likeness_sim::default_avatar::default_avatar_glb().expect("writes");
    let d = difference(&glb, "default avatar");
    assert!(d.rms_share <= SAME_WITHIN, "{d:?}");
}
