//! Speed of the model's hot paths on stable configurations of the 2 mm nitinol wire, sampled
//! uniformly in normalised units in [−30, 30]⁶ (fixed seed), without load and (the `loaded:`
//! cases) under the wire's weight.
//!
//! `cargo bench -p ftwire-rod --bench solve` (add `-- --measurement-time 2 --warm-up-time 1`
//! on a busy machine).
#![allow(missing_docs)]

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use ftwire_rod::{DEFAULT_NODES, Load, Rod, WireParams, sampling::Sampler};
use nalgebra::{Vector3, Vector6};
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

    // The same configurations under the wire's weight (2 mm nitinol, 6450 kg/m³, gravity
    // along −z of the base clamp frame): the loaded solver of `ftwire_rod::load`.
    let load =
        Load::from_gravity(6450.0, 0.001, Vector3::new(0.0, 0.0, -9.81)).expect("valid load");
    let loaded = rod.with_load(load);
    let mut i = 0;
    let mut next = || {
        i = (i + 1) % configurations.len();
        &configurations[i]
    };
    c.bench_function(
        "loaded: full solve (64-node shape + J(L) + stability + self-intersection)",
        |b| b.iter(|| loaded.solve(black_box(next()), DEFAULT_NODES)),
    );
    let mut i = 0;
    let mut next = || {
        i = (i + 1) % configurations.len();
        &configurations[i]
    };
    c.bench_function("loaded: jacobian + stability, no shape", |b| {
        b.iter(|| loaded.jacobian(black_box(next())))
    });
    let mut i = 0;
    let mut next = || {
        i = (i + 1) % configurations.len();
        &configurations[i]
    };
    c.bench_function("loaded: shape only (64 nodes)", |b| {
        b.iter(|| loaded.shape(black_box(next()), DEFAULT_NODES))
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
