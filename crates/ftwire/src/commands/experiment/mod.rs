//! `ftwire experiment <id>`: one module per experiment.

pub mod calibrate;
pub mod goal;
pub mod identify;
pub mod passage;
mod rollout;
pub mod shape;
pub mod track;

use ftwire_lab::error::LabError;

use crate::cli::experiment::{ExperimentArgs, ExperimentId};

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
