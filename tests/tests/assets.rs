//! The prebuilt bytes the phone ships (`bindings/likeness-assets`) are
//! still what the code builds: after a change to the default avatar,
//! regenerate them with
//! `likeness default-avatar --out bindings/likeness-assets/default-avatar.glb`.

use likeness::avatar::glb::read_avatar_bytes;

#[test]
fn the_shipped_default_avatar_is_the_one_sim_data_builds() {
    let built = likeness_sim::default_avatar::default_avatar_glb().unwrap();
    let shipped = likeness_assets::DEFAULT_AVATAR_GLB;
    if built == shipped {
        return;
    }
    // Bytes can differ by a last bit of a float where another machine's
    // maths library rounds `exp` or `sin` otherwise; the avatar may not.
    let regenerate = "bindings/likeness-assets/default-avatar.glb is not the default avatar \
                      sim-data builds: regenerate it with `likeness default-avatar --out \
                      bindings/likeness-assets/default-avatar.glb`";
    let built = read_avatar_bytes(&built, "built").unwrap().avatar;
    let shipped = read_avatar_bytes(shipped, "shipped").unwrap().avatar;
    assert_eq!(built.meshes(), shipped.meshes(), "{regenerate}");
    assert_eq!(built.parts().len(), shipped.parts().len(), "{regenerate}");
    for (b, s) in built.parts().iter().zip(shipped.parts()) {
        assert_eq!(
            (&b.name, &b.triangles),
            (&s.name, &s.triangles),
            "{regenerate}"
        );
        let close = |x: &[glam::Vec3], y: &[glam::Vec3]| {
            x.len() == y.len() && x.iter().zip(y).all(|(p, q)| p.distance(*q) < 1e-6)
        };
        assert!(
            close(&b.positions, &s.positions),
            "{}: {regenerate}",
            b.name
        );
        assert_eq!(b.targets.len(), s.targets.len(), "{regenerate}");
        for (tb, ts) in b.targets.iter().zip(&s.targets) {
            assert!(close(tb, ts), "{}: {regenerate}", b.name);
        }
    }
}
