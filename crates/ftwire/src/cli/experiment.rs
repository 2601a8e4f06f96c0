//! Arguments of `ftwire experiment <id>`: the experiments of paper §IV, run in the simulator.

use ftwire_lab::error::LabError;
use ftwire_lab::results::{OutGuard, ResultsFolder};

use clap::{Args, Subcommand, ValueEnum};
use ftwire::args::{Count, ResultsArgs, SeedArgs, SimSetupArgs};
use ftwire_lab::experiment::Gravity;
use ftwire_lab::experiment::limits::{
    PLAN_CANDIDATES, REST_SAMPLES, ROLLOUTS, TRIALS, WAYPOINT_MOVES,
};

pub use super::groups::NoiseModelArg;
use super::groups::{CalibrationArgs, ClosedLoopArgs, SceneArgs};
use serde::Serialize;

/// `ftwire experiment <id>`.
#[derive(Debug, Args)]
pub struct ExperimentArgs {
    /// Which experiment.
    #[command(subcommand)]
    pub id: ExperimentId,
}

/// The experiments.
#[derive(Debug, Subcommand)]
pub enum ExperimentId {
    /// Table I, Figs. 3–4: identify c and L of the nitinol wires from random motion at 10 Hz.
    Identify(IdentifyExperimentArgs),
    /// §IV-A: collect F/T and markers on a known wire, label by shape fitting (eq. 15), train
    /// and evaluate the calibration network.
    Calibrate(CalibrateExperimentArgs),
    /// Table II, Fig. 5: shape error from F/T over configurations of A_free, for the four wires
    /// (and beside it, the same rest fused with the gripper's reported pose).
    Shape(ShapeExperimentArgs),
    /// Table III, Figs. 6–7: steer the wire between A-connected pairs of A_free, closed loop
    /// (eq. 13–14) against open loop, with and without gripper noise; collision detection.
    Goal(GoalExperimentArgs),
    /// Table IV, Figs. 8–9: random start/goal pairs of Z_free, planned with RRT* and tracked
    /// open and closed loop under gripper noise; the shape error along the path.
    Track(TrackExperimentArgs),
    /// §IV-E, Figs. 11–13: one plan through a 50 mm passage between two boxes, then repeated
    /// open- and closed-loop roll-outs under gripper noise with collision detection armed.
    Passage(PassageExperimentArgs),
}

/// Options every experiment takes.
#[derive(Debug, Clone, Args, Serialize)]
pub struct CommonExperimentArgs {
    /// A wire preset (nitinol-2mm-630, nitinol-3mm-910, nitinol-3mm-820, cable-3mm-920) or a
    /// wire file (TOML); replaces the experiment's default wires, so one wire can be run alone.
    #[arg(long, value_name = "PRESET|FILE.toml")]
    pub wire: Option<String>,
    /// The seed of every random choice.
    #[command(flatten)]
    pub seed: SeedArgs,
    /// Number of trials; for `calibrate`, the configurations visited (each experiment has its own
    /// default, the paper's where it gives one), 1 to 10000.
    #[arg(long, value_name = "N", value_parser = Count(TRIALS))]
    pub trials: Option<usize>,
    /// The results folder (`--out`, `--force`) [default: results/<id>].
    #[command(flatten)]
    #[serde(flatten)]
    pub results: ResultsArgs,
    /// Gravity in the simulated world.
    #[arg(long, value_parser = ftwire::args::named::<Gravity>(&Gravity::NAMES), default_value_t = Gravity::On)]
    pub gravity: Gravity,
    /// The estimators' wire model: `kirchhoff`, the paper's (weightless, straight at rest), or
    /// `loaded`, with the wire's weight under the known gravity and its rest curvature (for a
    /// wire being identified, its linear density is identified too) [default: `loaded` with
    /// `--gravity on`, `kirchhoff` with `--gravity off`]. The summaries report the other model
    /// beside it.
    #[arg(long, value_parser = ftwire::args::named::<ModelArg>(&ModelArg::NAMES))]
    pub model: Option<ModelArg>,
    /// The simulated F/T sensor and rig (`--sensor`, `--rig`).
    #[command(flatten)]
    #[serde(flatten)]
    pub setup: SimSetupArgs,
}

