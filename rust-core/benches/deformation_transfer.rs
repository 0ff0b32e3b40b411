//! Deformation transfer of 52 shapes onto a face-sized mesh: building and
//! factoring the gradient system, transferring all 52 shapes (one batched
//! solve with 156 right-hand sides, plus the contact solves of the two
//! blinks), and both together, which is what the personalization does once
//! per session.
//!
//! The mesh is a synthetic stand-in for ARKit's mask (1,220 vertices, 2,304
//! triangles): a curved 37 × 34 grid with two eye holes of 6 × 2 cells and a
//! mouth slit of 9 × 1 cells, 1,248 vertices and 2,310 triangles, plus 28
//! virtual eye triangles. Shapes are smooth bumps; shapes 0 and 7 close an
//! eye. The target is the source with other proportions. Run with
//! `cargo bench -p likeness --bench deformation_transfer`.

use criterion::{Criterion, criterion_group, criterion_main};
use glam::{DMat3, DVec3, Vec3};
use likeness::geometry::deformation_transfer::DeformationTransfer;
use likeness::geometry::mesh_boundary::{EyeHole, eye_holes};
use likeness::personalize::generic_blendshapes::transfer_template;
use likeness::{BLENDSHAPE_COUNT, Template, Topology};
use std::hint::black_box;
use std::time::Duration;

#[path = "../src/test_support/face_grid.rs"]
mod face_grid;
use face_grid::Hole;

const NX: usize = 37;
const NY: usize = 34;
const CELL: f32 = 0.004;
const EYES: [Hole; 2] = [(22, 28, 22, 24), (8, 14, 22, 24)];
const MOUTH: Hole = (13, 22, 8, 9);

/// The shared fixture's face grid at this size.
fn mesh() -> (Topology, Vec<Vec3>) {
    let grid = face_grid::face_grid(NX, NY, CELL, 4.0, EYES, MOUTH);
    let topology = Topology::new(grid.positions.len(), grid.triangles).expect("valid grid");
    (topology, grid.positions)
}

/// 52 shapes: smooth bumps spread over the face; 0 and 7 close an eye.
fn template(neutral: &[Vec3], eyes: &[EyeHole; 2]) -> Template {
    let shapes = std::array::from_fn::<_, BLENDSHAPE_COUNT, _>(|j| {
        let mut shape = neutral.to_vec();
        if let Some(eye) = [0, 7].iter().position(|&b| b == j).map(|e| &eyes[e]) {
            for (&u, &l) in eye.upper.iter().zip(&eye.lower) {
                shape[u as usize] = neutral[l as usize];
            }
            return shape;
        }
        let a = j as f32 * 2.4;
        let centre = Vec3::new(0.05 * a.cos(), 0.05 * a.sin(), 0.0);
        let push = Vec3::new(a.sin(), a.cos(), 1.0) * 0.004;
        for (s, p) in shape.iter_mut().zip(neutral) {
            let t = ((p.truncate() - centre.truncate()).length() / 0.03).min(1.0);
            *s += (1.0 - t * t).powi(3) * push;
        }
        shape
    });
    Template {
        neutral: neutral.to_vec(),
        shapes,
    }
}

fn deformation_transfer(c: &mut Criterion) {
    let (topology, neutral) = mesh();
    let eyes = eye_holes(&topology, &neutral).expect("two eyes and a mouth");
    let virtual_triangles: Vec<[u32; 3]> = eyes.iter().flat_map(|e| e.triangles.clone()).collect();
    let template = template(&neutral, &eyes);
    let proportions = DMat3::from_diagonal(DVec3::new(1.05, 0.96, 1.1));
    let target: Vec<DVec3> = neutral.iter().map(|p| proportions * p.as_dvec3()).collect();
    eprintln!(
        "mesh: {} vertices, {} triangles + {} virtual",
        topology.vertex_count(),
        topology.triangles().len(),
        virtual_triangles.len()
    );
    let build = || DeformationTransfer::new(&topology, &virtual_triangles, &target);
    let dt = build().expect("factors");

    let mut group = c.benchmark_group("deformation_transfer");
    group.sample_size(20);
    group.measurement_time(Duration::from_secs(5));
    group.bench_function("build_and_factor", |b| b.iter(|| build().map(black_box)));
    group.bench_function("transfer_52", |b| {
        b.iter(|| transfer_template(&dt, black_box(&template)))
    });
    group.bench_function("factor_and_transfer_52", |b| {
        b.iter(|| build().and_then(|dt| transfer_template(&dt, black_box(&template))))
    });
    group.finish();
}

criterion_group!(benches, deformation_transfer);
criterion_main!(benches);
