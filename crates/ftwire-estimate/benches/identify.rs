//! Batch identification of the 3 mm nitinol wire from 3 exact samples (the paper's Table I
//! setting), absolute residual, default settings, from the swarm's start. Target: ≤ 20 ms.
//! Also the loaded model under gravity, identifying the linear density as well (beyond the
//! paper; its solves cost about 3 times the weightless ones).
//!
//! `cargo bench -p ftwire-estimate --bench identify -- --warm-up-time 1 --measurement-time 3`
#![allow(missing_docs)]

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use ftwire_core::{Pose, WireParams};
use ftwire_estimate::identify::ParameterConstraints;
use ftwire_estimate::identify::{IdentifierParams, identify};
use ftwire_estimate::{KirchhoffModel, WireModel};
use ftwire_rod::{Load, from_normalised, sampling::Sampler};
use nalgebra::{Vector3, Vector6};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn samples(model: &KirchhoffModel, seed: u64) -> Vec<(Vector6<f64>, Pose)> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let sampler = Sampler::new(3.0).expect("valid half-width");
    let a0 = sampler
        .sample_stable(model.rod(), &mut rng)
        .expect("a stable sample");
    let mut out = Vec::new();
    while out.len() < 3 {
        let d = Vector6::from_fn(|_, _| rng.random_range(-0.5..=0.5));
        let a = if out.is_empty() {
            a0
        } else {
            a0 + from_normalised(model.wire(), &d)
        };
        if model.is_stable(&a).expect("solvable") {
            out.push((a, model.tip(&a).expect("solvable")));
        }
    }
    out
}

fn bench(c: &mut Criterion) {
    let wire = WireParams::new([0.214, 0.278, 0.278], 0.82, 0.0015).expect("valid wire");
    let model = KirchhoffModel::new(wire);
    let sets: Vec<_> = (0..8).map(|s| samples(&model, 100 + s)).collect();
    let config = IdentifierParams::default();
    let mut i = 0;
    c.bench_function("identify, 3 samples, absolute, 3 mm nitinol", |b| {
        b.iter(|| {
            i = (i + 1) % sets.len();
            let mut rng = ChaCha8Rng::seed_from_u64(i as u64);
            identify(&model, black_box(&sets[i]), &config, &mut rng)
        })
    });
    let g = Vector3::new(0.0, 0.0, -9.81);
    let load = Load::from_gravity(6450.0, 0.0015, g).expect("valid load");
    let loaded = model.with_load(load);
    let sets: Vec<_> = (0..8).map(|s| samples(&loaded, 100 + s)).collect();
    let config = IdentifierParams {
        constraints: ParameterConstraints {
            weight: Some(g),
            ..ParameterConstraints::default()
        },
        ..IdentifierParams::default()
    };
    // The estimator starts from the weightless template: it knows gravity, not the wire.
    c.bench_function(
        "identify, 3 samples, absolute, 3 mm nitinol, loaded model with its weight",
        |b| {
            b.iter(|| {
                i = (i + 1) % sets.len();
                let mut rng = ChaCha8Rng::seed_from_u64(i as u64);
                identify(&model, black_box(&sets[i]), &config, &mut rng)
            })
        },
    );
}

criterion_group!(benches, bench);
criterion_main!(benches);
