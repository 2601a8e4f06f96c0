//! The calibration learns a synthetic sensor made in this test (not the simulator): the
//! simulator's sensor structure (mounting offset and rotation, gain and cross-talk, cubic
//! nonlinearity, bias, noise) at its magnitudes, with the nonlinearity scaled so that it shows
//! at a 2 mm nitinol wire's loads. The trained calibration's test error must be far below the
//! raw reading's and near the noise floor (what the exact inverse of the sensor achieves on the
//! same noisy readings).
//!
//! `cargo test -p ftwire-estimate --release --test calibration_synthetic -- --nocapture` prints
//! the numbers.

use ftwire_estimate::calibration::{Affine, Calibration, Dataset, Normaliser, TrainParams};
use nalgebra::{Matrix3, Matrix6, Rotation3, Vector3, Vector6};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;

/// The synthetic sensor: `raw = N(G · mount(a)) + bias + noise`, force first.
struct Sensor {
    rotation: Matrix3<f64>,
    offset: Vector3<f64>,
    gain: Matrix6<f64>,
    cubic: [f64; 6],
    full_scale: [f64; 6],
    bias: Vector6<f64>,
    noise: [f64; 6],
}

impl Sensor {
    /// The simulator's default mounting, gain and bias; its cubic shape with 10× its
    /// coefficients over a full scale of the wire's load range (at the simulator's own full
    /// scale of 500 N the cubic is ~1e-8 of these loads, invisible under the noise); its noise
    /// averaged over 100 readings per sample.
    fn new() -> Self {
        Self {
            cubic: [0.04, -0.03, 0.05, -0.04, 0.03, 0.02],
            full_scale: [0.8, 0.8, 0.8, 0.5, 0.5, 0.5],
            ..Self::simulator()
        }
    }

    /// Exactly the simulator's default sensor (full scale 500 N / 900 N / 20 N·m, cubic up to
    /// 0.5 % FS), with its noise averaged over 100 readings.
    fn simulator() -> Self {
        let r = -2.0 * std::f64::consts::FRAC_PI_3 / 3f64.sqrt();
        Self {
            rotation: Rotation3::from_scaled_axis(Vector3::new(r, r, r)).into_inner(),
            offset: Vector3::new(0.0, 0.0, 0.08),
            gain: Matrix6::from_row_slice(&[
                1.012, 0.008, -0.005, 0.0, 0.0, 0.0, //
                -0.006, 0.991, 0.007, 0.0, 0.0, 0.0, //
                0.004, -0.009, 1.006, 0.0, 0.0, 0.0, //
                0.0, 0.002, 0.0, 0.987, 0.010, -0.006, //
                -0.002, 0.0, 0.0, -0.008, 1.009, 0.005, //
                0.0, 0.0, 0.0, 0.006, -0.004, 1.015,
            ]),
            cubic: [0.004, -0.003, 0.005, -0.004, 0.003, 0.002],
            full_scale: [500.0, 500.0, 900.0, 20.0, 20.0, 20.0],
            bias: Vector6::new(0.35, -0.22, 0.61, 0.012, -0.008, 0.005),
            noise: [0.005, 0.005, 0.005, 0.0002, 0.0002, 0.0002],
        }
    }

    /// The reading without noise, for the configuration `a` (torque first, clamp frame).
    fn deterministic(&self, a: &Vector6<f64>) -> Vector6<f64> {
        let torque = a.fixed_rows::<3>(0).into_owned();
        let force = a.fixed_rows::<3>(3).into_owned();
        let f = self.rotation * force;
        let t = self.rotation * torque + self.offset.cross(&f);
        let g = self.gain * Vector6::new(f.x, f.y, f.z, t.x, t.y, t.z);
        Vector6::from_fn(|i, _| {
            let x = g[i] / self.full_scale[i];
            g[i] * (1.0 + self.cubic[i] * x * x)
        }) + self.bias
    }

