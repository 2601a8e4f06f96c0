//! `ftwire ros2 estimate`'s error bars: the standard deviation `σ(s)` of each published
//! shape along the wire, and, against a simulator's true centreline, the share of its points
//! within `2σ`.
//!
//! `σ(s)` is first order: the shape's derivative in `a`
//! ([`ftwire_estimate::shape::shape_sigma`]) times the covariance of the `ã` it is the shape
//! of, with the model's own error `e·s` added in quadrature when given. That covariance is
//! - the window's own noise: the sensor's data sheet, `window` readings averaged
//!   ([`ftwire_estimate::identify::MeasurementNoise::wrench_covariance`]);
//! - the calibration's gain error `diag(g ∘ ã)²` (`--gain-error`);
//! - the bias: with the bias observer, once it has used a rest, the covariance of its
//!   estimate `β̂` with the drift since that rest
//!   ([`ftwire_control::BiasObserver::bias_covariance`], the shape is of `ã − β̂`); before,
//!   or without the observer, the tare's error and the drift since the tare
//!   ([`ftwire_estimate::identify::BiasDrift`]), as `ftwire shape --log --sensor` does.

use ftwire_estimate::identify::MeasurementNoise;
use ftwire_estimate::shape::ModelError;
use nalgebra::{Matrix6, Vector3, Vector6};
use serde::Serialize;

/// What the error bars are drawn from.
#[derive(Debug, Clone, PartialEq)]
pub struct ErrorBars {
    /// The error of a window's `ã` (the module docs): the sensor's data sheet with the window
    /// and the tare's samples, and the gain error.
    pub noise: MeasurementNoise,
    /// The model's own error against the wire, `σ_model(s) = e·s` (`--model-error`).
    pub model_error: Option<ModelError>,
}

impl ErrorBars {
    /// The covariance of `a` (the shaped `ã − β̂`) at `since_tare` seconds after the tare;
    /// `observer_bias`: the bias observer's covariance of `β̂` now, once it has used a rest.
    pub fn covariance(
        &self,
        a: &Vector6<f64>,
        since_tare: f64,
        observer_bias: Option<Matrix6<f64>>,
    ) -> Matrix6<f64> {
        match observer_bias {
            Some(bias) => {
                let own = MeasurementNoise {
                    bias: None,
                    ..self.noise
                };
                own.sample_covariance(a, 0.0) + bias
            }
            None => self.noise.sample_covariance(a, since_tare.max(0.0)),
        }
    }
}

/// The error bars against true centrelines: points compared, and those within `2σ`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Coverage {
    /// True points compared (the base clamp point left out: its `σ` and error are 0).
    pub points: u64,
    /// Of them, within `2σ` of the estimate at their arc length.
    pub within: u64,
}

/// The summary's error bars.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SigmaSummary {
    /// The mean over the published shapes of `σ` at the tip \[mm\].
    pub tip_mean_mm: f64,
    /// The largest `σ` at a tip \[mm\].
    pub tip_max_mm: f64,
    /// With `--truth-topic`: the share of the true points within `2σ` of the estimate at
    /// their arc length (`null` without a truth).
    pub within_2sigma: Option<f64>,
}

impl Coverage {
    /// Compares the true centreline `truth` (base clamp first) with the `shape` and its
    /// `sigma` (the same nodes, evenly spaced in arc length, \[m\]): each true point after the
    /// first against the shape at its own arc length (its share of the truth's length,
    /// linearly between nodes). Nothing is counted for fewer than two points of either, or
    /// for lengths that do not match.
    pub fn add(&mut self, truth: &[Vector3<f64>], shape: &[Vector3<f64>], sigma: &[f64]) {
        if truth.len() < 2 || shape.len() < 2 || sigma.len() != shape.len() {
            return;
        }
        let mut arc = Vec::with_capacity(truth.len());
        let mut length = 0.0;
        arc.push(0.0);
        for pair in truth.windows(2) {
            length += (pair[1] - pair[0]).norm();
            arc.push(length);
        }
        if !(length.is_finite() && length > 0.0) {
            return;
        }
        #[allow(clippy::cast_precision_loss)] // a few hundred nodes
        let last = (shape.len() - 1) as f64;
        for (point, s) in truth.iter().zip(&arc).skip(1) {
            let x = (s / length * last).clamp(0.0, last);
            #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)] // in [0, last]
            let k = (x.floor() as usize).min(shape.len() - 2);
            #[allow(clippy::cast_precision_loss)]
            let t = x - k as f64;
            let estimate = shape[k] * (1.0 - t) + shape[k + 1] * t;
            let bar = sigma[k] * (1.0 - t) + sigma[k + 1] * t;
            self.points += 1;
            self.within += u64::from((point - estimate).norm() <= 2.0 * bar);
        }
    }