impl CommonExperimentArgs {
    /// The lab's common settings of these options.
    pub fn params(&self) -> ftwire_lab::experiment::CommonParams {
        ftwire_lab::experiment::CommonParams {
            wire: self.wire.clone(),
            seed: self.seed.seed,
            trials: self.trials,
            gravity: self.gravity,
            model: self.model,
            sensor: self.setup.sensor.clone(),
            rig: self.setup.rig.clone(),
            protocol: self.setup.protocol(),
        }
    }
}

impl CommonExperimentArgs {
    /// Opens the results folder: `--out`, or `results/<id>` (creating `results/` in the
    /// working folder when it is missing; a given `--out` must have an existing parent). The
    /// folder must not hold `--wire`, `--sensor`, `--rig` nor the `other` inputs
    /// ([`ftwire_lab::experiment::CommonParams::inputs`]).
    ///
    /// # Errors
    /// As [`ResultsArgs::open`].
    pub fn open_results(&self, id: &str, other: OutGuard) -> Result<ResultsFolder, LabError> {
        self.results.open(id, self.params().inputs(other))
    }
}

/// `ftwire experiment identify`.
#[derive(Debug, Clone, Args, Serialize)]
pub struct IdentifyExperimentArgs {
    /// The options every experiment takes.
    #[command(flatten)]
    pub common: CommonExperimentArgs,
    /// Write each trial's samples as a JSON Lines log into the results folder (`logs/`), in the
    /// format `ftwire identify --log` reads.
    #[arg(long)]
    pub save_log: bool,
    /// Sample counts to identify from, each from the first N samples of every trial, each 2 to
    /// 500 [default: 2,3,4,5,7,10,15,20,30].
    #[arg(long, value_name = "N,N,..", value_delimiter = ',')]
    pub samples: Option<Vec<usize>>,
    /// The residual form and the known relations between the parameters.
    #[command(flatten)]
    pub settings: crate::cli::identify::IdentifySettingsArgs,
    /// The twist of each identification move about the wire's tangent at the second gripper
    /// [degrees], alternating in sign (0: the paper's purely random moves; see
    /// `ftwire_estimate::identify::MotionPlan`).
    #[arg(long, value_name = "DEG", default_value_t = 40.0, allow_hyphen_values = true, value_parser = ftwire::args::parse_finite)]
    pub twist: f64,
    /// F/T samples averaged at each rest of the motion (at the simulated sensor's 1 kHz, 400
    /// is a 0.4 s rest): the white noise of `ã` falls as `1/√N`, while the sensor's bias
    /// drifts on for the time the rests take; the two balance near `σ √f / q ≈ 800` for the
    /// default sensor (noise σ, rate f, drift intensity q), but rests shorter or longer than
    /// the default change little: the tare's own noise, the same offset in every sample,
    /// dominates (`docs/identify-soft-wires.md`). 100 to 100000.
    #[arg(long, value_name = "N", default_value_t = ftwire_lab::identify::REST_SAMPLES, value_parser = Count(REST_SAMPLES))]
    pub rest_samples: usize,
    /// How `ã` is computed from the tared reading.
    #[arg(long, value_enum, default_value_t = IdentifyPipeline::Calibrated)]
    pub pipeline: IdentifyPipeline,
    /// The learnt calibration (`--calibration`).
    #[command(flatten)]
    #[serde(flatten)]
    pub calibration: CalibrationArgs,
    /// Treat the errors of the samples' ã as independent, without what they share: by default
    /// the fit models the tare's offset and the bias drift since the tare (the sensor's
    /// data-sheet intensity) and the map's gain error (--gain-error; by default 0.05 % in
    /// torque and 0.1 % in force through the learnt calibration, its accuracy against the
    /// sensor's exact inverse, or the sensor's own gain and cross-talk through the mounting
    /// alone), and estimates them with the wire. For comparison.
    #[arg(long)]
    pub no_bias_model: bool,
    /// Sample each trial until the wire is known to PCT %: identify from its first 2, 3, …
    /// samples and stop at the first estimate that is identified and whose 95 % interval
    /// half-widths (first-order covariance) of c1, c2, c3 and L are each within PCT % of the
    /// value (the loaded model's density does not hold the stop). The limit is the largest
    /// --samples count. summary.json gets `until` per wire. 0.01 to 100.
    #[arg(long, value_name = "PCT", value_parser = ftwire::args::parse_finite)]
    pub until: Option<f64>,
}

