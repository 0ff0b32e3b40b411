//! Encode and decode throughput of the session file on a synthetic 2-minute,
//! 60 fps session with a 1,220-vertex mesh in every frame (see
//! `synthetic/mod.rs`). Throughput is in bytes of f32/f64 session data
//! (positions, weights, timestamps) per second. The encoded size is printed
//! once at start-up. A second group does the same for the committed sample
//! session of simulated subject 1 (`sim-data/sessions/subject-1.likeness`,
//! meshes within 0.4 s of each capture). Run with
//! `cargo bench -p likeness --bench session_file`.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use likeness::session::file::{decode, encode};
use std::hint::black_box;
use std::time::{Duration, Instant};

mod synthetic;

fn session_file(c: &mut Criterion) {
    let started = Instant::now();
    let session = synthetic::session();
    let generated = started.elapsed();
    let bytes = encode(&session).expect("the synthetic session encodes");
    let data = synthetic::data_bytes(&session);
    eprintln!(
        "synthetic session: {} frames × {} vertices, {:.1} MB of f32/f64 data (generated in {:.1?}) \
         → session file of {} bytes ({:.2} MB, {:.1}:1)",
        synthetic::FRAMES,
        synthetic::VERTICES,
        data as f64 / 1e6,
        generated,
        bytes.len(),
        bytes.len() as f64 / 1e6,
        data as f64 / bytes.len() as f64,
    );
    assert_eq!(
        decode(&bytes)
            .expect("the synthetic session decodes")
            .frames
            .len(),
        synthetic::FRAMES
    );

    let mut group = c.benchmark_group("session_file");
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(15));
    group.throughput(Throughput::Bytes(data));
    group.bench_function("encode", |b| b.iter(|| encode(black_box(&session))));
    group.bench_function("decode", |b| b.iter(|| decode(black_box(&bytes))));
    group.finish();

    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../sim-data/sessions/subject-1.likeness"
    );
    let sample_bytes = std::fs::read(path).expect("the committed sample session exists");
    let sample = decode(&sample_bytes).expect("the committed sample decodes");
    let sample_data = synthetic::data_bytes(&sample);
    eprintln!(
        "sample subject-1: {} frames, {} with a mesh, {:.1} MB of f32/f64 data → {:.2} MB file",
        sample.frames.len(),
        sample
            .frames
            .iter()
            .filter(|f| f.vertices.is_some())
            .count(),
        sample_data as f64 / 1e6,
        sample_bytes.len() as f64 / 1e6,
    );
    let mut group = c.benchmark_group("session_file_sample");
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(10));
    group.throughput(Throughput::Bytes(sample_data));
    group.bench_function("encode", |b| b.iter(|| encode(black_box(&sample))));
    group.bench_function("decode", |b| b.iter(|| decode(black_box(&sample_bytes))));
    group.finish();
}

criterion_group!(benches, session_file);
criterion_main!(benches);
