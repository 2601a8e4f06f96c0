//! Speed of shape estimation (one `ã` → 64-node centreline + stability + jump test) and of one
//! marker fit (eq. 15, default settings, 0.3 mm noise), on stable configurations of the 2 mm
//! nitinol wire sampled uniformly in normalised units in [−10, 10]⁶ (fixed seed).
//!
//! `cargo bench -p ftwire-estimate --bench shape -- --warm-up-time 1 --measurement-time 3`
#![allow(missing_docs)]

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use ftwire_core::WireParams;
use ftwire_estimate::shape::{
    Correspondence, FitParams, Markers, ShapeEstimator, ShapeFitter, evenly_spaced_fractions,
};
use ftwire_estimate::{KirchhoffModel, WireModel};
use ftwire_rod::sampling::Sampler;
use nalgebra::{Point3, Vector3, Vector6};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;

fn setup() -> (KirchhoffModel, Vec<Vector6<f64>>, Vec<Markers>) {
    let wire = WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001).expect("valid wire");
    let model = KirchhoffModel::new(wire);
    let mut rng = ChaCha8Rng::seed_from_u64(2024);
    let sampler = Sampler::new(10.0).expect("valid range");
    let configurations: Vec<Vector6<f64>> = (0..32)
        .map(|_| {
            sampler
                .sample_stable(model.rod(), &mut rng)
                .expect("stable sample")
        })
        .collect();
    let fractions = evenly_spaced_fractions(11);
    let markers = configurations
        .iter()
        .map(|a| {
            let shape = model.shape(a, 11).expect("solvable");
            let positions: Vec<_> = shape
                .positions
                .iter()
                .map(|p| {
                    let noise =
                        Vector3::from_fn(|_, _| 3e-4 * rng.sample::<f64, _>(StandardNormal));
                    Some(Point3::from(p + noise))
                })
                .collect();
            Markers::new(&fractions, &positions).expect("valid markers")
        })
        .collect();
    (model, configurations, markers)
}

fn bench(c: &mut Criterion) {
    let (model, configurations, markers) = setup();
    let mut estimator = ShapeEstimator::new(model);
    let mut i = 0;
    c.bench_function("shape estimate (64 nodes, stability, jump test)", |b| {
        b.iter(|| {
            i = (i + 1) % configurations.len();
            estimator.estimate(black_box(&configurations[i]))
        })
    });
    // Its two parts, for comparison: the model's shape and its stability test.
    let mut i = 0;
    c.bench_function("part: model shape (64 nodes)", |b| {
        b.iter(|| {
            i = (i + 1) % configurations.len();
            model.shape(black_box(&configurations[i]), 64)
        })
    });
    let mut i = 0;
    c.bench_function("part: model stability test", |b| {
        b.iter(|| {
            i = (i + 1) % configurations.len();
            model.is_stable(black_box(&configurations[i]))
        })
    });
    let fitter = ShapeFitter::new(model);
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut i = 0;
    let mut group = c.benchmark_group("marker fit");
    group.sample_size(10);
    group.bench_function("11 markers, 0.3 mm noise, default settings", |b| {
        b.iter(|| {
            i = (i + 1) % markers.len();
            fitter.fit(black_box(&markers[i]), &mut rng)
        })
    });
    // The labels of `ftwire calibrate --log` without the markers' arc lengths: one per record.
    let closest = ShapeFitter::new(model)
        .with_config(FitParams {
            correspondence: Correspondence::ClosestPoint,
            ..FitParams::default()
        })
        .expect("valid settings");
    let mut i = 0;
    group.bench_function("11 markers, 0.3 mm noise, closest points", |b| {
        b.iter(|| {
            i = (i + 1) % markers.len();
            closest.fit(black_box(&markers[i]), &mut rng)
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