    /// The exact inverse of [`Sensor::deterministic`]: the best any calibration can do.
    fn invert(&self, raw: &Vector6<f64>) -> Vector6<f64> {
        let n = raw - self.bias;
        let g = Vector6::from_fn(|i, _| {
            let (k, fs) = (self.cubic[i], self.full_scale[i]);
            let mut x = n[i];
            for _ in 0..50 {
                let r = x * (1.0 + k * (x / fs).powi(2)) - n[i];
                x -= r / (1.0 + 3.0 * k * (x / fs).powi(2));
            }
            x
        });
        let s = self.gain.try_inverse().expect("gain near identity") * g;
        let f = Vector3::new(s[0], s[1], s[2]);
        let t = Vector3::new(s[3], s[4], s[5]) - self.offset.cross(&f);
        let force = self.rotation.transpose() * f;
        let torque = self.rotation.transpose() * t;
        Vector6::new(torque.x, torque.y, torque.z, force.x, force.y, force.z)
    }
}

/// Configurations uniform in the normalised box `[−5, 5]⁶` of the 2 mm / 630 mm nitinol wire
/// (torque scale `c2/L`, force scale `c2/L²`), and their noisy readings.
fn samples(sensor: &Sensor, n: usize, seed: u64) -> (Vec<Vector6<f64>>, Vec<Vector6<f64>>) {
    let (c2, length) = (0.055, 0.63);
    let scale = [c2 / length, c2 / length, c2 / length]
        .into_iter()
        .chain([c2 / (length * length); 3]);
    let scale: Vec<f64> = scale.collect();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let labels: Vec<Vector6<f64>> = (0..n)
        .map(|_| Vector6::from_fn(|i, _| scale[i] * rng.random_range(-5.0..=5.0)))
        .collect();
    let raw = labels
        .iter()
        .map(|a| {
            sensor.deterministic(a)
                + Vector6::from_fn(|i, _| sensor.noise[i] * rng.sample::<f64, _>(StandardNormal))
        })
        .collect();
    (raw, labels)
}

fn rmse<'a>(pairs: impl Iterator<Item = (Vector6<f64>, &'a Vector6<f64>)>) -> Vector6<f64> {
    let mut n = 0.0;
    let sum = pairs.fold(Vector6::zeros(), |acc, (p, a)| {
        n += 1.0;
        let e = p - a;
        acc + e.component_mul(&e)
    });
    (sum / n).map(f64::sqrt)
}

/// Test-split RMS errors of: the raw reading taken as `a` (reordered torque first), an affine
/// least-squares fit, the trained calibration, and the exact inverse (the noise floor).
struct Errors {
    raw: Vector6<f64>,
    affine: Vector6<f64>,
    trained: Vector6<f64>,
    floor: Vector6<f64>,
}

fn evaluate(samples_count: usize, config: &TrainParams, seed: u64) -> (Errors, Calibration) {
    evaluate_on(&Sensor::new(), samples_count, config, seed)
}

fn evaluate_on(
    sensor: &Sensor,
    samples_count: usize,
    config: &TrainParams,
    seed: u64,
) -> (Errors, Calibration) {
    let (raw, labels) = samples(sensor, samples_count, seed);
    let data = Dataset::new(raw.clone(), labels.clone()).expect("finite data");
    let calibration = Calibration::train(&data, config, seed).expect("trains");
    // The same split the trainer drew (its first use of the seeded generator).
    let split = data
        .split(&config.split, &mut ChaCha8Rng::seed_from_u64(seed))
        .expect("splits");
    let test: Vec<(Vector6<f64>, Vector6<f64>)> =
        data.pairs(&split.test).map(|(r, a)| (*r, *a)).collect();
    let input = Normaliser::fit(data.pairs(&split.train).map(|(r, _)| r));
    let output = Normaliser::fit(data.pairs(&split.train).map(|(_, a)| a));
    let normalised: Vec<_> = data
        .pairs(&split.train)
        .map(|(r, a)| (input.normalise(r), output.normalise(a)))
        .collect();
    let affine = Affine::fit(normalised.iter().map(|(z, y)| (z, y)));
    let errors = Errors {
        raw: rmse(
            test.iter()
                .map(|(r, a)| (Vector6::new(r[3], r[4], r[5], r[0], r[1], r[2]), a)),
        ),
        affine: rmse(
            test.iter()
                .map(|(r, a)| (output.denormalise(&affine.apply(&input.normalise(r))), a)),
        ),
        trained: calibration.rmse(test.iter().map(|(r, a)| (r, a))),
        floor: rmse(test.iter().map(|(r, a)| (sensor.invert(r), a))),
    };
    (errors, calibration)
}

