//! `ftwire experiment goal` (paper §IV-D, Table III, Figs. 6–7; collision detection §IV-E):
//! steer the wire from a start to a goal configuration by F/T feedback (eq. 13–14, K = 0.2),
//! against the open-loop roll-out of the straight line in `A`, with and without gripper noise.
//!
//! **Pairs.** `--pairs` (default 30) seeded pairs `(a_s, a_g)` of `A_free` of the wire
//! (`--wire`, default `nitinol-3mm-820`; uniform in the normalised box `[−10, 10]⁶`), A-connected
//! (the straight segment stays in `A_free` at 21 points), `a_g` stable under the controller's
//! model too. Rejected draws are counted in `pair_draws`. As in the paper's Table III, the runs
//! ignore the arms' kinematics (eq. 13–14 do, §III-C): the reach check is `AnyPose`. (On the
//! SDA10F with the base gripper at the left arm's preferred pose, 8 of 10 draws of the default
//! box had a start or goal out of reach, and the closed loop left the workspace within a few
//! steps on the rest.)
//!
//! **Runs.** For each pair the operator places the wire at `Γ(a_s)` anew (`Γ` of the steering
//! model: under the loaded model the true wire's base wrench is then `a_s`; under the weightless
//! one, with gravity on, the wire sags from it), the robot tares its
//! sensor, and `ã` comes through the learnt calibration (`--calibration FILE`, or one run first
//! and cached as `calibration.json`), [`SAMPLES_PER_REST`] samples per rest. The closed loop is
//! `ftwire_control::Controller` with the model of `--model`. The
//! open loop rolls out `Γ(ā(k/n))` (same model) with `n` the closed loop's step count on the
//! same pair and noise. `noise` runs wrap the simulated rig in `ftwire_control::NoisyRig` with
//! `--noise-model` (the same seeds for open and closed loop); `no_noise` runs have none. The
//! simulator's own execution error is off.
//!
//! **Stop rule and ε.** The closed loop stops when the *measured* `ã` is within ε (normalised)
//! of the goal. Each closed-loop run goes with the smallest ε of its table; since a run is
//! deterministic up to its stop, the larger ε's results are read off the same run at the first
//! step their rule holds (`epsilon_tradeoff`). The headline ε is [`EPSILON_NO_NOISE`] or
//! [`EPSILON_NOISE`]. Without noise and with `offset`, rests within [`SETTLE_RADIUS`] of the
//! goal average [`SETTLE_SAMPLES`] samples, so the reading the stop rule trusts is four times
//! the usual rest. What remains at a small ε is the sensor's bias drift since the tare: a
//! random walk of a few mN over a run's 10–20 s, a few hundredths in normalised force (`docs/drift.md`
//! has the measurement with the drift switched off).
//!
//! **Shape stop.** Under `increment` and `absolute` noise the noise runs stop instead on the
//! shape (`--shape-stop`, default 6 mm, `ftwire_control::tracking::SHAPE_STOP_NOISY`): once the
//! model's shape at the measured `ã` is within that mean distance of `Φ(a_g)`. Every move lands
//! the wire about 12 mm (mean along it) from where it was sent, so the loop can only end on a
//! lucky move; the stop on the shape the table scores picks one far better than ε on the six
//! wrench components. The headline is then where each run stopped, and the noise rows of
//! `epsilon_tradeoff` are read off the same runs up to that stop; `--shape-stop 0` runs the
//! ε stop alone.
//!
//! **Metrics** (ground truth, the binary only): `mean_mm` is the mean distance between the
//! simulator's final centreline and the model's `Φ(a_g)` at 100 matched arc lengths, averaged
//! over trials; `a_error_mean` is `‖N(a_true − a_g)‖` with the true base wrench. A trial whose
//! simulator or sensor failed (a refused or failed move, a failed measurement, an unreachable
//! pose) is listed in `failures` and left out of the means, which state how many they cover.
//!
//! **Collision detection.** The detector (`ftwire_control::collision`: each move's deviation
//! from the model's Newton prediction, summed over the last moves, against the noise floor
//! plus the model's error bound) has its floor at [`FLOOR_SIGMAS`] times the measured noise of
//! `ã` at rest (median over [`DETECTOR_MOTIONS`] free calibration motions, pairs of their own),
//! and its slope and threshold from the moves of those motions
//! (`CollisionDetector::calibrate_moves`: threshold [`CollisionDetector::DEFAULT_MARGIN`] times
//! the [`DETECTOR_QUANTILE`] quantile of their residuals, at least 1). `false_alarms` counts the
//! pairs' no-noise closed-loop motions on which it would have fired; then up to
//! [`CONTACT_TRIALS`] pairs are run again (no noise) with a 20 mm box at the middle of
//! `Φ(a_g)`, the detector on, and the delay is the detected step minus the first step with a
//! contact force in the simulator (`delays`, with the force at detection in
//! `detection_force_n`). After each detection the robot retreats (`ftwire_control::retreat`).
//!
//! Writes `summary.json` (the same for the same seed), `trials.csv`, `timings.json`
//! (`calibration_s`, `experiment_s`, and the medians `controller_step_us_median` and
//! `reach_check_us_median` of one controller step and one reach check), `calibration.json`
//! (when it ran one), and the figures `motion_in_a` (Fig. 6) and `shape_error_along_motion`
//! (Fig. 7).

use std::time::Instant;

use ftwire_control::open_loop::{
    a_connected, line_in_a, roll_out, straight_line_in_a, straight_line_in_b,
};
use ftwire_control::{
    AnyPose, BiasObserver, BiasObserverParams, CollisionDetector, ControlParams, Controller,
    FtFeedback, MoveCheck, NoiseModel, NoiseParams, NoisyRig, Outcome, Run, retreat,
};
use ftwire_core::{Pose, WireParams};
use ftwire_estimate::calibration::Calibration;
use ftwire_estimate::shape::{DEFAULT_METRIC_SAMPLES, centreline_distance};
use ftwire_estimate::{KirchhoffModel, WireModel};
use ftwire_lab::csv_table::{Cell, CsvTable, text, value};
use ftwire_lab::error::{LabError, from_estimate, from_rod, from_sim};
use ftwire_lab::experiment::calibration::rig_seed;
use ftwire_lab::experiment::rig::{SAMPLES_PER_REST, bias_observer, pipeline, place_among, tare};
use ftwire_lab::experiment::{Gravity, ModelKind, known_model};
use ftwire_lab::results::OutGuard;
use ftwire_lab::setup::SimSetup;
use ftwire_lab::tracking::touches;
use ftwire_lab::wire::WireSpec;
use ftwire_report::{Chart3d, LineChart, Series, SeriesKind};
use ftwire_rod::sampling::Sampler;
use ftwire_rod::{Rod, from_normalised, to_normalised};
use ftwire_sim::{BoxObstacle, SimRig};
use nalgebra::{Vector3, Vector6};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::Serialize;

