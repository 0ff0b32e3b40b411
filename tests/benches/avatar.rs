//! Finding the face and Eq. (4) on the default avatar (22,077 vertices in
//! six meshes, 52 targets): `cargo bench -p likeness-tests --bench avatar`.
//! Measures; asserts nothing.

use criterion::{Criterion, criterion_group, criterion_main};
use likeness::Blendshape;
use likeness::Blendshapes;
use likeness::avatar::glb::{NewGlbOptions, new_avatar_glb};
use likeness::avatar::partial_transfer::implant;
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
    // Everything after personalization but the registration: Eq. (4), the
    // partial transfer, rigid parts, eyelid repair, and the GLB in memory.
    let session = likeness::session::file::read(likeness_tests::committed::path(1)).expect("reads");
    let person =
        likeness::personalize::personalize(&session, likeness::personalize::Method::DEFAULT)
            .expect("personalizes")
            .shapes;
    let found = find_face(
        &built.avatar,
        &session.topology,
        &session.template.blendshapes().expect("a template"),
    )
    .expect("a face");
    let options = NewGlbOptions::default();
    group.bench_function(
        "after personalization: Eq. (4), implant, GLB (52 shapes)",
        |b| {
            b.iter(|| {
                let avatar = black_box(&built.avatar);
                let retargeting = retarget(avatar, &found, &person).expect("solves");
                let implanted = implant(
                    avatar,
                    &found,
                    &retargeting,
                    &person,
                    session.topology.triangles(),
                )
                .expect("implants");
                let mut with_shapes = avatar.clone();
                let offsets = avatar.vertex_offsets();
                for (p, part) in with_shapes.parts.iter_mut().enumerate() {
                    part.targets = Blendshape::ALL
                        .iter()
                        .map(|s| implanted.shapes[s.index()][offsets[p]..offsets[p + 1]].to_vec())
                        .collect();
                }
                for mesh in &mut with_shapes.meshes {
                    mesh.target_names = Blendshape::ALL
                        .iter()
                        .map(|s| s.name().to_string())
                        .collect();
                }
                new_avatar_glb(&with_shapes, &options, std::path::Path::new("bench.glb"))
                    .expect("encodes")
            })
        },
    );
    group.finish();
}

criterion_group!(benches, avatar);
criterion_main!(benches);
