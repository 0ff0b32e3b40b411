//! Finding the face and Eq. (4) on the default avatar (22,077 vertices in
//! six meshes, 52 targets), and finding the face on every generated test
//! avatar (`likeness_sim::avatar_variants`) and, when present, on
//! `../shared/avatars/ict-facekit.glb`, and on ARKit's own mesh when
//! `../shared/arkit-face/` is there: `cargo bench -p likeness-tests
//! --bench avatar`. Measures; asserts nothing.

use criterion::{Criterion, criterion_group, criterion_main};
use likeness::Blendshapes;
use likeness::avatar::glb::{new_avatar_glb, read_avatar_bytes};
use likeness::avatar::person_face::take_face;
use likeness::avatar::personal_avatar::{AvatarShapes, PersonInput, RestFace, personal_avatar};
use likeness::avatar::registration::find_face;
use likeness::avatar::retargeting::retarget;
use likeness_sim::default_avatar::default_avatar;
use likeness_sim::face_mask::face_mask;
use likeness_sim::template::generic_template;
use std::hint::black_box;
use std::path::Path;

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
    // ARKit's own mesh and template, as a real iPhone sends them: its
    // mask wraps round the cheeks, so the fit takes more steps.
    match likeness_sim::arkit_face::shared_arkit_face() {
        Some(face) => {
            let basis = likeness_sim::face_basis::FaceBasis::Arkit(face);
            let arkit_rig = basis.template().blendshapes().expect("a checked template");
            let arkit_mask = &basis.mask().topology;
            group.bench_function("find_face on ARKit's mesh (default avatar)", |b| {
                b.iter(|| {
                    find_face(black_box(&built.avatar), arkit_mask, &arkit_rig).expect("a face")
                })
            });
        }
        None => eprintln!(
            "skipping find_face on ARKit's mesh: no {}",
            likeness_sim::arkit_face::shared_arkit_face_dir().display()
        ),
    }
    let found = find_face(&built.avatar, mask, &rig).expect("a face");
    group.bench_function("retarget, Eq. (4), 52 shapes", |b| {
        b.iter(|| retarget(black_box(&built.avatar), &found, &rig).expect("solves"))
    });
    // Everything after personalization but the registration (given, as
    // the cache gives it), through the product's own call: Eq. (4), the
    // partial transfer with lid contacts, rigid parts, eyelid repair, and
    // the GLB written back in memory.
    let session = likeness::session::file::read(likeness_tests::committed::path(1)).expect("reads");
    let person =
        likeness::personalize::personalize(&session, likeness::personalize::Method::DEFAULT)
            .expect("personalizes")
            .shapes;
    let template = session.template.blendshapes().expect("a template");
    let found = find_face(&built.avatar, &session.topology, &template).expect("a face");
    let options = likeness_sim::default_avatar::glb_options(built);
    let bytes = new_avatar_glb(&built.avatar, &options, Path::new("default.glb")).expect("encodes");
    let glb = read_avatar_bytes(&bytes, "default.glb").expect("reads");
    let input = PersonInput {
        mask: &session.topology,
        rig: &template,
        personalized: &person,
    };
    group.bench_function("take_face: the person's neutral as the rest", |b| {
        b.iter(|| take_face(black_box(&glb.avatar), &found, person.neutral()).expect("a face"))
    });
    for (label, face) in [
        (
            "after personalization: Eq. (4), implant, GLB (52 shapes)",
            RestFace::Stock,
        ),
        (
            "after personalization, the person's face taken: take_face, Eq. (4), implant, GLB",
            RestFace::Person,
        ),
    ] {
        group.bench_function(label, |b| {
            b.iter(|| {
                personal_avatar(
                    black_box(&glb),
                    &input,
                    Some(found.clone()),
                    AvatarShapes::Personalized,
                    face,
                    &mut |_| true,
                )
                .expect("an avatar")
            })
        });
    }
    group.finish();
}

/// `find_face` on avatars our mask did not make.
fn other_avatars(c: &mut Criterion) {
    let session = likeness::session::file::read(likeness_tests::committed::path(1)).expect("reads");
    let template = session.template.blendshapes().expect("a template");
    let mut avatars: Vec<(String, likeness::avatar::Avatar)> =
        likeness_sim::avatar_variants::avatar_variants()
            .into_iter()
            .map(|v| {
                let glb = read_avatar_bytes(&v.glb, v.name).expect("reads");
                (v.name.to_string(), glb.avatar)
            })
            .collect();
    let ict = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../shared/avatars/ict-facekit.glb");
    if let Ok(glb) = likeness::avatar::glb::read_avatar(&ict) {
        avatars.push(("ict-facekit".into(), glb.avatar));
    }
    let mut group = c.benchmark_group("find_face");
    group.sample_size(10);
    for (name, avatar) in &avatars {
        let label = format!("{name} ({} vertices)", avatar.vertex_count());
        group.bench_function(label, |b| {
            b.iter(|| find_face(black_box(avatar), &session.topology, &template).expect("a face"))
        });
    }
    group.finish();
}

criterion_group!(benches, avatar, other_avatars);
criterion_main!(benches);
