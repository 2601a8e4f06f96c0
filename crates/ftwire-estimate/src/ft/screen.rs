//! Screening raw samples: what never enters an estimate.

use ftwire_core::FtSample;
use nalgebra::Vector6;

use crate::EstimateError;

/// Why a sample was skipped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SkipReason {
    /// The sensor delivered no sample (a read error on the rig).
    Dropout,
    /// A channel (force first, 0–5) is NaN or infinite.
    NonFinite {
        /// The channel.
        channel: usize,
    },
    /// A channel (force first, 0–5) was clipped at the sensor's range.
    Saturated {
        /// The channel.
        channel: usize,
    },
}

impl std::fmt::Display for SkipReason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        const CHANNELS: [&str; 6] = ["f1", "f2", "f3", "τ1", "τ2", "τ3"];
        let name = |c: usize| CHANNELS.get(c).copied().unwrap_or("?");
        match self {
            Self::Dropout => write!(f, "dropout"),
            Self::NonFinite { channel } => write!(f, "non-finite {}", name(*channel)),
            Self::Saturated { channel } => write!(f, "saturated {}", name(*channel)),
        }
    }
}

/// How many samples were offered, kept and skipped, and why.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct ScreenReport {
    /// Samples kept.
    pub accepted: usize,
    /// Read errors (no sample).
    pub dropouts: usize,
    /// Samples with a NaN or infinite channel.
    pub non_finite: usize,
    /// Samples with a clipped channel.
    pub saturated: usize,
    /// The first skipped samples (index among all offered, reason), at most
    /// [`ScreenReport::KEPT_SKIPS`].
    pub skips: Vec<(usize, SkipReason)>,
}

impl ScreenReport {
    /// How many skipped samples are listed individually.
    pub const KEPT_SKIPS: usize = 32;

    /// Samples skipped, for any reason.
    pub fn skipped(&self) -> usize {
        self.dropouts + self.non_finite + self.saturated
    }

    /// Samples offered.
    pub fn offered(&self) -> usize {
        self.accepted + self.skipped()
    }

    /// Adds another report's counts to this one.
    pub fn merge(&mut self, other: &ScreenReport) {
        let offset = self.offered();
        self.accepted += other.accepted;
        self.dropouts += other.dropouts;
        self.non_finite += other.non_finite;
        self.saturated += other.saturated;
        let room = Self::KEPT_SKIPS.saturating_sub(self.skips.len());
        self.skips.extend(
            other
                .skips
                .iter()
                .take(room)
                .map(|&(i, reason)| (i + offset, reason)),
        );
    }

    fn record(&mut self, reason: SkipReason) {
        let index = self.offered();
        match reason {
            SkipReason::Dropout => self.dropouts += 1,
            SkipReason::NonFinite { .. } => self.non_finite += 1,
            SkipReason::Saturated { .. } => self.saturated += 1,
        }
        if self.skips.len() < Self::KEPT_SKIPS {
            self.skips.push((index, reason));
        }
    }
}

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
