//! The goal experiment's `summary.json` (Table III, the ε trade-off, collision detection,
//! the pairs' draws and the failures), and the outcomes of the trials it is made of.

use ftwire_control::{BiasObserverParams, NoiseModel};
use serde::Serialize;

use super::closed::{ClosedTrial, Stop};
use super::collision::{Collision, DetectorSetup};
use super::pairs::PairDraws;
use super::trial::{Context, Truth};
use super::tuning::GAIN;
use super::variant::Variant;
use crate::csv_table::{Cell, text};
use crate::experiment::ModelKind;
use crate::experiment::stats::{mean_std, median};

/// Shape and configuration errors over the trials of one loop and variant (ground truth).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Metrics {
    /// Mean distance between the true final centreline and `Φ(a_g)` \[mm\].
    pub mean_mm: f64,
    /// Its sample standard deviation over the trials \[mm\].
    pub std_mm: f64,
    /// Mean `‖N(a_true − a_g)‖` \[normalised\].
    pub a_error_mean: f64,
    /// Trials in the means.
    pub trials: usize,
    /// Trials left out (see `failures`).
    pub failed: usize,
    /// Trials (of those in the means) in which the simulator's wire snapped to another
    /// equilibrium branch at least once.
    pub snapped: usize,
    /// `mean_mm` over the trials without a snap (ground truth used only to report this).
    pub mean_mm_without_snaps: f64,
}

/// One loop's metrics without and with noise.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Variants {
    /// The runs without gripper noise.
    pub no_noise: Metrics,
    /// The runs with the run's noise model.
    pub noise: Metrics,
}

/// Table III: open and closed loop.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Results {
    /// The open-loop roll-out of the straight line in `A`.
    pub open_loop: Variants,
    /// The closed loop, at its headline stop.
    pub closed_loop: Variants,
}

/// The closed loop's results at one ε of its table.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TradeoffRow {
    /// The stop's ε \[normalised\].
    pub epsilon: f64,
    /// As [`Metrics::mean_mm`] at that stop \[mm\].
    pub mean_mm: f64,
    /// As [`Metrics::std_mm`] \[mm\].
    pub std_mm: f64,
    /// As [`Metrics::a_error_mean`] \[normalised\].
    pub a_error_mean: f64,
    /// Median steps to the stop over the trials that did not fail.
    pub steps_median: f64,
    /// Trials whose measured ã came within ε.
    pub reached: usize,
    /// Trials in the means.
    pub trials: usize,
}

/// The ε trade-off tables without and with noise.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Tradeoff {
    /// One row per ε of the no-noise table.
    pub no_noise: Vec<TradeoffRow>,
    /// One row per ε of the noise table.
    pub noise: Vec<TradeoffRow>,
}

/// A trial left out of the means.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Failure {
    /// The pair (0-based).
    pub pair: usize,
    /// The loop and variant, as `closed_loop.noise`.
    pub variant: String,
    /// What failed.
    pub message: String,
}

/// The headline ε without and with noise \[normalised\].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Epsilons {
    /// Without noise.
    pub no_noise: f64,
    /// With the run's noise model.
    pub noise: f64,
}

/// The bias observers of a run's closed loops.
#[derive(Debug, Clone, Serialize)]
pub struct BiasObservers {
    /// Without noise (`None`: off).
    pub no_noise: Option<BiasObserverParams>,
    /// With the run's noise model (`None`: off).
    pub noise: Option<BiasObserverParams>,
}

/// `summary.json`'s body.
#[derive(Debug, Clone, Serialize)]
pub struct GoalSummary {
    /// The wire's name.
    pub wire: String,
    /// The steering model.
    pub model: ModelKind,
    /// The noise model of the `noise` runs.
    pub noise_model: NoiseModel,
    /// The bias observer's settings of the closed loops without noise and with noise (`null`
    /// where it is off: switched off, or under `absolute`; `fuse_rest` where each rest is
    /// also fused with the reported pose: without noise and under `increment`).
    pub bias_observer: BiasObservers,
    /// The gain K.
    pub gain: f64,
    /// The headline ε.
    pub epsilon: Epsilons,
    /// The noise runs' shape stop \[mm\] (0: off). When on, `results.closed_loop.noise` and
    /// `steps_median` are where those runs stopped, and `epsilon_tradeoff.noise` is read off
    /// the same runs up to that stop (a shape stop of 0 gives the ε stop alone).
    pub shape_stop_mm: f64,
    /// Start–goal pairs.
    pub pairs: usize,
    /// Table III.
    pub results: Results,
    /// Median steps of the closed loop with noise (at the headline ε).
    pub steps_median: f64,
    /// Median steps of the closed loop without noise.
    pub steps_median_no_noise: f64,
    /// The closed loop at every ε of the tables.
    pub epsilon_tradeoff: Tradeoff,
    /// Collision detection.
    pub collision: Collision,
    /// How the pairs were drawn.
    pub pair_draws: PairDraws,
    /// The trials left out of the means.
    pub failures: Vec<Failure>,
}

/// An open-loop trial's outcome: its final truth, whether it failed, and whether the wire
/// snapped during it.
pub(super) type OpenOutcome = (Truth, bool, bool);

/// The outcomes of the pairs' trials, by noise (the `noise` variant run without noise counts
/// as free), and the collision detector's counts.
pub(super) struct Outcomes {
    pub(super) open_free: Vec<OpenOutcome>,
    pub(super) open_noise: Vec<OpenOutcome>,
    /// Each free closed-loop trial's stops.
    pub(super) closed_free: Vec<Vec<Stop>>,
    /// Each noisy closed-loop trial's stops.
    pub(super) closed_noise: Vec<Vec<Stop>>,
    pub(super) failures: Vec<Failure>,
    pub(super) collision: Collision,
}

