//! `ftwire experiment identify`: paper §IV-B, Table I and Figs. 3–4. Identify `η = (c1, c2, c3,
//! L)` of the nitinol wires from random motion of the second gripper, over trials and numbers of
//! samples.
//!
//! The experiment, its protocol and its files are [`ftwire_lab::identify`]'s. This command
//! maps the options to [`IdentifyParams`] (`--twist`, default 40°; `--rest-samples`;
//! `--pipeline calibrated` with `--calibration FILE` or a calibration run first and cached,
//! or `--pipeline mounting`; `--model`; `--samples`; `--save-log`), writes `summary.json` and
//! `timings.json`, and prints each wire's 3-sample row beside Table I
//! ([`ftwire_lab::identify::IdentifyRun::text`]).
//!
//! Results folder (`--out`, default `results/identify`):
//! - `summary.json`: the run header, then `model`, `form`, `gravity`, `sensor`, `pipeline`
//!   (`calibrated` or `mounting`), `calibration` (the `--calibration` path, `"cached"` when one
//!   was run and cached, `null` for the mounting pipeline), `trials`, `sample_counts`;
//!   `wires`: a list of `{wire: {name, c, length, linear_density}, by_samples}` of `--model`;
//!   `wire` and `by_samples` repeated at the top level for the first wire; and `by_model`, a
//!   list of `{model, wires}` for every model run, `--model` first. Each `by_samples` row is
//!   `{samples, estimated, identified, mean[4], std[4], relative_error[4],
//!   mean_abs_relative_error[4], mean_abs_relative_error_identified[4], evaluations_median,
//!   linear_density}` over `(c1, c2, c3, L)` ([`ftwire_lab::identify::BySamples`]). Every
//!   value is the same for the same seed: the wall-clock times are in `timings.json`.
//! - `timings.json`: `calibration_s`, every identification's `compute_ms`, and
//!   `compute_ms_median`, a list of `{model, wire, samples, compute_ms_median}` over the trials.
//! - `identify.csv`, `error_vs_samples_<wire>.{png,svg}` (Fig. 3), `time_vs_samples.{png,svg}`
//!   (Fig. 4), with `--save-log` `logs/<wire>-trial<k>.jsonl` (the format `ftwire identify
//!   --log` reads), and `calibration.json` when a calibration was run.

use ftwire_lab::error::LabError;
use ftwire_lab::header::RunHeader;
use ftwire_lab::identify::{self, IdentifyParams, Pipeline};
use ftwire_lab::results::OutGuard;

use crate::cli::experiment::{IdentifyExperimentArgs, IdentifyPipeline};

/// The lab's settings of `args`.
fn params(args: &IdentifyExperimentArgs) -> IdentifyParams {
    IdentifyParams {
        common: args.common.params(),
        save_log: args.save_log,
        samples: args.samples.clone(),
        settings: args.settings.settings(),
        twist: args.twist,
        rest_samples: args.rest_samples,
        pipeline: match args.pipeline {
            IdentifyPipeline::Calibrated => Pipeline::Calibrated,
            IdentifyPipeline::Mounting => Pipeline::Mounting,
        },
        calibration: args.calibration.file.clone(),
        bias_model: !args.no_bias_model,
        until: args.until,
    }
}

/// Runs the experiment.
pub fn run(args: IdentifyExperimentArgs) -> Result<(), LabError> {
    let params = params(&args);
    params.check()?;
    let folder = args.common.open_results(
        "identify",
        OutGuard::default().input_opt("--calibration", args.calibration.path()),
    )?;
    let run = identify::run(&params, &folder, &mut |line| errln!("{line}"))?;
    let header = RunHeader::new("experiment identify", Some(args.common.seed.seed), &args)?;
    let target = folder.finish_run(&header, &run.summary, &run.timings)?;
    out!("{}", run.text(&target));
    Ok(())
}
