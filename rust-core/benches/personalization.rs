//! Personalization time (§3.2, the paper's Table 1) on the committed sample
//! session of simulated subject 1 (1,220 vertices, 52 captures): each
//! method's whole computation, template transfer included, as `personalize`
//! runs it. Also the template transfer alone, the fit alone, and the two
//! steps of `paper-cv`'s choice of λ (reducing the sampled vertices, then
//! the search over λ). Run with
//! `cargo bench -p likeness --bench personalization`; no time is asserted.

use criterion::{Criterion, criterion_group, criterion_main};
use likeness::personalize::blendshape_fit::{BlendshapeFit, Observation};
use likeness::personalize::lambda_criteria::RidgeCriteria;
use likeness::personalize::lambda_selection::{LambdaRule, search_lambda};
use likeness::personalize::regularization_weights::regularization_weights_per_shape;
use likeness::personalize::{Method, generic_blendshapes, personalize};
use likeness::session::file::decode;
use std::hint::black_box;
use std::time::Duration;

fn personalization(c: &mut Criterion) {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../sim-data/sessions/subject-1.likeness"
    );
    let bytes = std::fs::read(path).expect("the committed sample session exists");
    let session = decode(&bytes).expect("the sample decodes");
    let mut group = c.benchmark_group("personalization");
    group.sample_size(20);
    group.measurement_time(Duration::from_secs(8));
    for method in Method::ALL {
        group.bench_function(method.name(), |b| {
            b.iter(|| personalize(black_box(&session), method))
        });
    }
    group.bench_function("template transfer", |b| {
        b.iter(|| generic_blendshapes(black_box(&session)))
    });
    let generic = generic_blendshapes(&session).expect("transfers");
    let weights = regularization_weights_per_shape(&generic.shapes);
    let observations: Vec<Observation> = session
        .captures
        .iter()
        .map(|c| Observation {
            weights: c.weights.0.map(f64::from),
            vertices: &c.vertices,
            importance: 1.0,
        })
        .collect();
    group.bench_function("fit (λ = 1, assembly + 1,220 solves)", |b| {
        b.iter(|| {
            BlendshapeFit::new(&generic.shapes, &weights, &[true; 52], &observations).solve(1.0)
        })
    });
    let fit = BlendshapeFit::new(&generic.shapes, &weights, &[true; 52], &observations);
    group.bench_function("choice of λ: reduction of the sampled vertices", |b| {
        b.iter(|| RidgeCriteria::new(black_box(&fit)))
    });
    let criteria = RidgeCriteria::new(&fit);
    group.bench_function("choice of λ: GCV search on the reduced sample", |b| {
        b.iter(|| search_lambda(LambdaRule::Gcv, |lambda| Ok(criteria.terms(lambda)?.gcv())))
    });
    group.finish();
}

criterion_group!(benches, personalization);
criterion_main!(benches);