use super::stats::{mean_std, median};
use crate::cli::experiment::{GoalExperimentArgs, shape_stop};

/// The wire by default.
const DEFAULT_WIRE: &str = "nitinol-3mm-820";
/// The gain K (the paper's).
const GAIN: f64 = 0.2;
/// ε values of the no-noise (and `offset`) trade-off table, largest first \[normalised\].
const EPSILONS_NO_NOISE: [f64; 3] = [0.1, 0.05, 0.02];
/// The headline ε without noise and with `offset`: the smallest of the table, which the
/// settled rests ([`SETTLE_RADIUS`]) let every run reach; the sensor's bias drift over the
/// run, not ε, is then most of what is left (see the module docs).
const EPSILON_NO_NOISE: f64 = 0.02;
/// The ε of the free motions that calibrate the collision detector and of the contact runs.
const DETECTOR_EPSILON: f64 = 0.05;
/// The controller's settling radius \[normalised\] without noise and with `offset`: within it
/// each rest averages [`SETTLE_SAMPLES`] samples (`ControlParams::settle_radius`). It is
/// larger than every ε of [`EPSILONS_NO_NOISE`], so each of their stops reads a settled `ã`.
const SETTLE_RADIUS: f64 = 0.25;
/// F/T samples per rest within [`SETTLE_RADIUS`] (0.4 s at 1 kHz, as tracking's last leg).
const SETTLE_SAMPLES: usize = 400;
/// ε values of the `increment` / `absolute` trade-off table, largest first \[normalised\].
const EPSILONS_NOISE: [f64; 3] = [1.0, 0.5, 0.25];
/// The headline ε with `increment` / `absolute` noise.
const EPSILON_NOISE: f64 = 0.5;
/// Iteration limit without noise (and with `offset`).
const MAX_ITERATIONS_NO_NOISE: usize = 150;
/// Iteration limit with `increment` / `absolute` noise: the stop rule waits for a step that
/// lands within ε.
const MAX_ITERATIONS_NOISE: usize = 400;
/// Half-width of the normalised box the pairs are drawn from. In the default box (30) most
/// draws sit near the stability boundary, where the true wire and the model disagree about
/// stability and closed-loop runs snapped repeatedly in the simulator.
const PAIR_BOX: f64 = 5.0;
/// Distance \[normalised\] every point of a pair's segment keeps from the model's stability
/// boundary along each axis.
const STABILITY_MARGIN: f64 = 2.0;
/// Points of the segment checked for A-connectivity (`checks + 1`).
const CONNECT_CHECKS: usize = 20;
/// Draws per requested pair before giving up.
const MAX_DRAWS_PER_PAIR: usize = 200;
/// Free motions that calibrate the collision detector.
const DETECTOR_MOTIONS: usize = 5;
/// The quantile of the free residuals the threshold is set from (snaps of the true wire,
/// which the model does not have, are rare large residuals on free motion).
const DETECTOR_QUANTILE: f64 = 0.95;
/// Obstacle motions of the collision sub-run (at most `--pairs`).
const CONTACT_TRIALS: usize = 10;
/// The detector's floor in multiples of the measured noise of `ã` at rest.
const FLOOR_SIGMAS: f64 = 5.0;
/// Half edge of the obstacle box \[m\].
const BOX_HALF: f64 = 0.01;
/// Least distance \[m\] from the start shape to the box centre.
const BOX_CLEARANCE: f64 = 0.04;
/// Nodes of the model shapes.
const SHAPE_NODES: usize = 64;

/// Everything a trial needs that does not change between trials.
struct Context<'a> {
    wire: &'a WireSpec,
    params: WireParams,
    gravity: Gravity,
    model: KirchhoffModel,
    /// Which model `model` is: a loaded model places the true wire at its own `Γ(a_s)`.
    kind: ModelKind,
    calibration: &'a Calibration,
    /// The simulated sensor and rig (`--sensor`, `--rig`).
    rig: &'a SimSetup,
    seed: u64,
    /// Steer the closed loop by `ã` corrected for the sensor's drift (`--bias-observer`).
    bias_observer: bool,
}

/// A placed, tared rig of a trial and its feedback.
type TrialRig = (NoisyRig<SimRig>, FtFeedback<Calibration>);

/// How a closed-loop trial runs.
#[derive(Clone, Copy)]
struct ClosedSetup<'a> {
    noise: NoiseModel,
    /// The ε of its trade-off table (it runs with the smallest).
    epsilons: &'a [f64],
    max_iterations: usize,
    detector: Option<CollisionDetector>,
    /// The controller's settling radius (`0`: off; see [`SETTLE_RADIUS`]).
    settle_radius: f64,
    /// The controller's shape stop \[m\] (`0`: off, the stop is the smallest ε's).
    shape_stop: f64,
}

/// One start–goal pair.
struct Pair {
    a_s: Vector6<f64>,
    a_g: Vector6<f64>,
    goal_shape: Vec<Vector3<f64>>,
    start_shape: Vec<Vector3<f64>>,
}

/// The ground truth at one rest.
#[derive(Debug, Clone, Copy)]
struct Truth {
    shape_mm: f64,
    a_error: f64,
    contact: bool,
    /// Total contact force on the obstacles \[N\].
    contact_force: f64,
    /// The last move snapped the wire to another branch (simulator's report).
    snapped: bool,
}

/// One ε's stop on a closed-loop run.
#[derive(Debug, Clone)]
struct Stop {
    steps: usize,
    truth: Truth,
    reached: bool,
    failure: Option<String>,
    /// The wire snapped at least once before this stop.
    snapped: bool,
}