pub use ftwire_lab::experiment::ModelKind as ModelArg;

/// The F/T pipeline of `ftwire experiment identify`: how `ã` is computed from the tared reading.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum IdentifyPipeline {
    /// The learnt calibration network (`--calibration FILE`, or one run and cached first):
    /// corrects the sensor's gain, cross-talk and nonlinearity.
    Calibrated,
    /// The sensor's mounting transform only (no learnt correction): the sensor's gain error
    /// and cross-talk of about 1 % stay in `ã`. For comparison.
    Mounting,
}

/// `ftwire experiment calibrate`.
#[derive(Debug, Clone, Args, Serialize)]
pub struct CalibrateExperimentArgs {
    /// The options every experiment takes.
    #[command(flatten)]
    pub common: CommonExperimentArgs,
    /// Also write the session as a rig records it, into the results folder:
    /// `logs/recording.jsonl` (time, the raw reading not tared, the markers; no `b`), the input
    /// of `ftwire calibrate --log` and `ftwire shape --log`, and `logs/truth.jsonl` (the
    /// simulator's centreline of each line, for checking their shapes).
    #[arg(long)]
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub save_log: bool,
}

/// `ftwire experiment shape`.
#[derive(Debug, Clone, Args, Serialize)]
pub struct ShapeExperimentArgs {
    /// The options every experiment takes.
    #[command(flatten)]
    pub common: CommonExperimentArgs,
    /// Configurations of A_free per wire, 1 to 10000 (the paper: 50).
    #[arg(long, value_name = "N", value_parser = Count(TRIALS))]
    pub configs: Option<usize>,
    /// The learnt calibration (`--calibration`).
    #[command(flatten)]
    #[serde(flatten)]
    pub calibration: CalibrationArgs,
    /// Write the samples as a JSON Lines log into the results folder (`logs/`), in the format
    /// `ftwire shape --log` reads.
    #[arg(long)]
    pub save_log: bool,
    /// F/T samples averaged at each configuration (at the simulated sensor's 1 kHz, 100 is
    /// the 0.1 s of the paper's protocol): the white noise of `ã` falls as `1/√N`; the wire is
    /// placed just after taring, so the bias drift adds little here. 100 to 100000.
    #[arg(long, value_name = "N", default_value_t = ftwire_lab::experiment::rig::SAMPLES_PER_REST, value_parser = Count(REST_SAMPLES))]
    pub rest_samples: usize,
}

/// `ftwire experiment goal`.
#[derive(Debug, Clone, Args, Serialize)]
pub struct GoalExperimentArgs {
    /// The options every experiment takes (`--wire` defaults to nitinol-3mm-820).
    #[command(flatten)]
    pub common: CommonExperimentArgs,
    /// Start–goal pairs, 1 to 1000 (the paper: 30).
    #[arg(long, value_name = "N", default_value_t = 30, value_parser = Count(ROLLOUTS))]
    pub pairs: usize,
    /// The closed loop: `--noise-model` (of the `noise` runs), `--calibration`,
    /// `--bias-observer`, `--shape-stop` (of the `noise` runs).
    #[command(flatten)]
    #[serde(flatten)]
    pub closed_loop: ClosedLoopArgs,
}