    /// The share within `2σ`; `None` before any point.
    pub fn share(&self) -> Option<f64> {
        #[allow(clippy::cast_precision_loss)] // counts far below 2⁵²
        (self.points > 0).then(|| self.within as f64 / self.points as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ftwire_estimate::identify::BiasDrift;

    fn straight(n: usize, length: f64) -> Vec<Vector3<f64>> {
        (0..n)
            .map(|k| Vector3::new(length * k as f64 / (n - 1) as f64, 0.0, 0.0))
            .collect()
    }

    #[test]
    fn points_are_compared_at_their_own_arc_length() {
        let shape = straight(5, 1.0);
        // σ grows along the wire: 0, 1, 2, 3, 4 mm.
        let sigma: Vec<f64> = (0..5).map(|k| 1e-3 * k as f64).collect();
        // A truth with other nodes, each 3 mm to the side: within 2σ only where σ ≥ 1.5 mm,
        // from s = 0.375 on.
        let truth: Vec<Vector3<f64>> = straight(9, 1.0)
            .into_iter()
            .map(|p| p + Vector3::new(0.0, 3e-3, 0.0))
            .collect();
        let mut coverage = Coverage::default();
        coverage.add(&truth, &shape, &sigma);
        // The 8 points after the base: s = 0.125 … 1; σ = 0.5 … 4 mm; within from s = 0.375.
        assert_eq!((coverage.points, coverage.within), (8, 6));
        assert_eq!(coverage.share(), Some(0.75));
        // Mismatched or degenerate input counts nothing.
        coverage.add(&truth[..1], &shape, &sigma);
        coverage.add(&truth, &shape, &sigma[..3]);
        coverage.add(&[Vector3::zeros(); 4], &shape, &sigma);
        assert_eq!(coverage.points, 8);
        assert_eq!(Coverage::default().share(), None);
    }

    #[test]
    fn the_observers_bias_replaces_the_drift_since_the_tare() {
        let drift = BiasDrift::from_sensor(
            &Matrix6::identity(),
            [2e-3, 2e-3, 2e-3, 1e-4, 1e-4, 1e-4],
            [2e-3, 2e-3, 2e-3, 1e-4, 1e-4, 1e-4],
            f64::INFINITY,
        )
        .expect("valid");
        let bars = ErrorBars {
            noise: MeasurementNoise {
                gain: 1e-3,
                bias: Some(drift),
                ..MeasurementNoise::default()
            },
            model_error: None,
        };
        let a = Vector6::new(0.0, 0.1, 0.0, 0.5, 0.0, 0.0);
        let early = bars.covariance(&a, 1.0, None);
        let late = bars.covariance(&a, 100.0, None);
        assert!(
            late[(3, 3)] > early[(3, 3)],
            "the drift since the tare grows"
        );
        let observer = Matrix6::identity() * 1e-8;
        let fused = bars.covariance(&a, 100.0, Some(observer));
        let own = MeasurementNoise::default().wrench_covariance();
        // The window's own noise, the gain error on the 0.5 N channel, the observer's bias.
        let expected = own[(3, 3)] + (1e-3 * 0.5_f64).powi(2) + 1e-8;
        assert!((fused[(3, 3)] - expected).abs() < 1e-15, "{fused}");
        assert_eq!(
            bars.covariance(&a, -5.0, None),
            bars.covariance(&a, 0.0, None)
        );
    }
}