/// A closed-loop trial.
struct ClosedTrial {
    /// One stop per ε of the table, in its order.
    stops: Vec<Stop>,
    run: Option<Run>,
    /// Truth at the start and after each step.
    truths: Vec<Truth>,
    /// The rig and its feedback where the run left them.
    rig: Option<TrialRig>,
}

/// An open-loop trial.
struct OpenTrial {
    truth: Truth,
    failure: Option<String>,
    measured: Vec<Option<Vector6<f64>>>,
    truths: Vec<Truth>,
}

#[derive(Debug, Clone, Serialize)]
struct Metrics {
    mean_mm: f64,
    std_mm: f64,
    a_error_mean: f64,
    /// Trials in the means.
    trials: usize,
    /// Trials left out (see `failures`).
    failed: usize,
    /// Trials (of those in the means) in which the simulator's wire snapped to another
    /// equilibrium branch at least once.
    snapped: usize,
    /// `mean_mm` over the trials without a snap (ground truth used only to report this).
    mean_mm_without_snaps: f64,
}

#[derive(Debug, Clone, Serialize)]
struct Variants {
    no_noise: Metrics,
    noise: Metrics,
}

#[derive(Debug, Clone, Serialize)]
struct Results {
    open_loop: Variants,
    closed_loop: Variants,
}

#[derive(Debug, Clone, Serialize)]
struct TradeoffRow {
    epsilon: f64,
    mean_mm: f64,
    std_mm: f64,
    a_error_mean: f64,
    steps_median: f64,
    /// Trials whose measured ã came within ε.
    reached: usize,
    trials: usize,
}

#[derive(Debug, Clone, Serialize)]
struct Tradeoff {
    no_noise: Vec<TradeoffRow>,
    noise: Vec<TradeoffRow>,
}

#[derive(Debug, Clone, Default, Serialize)]
struct Collision {
    false_alarms: usize,
    /// Of the false alarms, those raised on a step where the simulator's wire snapped to
    /// another branch (a real disagreement with the model, though no contact).
    false_alarms_at_snaps: usize,
    trials: usize,
    detection_delay_steps_median: f64,
    /// Free motions checked for false alarms.
    free_motions: usize,
    /// Contacts detected, missed, and alarms before any contact, on the obstacle motions.
    detected: usize,
    missed: usize,
    early_alarms: usize,
    /// Obstacle motions that never touched the box, or could not be run.
    no_contact: usize,
    /// Detected step minus the first step with a contact force, per detected contact.
    delays: Vec<usize>,
    /// The simulator's total contact force at each detection \[N\] (in the order of `delays`).
    detection_force_n: Vec<f64>,
    /// The detector: threshold on the residual, floor \[normalised\], slope \[-\] and window
    /// \[moves\] (see `ftwire_control::CollisionDetector`).
    threshold: f64,
    floor: f64,
    slope: f64,
    window: usize,
    /// Retreats that found a pose agreeing with the way out.
    retreat_agreed: usize,
}

#[derive(Debug, Clone, Default, Serialize)]
struct PairDraws {
    drawn: usize,
    not_connected: usize,
    unstable_for_model: usize,
    /// Segments that come within the stability margin of the boundary.
    near_boundary: usize,
}

#[derive(Debug, Clone, Serialize)]
struct Failure {
    pair: usize,
    variant: String,
    message: String,
}

#[derive(Debug, Clone, Serialize)]
struct Epsilons {
    no_noise: f64,
    noise: f64,
}

#[derive(Serialize)]
struct GoalSummary {
    wire: String,
    model: ModelKind,
    noise_model: NoiseModel,
    /// The bias observer's settings of the closed loops without noise and with noise (`null`
    /// where it is off: `--bias-observer off`, or under `absolute`; `fuse_rest` where each rest is
    /// also fused with the reported pose: without noise and under `increment`).
    bias_observer: BiasObservers,
    gain: f64,
    epsilon: Epsilons,
    /// The noise runs' shape stop \[mm\] (0: off). When on, `results.closed_loop.noise` and
    /// `steps_median` are where those runs stopped, and `epsilon_tradeoff.noise` is read off
    /// the same runs up to that stop (`--shape-stop 0` gives the ε stop alone).
    shape_stop_mm: f64,
    pairs: usize,
    results: Results,
    /// Median steps of the closed loop with noise (at the headline ε).
    steps_median: f64,
    /// Median steps of the closed loop without noise.
    steps_median_no_noise: f64,
    epsilon_tradeoff: Tradeoff,
    collision: Collision,
    pair_draws: PairDraws,
    failures: Vec<Failure>,
}

/// The bias observers of a run's closed loops.
#[derive(Serialize)]
struct BiasObservers {
    no_noise: Option<BiasObserverParams>,
    noise: Option<BiasObserverParams>,
}

