//! `ftwire experiment shape` (placeholder of the scaffolding branch; replaced by the experiment).

use ftwire::error::CliError;

use crate::cli::experiment::ShapeExperimentArgs;

/// Runs the experiment.
pub fn run(args: ShapeExperimentArgs) -> Result<(), CliError> {
    Err(CliError::no_answer(format!(
        "experiment shape is not written yet: {args:?}"
    )))
}
