//! `ftwire experiment <id>`: one module per experiment.

pub mod calibrate;
pub mod goal;
pub mod identify;
pub mod shape;

use ftwire::error::CliError;

use crate::cli::experiment::{ExperimentArgs, ExperimentId};

/// Runs the chosen experiment.
pub fn run(args: ExperimentArgs) -> Result<(), CliError> {
    match args.id {
        ExperimentId::Identify(args) => identify::run(args),
        ExperimentId::Calibrate(args) => calibrate::run(args),
        ExperimentId::Shape(args) => shape::run(args),
        ExperimentId::Goal(args) => goal::run(args),
    }
}
