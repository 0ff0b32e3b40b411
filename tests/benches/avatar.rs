//! Finding the face and Eq. (4) on the default avatar (22,077 vertices in
//! six meshes, 52 targets): `cargo bench -p likeness-tests --bench avatar`.
//! Measures; asserts nothing.

use criterion::{Criterion, criterion_group, criterion_main};
use likeness::Blendshapes;
use likeness::avatar::registration::find_face;
use likeness::avatar::retargeting::retarget;
use likeness_sim::default_avatar::default_avatar;
use likeness_sim::face_mask::face_mask;
use likeness_sim::template::generic_template;
use std::hint::black_box;

fn rig() -> Blendshapes {
    generic_template()
        .blendshapes()
        .expect("a checked template")
}

fn avatar(c: &mut Criterion) {
    let built = default_avatar();
    let rig = rig();
    let mask = &face_mask().topology;
    let mut group = c.benchmark_group("avatar");
    group.sample_size(10);
    group.bench_function("find_face (22k-vertex default avatar)", |b| {
        b.iter(|| find_face(black_box(&built.avatar), mask, &rig).expect("a face"))
    });
    let found = find_face(&built.avatar, mask, &rig).expect("a face");
    group.bench_function("retarget, Eq. (4), 52 shapes", |b| {
        b.iter(|| retarget(black_box(&built.avatar), &found, &rig).expect("solves"))
    });
    group.finish();
}

criterion_group!(benches, avatar);
criterion_main!(benches);