/// Means over the trials that did not fail; each trial is its final truth, whether it failed,
/// and whether the wire snapped during it.
fn metrics(trials: &[(Truth, bool, bool)]) -> Metrics {
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

impl Context<'_> {
    fn shape(&self, a: &Vector6<f64>) -> Result<Vec<Vector3<f64>>, LabError> {
        Ok(self
            .model
            .shape(a, SHAPE_NODES)
            .map_err(|e| from_estimate(e, "the model's shape"))?
            .positions)
    }

    /// The reach check of the runs: none, as in the paper's Table III (see the module docs).
    fn reach(&self) -> AnyPose {
        AnyPose
    }

    fn truth(&self, rig: &SimRig, pair: &Pair) -> Result<Truth, LabError> {
        let equilibrium = rig.equilibrium();
        let centreline: Vec<Vector3<f64>> = equilibrium
            .wire_centreline()
            .iter()
            .map(|p| p.coords)
            .collect();
        let distance = centreline_distance(&pair.goal_shape, &centreline, DEFAULT_METRIC_SAMPLES)
            .map_err(|e| from_estimate(e, "the shape error"))?;
        let a_true = equilibrium.base_wrench.to_vector();
        Ok(Truth {
            shape_mm: 1e3 * distance,
            a_error: to_normalised(&self.params, &(a_true - pair.a_g)).norm(),
            contact: touches(&equilibrium.contact_forces),
            contact_force: equilibrium.contact_forces.iter().map(|f| f.norm()).sum(),
            snapped: rig
                .simulator()
                .last_motion()
                .is_some_and(|m| !m.snaps.is_empty()),
        })
    }

    /// The bias observer of a closed loop under `noise`, when `--bias-observer on` and the
    /// noise model uses one ([`bias_observer`]).
    fn observer_settings(&self, noise: NoiseModel) -> Option<BiasObserverParams> {
        bias_observer(self.rig, noise, self.bias_observer)
    }

    /// The placed, tared rig of trial `k` (with `obstacles`) and its feedback; `None` when the
    /// simulator cannot place the wire.
    fn rig(
        &self,
        pair: &Pair,
        k: u64,
        noise: NoiseModel,
        obstacles: &[BoxObstacle],
    ) -> Result<Option<TrialRig>, LabError> {
        let config = self
            .rig
            .rig_config(rig_seed(self.seed.wrapping_add(0x60A1), k as usize));
        // The start is `a_s` of the steering model: under the loaded model the true wire's
        // base wrench is then `a_s`, as the pair was drawn (under the weightless one it sags).
        let placed = place_among(
            self.wire,
            self.gravity,
            self.kind,
            &pair.a_s,
            config,
            obstacles,
        );
        let Ok(mut sim) = placed else {
            return Ok(None);
        };
        let tare = tare(&mut sim)?;
        let feedback = FtFeedback::new(pipeline(tare, self.calibration.clone())?, SAMPLES_PER_REST);
        let noisy = NoisyRig::new(
            sim,
            noise,
            NoiseParams::default(),
            rig_seed(self.seed.wrapping_add(0x5EED), k as usize),
        )
        .map_err(|e| LabError::bad_input(e.to_string()))?;
        Ok(Some((noisy, feedback)))
    }

    /// The closed loop on `pair` with the smallest of `epsilons`, read off at each.
    fn closed(
        &self,
        pair: &Pair,
        k: u64,
        setup: &ClosedSetup<'_>,
        obstacles: &[BoxObstacle],
    ) -> Result<ClosedTrial, LabError> {
        let ClosedSetup {
            noise,
            epsilons,
            max_iterations,
            detector,
            settle_radius,
            shape_stop,
        } = *setup;
        // One stop per ε, then the run's own end.
        let failed = |message: String| ClosedTrial {
            stops: (0..=epsilons.len())
                .map(|_| Stop {
                    steps: 0,
                    truth: Truth {
                        shape_mm: f64::NAN,
                        a_error: f64::NAN,
                        contact: false,
                        contact_force: 0.0,
                        snapped: false,
                    },
                    reached: false,
                    failure: Some(message.clone()),
                    snapped: false,
                })
                .collect(),
            run: None,
            truths: Vec::new(),
            rig: None,
        };
        let Some((mut rig, feedback)) = self.rig(pair, k, noise, obstacles)? else {
            return Ok(failed("the simulator could not place the wire".into()));
        };
        let settings = ControlParams {
            gain: GAIN,
            epsilon: epsilons.iter().copied().fold(f64::INFINITY, f64::min),
            max_iterations,
            settle_radius,
            settle_samples: SETTLE_SAMPLES,
            shape_tolerance: shape_stop,
            ..ControlParams::default()
        };
        let mut controller = Controller::new(self.model, settings)
            .map_err(|e| LabError::bad_input(e.to_string()))?;
        if let Some(d) = detector {
            controller = controller.with_detector(d);
        }
        let mut truths = vec![self.truth(rig.inner(), pair)?];
        let mut truth_error = None;
        let mut reach = self.reach();
        let mut observer = self
            .observer_settings(noise)
            .map(|settings| BiasObserver::new(self.model, settings))
            .transpose()
            .map_err(|e| LabError::bad_input(e.to_string()))?;
        let run = controller.run_with_bias_observer(
            &mut rig,
            &feedback,
            &mut reach,
            &pair.a_g,
            observer.as_mut(),
            |rig, _| match self.truth(rig.inner(), pair) {
                Ok(t) => truths.push(t),
                Err(e) => truth_error = Some(e),
            },
        );
        if let Some(e) = truth_error {
            return Err(e);
        }
        let run = match run {
            Ok(run) => run,
            Err(e) => return Ok(failed(format!("refused: {e}"))),
        };
        // The measured distance to the goal at the start and after each step.
        let distances: Vec<f64> = std::iter::once(run.start_estimate)
            .chain(run.steps.iter().map(|s| s.estimate))
            .map(|a| controller.distance(&a, &pair.a_g))
            .collect();
        let failure = match &run.outcome {
            Outcome::Reached { .. } | Outcome::IterationLimit { .. } => None,
            Outcome::CollisionDetected { .. } => None,
            other => Some(format!("{}: {other:?}", other.name())),
        };
        let mut stops: Vec<Stop> = epsilons
            .iter()
            .map(|&eps| {
                let hit = distances.iter().position(|&d| d < eps);
                let steps = hit.unwrap_or(distances.len() - 1);
                Stop {
                    steps,
                    truth: truths[steps.min(truths.len() - 1)],
                    reached: hit.is_some(),
                    failure: if hit.is_some() { None } else { failure.clone() },
                    snapped: truths.iter().take(steps + 1).any(|t| t.snapped),
                }
            })
            .collect();
        // Where the run itself stopped (the shape stop's headline).
        let end = distances.len() - 1;
        let reached = matches!(run.outcome, Outcome::Reached { .. });
        stops.push(Stop {
            steps: end,
            truth: truths[end.min(truths.len() - 1)],
            reached,
            failure: if reached { None } else { failure },
            snapped: truths.iter().any(|t| t.snapped),
        });
        Ok(ClosedTrial {
            stops,
            run: Some(run),
            truths,
            rig: Some((rig, feedback)),
        })
    }

    /// The open loop along `poses` on `pair`.
    fn open(
        &self,
        pair: &Pair,
        k: u64,
        noise: NoiseModel,
        poses: &[Pose],
    ) -> Result<OpenTrial, LabError> {
        let Some((mut rig, feedback)) = self.rig(pair, k, noise, &[])? else {
            return Ok(OpenTrial {
                truth: Truth {
                    shape_mm: f64::NAN,
                    a_error: f64::NAN,
                    contact: false,
                    contact_force: 0.0,
                    snapped: false,
                },
                failure: Some("the simulator could not place the wire".into()),
                measured: Vec::new(),
                truths: Vec::new(),
            });
        };
        let mut truths = vec![self.truth(rig.inner(), pair)?];
        let mut truth_error = None;
        let out = roll_out(&mut rig, poses, Some(&feedback), |rig, _| {
            match self.truth(rig.inner(), pair) {
                Ok(t) => truths.push(t),
                Err(e) => truth_error = Some(e),
            }
        })
        .map_err(|e| LabError::no_answer(e.to_string()))?;
        if let Some(e) = truth_error {
            return Err(e);
        }
        Ok(OpenTrial {
            truth: self.truth(rig.inner(), pair)?,
            failure: out
                .failed
                .map(|(step, message)| format!("move {step}: {message}")),
            measured: out.measured,
            truths,
        })
    }
}

