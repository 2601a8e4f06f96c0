//! Speed of `Calibration::apply` (target: a few µs) and of one training epoch, for the default
//! 6-64-64-6 tanh network.
//!
//! `cargo bench -p ftwire-estimate --bench calibration -- --warm-up-time 1 --measurement-time 3`

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use ftwire_estimate::calibration::{Calibration, Dataset, TrainParams};
use nalgebra::Vector6;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// 1 000 samples of a mildly nonlinear sensor with cross-talk.
fn data() -> Result<Dataset, ftwire_estimate::EstimateError> {
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let labels: Vec<Vector6<f64>> = (0..1000)
        .map(|_| Vector6::from_fn(|_, _| rng.random_range(-1.0..=1.0)))
        .collect();
    let raw = labels
        .iter()
        .map(|a| {
            let s = Vector6::new(a[3], a[4], a[5], a[0], a[1], a[2]);
            s + 0.01 * s.map(|x| x.powi(3)) + 0.01 * Vector6::repeat(s.sum())
        })
        .collect();
    Dataset::new(raw, labels)
}

fn bench(c: &mut Criterion) {
    let Ok(data) = data() else {
        return;
    };
    let one_epoch = TrainParams {
        max_epochs: 1,
        ..TrainParams::default()
    };
    let Ok(calibration) = Calibration::train(&data, &one_epoch, 3) else {
        return;
    };
    let raw = data.raw().to_vec();
    c.bench_function("calibration apply (6-64-64-6 tanh)", |b| {
        let mut i = 0;
        b.iter(|| {
            i = (i + 1) % raw.len();
            black_box(calibration.apply(black_box(&raw[i])))
        });
    });
    c.bench_function("calibration train one epoch (700 samples)", |b| {
        b.iter(|| black_box(Calibration::train(&data, &one_epoch, 3)));
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
