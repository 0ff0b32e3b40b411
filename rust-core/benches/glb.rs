//! glTF avatar read and write time and file size, dense against sparse
//! targets, on a synthetic avatar the size of the project's default one: a
//! 141 × 141 vertex head grid (19,881 vertices, 39,200 triangles) with all
//! 52 ARKit shapes, each moving a band of about 8% of the vertices (most
//! shapes move a small part of a face or body), plus a 400-vertex teeth
//! mesh that only `jawOpen` moves. Sizes are printed first; the timings are
//! criterion's. Run with `cargo bench -p likeness --bench glb`; no time is
//! asserted.

use criterion::{Criterion, criterion_group, criterion_main};
use glam::Vec3;
use likeness::Blendshape;
use likeness::avatar::glb::{
    NewGlbOptions, NewShapes, TargetEncoding, new_avatar_glb, read_avatar_bytes, written_back_glb,
};
use likeness::avatar::{Avatar, AvatarPart};
use likeness_sim::grid_avatar;
use std::hint::black_box;
use std::path::Path;

/// A `side × side` grid (1 mm apart) as a part of mesh `mesh`, with
/// one target per shape of `targets`, each moving a band of about 8% of the
/// rows whose place depends on the shape.
fn grid(mesh: usize, side: u32, targets: &[Blendshape]) -> AvatarPart {
    let band = side / 12;
    grid_avatar::part(
        mesh,
        grid_avatar::grid(side, side, 1e-3, 0.0),
        targets.len(),
        |t, v, _| {
            let first = (targets[t].index() as u32 * 7) % (side - band);
            let row = v as u32 / side;
            if (first..first + band).contains(&row) {
                Vec3::new(0.0, -1e-4 * (row - first) as f32, 2e-4)
            } else {
                Vec3::ZERO
            }
        },
    )
}

fn avatar() -> Avatar {
    let names = |s: &[Blendshape]| s.iter().map(|s| s.name()).collect::<Vec<_>>();
    grid_avatar::avatar(
        &[
            ("Head", &names(&Blendshape::ALL)[..]),
            ("Teeth", &names(&[Blendshape::JawOpen])),
        ],
        vec![
            grid(0, 141, &Blendshape::ALL),
            grid(1, 20, &[Blendshape::JawOpen]),
        ],
    )
}

fn glb(c: &mut Criterion) {
    let avatar = avatar();
    let file = Path::new("bench.glb");
    let sparse_opts = NewGlbOptions::default();
    let dense_opts = NewGlbOptions {
        encoding: TargetEncoding::Dense,
        ..Default::default()
    };
    let sparse = new_avatar_glb(&avatar, &sparse_opts, file).expect("writes");
    let dense = new_avatar_glb(&avatar, &dense_opts, file).expect("writes");
    let read = read_avatar_bytes(&sparse, "bench.glb").expect("reads");
    let mut shapes = NewShapes::new();
    for s in Blendshape::ALL {
        // The shapes the file already has, written back.
        let per_part = read
            .avatar
            .parts()
            .iter()
            .map(|p| {
                let names = &read.avatar.meshes()[p.mesh].target_names;
                match names.iter().position(|n| n == s.name()) {
                    Some(t) => p.targets[t].clone(),
                    None => vec![Vec3::ZERO; p.positions.len()],
                }
            })
            .collect();
        shapes.set(s, per_part);
    }
    let back = written_back_glb(&read, &shapes, TargetEncoding::Smallest, file).expect("writes");
    println!(
        "glb: {} vertices, 52 + 1 targets: new sparse {} bytes, new dense {} bytes, written back (52 new shapes, sparse) {} bytes",
        avatar.vertex_count(),
        sparse.len(),
        dense.len(),
        back.len()
    );
    let mut group = c.benchmark_group("glb");
    group.sample_size(10);
    group.bench_function("write new, sparse", |b| {
        b.iter(|| new_avatar_glb(black_box(&avatar), &sparse_opts, file))
    });
    group.bench_function("write new, dense", |b| {
        b.iter(|| new_avatar_glb(black_box(&avatar), &dense_opts, file))
    });
    group.bench_function("read, sparse", |b| {
        b.iter(|| read_avatar_bytes(black_box(&sparse), "bench.glb"))
    });
    group.bench_function("read, dense", |b| {
        b.iter(|| read_avatar_bytes(black_box(&dense), "bench.glb"))
    });
    group.bench_function("write back 52 shapes", |b| {
        b.iter(|| written_back_glb(black_box(&read), &shapes, TargetEncoding::Smallest, file))
    });
    group.finish();
}

criterion_group!(benches, glb);
criterion_main!(benches);