/// Draws `count` pairs (see the module docs).
fn draw_pairs(
    ctx: &Context<'_>,
    rod: &Rod,
    count: usize,
    rng: &mut ChaCha8Rng,
    draws: &mut PairDraws,
) -> Result<Vec<Pair>, LabError> {
    let sampler = Sampler {
        half_width: PAIR_BOX,
        ..Sampler::default()
    };
    let mut pairs = Vec::with_capacity(count);
    while pairs.len() < count {
        if draws.drawn >= MAX_DRAWS_PER_PAIR * count.max(1) {
            return Err(LabError::no_answer(format!(
                "found only {} A-connected pairs in {} draws",
                pairs.len(),
                draws.drawn
            )));
        }
        draws.drawn += 1;
        let a_s = sampler
            .sample_free(rod, rng)
            .map_err(|e| from_rod(e, "sampling A_free"))?;
        let a_g = sampler
            .sample_free(rod, rng)
            .map_err(|e| from_rod(e, "sampling A_free"))?;
        if !a_connected(rod, &a_s, &a_g, CONNECT_CHECKS)
            .map_err(|e| LabError::no_answer(e.to_string()))?
        {
            draws.not_connected += 1;
            continue;
        }
        if !ctx.model.is_stable(&a_g).unwrap_or(false)
            || !ctx.model.is_stable(&a_s).unwrap_or(false)
        {
            draws.unstable_for_model += 1;
            continue;
        }
        if !stable_with_margin(ctx, &a_s, &a_g, STABILITY_MARGIN) {
            draws.near_boundary += 1;
            continue;
        }
        pairs.push(Pair {
            a_s,
            a_g,
            goal_shape: ctx.shape(&a_g)?,
            start_shape: ctx.shape(&a_s)?,
        });
    }
    Ok(pairs)
}

/// Whether every point of the segment's check grid stays in `A_stable` of the model when moved
/// by `margin` (normalised) along each axis, both ways.
fn stable_with_margin(
    ctx: &Context<'_>,
    a_s: &Vector6<f64>,
    a_g: &Vector6<f64>,
    margin: f64,
) -> bool {
    line_in_a(a_s, a_g, CONNECT_CHECKS).iter().all(|a| {
        (0..12).all(|k| {
            let mut step = Vector6::zeros();
            step[k / 2] = if k % 2 == 0 { margin } else { -margin };
            let moved = a + from_normalised(&ctx.params, &step);
            ctx.model.is_stable(&moved).unwrap_or(false)
        })
    })
}

/// The box of the collision sub-run for `pair`: 20 mm at a node of `Φ(a_g)` (middle first)
/// far enough from the start shape; `None` when no node qualifies.
fn obstacle_for(pair: &Pair) -> Result<Option<BoxObstacle>, LabError> {
    let n = pair.goal_shape.len();
    for fraction in [0.5, 0.35, 0.65] {
        let centre = pair.goal_shape[((n - 1) as f64 * fraction).round() as usize];
        let clearance = pair
            .start_shape
            .iter()
            .map(|p| (p - centre).norm())
            .fold(f64::INFINITY, f64::min);
        if clearance >= BOX_CLEARANCE {
            let pose = Pose::translation(centre.x, centre.y, centre.z);
            return BoxObstacle::new(pose, Vector3::repeat(BOX_HALF))
                .map(Some)
                .map_err(|e| from_sim(e, "the obstacle"));
        }
    }
    Ok(None)
}

/// The first step of `run` at which `detector` would have fired.
fn first_alarm(detector: &CollisionDetector, run: &Run) -> Option<usize> {
    let moves: Vec<MoveCheck> = run.steps.iter().map(|s| s.check).collect();
    detector.first_alarm(&moves)
}

