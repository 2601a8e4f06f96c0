//! `ftwire experiment calibrate` (placeholder of the scaffolding branch; replaced by the experiment).

use ftwire::error::CliError;

use crate::cli::experiment::CalibrateExperimentArgs;

/// Runs the experiment.
pub fn run(args: CalibrateExperimentArgs) -> Result<(), CliError> {
    Err(CliError::no_answer(format!(
        "experiment calibrate is not written yet: {args:?}"
    )))
}