fn print(name: &str, errors: &Errors, calibration: &Calibration) {
    let record = calibration.record();
    println!(
        "{name}: {} samples, epochs {} (best {}, {:?})",
        record.samples.train + record.samples.validation + record.samples.test,
        record.epochs,
        record.best_epoch,
        record.stop
    );
    for (label, e) in [
        ("raw", errors.raw),
        ("affine", errors.affine),
        ("trained", errors.trained),
        ("floor", errors.floor),
    ] {
        println!(
            "  {label:>8} τ [mN·m] {:7.3} {:7.3} {:7.3}   f [mN] {:7.3} {:7.3} {:7.3}",
            1e3 * e[0],
            1e3 * e[1],
            1e3 * e[2],
            1e3 * e[3],
            1e3 * e[4],
            1e3 * e[5]
        );
    }
}

/// With the default configuration and 3 000 samples the trained calibration is within 35 % of
/// the noise floor on every component, far below the raw reading's error and below the affine
/// fit's.
#[test]
fn trained_calibration_reaches_the_noise_floor() {
    let config = TrainParams::default();
    let (errors, calibration) = evaluate(3000, &config, 11);
    print("residual 6-64-64-6", &errors, &calibration);
    for i in 0..6 {
        assert!(
            errors.trained[i] < 1.35 * errors.floor[i],
            "component {i}: trained {} vs floor {}",
            errors.trained[i],
            errors.floor[i]
        );
        assert!(errors.trained[i] < 0.02 * errors.raw[i]);
        assert!(errors.trained[i] < errors.affine[i]);
    }
    let recorded = calibration.record().test_rmse.expect("a test split");
    for (recorded, trained) in recorded.iter().zip(errors.trained.iter()) {
        approx::assert_relative_eq!(*recorded, *trained, max_relative = 1e-12);
    }
}

/// The residual network against a plain one on the same small data set (printed; the residual
/// one must not be worse).
#[test]
fn residual_beats_plain_network() {
    let samples = 300;
    let residual = TrainParams::default();
    let plain = TrainParams {
        residual: false,
        ..TrainParams::default()
    };
    let (with, with_calibration) = evaluate(samples, &residual, 5);
    let (without, without_calibration) = evaluate(samples, &plain, 5);
    print(&format!("residual, {samples}"), &with, &with_calibration);
    print(&format!("plain, {samples}"), &without, &without_calibration);
    assert!(with.trained.sum() <= without.trained.sum());
}

/// With the simulator's own sensor the loads of a 2 mm wire are linear to well below the noise:
/// the affine fit is already at the floor, and the network must not spoil it.
#[test]
fn linear_sensor_stays_at_the_noise_floor() {
    let (errors, calibration) = evaluate_on(&Sensor::simulator(), 1000, &TrainParams::default(), 7);
    print("simulator's sensor, residual", &errors, &calibration);
    for i in 0..6 {
        assert!(errors.affine[i] < 1.1 * errors.floor[i], "component {i}");
        assert!(errors.trained[i] < 1.1 * errors.floor[i], "component {i}");
    }
}
