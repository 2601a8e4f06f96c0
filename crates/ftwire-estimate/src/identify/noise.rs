//! The measurement noise identification assumes, to judge whether a fit is as good as the data
//! allow.

use nalgebra::{Matrix6, Vector6};

use super::BiasDrift;
use crate::EstimateError;

/// Standard deviations of the measurement errors, per component, independent between samples,
/// and optionally the sensor bias every sample shares ([`BiasDrift`]).
///
/// Identification whitens the final fit with them and tests it against them: a weighted cost
/// far above what this noise explains means the model does not fit the data (wrong basin,
/// untared sensor, a load the model lacks), and the estimate is flagged not identified.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeasurementNoise {
    /// Orientation error of `b̃` per axis \[rad\] (default `0.05°`).
    pub rotation: f64,
    /// Position error of `b̃` per axis \[m\] (default `1e-4`, 0.1 mm).
    pub translation: f64,
    /// Torque error of `ã` per axis after taring and averaging \[N·m\] (default `1e-4`).
    pub torque: f64,
    /// Force error of `ã` per axis after taring and averaging \[N\] (default `2e-3`).
    pub force: f64,
    /// The full covariance of a sample's own error of `ã` (torque first) \[N²·m², N·m·N,
    /// N²\], in place of the diagonal of [`Self::torque`] and [`Self::force`] when given
    /// (default `None`): a sensor mounted a lever arm from the clamp turns its force noise into
    /// torque noise at the clamp too, so the two are correlated.
    pub wrench: Option<Matrix6<f64>>,
    /// The relative error of each channel of `ã` that every sample shares, as a fraction of
    /// the channel's value (default `0`): a calibration's gain error, or the wire model's own
    /// scale error against the wire. `ã_i` then carries `diag(ã_i) γ` with `γ ~ N(0, gain² I)`
    /// the same for every sample, so more samples do not average it away; the final fit
    /// estimates it with the wire as it does the bias (absolute form only).
    pub gain: f64,
    /// The torque channels' shared relative error where it differs from [`Self::gain`], which
    /// is then the force channels' (default `None`: [`Self::gain`] for all six). A learnt
    /// calibration is typically closer in torque than in force.
    pub torque_gain: Option<f64>,
    /// The tare's offset and the bias drift that all samples share, or `None` to treat the
    /// errors of `ã` as independent between samples (default `None`). Used with samples
    /// that carry their time since the tare ([`super::Sample::time`]), absolute form only.
    pub bias: Option<BiasDrift>,
}

impl Default for MeasurementNoise {
    fn default() -> Self {
        Self {
            rotation: 0.05_f64.to_radians(),
            translation: 1e-4,
            torque: 1e-4,
            force: 2e-3,
            wrench: None,
            gain: 0.0,
            torque_gain: None,
            bias: None,
        }
    }
}

impl MeasurementNoise {
    /// Checks that every standard deviation is finite and positive.
    ///
    /// # Errors
    /// [`EstimateError::BadIdentifySetting`] naming the first bad field.
    pub fn validate(&self) -> Result<(), EstimateError> {
        let fields = [
            ("noise.rotation", self.rotation),
            ("noise.translation", self.translation),
            ("noise.torque", self.torque),
            ("noise.force", self.force),
        ];
        for (field, value) in fields {
            if !(value.is_finite() && value > 0.0) {
                return Err(EstimateError::BadIdentifySetting {
                    field,
                    value,
                    allowed: "finite and > 0",
                });
            }
        }
        let gains = [
            ("noise.gain", self.gain),
            ("noise.torque_gain", self.torque_gain.unwrap_or(0.0)),
        ];
        for (field, value) in gains {
            if !(value.is_finite() && (0.0..1.0).contains(&value)) {
                return Err(EstimateError::BadIdentifySetting {
                    field,
                    value,
                    allowed: "finite, from 0 to below 1 (a fraction of each channel)",
                });
            }
        }
        if let Some(m) = &self.wrench {
            let bad = |value, allowed| {
                Err(EstimateError::BadIdentifySetting {
                    field: "noise.wrench",
                    value,
                    allowed,
                })
            };
            if let Some(v) = m.iter().find(|v| !v.is_finite()) {
                return bad(*v, "finite");
            }
            let asymmetry = (m - m.transpose()).amax();
            if asymmetry > 1e-12 * m.amax().max(f64::MIN_POSITIVE) {
                return bad(asymmetry, "a symmetric matrix");
            }
            if m.cholesky().is_none() {
                return bad(m.diagonal().min(), "a positive-definite covariance");
            }
        }
        self.bias.as_ref().map_or(Ok(()), BiasDrift::validate)
    }

    /// The covariance of a pose error as a body twist `(δω, δx)`.
    pub fn pose_covariance(&self) -> Matrix6<f64> {
        let (r, t) = (self.rotation.powi(2), self.translation.powi(2));
        Matrix6::from_diagonal(&Vector6::new(r, r, r, t, t, t))
    }

    /// The whole covariance of one sample's `ã` read `since_tare` seconds after the tare: its
    /// own ([`Self::wrench_covariance`]), the bias's `Σ₀ + Q k(t, t)` ([`Self::bias`]) and the
    /// gain error's `diag(g ∘ ã)²` ([`Self::gains`]) — what a single sample's shape or
    /// estimate carries, the shared parts included.
    pub fn sample_covariance(&self, a: &Vector6<f64>, since_tare: f64) -> Matrix6<f64> {
        let shared = self
            .bias
            .map_or_else(Matrix6::zeros, |b| b.covariance(since_tare, since_tare));
        let scaled = a.component_mul(&self.gains());
        let gain = Matrix6::from_diagonal(&scaled.component_mul(&scaled));
        self.wrench_covariance() + shared + gain
    }

    /// The shared relative error of each channel of `ã` (torque first): [`Self::torque_gain`]
    /// (or [`Self::gain`]) for the torques, [`Self::gain`] for the forces.
    pub fn gains(&self) -> Vector6<f64> {
        let t = self.torque_gain.unwrap_or(self.gain);
        Vector6::new(t, t, t, self.gain, self.gain, self.gain)
    }

    /// The covariance of a configuration error `(δτ, δf)`: [`Self::wrench`] when given,
    /// otherwise the diagonal of [`Self::torque`] and [`Self::force`].
    pub fn wrench_covariance(&self) -> Matrix6<f64> {
        if let Some(m) = self.wrench {
            return m;
        }
        let (m, f) = (self.torque.powi(2), self.force.powi(2));
        Matrix6::from_diagonal(&Vector6::new(m, m, m, f, f, f))
    }

    /// The largest pose change between `b̃_0` and any other `b̃`, in standard deviations of the
    /// pose noise (largest component of the relative twist).
    pub fn pose_spread<'a>(&self, poses: impl IntoIterator<Item = &'a ftwire_core::Pose>) -> f64 {
        let mut poses = poses.into_iter();
        let Some(first) = poses.next() else {
            return 0.0;
        };
        poses
            .map(|b| {
                let xi = ftwire_rod::se3::log(&(first.inverse() * b));
                let rot = xi.fixed_rows::<3>(0).amax() / self.rotation;
                let pos =
                    (b.translation.vector - first.translation.vector).amax() / self.translation;
                rot.max(pos)
            })
            .fold(0.0, f64::max)
    }
}
