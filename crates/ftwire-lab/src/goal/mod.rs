//! The goal experiment (paper §IV-D, Table III, Figs. 6–7; collision detection §IV-E): steer
//! the wire from a start to a goal configuration by F/T feedback (eq. 13–14, K = [`GAIN`]),
//! against the open-loop roll-out of the straight line in `A`, with and without gripper noise.
//!
//! **Pairs.** [`GoalParams::pairs`] (default [`DEFAULT_PAIRS`]) seeded pairs `(a_s, a_g)` of
//! `A_free` of the wire (`common.wire`, default [`DEFAULT_WIRE`]; uniform in a normalised box),
//! A-connected (the straight segment stays in `A_free` at 21 points), `a_g` stable under the
//! controller's model too, and the segment clear of the model's stability boundary. Rejected
//! draws are counted in `pair_draws`. As in the paper's Table III, the runs ignore the arms'
//! kinematics (eq. 13–14 do, §III-C): the reach check is `ftwire_control::AnyPose`. (On the
//! SDA10F with the base gripper at the left arm's preferred pose, most draws of the default
//! box had a start or goal out of reach, and the closed loop left the workspace within a few
//! steps on the rest.)
//!
//! **Runs.** For each pair the operator places the wire at `Γ(a_s)` anew (`Γ` of the steering
//! model: under the loaded model the true wire's base wrench is then `a_s`; under the
//! weightless one, with gravity on, the wire sags from it), the robot tares its sensor, and
//! `ã` comes through the learnt calibration ([`GoalParams::calibration`], or one run first and
//! cached as `calibration.json`), [`crate::experiment::rig::SAMPLES_PER_REST`] samples per
//! rest. The closed loop is `ftwire_control::Controller` with the model of `common.model`.
//! The open loop rolls out `Γ(ā(k/n))` (same model) with `n` the closed loop's step count on
//! the same pair and noise. `noise` runs wrap the simulated rig in `ftwire_control::NoisyRig`
//! with [`GoalParams::noise_model`] (the same seeds for open and closed loop); `no_noise` runs
//! have none. The simulator's own execution error is off.
//!
//! **Stop rule and ε.** The closed loop stops when the *measured* `ã` is within ε
//! (normalised) of the goal. Each closed-loop run goes with the smallest ε of its table; since
//! a run is deterministic up to its stop, the larger ε's results are read off the same run at
//! the first step their rule holds (`epsilon_tradeoff`). The headline ε is
//! [`EPSILON_NO_NOISE`] or [`EPSILON_NOISE`]. Without noise and with `offset`, rests within
//! [`SETTLE_RADIUS`] of the goal average [`SETTLE_SAMPLES`] samples, so the reading the stop
//! rule trusts is four times the usual rest. What remains at a small ε is the sensor's bias
//! drift since the tare: a random walk of a few mN over a run, a few hundredths in normalised
//! force (`docs/drift.md` has the measurement with the drift switched off).
//!
//! **Shape stop.** Under `increment` and `absolute` noise the noise runs stop instead on the
//! shape ([`GoalParams::shape_stop_mm`], default `ftwire_control::tracking::SHAPE_STOP_NOISY`):
//! once the model's shape at the measured `ã` is within that mean distance of `Φ(a_g)`. Every
//! move lands the wire about a centimetre (mean along it) from where it was sent, so the loop
//! can only end on a lucky move; the stop on the shape the table scores picks one far better
//! than ε on the six wrench components. The headline is then where each run stopped, and the
//! noise rows of `epsilon_tradeoff` are read off the same runs up to that stop; a shape stop
//! of 0 runs the ε stop alone.
//!
//! **Metrics** (ground truth, the lab only): `mean_mm` is the mean distance between the
//! simulator's final centreline and the model's `Φ(a_g)` at 100 matched arc lengths, averaged
//! over trials; `a_error_mean` is `‖N(a_true − a_g)‖` with the true base wrench. A trial whose
//! simulator or sensor failed (a refused or failed move, a failed measurement, an unreachable
//! pose) is listed in `failures` and left out of the means, which state how many they cover.
//!
//! **Collision detection.** The detector (`ftwire_control::collision`: each move's deviation
//! from the model's Newton prediction, summed over the last moves, against the noise floor
//! plus the model's error bound) has its floor at a few times the measured noise of `ã` at
//! rest (median over free calibration motions, pairs of their own), and its slope and
//! threshold from the moves of those motions (`CollisionDetector::calibrate_moves`: threshold
//! `CollisionDetector::DEFAULT_MARGIN` times a high quantile of their residuals, at least 1).
//! `false_alarms` counts the pairs' no-noise closed-loop motions on which it would have fired;
//! then the first pairs are run again (no noise) with a 20 mm box at the middle of `Φ(a_g)`,
//! the detector on, and the delay is the detected step minus the first step with a contact
//! force in the simulator (`delays`, with the force at detection in `detection_force_n`).
//! After each detection the robot retreats (`ftwire_control::retreat`).
//!
//! [`run`] writes `trials.csv`, `calibration.json` (when it ran one), and the figures
//! `motion_in_a` (Fig. 6) and `shape_error_along_motion` (Fig. 7). The caller writes
//! `summary.json` ([`GoalRun::summary`], the same for the same seed) and `timings.json`
//! ([`GoalRun::timings`]), and may print [`GoalRun::text`], the results as text beside
//! Table III. Guarded by `tests/experiments.rs` and the recorded summary of
//! `crates/ftwire/tests/goal_experiment.rs`.

