//! `ftwire experiment calibrate` (paper §IV-A): collect F/T readings and markers on a known
//! wire, label them by shape fitting (eq. 15), train the calibration network, and compare it
//! with the tared mounting-only pipeline on the test split.
//!
//! The experiment is [`ftwire_lab::calibrate`]'s. `--wire` replaces the known wire (default
//! [`ftwire_lab::experiment::calibration::KNOWN_WIRE`]); `--trials` is the number of
//! configurations collected (default
//! [`ftwire_lab::experiment::calibration::DEFAULT_SAMPLES`]). Writes `summary.json`,
//! `calibration.json` (the weights, in the format `--calibration` loads), `samples.csv` (one
//! row per configuration) and `timings.json`, and prints the results
//! ([`ftwire_lab::calibrate::CalibrateRun::text`]).

use ftwire_lab::calibrate::{self, CalibrateParams};
use ftwire_lab::error::LabError;
use ftwire_lab::header::RunHeader;
use ftwire_lab::results::OutGuard;

use crate::cli::experiment::CalibrateExperimentArgs;

/// The lab's settings of `args`.
fn params(args: &CalibrateExperimentArgs) -> CalibrateParams {
    CalibrateParams {
        common: args.common.params(),
        save_log: args.save_log,
    }
}

/// Runs the experiment.
pub fn run(args: CalibrateExperimentArgs) -> Result<(), LabError> {
    let params = params(&args);
    params.check()?;
    let folder = args.common.open_results("calibrate", OutGuard::default())?;
    let header = RunHeader::new("experiment calibrate", Some(args.common.seed.seed), &args)?;
    let run = calibrate::run(&params, &folder, &mut |line| errln!("{line}"))?;
    let target = folder.finish_run(&header, &run.summary, &run.timings)?;
    out!("{}", run.text(&target));
    Ok(())
}
