//! `--until PCT`: sample until the wire is known to a stated precision.
//!
//! Each trial identifies from its first `n = 2, 3, …` samples and stops at the first `n`
//! whose estimate is identified (no flag) and whose every 95 % half-width
//! ([`Estimate::interval95`]) is within `PCT` % of its value. The limit is the trial's
//! recording, the largest `--samples` count; a trial that reaches it unsatisfied counts as
//! not reached and reports its last estimate.

use ftwire_estimate::identify::Sample;
use ftwire_estimate::identify::{Estimate, IdentifierParams};
use serde::Serialize;

use crate::experiment::stats::median;
use crate::wire::WireSpec;
use ftwire_logs::identification::run_identification;

/// Smallest `--until` target \[%\].
pub const MIN_TARGET_PERCENT: f64 = 0.01;
/// Largest `--until` target \[%\].
pub const MAX_TARGET_PERCENT: f64 = 100.0;

/// One trial sampled until the target.
#[derive(Debug, Clone)]
pub struct UntilTrial {
    /// Samples used at the stop (the limit when not reached).
    pub samples: usize,
    /// Whether the target was met within the limit.
    pub reached: bool,
    /// The estimate at the stop, `None` when every identification failed.
    pub estimate: Option<Estimate>,
}

/// Whether `estimate` meets the target: identified, and the 95 % half-width of each of
/// `(c1, c2, c3, L)` within `target_percent` % of its value (the loaded model's linear density
/// is reported with its interval but does not hold the stop: it is the weight's nuisance
/// parameter, known far less precisely than the wire's stiffness and length).
pub fn meets(estimate: &Estimate, target_percent: f64) -> bool {
    let Some(intervals) = estimate.interval95() else {
        return false;
    };
    estimate.is_identified()
        && estimate
            .values()
            .iter()
            .zip(intervals)
            .take(4)
            .all(|(v, [low, high])| 0.5 * (high - low) <= 0.01 * target_percent * v.abs())
}

/// Identifies from growing prefixes of `pairs` (2 up to all of them) with `config` and the
/// search seed `seed` until the target holds.
pub fn sample_until(
    pairs: &[Sample],
    config: &IdentifierParams,
    seed: u64,
    target_percent: f64,
) -> UntilTrial {
    let mut last = None;
    for n in 2..=pairs.len() {
        let Ok(estimate) = run_identification(&pairs[..n], config, seed) else {
            continue;
        };
        if meets(&estimate, target_percent) {
            return UntilTrial {
                samples: n,
                reached: true,
                estimate: Some(estimate),
            };
        }
        last = Some(estimate);
    }
    UntilTrial {
        samples: pairs.len(),
        reached: false,
        estimate: last,
    }
}

/// `summary.json`'s `until`: one wire's trials sampled until the target. Errors are relative
/// fractions (0.005 is 0.5 %), each `[4]` over `(c1, c2, c3, L)`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct UntilSummary {
    /// The target: every 95 % half-width within this percentage of its value.
    pub target_percent: f64,
    /// The sample limit (the largest `--samples` count).
    pub limit: usize,
    /// Trials.
    pub trials: usize,
    /// Trials that met the target within the limit.
    pub reached: usize,
    /// Median samples used over the trials (the limit for those not reached).
    pub samples_median: f64,
    /// Most samples used.
    pub samples_max: usize,
    /// Samples each trial used, in trial order.
    pub samples: Vec<usize>,
    /// Mean over the trials of the absolute relative error at the stop.
    pub mean_abs_relative_error: [f64; 4],
    /// Largest absolute relative error at the stop.
    pub max_abs_relative_error: [f64; 4],
    /// The share of the trials whose 95 % interval at the stop holds the true value.
    pub coverage95: [f64; 4],
}

impl UntilSummary {
    /// The summary of `trials` on `wire`.
    pub fn new(wire: &WireSpec, target_percent: f64, limit: usize, trials: &[UntilTrial]) -> Self {
        let truth = [wire.c[0], wire.c[1], wire.c[2], wire.length];
        let count = trials.len().max(1) as f64;
        let errors: Vec<[f64; 4]> = trials
            .iter()
            .map(|t| match &t.estimate {
                Some(e) => {
                    let v = e.values();
                    std::array::from_fn(|j| (v[j] - truth[j]).abs() / truth[j])
                }
                None => [f64::INFINITY; 4],
            })
            .collect();
        let coverage95 = std::array::from_fn(|j| {
            let inside = trials
                .iter()
                .filter(|t| {
                    t.estimate
                        .as_ref()
                        .and_then(Estimate::interval95)
                        .is_some_and(|i| i[j][0] <= truth[j] && truth[j] <= i[j][1])
                })
                .count();
            inside as f64 / count
        });
        let used: Vec<usize> = trials.iter().map(|t| t.samples).collect();
        Self {
            target_percent,
            limit,
            trials: trials.len(),
            reached: trials.iter().filter(|t| t.reached).count(),
            samples_median: median(&used.iter().map(|&n| n as f64).collect::<Vec<_>>()),
            samples_max: used.iter().copied().max().unwrap_or(0),
            samples: used,
            mean_abs_relative_error: std::array::from_fn(|j| {
                errors.iter().map(|e| e[j]).sum::<f64>() / count
            }),
            max_abs_relative_error: std::array::from_fn(|j| {
                errors.iter().map(|e| e[j]).fold(0.0, f64::max)
            }),
            coverage95,
        }
    }
}
