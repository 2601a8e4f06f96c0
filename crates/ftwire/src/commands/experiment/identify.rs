//! `ftwire experiment identify` (placeholder of the scaffolding branch; replaced by the experiment).

use ftwire::error::CliError;

use crate::cli::experiment::IdentifyExperimentArgs;

/// Runs the experiment.
pub fn run(args: IdentifyExperimentArgs) -> Result<(), CliError> {
    Err(CliError::no_answer(format!(
        "experiment identify is not written yet: {args:?}"
    )))
}
