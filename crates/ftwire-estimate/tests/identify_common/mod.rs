//! Data for the identification tests, made with the Kirchhoff model itself.
#![allow(dead_code)]

use ftwire_core::{Pose, WireParams};
use ftwire_estimate::identify::MeasurementNoise;
use ftwire_estimate::{EstimateError, KirchhoffModel, WireModel};
use ftwire_rod::{from_normalised, sampling::Sampler, se3};
use nalgebra::Vector6;
use rand::{Rng, RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

/// The 3 mm nitinol wire of Table I.
pub fn thick() -> Result<KirchhoffModel, EstimateError> {
    Ok(KirchhoffModel::new(WireParams::new(
        [0.214, 0.278, 0.278],
        0.82,
        0.0015,
    )?))
}

/// The 2 mm nitinol wire of Table I.
pub fn thin() -> Result<KirchhoffModel, EstimateError> {
    Ok(KirchhoffModel::new(WireParams::new(
        [0.042, 0.055, 0.055],
        0.63,
        0.001,
    )?))
}

/// Measurement noise: relative to the wire's torque and force scales for `ã`, absolute for `b̃`.
#[derive(Debug, Clone, Copy)]
pub struct Noise {
    /// Standard deviation of `ã` as a fraction of `c2/L` (torque) and `c2/L²` (force).
    pub wrench: f64,
    /// Standard deviation of the position of `b̃` [m].
    pub translation: f64,
    /// Standard deviation of the orientation of `b̃` per axis [rad].
    pub rotation: f64,
}

/// The noise of the brief: 0.2 % of the wrench scales, 0.1 mm and 0.05°.
pub const SENSOR: Noise = Noise {
    wrench: 2e-3,
    translation: 1e-4,
    rotation: 0.05 * std::f64::consts::PI / 180.0,
};

/// The identification's noise model matching `noise` on `wire`.
pub fn noise_model(wire: &WireParams, noise: Noise) -> MeasurementNoise {
    MeasurementNoise {
        rotation: noise.rotation,
        translation: noise.translation,
        torque: noise.wrench * wire.torque_scale(),
        force: noise.wrench * wire.force_scale(),
        wrench: None,
        gain: 0.0,
        torque_gain: None,
        bias: None,
    }
}

/// A stable `a0` (normalised box `[−half_width, half_width]⁶`) and `n` stable configurations
/// near it (each `a0` plus a uniform normalised step in `±step` per component), with their
/// exact tip poses, then `noise` added.
pub fn samples(
    model: &KirchhoffModel,
    seed: u64,
    n: usize,
    step: f64,
    noise: Option<Noise>,
) -> Result<Vec<(Vector6<f64>, Pose)>, EstimateError> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let wire = *model.wire();
    let a0 = Sampler::new(3.0)?.sample_stable(model.rod(), &mut rng)?;
    let mut out = Vec::with_capacity(n);
    while out.len() < n {
        let d = Vector6::from_fn(|_, _| rng.random_range(-step..=step));
        let a = if out.is_empty() {
            a0
        } else {
            a0 + from_normalised(&wire, &d)
        };
        if !model.is_stable(&a)? {
            continue;
        }
        out.push((a, model.tip(&a)?));
    }
    if let Some(noise) = noise {
        add_noise(&wire, &mut out, noise, &mut rng);
    }
    Ok(out)
}

/// Adds Gaussian noise to `ã` and `b̃` (pose noise in the body frame).
pub fn add_noise<R: Rng>(
    wire: &WireParams,
    data: &mut [(Vector6<f64>, Pose)],
    noise: Noise,
    rng: &mut R,
) {
    let unit = Normal::new(0.0, 1.0).unwrap_or_else(|_| unreachable!());
    let (ts, fs) = (wire.torque_scale(), wire.force_scale());
    for (a, b) in data.iter_mut() {
        for i in 0..6 {
            let scale = if i < 3 { ts } else { fs };
            a[i] += noise.wrench * scale * unit.sample(rng);
        }
        let xi = Vector6::from_fn(|i, _| {
            let s = if i < 3 {
                noise.rotation
            } else {
                noise.translation
            };
            s * unit.sample(rng)
        });
        *b *= se3::exp(&xi);
    }
}

/// Relative errors of `(c1, c2, c3, L)`.
pub fn errors(c: [f64; 3], length: f64, truth: &WireParams) -> [f64; 4] {
    let t = truth.c();
    [
        (c[0] / t[0] - 1.0).abs(),
        (c[1] / t[1] - 1.0).abs(),
        (c[2] / t[2] - 1.0).abs(),
        (length / truth.length() - 1.0).abs(),
    ]
}

/// The largest of the errors.
pub fn worst(e: [f64; 4]) -> f64 {
    e.into_iter().fold(0.0, f64::max)
}
