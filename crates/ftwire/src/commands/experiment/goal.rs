//! `ftwire experiment goal` (paper §IV-D, Table III, Figs. 6–7; collision detection §IV-E):
//! steer the wire from a start to a goal configuration by F/T feedback (eq. 13–14, K = 0.2),
//! against the open-loop roll-out of the straight line in `A`, with and without gripper noise.
//!
//! The experiment, its metrics and its files are [`ftwire_lab::goal`]'s. This command maps
//! the options to [`GoalParams`], writes `summary.json` (the same for the same seed) and
//! `timings.json` (`calibration_s`, `experiment_s`, and the medians
//! `controller_step_us_median` and `reach_check_us_median` of one controller step and one
//! reach check), and prints the summary's tables beside the paper's Table III.

use ftwire_lab::error::LabError;
use ftwire_lab::goal::{self, GoalParams, GoalRun};
use ftwire_lab::header::RunHeader;
use ftwire_lab::paper::TABLE_III;
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
    let run = goal::run(&params, &folder, &mut |line| eprintln!("{line}"))?;
    let target = folder.finish_run(&header, &run.summary, &run.timings)?;
    print_summary(&run);
    println!(
        "calibration {:.1} s, experiment {:.1} s; results in {}",
        run.timings.calibration_s,
        run.timings.experiment_s,
        target.display()
    );
    Ok(())
}

/// Prints the summary's tables beside the paper's Table III, and the controller step's
/// median time \[µs\].
fn print_summary(run: &GoalRun) {
    let s = &run.summary;
    println!(
        "goal: {} ({} model), {} pairs, K = {}, noise model {}",
        s.wire,
        s.model.name(),
        s.pairs,
        s.gain,
        s.noise_model.name()
    );
    println!(
        "{:<24} {:>9} {:>8} {:>9} {:>7} {:>7} {:>7} {:>9}",
        "", "mean_mm", "std_mm", "a_error", "trials", "failed", "snapped", "no-snap"
    );
    for (name, m) in [
        ("open loop, no noise", &s.results.open_loop.no_noise),
        ("closed loop, no noise", &s.results.closed_loop.no_noise),
        ("open loop, noise", &s.results.open_loop.noise),
        ("closed loop, noise", &s.results.closed_loop.noise),
    ] {
        println!(
            "{name:<24} {:>9.2} {:>8.2} {:>9.3} {:>7} {:>7} {:>7} {:>9.2}",
            m.mean_mm,
            m.std_mm,
            m.a_error_mean,
            m.trials,
            m.failed,
            m.snapped,
            m.mean_mm_without_snaps
        );
    }
    let [(_, open_free, closed_free), (_, open_noise, closed_noise)] = TABLE_III;
    println!(
        "paper Table III: open {open_free:.2} / {open_noise:.2}, closed {closed_free:.2} / \
         {closed_noise:.2} (no noise / noise)"
    );
    if s.shape_stop_mm > 0.0 {
        println!(
            "closed loop, noise: the shape stop at {} mm; the ε rows below are read off those runs",
            s.shape_stop_mm
        );
    }
    for (name, rows) in [
        ("no noise", &s.epsilon_tradeoff.no_noise),
        ("noise", &s.epsilon_tradeoff.noise),
    ] {
        for r in rows {
            println!(
                "ε = {:<5} ({name}): mean {:.2} mm, steps median {}, reached {}/{}",
                r.epsilon, r.mean_mm, r.steps_median, r.reached, r.trials
            );
        }
    }
    println!(
        "steps median {} (noise), {} (no noise); controller step {:.1} µs (median)",
        s.steps_median, s.steps_median_no_noise, run.timings.controller_step_us_median
    );
    let c = &s.collision;
    println!(
        "collision: {} false alarms ({} at snaps) in {} free motions; {} contacts, {} detected, {} missed, delay median {} steps ({:?}), {} early alarms, {} without contact; threshold {:.3}, floor {:.4}",
        c.false_alarms,
        c.false_alarms_at_snaps,
        c.free_motions,
        c.trials,
        c.detected,
        c.missed,
        c.detection_delay_steps_median,
        c.delays,
        c.early_alarms,
        c.no_contact,
        c.threshold,
        c.floor
    );
}
