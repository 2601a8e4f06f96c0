//! Speed of the model's hot paths on stable configurations of the 2 mm nitinol wire, sampled
//! uniformly in normalised units in [−30, 30]⁶ (fixed seed).
//!
//! `cargo bench -p ftwire-rod --bench solve` (add `-- --measurement-time 2 --warm-up-time 1`
//! on a busy machine).
#![allow(missing_docs)]

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use ftwire_rod::{DEFAULT_NODES, Rod, WireParams, sampling::Sampler};
use nalgebra::Vector6;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

fn setup() -> (Rod, Vec<Vector6<f64>>) {
    let wire = WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001).expect("valid wire");
    let rod = Rod::new(wire);
    let mut rng = ChaCha8Rng::seed_from_u64(2024);
    let sampler = Sampler::default();
    let configurations = (0..64)
        .map(|_| {
            sampler
                .sample_stable(&rod, &mut rng)
                .expect("stable sample")
        })
        .collect();
    (rod, configurations)
}

fn bench(c: &mut Criterion) {
    let (rod, configurations) = setup();
    let mut i = 0;
    let mut next = || {
        i = (i + 1) % configurations.len();
        &configurations[i]
    };
    c.bench_function(
        "full solve (64-node shape + J(L) + stability + self-intersection)",
        |b| b.iter(|| rod.solve(black_box(next()), DEFAULT_NODES)),
    );
    let mut i = 0;
    let mut next = || {
        i = (i + 1) % configurations.len();
        &configurations[i]
    };
    c.bench_function("jacobian + stability, no shape", |b| {
        b.iter(|| rod.jacobian(black_box(next())))
    });
    let mut i = 0;
    let mut next = || {
        i = (i + 1) % configurations.len();
        &configurations[i]
    };
    c.bench_function("shape only (64 nodes)", |b| {
        b.iter(|| rod.shape(black_box(next()), DEFAULT_NODES))
    });
    let mut i = 0;
    let mut next = || {
        i = (i + 1) % configurations.len();
        &configurations[i]
    };
    c.bench_function("is_stable (early exit), stable inputs", |b| {
        b.iter(|| rod.is_stable(black_box(next())))
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
