//! `ftwire experiment goal` (paper §IV-D, Table III, Figs. 6–7; collision detection §IV-E):
//! steer the wire from a start to a goal configuration by F/T feedback (eq. 13–14, K = 0.2),
//! against the open-loop roll-out of the straight line in `A`, with and without gripper noise.
//!
//! The experiment, its metrics and its files are [`ftwire_lab::goal`]'s. This command maps
//! the options to [`GoalParams`], writes `summary.json` (the same for the same seed) and
//! `timings.json` (`calibration_s`, `experiment_s`, and the medians
//! `controller_step_us_median` and `reach_check_us_median` of one controller step and one
//! reach check), and prints the summary's tables beside the paper's Table III
//! ([`ftwire_lab::goal::GoalRun::text`]).

use ftwire_lab::error::LabError;
use ftwire_lab::goal::{self, GoalParams};
use ftwire_lab::header::RunHeader;
use ftwire_lab::results::OutGuard;

use crate::cli::experiment::GoalExperimentArgs;

/// The lab's settings of `args`.
fn params(args: &GoalExperimentArgs) -> GoalParams {
    GoalParams {
        common: args.common.params(),
        pairs: args.pairs,
        noise_model: args.closed_loop.noise_model().model(),
        calibration: args.closed_loop.calibration.file.clone(),
        bias_observer: args.closed_loop.bias_observer.on(),
        shape_stop_mm: args.closed_loop.shape_stop,
    }
}

/// Runs the experiment.
pub fn run(args: GoalExperimentArgs) -> Result<(), LabError> {
    let params = params(&args);
    params.check()?;
    let folder = args.common.open_results(
        "goal",
        OutGuard::default().input_opt("--calibration", args.closed_loop.calibration.path()),
    )?;
    let header = RunHeader::new("experiment goal", Some(args.common.seed.seed), &args)?;
    let run = goal::run(&params, &folder, &mut |line| errln!("{line}"))?;
    let target = folder.finish_run(&header, &run.summary, &run.timings)?;
    out!("{}", run.text(&target));
    Ok(())
}
