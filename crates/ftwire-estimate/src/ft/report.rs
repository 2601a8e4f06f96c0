//! What screening kept and skipped, and why.

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

    pub(crate) fn record(&mut self, reason: SkipReason) {
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
