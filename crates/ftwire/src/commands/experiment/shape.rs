//! `ftwire experiment shape` (paper Table II, Fig. 5): the shape seen from the F/T sensor
//! alone, against the simulator's true centreline, over configurations of `A_free`.
//!
//! The experiment, its metrics and its files are [`ftwire_lab::shape`]'s. This command maps
//! the options to [`ShapeParams`], writes `summary.json` (the same for the same seed) and
//! `timings.json` (`calibration_s`, `experiment_s`, and `estimate_us_median`: `[wire, µs]`
//! pairs), and prints each wire's row beside the paper's Table II
//! ([`ftwire_lab::shape::ShapeRun::text`]).

use ftwire_lab::error::LabError;
use ftwire_lab::header::RunHeader;
use ftwire_lab::results::OutGuard;
use ftwire_lab::shape::{self, ShapeParams};

use crate::cli::experiment::ShapeExperimentArgs;

/// The lab's settings of `args`.
fn params(args: &ShapeExperimentArgs) -> ShapeParams {
    ShapeParams {
        common: args.common.params(),
        configs: args.configs,
        calibration: args.calibration.file.clone(),
        save_log: args.save_log,
        rest_samples: args.rest_samples,
    }
}

/// Runs the experiment.
pub fn run(args: ShapeExperimentArgs) -> Result<(), LabError> {
    let params = params(&args);
    params.check()?;
    let folder = args.common.open_results(
        "shape",
        OutGuard::default().input_opt("--calibration", args.calibration.path()),
    )?;
    let header = RunHeader::new("experiment shape", Some(args.common.seed.seed), &args)?;
    let run = shape::run(&params, &folder, &mut |line| errln!("{line}"))?;
    let target = folder.finish_run(&header, &run.summary, &run.timings)?;
    out!("{}", run.text(&target));
    Ok(())
}