mod closed;
mod collision;
mod figures;
mod pairs;
mod summary;
mod text;
mod trial;
mod tuning;
mod variant;

use std::path::PathBuf;
use std::time::Instant;

use ftwire_control::NoiseModel;
use ftwire_control::open_loop::straight_line_in_a;
use ftwire_control::tracking::TrackingPolicy;
use ftwire_estimate::WireModel;
use ftwire_rod::Rod;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::Serialize;

use self::closed::ClosedTrial;
pub use self::collision::Collision;
use self::collision::{DetectorSetup, calibrate_detector, contact_runs, count_false_alarm};
pub use self::pairs::PairDraws;
use self::pairs::draw_pairs;
pub use self::summary::{
    BiasObservers, Epsilons, Failure, GoalSummary, Metrics, Results, Tradeoff, TradeoffRow,
    Variants,
};
use self::summary::{Outcomes, failure_cell, summarise};
use self::trial::Context;
use self::trial::Pair;
pub use self::tuning::{
    EPSILON_NO_NOISE, EPSILON_NOISE, EPSILONS_NO_NOISE, EPSILONS_NOISE, GAIN,
    MAX_ITERATIONS_NO_NOISE, MAX_ITERATIONS_NOISE, SETTLE_RADIUS, SETTLE_SAMPLES,
};
use self::variant::{Variant, VariantTrials};
use crate::csv_table::{Cell, CsvTable, text, value};
use crate::error::LabError;
use crate::experiment::calibration::load_or_run_reporting;
use crate::experiment::stats::median;
use crate::experiment::{CommonParams, Progress, known_model};
use crate::results::ResultsFolder;
use crate::wire::WireSpec;

/// The wire by default.
pub const DEFAULT_WIRE: &str = "nitinol-3mm-820";
/// Start–goal pairs by default (the paper's 30).
pub const DEFAULT_PAIRS: usize = 30;
/// The most start–goal pairs a run takes.
pub const MAX_PAIRS: usize = 1000;

