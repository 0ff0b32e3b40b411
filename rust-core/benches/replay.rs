//! Guided-capture replay time (§3.1): the committed sample session of
//! simulated subject 1 (8,461 frames = 141 s at 60 fps, 52 prompts and 21
//! test expressions) fed frame by frame through the state machine, as
//! recorded (meshes only near the captures) and with a mesh on every frame,
//! as a phone delivers them. Reading the file is not timed; moving the
//! frames through and dropping them is. Run with
//! `cargo bench -p likeness --bench replay`; no time is asserted.

use criterion::{BatchSize, Criterion, criterion_group, criterion_main};
use likeness::capture::guided_capture::GuidedCaptureConfig;
use likeness::capture::replay::replay_session;
use likeness::session::file::decode;

fn replay(c: &mut Criterion) {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../sim-data/sessions/subject-1.likeness"
    );
    let bytes = std::fs::read(path).expect("the committed sample session exists");
    let recorded = decode(&bytes).expect("the sample decodes");
    let mut every_mesh = recorded.clone().into_parts();
    let mut last = recorded.neutral.clone();
    for frame in every_mesh.frames.iter_mut() {
        match &frame.vertices {
            Some(v) => last = v.clone(),
            None => frame.vertices = Some(last.clone()),
        }
    }
    let every_mesh = likeness::Session::new(every_mesh).expect("still a valid session");
    let mut group = c.benchmark_group("replay");
    group.sample_size(20);
    for (name, session) in [
        ("as recorded", &recorded),
        ("mesh on every frame", &every_mesh),
    ] {
        group.bench_function(name, |b| {
            b.iter_batched(
                || session.clone(),
                |s| replay_session(s, GuidedCaptureConfig::default()).expect("replays"),
                BatchSize::LargeInput,
            )
        });
    }
    group.finish();
}

criterion_group!(benches, replay);
criterion_main!(benches);