/// Runs the experiment.
#[allow(clippy::too_many_lines)]
pub fn run(args: GoalExperimentArgs) -> Result<(), LabError> {
    let common = &args.common;
    let seed = common.seed.seed;
    let shape_stop = shape_stop(args.shape_stop, args.noise_model)?;
    let wire_name = common
        .wire
        .clone()
        .unwrap_or_else(|| DEFAULT_WIRE.to_owned());
    let wire = WireSpec::load(&wire_name).map_err(|e| LabError::bad_input(e.to_string()))?;
    let setup = common.setup.load()?;
    let kind = common.model();
    let model = known_model(&wire, common.gravity, kind)?;
    let params = *model.wire();
    let rod = Rod::new(params);
    let super::CalibratedRun {
        folder,
        header,
        calibration,
        calibration_s,
    } = super::CalibratedRun::start(
        "goal",
        common,
        &args,
        args.calibration.as_deref(),
        &setup,
        OutGuard::default(),
    )?;
    let noise = args.noise_model.model();
    let ctx = Context {
        wire: &wire,
        params,
        gravity: common.gravity,
        model,
        kind,
        calibration: &calibration,
        rig: &setup,
        seed,
        bias_observer: args.bias_observer.on(),
    };
    let (noise_epsilons, noise_headline, noise_iterations) = match noise {
        NoiseModel::Increment | NoiseModel::Absolute => {
            (EPSILONS_NOISE, EPSILON_NOISE, MAX_ITERATIONS_NOISE)
        }
        NoiseModel::Offset | NoiseModel::None => {
            (EPSILONS_NO_NOISE, EPSILON_NO_NOISE, MAX_ITERATIONS_NO_NOISE)
        }
    };
    let headline = |table: &[f64], eps: f64| table.iter().position(|&e| e == eps).unwrap_or(0);
    // With the shape stop the noise runs' headline is where each run stopped (the stop after
    // the ε table's, see `closed`); the ε table is read off the same runs.
    let (h_free, h_noise) = (
        headline(&EPSILONS_NO_NOISE, EPSILON_NO_NOISE),
        if shape_stop > 0.0 {
            noise_epsilons.len()
        } else {
            headline(&noise_epsilons, noise_headline)
        },
    );

    let start = Instant::now();
    let mut draws = PairDraws::default();
    let mut rng = ChaCha8Rng::seed_from_u64(seed.wrapping_add(14));
    let pairs = draw_pairs(&ctx, &rod, args.pairs, &mut rng, &mut draws)?;
    let mut rng = ChaCha8Rng::seed_from_u64(seed.wrapping_add(1_014));
    let mut scratch = PairDraws::default();
    let detector_pairs = draw_pairs(&ctx, &rod, DETECTOR_MOTIONS, &mut rng, &mut scratch)?;
    eprintln!("{} pairs drawn ({:?})", pairs.len(), draws);

    // The collision detector: floor from the measured noise, threshold from free motions.
    let free_setup = ClosedSetup {
        noise: NoiseModel::None,
        epsilons: &[DETECTOR_EPSILON],
        max_iterations: MAX_ITERATIONS_NO_NOISE,
        detector: None,
        settle_radius: 0.0,
        shape_stop: 0.0,
    };
    let mut noise_levels = Vec::new();
    let mut calibration_runs = Vec::new();
    for (i, pair) in detector_pairs.iter().enumerate() {
        let k = 10_000 + i as u64;
        if let Some((mut rig, feedback)) = ctx.rig(pair, k, NoiseModel::None, &[])?
            && let Ok(m) = feedback.measure(&mut rig)
        {
            noise_levels.push(to_normalised(&params, &m.a_std_error).norm());
        }
        let trial = ctx.closed(pair, k, &free_setup, &[])?;
        calibration_runs.extend(trial.run);
    }
    let floor = FLOOR_SIGMAS * median(&noise_levels);
    let floor = if floor.is_finite() && floor > 0.0 {
        floor
    } else {
        CollisionDetector::DEFAULT_FLOOR
    };
    let free_moves: Vec<Vec<MoveCheck>> = calibration_runs
        .iter()
        .map(|run| run.steps.iter().map(|s| s.check).collect())
        .collect();
    let free_moves: Vec<&[MoveCheck]> = free_moves.iter().map(Vec::as_slice).collect();
    let detector = CollisionDetector::calibrate_moves(
        &free_moves,
        DETECTOR_QUANTILE,
        CollisionDetector::DEFAULT_MARGIN,
        floor,
    )
    .map_err(|e| LabError::no_answer(format!("calibrating the collision detector: {e}")))?;
    eprintln!(
        "collision detector: floor {floor:.4}, slope {:.3}, threshold {:.3} from {} free steps",
        detector.slope(),
        detector.threshold(),
        free_moves.iter().map(|m| m.len()).sum::<usize>()
    );

    let mut csv = CsvTable::new(
        "trials.csv",
        &[
            "pair", "variant", "epsilon", "steps", "mean_mm", "a_error", "snapped", "outcome",
            "failure",
        ],
    )?;
    let mut failures = Vec::new();
    let mut closed_free = Vec::new();
    let mut closed_noise = Vec::new();
    let mut open_free = Vec::new();
    let mut open_noise = Vec::new();
    let mut plan_us = Vec::new();
    let mut reach_us = Vec::new();
    let mut collision = Collision {
        threshold: detector.threshold(),
        floor,
        slope: detector.slope(),
        window: detector.window(),
        ..Collision::default()
    };
    let mut sample = None;
    for (i, pair) in pairs.iter().enumerate() {
        let k = i as u64;
        let mut pair_rows = Vec::new();
        for (variant, model_noise, table, h, iterations) in [
            (
                "no_noise",
                NoiseModel::None,
                &EPSILONS_NO_NOISE,
                h_free,
                MAX_ITERATIONS_NO_NOISE,
            ),
            ("noise", noise, &noise_epsilons, h_noise, noise_iterations),
        ] {
            let setup = ClosedSetup {
                noise: model_noise,
                epsilons: table,
                max_iterations: iterations,
                detector: None,
                // Where the sensor's noise limits the stop (no noise, `offset`), the last rests
                // average longer; under `increment` / `absolute` the gripper's noise does.
                settle_radius: match model_noise {
                    NoiseModel::None | NoiseModel::Offset => SETTLE_RADIUS,
                    NoiseModel::Increment | NoiseModel::Absolute => 0.0,
                },
                shape_stop: if model_noise == NoiseModel::None {
                    0.0
                } else {
                    shape_stop
                },
            };
            let closed = ctx.closed(pair, k, &setup, &[])?;
            if let Some(run) = &closed.run {
                plan_us.extend(run.steps.iter().map(|s| 1e6 * s.plan_s));
                reach_us.extend(run.steps.iter().map(|s| 1e6 * s.reach_s));
                if model_noise == NoiseModel::None {
                    collision.free_motions += 1;
                    if let Some(step) = first_alarm(&detector, run) {
                        collision.false_alarms += 1;
                        if closed.truths.get(step + 1).is_some_and(|t| t.snapped) {
                            collision.false_alarms_at_snaps += 1;
                        }
                    }
                }
            }
            let outcome = closed.run.as_ref().map_or("not_run", |r| r.outcome.name());
            for (&eps, stop) in table.iter().zip(&closed.stops) {
                csv.row([
                    value(i),
                    text(&format!("closed_{variant}")),
                    value(eps),
                    value(stop.steps),
                    value(stop.truth.shape_mm),
                    value(stop.truth.a_error),
                    value(stop.snapped),
                    text(outcome),
                    failure_cell(stop.failure.as_deref()),
                ])?;
            }
            let stop = &closed.stops[h];
            if let Some(message) = &stop.failure {
                failures.push(Failure {
                    pair: i,
                    variant: format!("closed_loop.{variant}"),
                    message: message.clone(),
                });
            }
            let steps = stop.steps.max(1);
            let poses = straight_line_in_a(&ctx.model, &pair.a_s, &pair.a_g, steps)
                .map_err(|e| LabError::no_answer(format!("the straight line in A: {e}")))?;
            let open = ctx.open(pair, k, model_noise, &poses)?;
            csv.row([
                value(i),
                text(&format!("open_{variant}")),
                Cell::empty(),
                value(steps),
                value(open.truth.shape_mm),
                value(open.truth.a_error),
                value(open.truths.iter().any(|t| t.snapped)),
                text("open_loop"),
                failure_cell(open.failure.as_deref()),
            ])?;
            if let Some(message) = &open.failure {
                failures.push(Failure {
                    pair: i,
                    variant: format!("open_loop.{variant}"),
                    message: message.clone(),
                });
            }
            let open_failed = open.failure.is_some();
            let open_snapped = open.truths.iter().any(|t| t.snapped);
            match model_noise {
                NoiseModel::None => {
                    open_free.push((open.truth, open_failed, open_snapped));
                    closed_free.push(closed.stops.clone());
                }
                _ => {
                    open_noise.push((open.truth, open_failed, open_snapped));
                    closed_noise.push(closed.stops.clone());
                }
            }
            pair_rows.push((variant, closed, open, steps));
        }
        if i == 0 {
            sample = Some(pair_rows);
        }
        eprintln!("pair {} / {} done", i + 1, pairs.len());
    }

    // The collision sub-run: motions into a box.
    for (i, pair) in pairs.iter().take(CONTACT_TRIALS).enumerate() {
        let Some(obstacle) = obstacle_for(pair)? else {
            collision.no_contact += 1;
            continue;
        };
        let k = 20_000 + i as u64;
        let setup = ClosedSetup {
            detector: Some(detector),
            ..free_setup
        };
        let trial = ctx.closed(pair, k, &setup, &[obstacle])?;
        let Some(run) = trial.run else {
            collision.no_contact += 1;
            continue;
        };
        // truths[j] is the rest after step j − 1 (truths[0] the start).
        let first_contact = trial.truths.iter().position(|t| t.contact);
        let detected = match run.outcome {
            Outcome::CollisionDetected { step, .. } => Some(step + 1),
            _ => None,
        };
        match (first_contact, detected) {
            (None, None) => collision.no_contact += 1,
            (None, Some(_)) => collision.early_alarms += 1,
            (Some(c), Some(d)) if d < c => collision.early_alarms += 1,
            (Some(_), None) => {
                collision.trials += 1;
                collision.missed += 1;
            }
            (Some(c), Some(d)) => {
                collision.trials += 1;
                collision.detected += 1;
                collision.delays.push(d - c);
                collision
                    .detection_force_n
                    .push(trial.truths.get(d).map_or(f64::NAN, |t| t.contact_force));
            }
        }
        if detected.is_some()
            && let Some((mut rig, feedback)) = trial.rig
            && retreat(&mut rig, &feedback, &run, &params, 10.0 * floor).is_ok_and(|r| r.agreed)
        {
            collision.retreat_agreed += 1;
        }
    }
    collision.detection_delay_steps_median = median(
        &collision
            .delays
            .iter()
            .map(|&d| d as f64)
            .collect::<Vec<_>>(),
    );
    let experiment_s = start.elapsed().as_secs_f64();

    // Summaries.
    let closed_at = |trials: &[Vec<Stop>], h: usize| -> Vec<(Truth, bool, bool)> {
        trials
            .iter()
            .map(|stops| (stops[h].truth, stops[h].failure.is_some(), stops[h].snapped))
            .collect()
    };
    let steps_of = |trials: &[Vec<Stop>], h: usize| -> f64 {
        median(
            &trials
                .iter()
                .filter(|s| s[h].failure.is_none())
                .map(|s| s[h].steps as f64)
                .collect::<Vec<_>>(),
        )
    };
    let tradeoff = |trials: &[Vec<Stop>], table: &[f64]| -> Vec<TradeoffRow> {
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
    };
    let summary = GoalSummary {
        wire: wire.name.clone(),
        model: kind,
        noise_model: noise,
        bias_observer: BiasObservers {
            no_noise: ctx.observer_settings(NoiseModel::None),
            noise: ctx.observer_settings(noise),
        },
        gain: GAIN,
        epsilon: Epsilons {
            no_noise: EPSILON_NO_NOISE,
            noise: noise_headline,
        },
        shape_stop_mm: 1e3 * shape_stop,
        pairs: pairs.len(),
        results: Results {
            open_loop: Variants {
                no_noise: metrics(&open_free),
                noise: metrics(&open_noise),
            },
            closed_loop: Variants {
                no_noise: metrics(&closed_at(&closed_free, h_free)),
                noise: metrics(&closed_at(&closed_noise, h_noise)),
            },
        },
        steps_median: steps_of(&closed_noise, h_noise),
        steps_median_no_noise: steps_of(&closed_free, h_free),
        epsilon_tradeoff: Tradeoff {
            no_noise: tradeoff(&closed_free, &EPSILONS_NO_NOISE),
            noise: tradeoff(&closed_noise, &noise_epsilons),
        },
        collision,
        pair_draws: draws,
        failures,
    };

    // Figures of the first pair.
    if let Some(rows) = &sample {
        let pair = &pairs[0];
        let n = |a: &Vector6<f64>| to_normalised(&params, a);
        let point = |a: &Vector6<f64>| {
            let v = n(a);
            [v[1], v[2], v[3]]
        };
        let mut chart = Chart3d::new(format!(
            "motion in A (normalised τ2, τ3, f1), pair 0, {} noise",
            noise.name()
        ))
        .with_curve(
            "straight line a(σ)",
            line_in_a(&pair.a_s, &pair.a_g, 20)
                .iter()
                .map(point)
                .collect(),
            SeriesKind::Line,
        );
        let mut errors = LineChart::new(
            "shape error along the motion, pair 0",
            "step",
            "mean distance to Φ(a_g) [mm]",
        );
        for (variant, closed, open, steps) in rows {
            if let Some(run) = &closed.run {
                let h = if *variant == "no_noise" {
                    h_free
                } else {
                    h_noise
                };
                let stop = closed.stops[h].steps;
                let path: Vec<[f64; 3]> = std::iter::once(run.start)
                    .chain(run.steps.iter().map(|s| s.measured))
                    .take(stop + 1)
                    .map(|a| point(&a))
                    .collect();
                if *variant == "noise" {
                    chart = chart.with_curve("closed loop ã (noise)", path, SeriesKind::Line);
                }
                errors = errors.with_series(Series::line(
                    format!("closed loop, {variant}"),
                    closed
                        .truths
                        .iter()
                        .take(stop + 1)
                        .enumerate()
                        .map(|(j, t)| (j as f64, t.shape_mm))
                        .collect(),
                ));
            }
            if *variant == "noise" {
                let path: Vec<[f64; 3]> = std::iter::once(Some(pair.a_s))
                    .chain(open.measured.iter().copied())
                    .flatten()
                    .map(|a| point(&a))
                    .collect();
                chart = chart.with_curve("open loop ã (noise)", path, SeriesKind::Line);
            }
            errors = errors.with_series(Series::line(
                format!("open loop, straight line in A, {variant}"),
                open.truths
                    .iter()
                    .enumerate()
                    .map(|(j, t)| (j as f64, t.shape_mm))
                    .collect(),
            ));
            if *variant == "no_noise" {
                // Fig. 7's dotted curve: the straight line in B, same steps, no noise.
                let b_s = ctx
                    .model
                    .tip(&pair.a_s)
                    .map_err(|e| from_estimate(e, "Γ(a_s)"))?;
                let b_g = ctx
                    .model
                    .tip(&pair.a_g)
                    .map_err(|e| from_estimate(e, "Γ(a_g)"))?;
                let poses = straight_line_in_b(&b_s, &b_g, *steps)
                    .map_err(|e| LabError::no_answer(e.to_string()))?;
                let line_b = ctx.open(pair, 0, NoiseModel::None, &poses)?;
                errors = errors.with_series(Series::line(
                    "open loop, straight line in B, no_noise",
                    line_b
                        .truths
                        .iter()
                        .enumerate()
                        .map(|(j, t)| (j as f64, t.shape_mm))
                        .collect(),
                ));
            }
        }
        chart = chart
            .with_curve("start", vec![point(&pair.a_s)], SeriesKind::Points)
            .with_curve("goal", vec![point(&pair.a_g)], SeriesKind::Points);
        folder.write_figure("motion_in_a", |dir| chart.write(dir, "motion_in_a"))?;
        folder.write_figure("shape_error_along_motion", |dir| {
            errors.write(dir, "shape_error_along_motion")
        })?;
    }

    folder.write("trials.csv", csv.into_bytes()?)?;
    let controller_step_us_median = median(&plan_us);
    folder.write_json(
        "timings.json",
        &serde_json::json!({
            "calibration_s": calibration_s,
            "experiment_s": experiment_s,
            "controller_step_us_median": controller_step_us_median,
            "reach_check_us_median": median(&reach_us),
        }),
    )?;
    let target = folder.finish(&header, &summary)?;
    print_summary(&summary, controller_step_us_median);
    println!(
        "calibration {calibration_s:.1} s, experiment {experiment_s:.1} s; results in {}",
        target.display()
    );
    Ok(())
}