impl Outcomes {
    /// No outcomes yet; the collision counts start with `setup`'s detector.
    pub(super) fn new(setup: &DetectorSetup) -> Self {
        Self {
            open_free: Vec::new(),
            open_noise: Vec::new(),
            closed_free: Vec::new(),
            closed_noise: Vec::new(),
            failures: Vec::new(),
            collision: Collision {
                threshold: setup.detector.threshold(),
                floor: setup.floor,
                slope: setup.detector.slope(),
                window: setup.detector.window(),
                ..Collision::default()
            },
        }
    }

    /// Adds the open and closed loop of a trial under `noise`.
    pub(super) fn push(&mut self, noise: NoiseModel, open: OpenOutcome, closed: &ClosedTrial) {
        match noise {
            NoiseModel::None => {
                self.open_free.push(open);
                self.closed_free.push(closed.stops.clone());
            }
            _ => {
                self.open_noise.push(open);
                self.closed_noise.push(closed.stops.clone());
            }
        }
    }
}

/// A failure's message as a `trials.csv` cell, its commas as `;` (as the file has always had
/// them, for readers that split lines at commas).
pub(super) fn failure_cell(failure: Option<&str>) -> Cell {
    text(&failure.unwrap_or_default().replace(',', ";"))
}

/// Means over the trials that did not fail.
fn metrics(trials: &[OpenOutcome]) -> Metrics {
    let ok: Vec<&Truth> = trials
        .iter()
        .filter(|(_, failed, _)| !failed)
        .map(|(t, _, _)| t)
        .collect();
    let snapped = trials.iter().filter(|(_, failed, s)| !failed && *s).count();
    let unsnapped: Vec<f64> = trials
        .iter()
        .filter(|(_, failed, s)| !failed && !s)
        .map(|(t, _, _)| t.shape_mm)
        .collect();
    let (mean_mm, std_mm) = mean_std(&ok.iter().map(|t| t.shape_mm).collect::<Vec<_>>());
    Metrics {
        mean_mm,
        std_mm,
        a_error_mean: mean_std(&ok.iter().map(|t| t.a_error).collect::<Vec<_>>()).0,
        trials: ok.len(),
        failed: trials.len() - ok.len(),
        snapped,
        mean_mm_without_snaps: mean_std(&unsnapped).0,
    }
}

/// The closed-loop trials at their stop `h`, as outcomes.
fn closed_at(trials: &[Vec<Stop>], h: usize) -> Vec<OpenOutcome> {
    trials
        .iter()
        .map(|stops| (stops[h].truth, stops[h].failure.is_some(), stops[h].snapped))
        .collect()
}

/// The median steps to stop `h` of the closed-loop trials that did not fail there.
fn steps_of(trials: &[Vec<Stop>], h: usize) -> f64 {
    median(
        &trials
            .iter()
            .filter(|s| s[h].failure.is_none())
            .map(|s| s[h].steps as f64)
            .collect::<Vec<_>>(),
    )
}

/// The trade-off rows of the closed-loop trials, one per ε of `table`.
fn tradeoff(trials: &[Vec<Stop>], table: &[f64]) -> Vec<TradeoffRow> {
    table
        .iter()
        .enumerate()
        .map(|(h, &epsilon)| {
            let m = metrics(&closed_at(trials, h));
            TradeoffRow {
                epsilon,
                mean_mm: m.mean_mm,
                std_mm: m.std_mm,
                a_error_mean: m.a_error_mean,
                steps_median: steps_of(trials, h),
                reached: trials.iter().filter(|s| s[h].reached).count(),
                trials: m.trials,
            }
        })
        .collect()
}

/// The summary of a run with `noise` in its noise runs and their shape stop \[m\], over
/// `pairs` pairs drawn as `draws`, from the trials' `outcomes`.
pub(super) fn summarise(
    ctx: &Context<'_>,
    (noise, shape_stop): (NoiseModel, f64),
    [free, noisy]: &[Variant; 2],
    pairs: usize,
    draws: PairDraws,
    outcomes: Outcomes,
) -> GoalSummary {
    let Outcomes {
        open_free,
        open_noise,
        closed_free,
        closed_noise,
        failures,
        collision,
    } = outcomes;
    GoalSummary {
        wire: ctx.wire.name.clone(),
        model: ctx.kind,
        noise_model: noise,
        bias_observer: BiasObservers {
            no_noise: ctx.observer_settings(NoiseModel::None),
            noise: ctx.observer_settings(noise),
        },
        gain: GAIN,
        epsilon: Epsilons {
            no_noise: free.headline_epsilon,
            noise: noisy.headline_epsilon,
        },
        shape_stop_mm: 1e3 * shape_stop,
        pairs,
        results: Results {
            open_loop: Variants {
                no_noise: metrics(&open_free),
                noise: metrics(&open_noise),
            },
            closed_loop: Variants {
                no_noise: metrics(&closed_at(&closed_free, free.headline)),
                noise: metrics(&closed_at(&closed_noise, noisy.headline)),
            },
        },
        steps_median: steps_of(&closed_noise, noisy.headline),
        steps_median_no_noise: steps_of(&closed_free, free.headline),
        epsilon_tradeoff: Tradeoff {
            no_noise: tradeoff(&closed_free, &free.epsilons),
            noise: tradeoff(&closed_noise, &noisy.epsilons),
        },
        collision,
        pair_draws: draws,
        failures,
    }
}
