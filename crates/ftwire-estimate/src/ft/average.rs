//! Averaging the samples taken while the rig is at rest.

use ftwire_core::FtSample;
use nalgebra::Vector6;

use super::{Screen, ScreenReport};
use crate::EstimateError;

/// The mean of the good raw samples of one rest period, with its measured noise.
#[derive(Debug, Clone, PartialEq)]
pub struct Averaged {
    /// Mean raw reading (force first, sensor frame, sensor units).
    pub mean: Vector6<f64>,
    /// Sample standard deviation per channel: the sensor's noise as measured in this period.
    pub std: Vector6<f64>,
    /// Standard error of the mean per channel, `std / √n`: the noise left in [`Averaged::mean`].
    pub std_error: Vector6<f64>,
    /// Time of the last sample used \[s\].
    pub time: f64,
    /// What was kept and skipped.
    pub screen: ScreenReport,
}

/// Block averaging of the samples read while the rig is at rest (quasi-static motion: move,
/// stop, read `K` samples, average).
///
/// The mean of `K` samples has `1/√K` of the white noise; it lags the last sample by
/// `(K − 1)/(2r)` at sample rate `r`, which costs nothing on a rig at rest. Bias drift is not
/// averaged away: that is the tare's job ([`super::Tare`]).
///
/// # Example
/// ```
/// use ftwire_core::FtSample;
/// use ftwire_estimate::ft::RestAverage;
/// use nalgebra::Vector6;
///
/// let samples: Vec<Option<FtSample>> = (0..4)
///     .map(|i| Some(FtSample { time: i as f64 * 1e-3, raw: Vector6::repeat(i as f64), ..Default::default() }))
///     .chain([None])
///     .collect();
/// let averaged = RestAverage::new(3)?.average(samples.iter().map(Option::as_ref))?;
/// assert_eq!(averaged.mean, Vector6::repeat(1.5));
/// assert_eq!((averaged.screen.accepted, averaged.screen.dropouts), (4, 1));
/// # Ok::<(), ftwire_estimate::EstimateError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct RestAverage {
    min_samples: usize,
    screen: Screen,
}

impl RestAverage {
    /// Averages that need at least `min_samples` good samples (at least 2, so the noise can be
    /// measured).
    ///
    /// # Errors
    /// [`EstimateError::BadSetting`] when `min_samples < 2`.
    pub fn new(min_samples: usize) -> Result<Self, EstimateError> {
        if min_samples < 2 {
            return Err(EstimateError::BadSetting {
                name: "min_samples",
                value: min_samples as f64,
                allowed: "at least 2",
            });
        }
        Ok(Self {
            min_samples,
            screen: Screen::new(),
        })
    }

    /// Uses this screen (e.g. one with a full scale) for the samples.
    #[must_use]
    pub fn with_screen(mut self, screen: Screen) -> Self {
        self.screen = screen;
        self
    }

    /// The fewest good samples an average needs.
    pub fn min_samples(&self) -> usize {
        self.min_samples
    }

    /// Averages one rest period's samples (`None` for a dropout).
    ///
    /// # Errors
    /// [`EstimateError::TooFewGoodSamples`] when fewer than the minimum survive screening; the
    /// error carries the screen's report.
    pub fn average<'a>(
        &self,
        samples: impl IntoIterator<Item = Option<&'a FtSample>>,
    ) -> Result<Averaged, EstimateError> {
        let mut screen = self.screen.clone();
        screen.reset();
        // Welford's running mean and variance: one pass, stable.
        let mut n = 0usize;
        let mut mean = Vector6::zeros();
        let mut m2 = Vector6::zeros();
        let mut time = f64::NAN;
        for sample in samples {
            if let Some(raw) = screen.accept(sample) {
                n += 1;
                let delta = raw - mean;
                mean += delta / n as f64;
                m2 += delta.component_mul(&(raw - mean));
                time = sample.map_or(time, |s| s.time);
            }
        }
        let report = screen.report().clone();
        if n < self.min_samples {
            return Err(EstimateError::TooFewGoodSamples {
                good: n,
                needed: self.min_samples,
                report: Box::new(report),
            });
        }
        let std = (m2 / (n - 1) as f64).map(f64::sqrt);
        Ok(Averaged {
            mean,
            std_error: std / (n as f64).sqrt(),
            std,
            time,
            screen: report,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;
    use rand_distr::{Distribution, Normal};

    fn noisy(n: usize, sigma: f64, seed: u64) -> Result<Vec<FtSample>, rand_distr::NormalError> {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let normal = Normal::new(0.0, sigma)?;
        let truth = Vector6::new(1.0, -2.0, 3.0, 0.1, -0.2, 0.3);
        Ok((0..n)
            .map(|i| FtSample {
                time: i as f64 * 1e-3,
                raw: truth + Vector6::from_fn(|_, _| normal.sample(&mut rng)),
                ..Default::default()
            })
            .collect())
    }

    #[test]
    fn the_measured_noise_is_the_noise_and_the_mean_has_a_root_n_less()
    -> Result<(), Box<dyn std::error::Error>> {
        let sigma = 0.05;
        let samples = noisy(2000, sigma, 11)?;
        let avg = RestAverage::new(2)?.average(samples.iter().map(Some))?;
        for i in 0..6 {
            assert!(
                (avg.std[i] / sigma - 1.0).abs() < 0.05,
                "std {} vs {sigma}",
                avg.std[i]
            );
            assert!((avg.std_error[i] - avg.std[i] / 2000f64.sqrt()).abs() < 1e-15);
        }
        let truth = Vector6::new(1.0, -2.0, 3.0, 0.1, -0.2, 0.3);
        // Four standard errors: fails by chance with probability ~1e-4 per channel.
        assert!(((avg.mean - truth).abs() - avg.std_error * 4.0).max() < 0.0);
        Ok(())
    }

    #[test]
    fn non_finite_samples_are_skipped_and_counted_never_averaged()
    -> Result<(), Box<dyn std::error::Error>> {
        let mut samples = noisy(10, 0.01, 3)?;
        samples[4].raw[2] = f64::NAN;
        samples[7].raw[5] = f64::INFINITY;
        let avg = RestAverage::new(5)?.average(samples.iter().map(Some))?;
        assert!(avg.mean.iter().all(|v| v.is_finite()));
        assert_eq!((avg.screen.accepted, avg.screen.non_finite), (8, 2));
        assert_eq!(avg.screen.skips[0].0, 4);
        Ok(())
    }

    #[test]
    fn too_few_good_samples_is_an_error_that_says_why() -> Result<(), Box<dyn std::error::Error>> {
        let samples = noisy(3, 0.01, 5)?;
        let offered = [Some(&samples[0]), None, None, Some(&samples[1])];
        match RestAverage::new(3)?.average(offered) {
            Err(EstimateError::TooFewGoodSamples {
                good: 2,
                needed: 3,
                report,
            }) => {
                assert_eq!(report.dropouts, 2);
            }
            other => panic!("expected TooFewGoodSamples, got {other:?}"),
        }
        Ok(())
    }
}