/// The settings of the goal experiment.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GoalParams {
    /// The settings every experiment takes (`wire` replaces [`DEFAULT_WIRE`]; `trials` is not
    /// used: see `pairs`).
    pub common: CommonParams,
    /// Start–goal pairs, 1 to [`MAX_PAIRS`] (default [`DEFAULT_PAIRS`]).
    pub pairs: usize,
    /// The gripper noise of the `noise` runs (default `increment`, the paper's).
    pub noise_model: NoiseModel,
    /// Learnt calibration weights (`ftwire_estimate::calibration` JSON); `None`: a
    /// calibration is first run on the known wire and cached in the results folder.
    pub calibration: Option<PathBuf>,
    /// Steer the closed loop by `ã` corrected for the F/T sensor's bias drift
    /// (`ftwire_control::BiasObserver`, where the noise model allows one:
    /// [`crate::experiment::rig::bias_observer`]); `false` steers by the tared `ã` alone
    /// (default `true`).
    pub bias_observer: bool,
    /// The `noise` runs' shape stop \[mm\], at least 0 (0: off, the ε stop alone); `None`: the
    /// default of the noise model (`ftwire_control::TrackingPolicy::shape_stop`).
    pub shape_stop_mm: Option<f64>,
}

impl Default for GoalParams {
    fn default() -> Self {
        Self {
            common: CommonParams::default(),
            pairs: DEFAULT_PAIRS,
            noise_model: NoiseModel::Increment,
            calibration: None,
            bias_observer: true,
            shape_stop_mm: None,
        }
    }
}

impl GoalParams {
    /// The wire: `common.wire`, or [`DEFAULT_WIRE`].
    ///
    /// # Errors
    /// Bad input for an unknown preset or a bad wire file.
    pub fn wire(&self) -> Result<WireSpec, LabError> {
        self.common.wire_or(DEFAULT_WIRE)
    }

    /// The `noise` runs' shape stop \[m\]: [`GoalParams::shape_stop_mm`], or the default of
    /// the noise model.
    ///
    /// # Errors
    /// Bad input for a negative distance.
    pub fn shape_stop(&self) -> Result<f64, LabError> {
        match self.shape_stop_mm {
            None => Ok(TrackingPolicy::for_noise(self.noise_model).shape_stop),
            Some(mm) if mm >= 0.0 => Ok(1e-3 * mm),
            Some(mm) => Err(LabError::bad_input(format!(
                "--shape-stop {mm}: give a distance ≥ 0 mm (0: off)"
            ))),
        }
    }

    /// Checks the settings as [`run`] does before any work (the pairs, the shape stop, the
    /// wire and its model, the sensor and rig files), so that a caller can refuse bad input
    /// before it opens a results folder.
    ///
    /// # Errors
    /// Bad input naming what is wrong.
    pub fn check(&self) -> Result<(), LabError> {
        if !(1..=MAX_PAIRS).contains(&self.pairs) {
            return Err(LabError::bad_input(format!(
                "--pairs {}: give 1 to {MAX_PAIRS}",
                self.pairs
            )));
        }
        self.shape_stop()?;
        let wire = self.wire()?;
        self.common.setup()?;
        known_model(&wire, self.common.gravity, self.common.model())?;
        Ok(())
    }
}

/// `timings.json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GoalTimings {
    /// Loading or running the calibration \[s\].
    pub calibration_s: f64,
    /// The experiment after the calibration \[s\].
    pub experiment_s: f64,
    /// The median time of one controller step (its plan) \[µs\].
    pub controller_step_us_median: f64,
    /// The median time of one reach check \[µs\].
    pub reach_check_us_median: f64,
}

/// A finished goal experiment.
#[derive(Debug, Clone)]
pub struct GoalRun {
    /// `summary.json`'s body (after the run header).
    pub summary: GoalSummary,
    /// `timings.json`.
    pub timings: GoalTimings,
}

/// What the pairs' trials add up to: the rows of `trials.csv`, the outcomes the summary is
/// made of, the controller's timings, and the first pair's trials for the figures.
struct Tally {
    csv: CsvTable,
    outcomes: Outcomes,
    /// One controller step's plan time per step \[µs\].
    plan_us: Vec<f64>,
    /// One reach check's time per step \[µs\].
    reach_us: Vec<f64>,
    /// The first pair's trials.
    sample: Option<Vec<VariantTrials>>,
}