/// A failure's message as a `trials.csv` cell, its commas as `;` (as the file has always had
/// them, for readers that split lines at commas).
fn failure_cell(failure: Option<&str>) -> Cell {
    text(&failure.unwrap_or_default().replace(',', ";"))
}

/// Prints the summary's tables, and the controller step's median time \[µs\].
fn print_summary(s: &GoalSummary, controller_step_us_median: f64) {
    println!(
        "goal: {} ({} model), {} pairs, K = {}, noise model {}",
        s.wire,
        s.model.name(),
        s.pairs,
        s.gain,
        s.noise_model.name()
    );
    println!(
        "{:<24} {:>9} {:>8} {:>9} {:>7} {:>7} {:>7} {:>9}",
        "", "mean_mm", "std_mm", "a_error", "trials", "failed", "snapped", "no-snap"
    );
    for (name, m) in [
        ("open loop, no noise", &s.results.open_loop.no_noise),
        ("closed loop, no noise", &s.results.closed_loop.no_noise),
        ("open loop, noise", &s.results.open_loop.noise),
        ("closed loop, noise", &s.results.closed_loop.noise),
    ] {
        println!(
            "{name:<24} {:>9.2} {:>8.2} {:>9.3} {:>7} {:>7} {:>7} {:>9.2}",
            m.mean_mm,
            m.std_mm,
            m.a_error_mean,
            m.trials,
            m.failed,
            m.snapped,
            m.mean_mm_without_snaps
        );
    }
    println!("paper Table III: open 4.80 / 17.35, closed 9.67 / 9.11 (no noise / noise)");
    if s.shape_stop_mm > 0.0 {
        println!(
            "closed loop, noise: the shape stop at {} mm; the ε rows below are read off those runs",
            s.shape_stop_mm
        );
    }
    for (name, rows) in [
        ("no noise", &s.epsilon_tradeoff.no_noise),
        ("noise", &s.epsilon_tradeoff.noise),
    ] {
        for r in rows {
            println!(
                "ε = {:<5} ({name}): mean {:.2} mm, steps median {}, reached {}/{}",
                r.epsilon, r.mean_mm, r.steps_median, r.reached, r.trials
            );
        }
    }
    println!(
        "steps median {} (noise), {} (no noise); controller step {:.1} µs (median)",
        s.steps_median, s.steps_median_no_noise, controller_step_us_median
    );
    let c = &s.collision;
    println!(
        "collision: {} false alarms ({} at snaps) in {} free motions; {} contacts, {} detected, {} missed, delay median {} steps ({:?}), {} early alarms, {} without contact; threshold {:.3}, floor {:.4}",
        c.false_alarms,
        c.false_alarms_at_snaps,
        c.free_motions,
        c.trials,
        c.detected,
        c.missed,
        c.detection_delay_steps_median,
        c.delays,
        c.early_alarms,
        c.no_contact,
        c.threshold,
        c.floor
    );
}
