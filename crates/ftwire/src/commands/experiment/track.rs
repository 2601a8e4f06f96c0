//! `ftwire experiment track` (paper §IV-D, Table IV, Figs. 8–9): plan paths in `A_free` with
//! RRT* between random start and goal configurations, and track them open and closed loop
//! under gripper noise; the shape error along the path.
//!
//! The experiment, its metric and its files are [`ftwire_lab::track`]'s. This command maps the
//! options to [`TrackParams`] (`--noise-model`, `--calibration`, `--gain`, `--shape-stop`,
//! `--waypoint-moves`, `--near-shape-stop` and `--bias-observer` to its roll-out settings),
//! writes `summary.json` (the same for the same seed) and `timings.json`, and prints where.

use ftwire_lab::error::LabError;
use ftwire_lab::header::RunHeader;
use ftwire_lab::results::OutGuard;
use ftwire_lab::track::{self, ArmReach, TrackParams};

use super::rollout::rollout_params;
use crate::cli::experiment::{ReachArg, TrackExperimentArgs};

/// The lab's settings of `args`.
///
/// # Errors
/// Bad input for a bad gain or a negative distance.
fn params(args: &TrackExperimentArgs) -> Result<TrackParams, LabError> {
    Ok(TrackParams {
        common: args.common.params(),
        rollout: rollout_params(&args.rollout)?,
        pairs: args.pairs,
        reach: match args.reach {
            ReachArg::Any => ArmReach::Any,
            ReachArg::Robot => ArmReach::Robot,
        },
    })
}

/// Runs the experiment.
///
/// # Errors
/// Bad input for bad options or a bad wire; no answer when too few pairs can be planned.
pub fn run(args: TrackExperimentArgs) -> Result<(), LabError> {
    let params = params(&args)?;
    params.check()?;
    let folder = args.common.open_results(
        "track",
        OutGuard::default().input_opt("--calibration", args.rollout.closed_loop.calibration.path()),
    )?;
    let header = RunHeader::new("experiment track", Some(args.common.seed.seed), &args)?;
    let run = track::run(&params, &folder, &mut |line| errln!("{line}"))?;
    folder.write_json("timings.json", &run.timings)?;
    let target = folder.finish(&header, &run.summary)?;
    outln!("results in {}", target.display());
    Ok(())
}
