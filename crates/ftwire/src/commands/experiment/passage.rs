//! `ftwire experiment passage` (paper §IV-E, Figs. 11–13): steer the wire through a narrow
//! passage between two boxes, by a plan tracked open and closed loop under gripper noise,
//! with the collision detector armed.
//!
//! The experiment, its scoring and its files are [`ftwire_lab::passage`]'s. This command maps
//! the options to [`PassageParams`] (`--scene`, `--attempts`, `--plan-candidates`,
//! `--no-polish`, and the roll-out options as `experiment track` does), writes `summary.json`
//! (the same for the same seed) and `timings.json`, and prints where.

use ftwire_lab::error::LabError;
use ftwire_lab::header::RunHeader;
use ftwire_lab::passage::{self, PassageParams};
use ftwire_lab::results::OutGuard;

use super::rollout::rollout_params;
use crate::cli::experiment::PassageExperimentArgs;

/// The lab's settings of `args`.
///
/// # Errors
/// Bad input for a bad gain or a negative distance.
fn params(args: &PassageExperimentArgs) -> Result<PassageParams, LabError> {
    Ok(PassageParams {
        common: args.common.params(),
        rollout: rollout_params(&args.rollout)?,
        scene: args.scene.file.clone(),
        attempts: args.attempts,
        plan_candidates: args.plan_candidates,
        polish: !args.no_polish,
    })
}

/// Runs the experiment.
///
/// # Errors
/// Bad input for bad options, a bad scene or wire; no answer when no plan is found.
pub fn run(args: PassageExperimentArgs) -> Result<(), LabError> {
    let params = params(&args)?;
    params.check()?;
    let folder = args.common.open_results(
        "passage",
        OutGuard::default()
            .input_opt("--scene", args.scene.path())
            .input_opt("--calibration", args.rollout.closed_loop.calibration.path()),
    )?;
    let header = RunHeader::new("experiment passage", Some(args.common.seed.seed), &args)?;
    let run = passage::run(&params, &folder, &mut |line| errln!("{line}"))?;
    folder.write_json("timings.json", &run.timings)?;
    let target = folder.finish(&header, &run.summary)?;
    outln!("results in {}", target.display());
    Ok(())
}

#[cfg(test)]
mod tests {
    use clap::Parser;

    use super::*;
    use crate::cli::experiment::ExperimentId;
    use crate::cli::{Cli, Command};

    /// The arguments of `ftwire experiment passage ARGS`.
    fn parse(args: &[&str]) -> PassageExperimentArgs {
        let line = ["ftwire", "experiment", "passage"].iter().chain(args);
        let cli = Cli::try_parse_from(line).expect("valid arguments");
        let Command::Experiment(experiment) = cli.command else {
            panic!("not an experiment")
        };
        let ExperimentId::Passage(passage) = experiment.id else {
            panic!("not the passage experiment")
        };
        passage
    }

    #[test]
    fn the_options_reach_the_lab() {
        let given = params(&parse(&[
            "--attempts",
            "3",
            "--plan-candidates",
            "2",
            "--no-polish",
            "--noise-model",
            "offset",
            "--seed",
            "5",
        ]))
        .expect("valid settings");
        assert_eq!(given.attempts, 3);
        assert_eq!(given.plan_candidates, 2);
        assert!(!given.polish);
        assert_eq!(given.common.seed, 5);
        assert_eq!(given.rollout.noise, ftwire_control::NoiseModel::Offset);
        let defaults = params(&parse(&[])).expect("valid settings");
        let lab = PassageParams::default();
        assert_eq!(
            (defaults.attempts, defaults.plan_candidates, defaults.polish),
            (lab.attempts, lab.plan_candidates, lab.polish)
        );
        assert_eq!(defaults.rollout, lab.rollout);
    }
}