/// Runs the goal experiment (module docs) into `folder`, reporting its phases to
/// `progress`.
///
/// # Errors
/// Bad input as [`GoalParams::check`] and for an unreadable calibration file; no answer when
/// too few A-connected pairs are found or the detector cannot be calibrated; I/O errors of
/// the folder.
pub fn run(
    params: &GoalParams,
    folder: &ResultsFolder,
    progress: Progress<'_>,
) -> Result<GoalRun, LabError> {
    params.check()?;
    let common = &params.common;
    let shape_stop = params.shape_stop()?;
    let wire = params.wire()?;
    let setup = common.setup()?;
    let kind = common.model();
    let model = known_model(&wire, common.gravity, kind)?;
    let (calibration, calibration_s) = load_or_run_reporting(
        folder,
        params.calibration.as_deref(),
        (common.gravity, kind),
        (&setup, common.seed),
        progress,
    )?;
    let ctx = Context {
        wire: &wire,
        params: *model.wire(),
        gravity: common.gravity,
        model,
        kind,
        calibration: &calibration,
        rig: &setup,
        seed: common.seed,
        bias_observer: params.bias_observer,
    };
    let variants = Variant::both(params.noise_model, shape_stop);
    let start = Instant::now();
    let (pairs, draws, detector_pairs) = draw_all(&ctx, params.pairs, progress)?;
    let detector = calibrate_detector(&ctx, &detector_pairs, progress)?;
    let mut tally = run_pairs(&ctx, &pairs, &variants, &detector, progress)?;
    contact_runs(&ctx, &pairs, &detector, &mut tally.outcomes.collision)?;
    let experiment_s = start.elapsed().as_secs_f64();
    let summary = summarise(
        &ctx,
        (params.noise_model, shape_stop),
        &variants,
        pairs.len(),
        draws,
        tally.outcomes,
    );
    if let (Some(rows), Some(pair)) = (&tally.sample, pairs.first()) {
        figures::write(folder, &ctx, pair, rows, &variants)?;
    }
    folder.write("trials.csv", tally.csv.into_bytes()?)?;
    Ok(GoalRun {
        summary,
        timings: GoalTimings {
            calibration_s,
            experiment_s,
            controller_step_us_median: median(&tally.plan_us),
            reach_check_us_median: median(&tally.reach_us),
        },
    })
}

/// The pairs of the run (and how many draws it took), and the pairs of the detector's free
/// calibration motions, each from a generator of its own.
fn draw_all(
    ctx: &Context<'_>,
    count: usize,
    progress: Progress<'_>,
) -> Result<(Vec<Pair>, PairDraws, Vec<Pair>), LabError> {
    let rod = Rod::new(ctx.params);
    let mut draws = PairDraws::default();
    let mut rng = ChaCha8Rng::seed_from_u64(ctx.seed.wrapping_add(14));
    let pairs = draw_pairs(ctx, &rod, count, &mut rng, &mut draws)?;
    let mut rng = ChaCha8Rng::seed_from_u64(ctx.seed.wrapping_add(1_014));
    let mut scratch = PairDraws::default();
    let detector_pairs = draw_pairs(
        ctx,
        &rod,
        collision::DETECTOR_MOTIONS,
        &mut rng,
        &mut scratch,
    )?;
    progress(&format!("{} pairs drawn ({:?})", pairs.len(), draws));
    Ok((pairs, draws, detector_pairs))
}

