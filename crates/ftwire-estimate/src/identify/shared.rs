//! What the samples of an identification share, as a prior covariance: the sensor's bias
//! ([`super::drift`]) with each sample's time since the tare, the map's gain error
//! ([`MeasurementNoise::gain`]) with each sample's `ã`, and, in the polish, each rest's own
//! noise. The whitening of [`super::Residuals`] and the joint fit (`identify/joint.rs`) both
//! use it.

use nalgebra::{DMatrix, Matrix6, Vector6};

use super::drift::BiasDrift;
use super::noise::MeasurementNoise;
use super::sample::Sample;

/// What every sample shares: the bias with each sample's time since the tare, and the
/// relative gain error with each sample's `ã`.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct SharedBias {
    /// The bias and the samples' times, when both are known.
    pub(super) bias: Option<(BiasDrift, Vec<f64>)>,
    /// Each channel's squared gain error ([`MeasurementNoise::gains`]) and the samples' `ã`.
    pub(super) gain: (Vector6<f64>, Vec<Vector6<f64>>),
    /// In the polish, each rest's own noise `Σ_a` ([`MeasurementNoise::wrench_covariance`]),
    /// estimated per sample with the shared path so that each outer iteration linearises `Γ`
    /// at the estimated true `a_i`, not at the noisy `ã_i` (module docs); `None` where the own
    /// noise stays in each sample's own covariance (the whitening of [`super::Residuals`]).
    pub(super) own: Option<Matrix6<f64>>,
}

/// What `samples` share under `noise`: `Some` with a bias model and every sample's time
/// known, or with a gain error.
pub(super) fn shared_bias(samples: &[Sample], noise: &MeasurementNoise) -> Option<SharedBias> {
    let bias = noise.bias.and_then(|bias| {
        let times = samples
            .iter()
            .map(|s| s.time)
            .collect::<Option<Vec<f64>>>()?;
        Some((bias, times))
    });
    let gains = noise.gains();
    if bias.is_none() && gains.amax() <= 0.0 {
        return None;
    }
    Some(SharedBias {
        own: None,
        bias,
        gain: (
            gains.component_mul(&gains),
            samples.iter().map(|s| s.a).collect(),
        ),
    })
}

impl SharedBias {
    /// The samples.
    pub(super) fn len(&self) -> usize {
        self.gain.1.len()
    }

    /// `Cov(β_i, β_j)`: the bias's `Σ₀ + Q k(t_i, t_j)`, the gain's
    /// `diag(g)² diag(ã_i) diag(ã_j)` and, for `i = j`, the rest's own `Σ_a`.
    fn block(&self, i: usize, j: usize) -> Matrix6<f64> {
        let (squared, a) = &self.gain;
        let mut block = Matrix6::from_diagonal(&a[i].component_mul(&a[j]).component_mul(squared));
        if i == j
            && let Some(own) = self.own
        {
            block += own;
        }
        if let Some((bias, times)) = &self.bias {
            block += bias.covariance(times[i], times[j]);
        }
        block
    }

    /// `K`, the stacked prior covariance of the shared path (`6N × 6N`).
    pub(super) fn prior(&self) -> DMatrix<f64> {
        let n = self.len();
        let mut k = DMatrix::zeros(6 * n, 6 * n);
        for i in 0..n {
            for j in 0..=i {
                let block = self.block(i, j);
                k.fixed_view_mut::<6, 6>(6 * i, 6 * j).copy_from(&block);
                k.fixed_view_mut::<6, 6>(6 * j, 6 * i)
                    .copy_from(&block.transpose());
            }
        }
        k
    }

    /// `C = R + G K Gᵀ`: the stacked residual's covariance, from each sample's `W J_i` (`wj`)
    /// and own covariance (`own`, the blocks of `R`).
    pub(super) fn covariance(&self, wj: &[Matrix6<f64>], own: &[Matrix6<f64>]) -> DMatrix<f64> {
        let n = own.len().min(wj.len()).min(self.len());
        let mut cov = DMatrix::zeros(6 * n, 6 * n);
        for i in 0..n {
            for j in 0..=i {
                let mut block = wj[i] * self.block(i, j) * wj[j].transpose();
                if i == j {
                    block += own[i];
                }
                cov.fixed_view_mut::<6, 6>(6 * i, 6 * j).copy_from(&block);
                cov.fixed_view_mut::<6, 6>(6 * j, 6 * i)
                    .copy_from(&block.transpose());
            }
        }
        cov
    }
}
