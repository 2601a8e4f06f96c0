//! Screening raw samples: what never enters an estimate.

use ftwire_core::FtSample;
use nalgebra::Vector6;

use super::report::{ScreenReport, SkipReason};
use crate::EstimateError;

/// Screens raw samples: keeps the good ones, skips and counts the others.
///
/// A sample is skipped when it is missing (a dropout), when a channel is not finite, when the
/// sensor flagged it as clipped, or — for sensors that do not flag clipping — when a channel's
/// magnitude reaches the full scale given with [`Screen::with_full_scale`].
///
/// # Example
/// ```
/// use ftwire_core::FtSample;
/// use ftwire_estimate::ft::Screen;
/// use nalgebra::Vector6;
///
/// let mut screen = Screen::new().with_full_scale([500.0, 500.0, 900.0, 20.0, 20.0, 20.0])?;
/// let good = FtSample { time: 0.0, raw: Vector6::repeat(0.1), ..Default::default() };
/// let clipped = FtSample { time: 0.001, raw: Vector6::new(500.0, 0.0, 0.0, 0.0, 0.0, 0.0), ..Default::default() };
/// assert!(screen.accept(Some(&good)).is_some());
/// assert!(screen.accept(Some(&clipped)).is_none());
/// assert!(screen.accept(None).is_none());
/// assert_eq!((screen.report().accepted, screen.report().saturated, screen.report().dropouts), (1, 1, 1));
/// # Ok::<(), ftwire_estimate::EstimateError>(())
/// ```
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Screen {
    full_scale: Option<[f64; 6]>,
    report: ScreenReport,
}

impl Screen {
    /// A screen that trusts the sensor's own saturation flags.
    pub fn new() -> Self {
        Self::default()
    }

    /// Also treats a channel as clipped when its magnitude reaches `full_scale` (force first,
    /// \[N\] and \[N·m\]).
    ///
    /// # Errors
    /// [`EstimateError::BadSetting`] when a full scale is not finite and positive.
    pub fn with_full_scale(mut self, full_scale: [f64; 6]) -> Result<Self, EstimateError> {
        if let Some(value) = full_scale.iter().find(|v| !(v.is_finite() && **v > 0.0)) {
            return Err(EstimateError::BadSetting {
                name: "full_scale",
                value: *value,
                allowed: "finite and > 0 on every channel",
            });
        }
        self.full_scale = Some(full_scale);
        Ok(self)
    }

    /// Offers one sample (`None` for a dropout); returns its raw reading if it is kept.
    pub fn accept(&mut self, sample: Option<&FtSample>) -> Option<Vector6<f64>> {
        match self.verdict(sample) {
            Ok(raw) => {
                self.report.accepted += 1;
                Some(raw)
            }
            Err(reason) => {
                self.report.record(reason);
                None
            }
        }
    }

    /// What has been kept and skipped so far.
    pub fn report(&self) -> &ScreenReport {
        &self.report
    }

    /// Clears the counts (the settings stay).
    pub fn reset(&mut self) {
        self.report = ScreenReport::default();
    }

    fn verdict(&self, sample: Option<&FtSample>) -> Result<Vector6<f64>, SkipReason> {
        let sample = sample.ok_or(SkipReason::Dropout)?;
        let raw = sample.raw;
        if let Some(channel) = raw.iter().position(|v| !v.is_finite()) {
            return Err(SkipReason::NonFinite { channel });
        }
        if let Some(channel) = sample.saturated.iter().position(|&s| s) {
            return Err(SkipReason::Saturated { channel });
        }
        if let Some(full_scale) = &self.full_scale
            && let Some(channel) = raw
                .iter()
                .zip(full_scale)
                .position(|(v, fs)| v.abs() >= *fs)
        {
            return Err(SkipReason::Saturated { channel });
        }
        Ok(raw)
    }
}