/// Runs both variants' closed and open loops on every pair, in order.
fn run_pairs(
    ctx: &Context<'_>,
    pairs: &[Pair],
    variants: &[Variant; 2],
    detector: &DetectorSetup,
    progress: Progress<'_>,
) -> Result<Tally, LabError> {
    let mut tally = Tally {
        csv: CsvTable::new(
            "trials.csv",
            &[
                "pair", "variant", "epsilon", "steps", "mean_mm", "a_error", "snapped", "outcome",
                "failure",
            ],
        )?,
        outcomes: Outcomes::new(detector),
        plan_us: Vec::new(),
        reach_us: Vec::new(),
        sample: None,
    };
    for (i, pair) in pairs.iter().enumerate() {
        let mut pair_rows = Vec::new();
        for variant in variants {
            pair_rows.push(run_variant(ctx, (i, pair), variant, detector, &mut tally)?);
        }
        if i == 0 {
            tally.sample = Some(pair_rows);
        }
        progress(&format!("pair {} / {} done", i + 1, pairs.len()));
    }
    Ok(tally)
}

/// The closed loop of `variant` on pair `i`, then the open loop with its step count; their
/// rows and outcomes go to `tally`.
fn run_variant(
    ctx: &Context<'_>,
    (i, pair): (usize, &Pair),
    variant: &Variant,
    detector: &DetectorSetup,
    tally: &mut Tally,
) -> Result<VariantTrials, LabError> {
    let k = i as u64;
    let closed = ctx.closed(pair, k, &variant.setup(), &[])?;
    if let Some(run) = &closed.run {
        tally
            .plan_us
            .extend(run.steps.iter().map(|s| 1e6 * s.plan_s));
        tally
            .reach_us
            .extend(run.steps.iter().map(|s| 1e6 * s.reach_s));
        if variant.noise == NoiseModel::None {
            count_false_alarm(&mut tally.outcomes.collision, detector, &closed, run);
        }
    }
    closed_rows(&mut tally.csv, i, variant, &closed)?;
    let stop = &closed.stops[variant.headline];
    if let Some(message) = &stop.failure {
        tally.outcomes.failures.push(Failure {
            pair: i,
            variant: format!("closed_loop.{}", variant.name),
            message: message.clone(),
        });
    }
    let steps = stop.steps.max(1);
    let poses = straight_line_in_a(&ctx.model, &pair.a_s, &pair.a_g, steps)
        .map_err(|e| LabError::no_answer(format!("the straight line in A: {e}")))?;
    let open = ctx.open(pair, k, variant.noise, &poses)?;
    let snapped = open.truths.iter().any(|t| t.snapped);
    tally.csv.row([
        value(i),
        text(&format!("open_{}", variant.name)),
        Cell::empty(),
        value(steps),
        value(open.truth.shape_mm),
        value(open.truth.a_error),
        value(snapped),
        text("open_loop"),
        failure_cell(open.failure.as_deref()),
    ])?;
    if let Some(message) = &open.failure {
        tally.outcomes.failures.push(Failure {
            pair: i,
            variant: format!("open_loop.{}", variant.name),
            message: message.clone(),
        });
    }
    tally.outcomes.push(
        variant.noise,
        (open.truth, open.failure.is_some(), snapped),
        &closed,
    );
    Ok(VariantTrials {
        variant: variant.name,
        closed,
        open,
        steps,
    })
}

/// The rows of `trials.csv` of a closed-loop trial on pair `i`: one per ε of its table.
fn closed_rows(
    csv: &mut CsvTable,
    i: usize,
    variant: &Variant,
    closed: &ClosedTrial,
) -> Result<(), LabError> {
    let outcome = closed.run.as_ref().map_or("not_run", |r| r.outcome.name());
    for (&eps, stop) in variant.epsilons.iter().zip(&closed.stops) {
        csv.row([
            value(i),
            text(&format!("closed_{}", variant.name)),
            value(eps),
            value(stop.steps),
            value(stop.truth.shape_mm),
            value(stop.truth.a_error),
            value(stop.snapped),
            text(outcome),
            failure_cell(stop.failure.as_deref()),
        ])?;
    }
    Ok(())
}
