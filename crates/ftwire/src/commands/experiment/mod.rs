//! `ftwire experiment <id>`: one module per experiment.

pub mod calibrate;
pub mod goal;
pub mod identify;
pub mod passage;
pub mod shape;
mod stats;
pub mod track;

use ftwire_estimate::calibration::Calibration;
use ftwire_lab::error::LabError;
use ftwire_lab::experiment::calibration::load_or_run_into;
use ftwire_lab::header::RunHeader;
use ftwire_lab::results::{OutGuard, ResultsFolder};
use ftwire_lab::setup::SimSetup;
use ftwire_lab::tracking::RolloutParams;
use serde::Serialize;

use crate::cli::experiment::{CommonExperimentArgs, ExperimentArgs, ExperimentId, RolloutArgs};

/// Runs the chosen experiment.
pub fn run(args: ExperimentArgs) -> Result<(), LabError> {
    match args.id {
        ExperimentId::Identify(args) => identify::run(args),
        ExperimentId::Calibrate(args) => calibrate::run(args),
        ExperimentId::Shape(args) => shape::run(args),
        ExperimentId::Goal(args) => goal::run(args),
        ExperimentId::Track(args) => track::run(args),
        ExperimentId::Passage(args) => passage::run(args),
    }
}

/// The lab's roll-out settings of `track` and `passage` (the tracking policy of
/// `--noise-model` with `--gain`, `--shape-stop`, `--waypoint-moves` and `--near-shape-stop`).
///
/// # Errors
/// Bad input for a bad gain or a negative distance, naming the option.
fn rollout_params(args: &RolloutArgs) -> Result<RolloutParams, LabError> {
    Ok(RolloutParams {
        noise: args.noise_model.model(),
        calibration: args.calibration.clone(),
        policy: args.policy()?,
        bias_observer: args.bias_observer.on(),
    })
}

/// A started run that reads F/T through a learnt calibration: its results folder, its
/// header, the calibration (`--calibration FILE`, or one run first and cached in the folder),
/// and the time the calibration took.
pub struct CalibratedRun {
    /// The results folder (written whole on `finish`).
    pub folder: ResultsFolder,
    /// The run header of `summary.json`.
    pub header: RunHeader,
    /// The learnt calibration.
    pub calibration: Calibration,
    /// Wall time of loading or running the calibration \[s\].
    pub calibration_s: f64,
}

impl CalibratedRun {
    /// Opens the results folder of experiment `id` (`--out`, default `results/<id>`; it must
    /// not hold `--calibration` nor the `other` inputs) and loads the calibration, or runs one
    /// on the sensor and rig of `setup`.
    ///
    /// # Errors
    /// As [`CommonExperimentArgs::open_results`] and `load_or_run_into`.
    pub fn start(
        id: &str,
        common: &CommonExperimentArgs,
        args: &impl Serialize,
        calibration: Option<&std::path::Path>,
        setup: &SimSetup,
        other: OutGuard,
    ) -> Result<Self, LabError> {
        let folder = common.open_results(id, other.input_opt("--calibration", calibration))?;
        let seed = common.seed.seed;
        let header = RunHeader::new(&format!("experiment {id}"), Some(seed), args)?;
        let (calibration, calibration_s) = load_or_run_into(
            &folder,
            calibration,
            (common.gravity, common.model()),
            setup,
            seed,
        )?;
        Ok(Self {
            folder,
            header,
            calibration,
            calibration_s,
        })
    }
}
