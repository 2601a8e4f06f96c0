//! `ftwire experiment <id>`: one module per experiment.

pub mod calibrate;
pub mod goal;
pub mod identify;
pub mod passage;
pub mod shape;
pub mod track;

use ftwire_lab::error::LabError;
use ftwire_lab::tracking::RolloutParams;

use crate::cli::experiment::{ExperimentArgs, ExperimentId, RolloutArgs};

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
        noise: args.closed_loop.noise_model().model(),
        calibration: args.closed_loop.calibration.file.clone(),
        policy: args.policy()?,
        bias_observer: args.closed_loop.bias_observer.on(),
    })
}