/// The options of the experiments that roll a plan out (`track`, `passage`).
#[derive(Debug, Clone, Args, Serialize)]
pub struct RolloutArgs {
    /// The closed loop: `--noise-model` (the roll-outs'), `--calibration`,
    /// `--bias-observer`, `--shape-stop` (each leg's).
    #[command(flatten)]
    #[serde(flatten)]
    pub closed_loop: ClosedLoopArgs,
    /// The controller's gain K of eq. 13, in (0, 1]: each closed-loop move corrects the
    /// fraction K of the remaining configuration error, `δa = K (a_goal − ã)` [default: 1
    /// under `increment` and `absolute`, 0.5 otherwise; the paper's is 0.2]. A larger gain
    /// undoes each move's execution error sooner (under `increment` noise the wire's
    /// stationary spread about the path is `1/√(K (2 − K))` times one move's error) and takes
    /// fewer moves, each of them a rest in which the sensor drifts (`docs/control-noise.md`).
    #[arg(long, value_name = "K", value_parser = ftwire::args::parse_finite)]
    pub gain: Option<f64>,
    /// Most moves of the closed loop toward each waypoint before the last, 1 to 1000
    /// [default: 20]. A tighter `--shape-stop` under `increment` needs more: every move lands
    /// the wire about 12 mm from where it was sent, and the stop waits for a landing within it.
    #[arg(long, value_name = "N", value_parser = Count(WAYPOINT_MOVES))]
    pub waypoint_moves: Option<usize>,
    /// The shape stop in mm of the legs from or to a waypoint whose planned wire is within
    /// 25 mm of a box: every landing there is a chance to touch it [default: the larger of
    /// `--shape-stop` and 10 under `increment` and `absolute`, `--shape-stop` otherwise].
    #[arg(long, value_name = "MM", allow_hyphen_values = true, value_parser = ftwire::args::parse_finite)]
    pub near_shape_stop: Option<f64>,
}

/// `ftwire experiment track`.
#[derive(Debug, Clone, Args, Serialize)]
pub struct TrackExperimentArgs {
    /// The options every experiment takes (`--wire` defaults to nitinol-3mm-820).
    #[command(flatten)]
    pub common: CommonExperimentArgs,
    /// Start–goal pairs, 1 to 1000 (the paper: 10).
    #[arg(long, value_name = "N", default_value_t = 10, value_parser = Count(ROLLOUTS))]
    pub pairs: usize,
    /// What limits the closed loop's commanded poses: `any` ignores the arms' kinematics,
    /// as the paper's noise experiments and `experiment goal` do (under `increment` noise the
    /// believed pose wanders from the true one by a random walk of 10 mm a move, and soon
    /// leaves the arms' workspace); `robot` stops a run at a pose the SDA10F cannot reach.
    /// The pairs and the plans are in `Z_free` (reachable) either way.
    #[arg(long, value_enum, default_value_t = ReachArg::Any)]
    pub reach: ReachArg,
    /// Noise, calibration and gain.
    #[command(flatten)]
    pub rollout: RolloutArgs,
}

/// `ftwire experiment passage`.
#[derive(Debug, Clone, Args, Serialize)]
pub struct PassageExperimentArgs {
    /// The options every experiment takes (`--wire` defaults to nitinol-3mm-820, the wire
    /// the shipped passage is made for).
    #[command(flatten)]
    pub common: CommonExperimentArgs,
    /// The scene (`--scene`).
    #[command(flatten)]
    #[serde(flatten)]
    pub scene: SceneArgs,
    /// Roll-outs of each of open and closed loop, 1 to 1000 (the paper: 10).
    #[arg(long, value_name = "N", default_value_t = 50, value_parser = Count(ROLLOUTS))]
    pub attempts: usize,
    /// Track the plan's waypoints as resampled, without the clearance polish (by default,
    /// under `increment` and `absolute` noise, each waypoint whose landings, a move there
    /// landing 2 σ of the noise off on one axis, come closer than 15 mm to a box is moved away
    /// from it, its legs kept in `Z_free`; `ftwire_plan::PlanPolicy::polish_params`).
    #[arg(long)]
    pub no_polish: bool,
    /// Plans made, each from its own seed, of which the one whose tracked waypoints expect
    /// the fewest touching landings under the paper's noise is tracked (`ftwire_plan::choose_plan`;
    /// under `increment` and `absolute` only: one plan otherwise), 1 to 100; 1 tracks the first
    /// plan.
    #[arg(long, value_name = "N", default_value_t = ftwire_plan::PLAN_CANDIDATES, value_parser = Count(PLAN_CANDIDATES))]
    pub plan_candidates: usize,
    /// Noise, calibration and gain.
    #[command(flatten)]
    pub rollout: RolloutArgs,
}

/// `experiment track --reach`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ReachArg {
    /// No limit from the arms.
    Any,
    /// The SDA10F's dual-arm IK and arm collisions.
    Robot,
}
