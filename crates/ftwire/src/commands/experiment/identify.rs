//! `ftwire experiment identify`: paper §IV-B, Table I and Figs. 3–4. Identify `η = (c1, c2, c3,
//! L)` of the nitinol wires from random motion of the second gripper, over trials and numbers of
//! samples.
//!
//! The experiment, its protocol and its files are [`ftwire_lab::identify`]'s. This command
//! maps the options to [`IdentifyParams`] (`--twist`, default 40°; `--rest-samples`;
//! `--pipeline calibrated` with `--calibration FILE` or a calibration run first and cached,
//! or `--pipeline mounting`; `--model`; `--samples`; `--save-log`), writes `summary.json` and
//! `timings.json`, and prints each wire's 3-sample row beside Table I.
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

use std::fmt::Write as _;
use std::path::Path;

use ftwire_lab::error::LabError;
use ftwire_lab::header::RunHeader;
use ftwire_lab::identify::until::UntilSummary;
use ftwire_lab::identify::{self, IdentifyParams, IdentifySummary, PARAMETERS, Pipeline};
use ftwire_lab::paper::TABLE_I;
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
    let run = identify::run(&params, &folder, &mut |line| eprintln!("{line}"))?;
    let header = RunHeader::new("experiment identify", Some(args.common.seed.seed), &args)?;
    let target = folder.finish_run(&header, &run.summary, &run.timings)?;
    let summary = &run.summary;
    let median_ms = |w: usize, n: usize| {
        summary.wires.get(w).map_or(f64::NAN, |r| {
            run.timings.median_ms(summary.model, &r.wire.name, n)
        })
    };
    print!("{}", table(summary, &target, &median_ms));
    Ok(())
}

/// The printed table: per wire, the 3-sample row (or the smallest count) beside Table I, and
/// one line per sample count with its median time from `median_ms` (of the wire's index and
/// the count).
fn table(
    summary: &IdentifySummary,
    target: &Path,
    median_ms: &dyn Fn(usize, usize) -> f64,
) -> String {
    let mut text = String::new();
    let _ = writeln!(
        text,
        "identify: gravity {:?}, {} model, {} sensor, {:?} pipeline{}, {:?} residual, {} \
         trials; results in {}",
        summary.gravity,
        summary.model.name(),
        summary.sensor,
        summary.pipeline,
        summary
            .calibration
            .as_ref()
            .map_or_else(String::new, |c| format!(" ({c})")),
        summary.form,
        summary.trials,
        target.display()
    );
    for (w, result) in summary.wires.iter().enumerate() {
        let paper = TABLE_I
            .iter()
            .find(|(name, _)| *name == result.wire.name)
            .map(|(_, rows)| rows);
        let Some(row) = result
            .by_samples
            .iter()
            .find(|r| r.samples == 3)
            .or_else(|| result.by_samples.first())
        else {
            continue;
        };
        let _ = writeln!(
            text,
            "\n{} ({} samples; {} of {} trials identified)",
            result.wire.name, row.samples, row.identified, summary.trials
        );
        let _ = writeln!(
            text,
            "  {:<3} {:>8} {:>22} {:>10} {:>12}   paper (Table I, 3 samples)",
            "", "true", "estimated", "err(mean)", "mean|err|"
        );
        let truth = [
            result.wire.c[0],
            result.wire.c[1],
            result.wire.c[2],
            result.wire.length,
        ];
        for (j, parameter) in PARAMETERS.iter().enumerate() {
            let paper_text = paper.map_or_else(
                || "—".to_owned(),
                |rows| {
                    let (_, estimate, pm, error) = rows[j];
                    format!("{estimate:.3} ± {pm:.3}, {error:.1} %")
                },
            );
            let _ = writeln!(
                text,
                "  {parameter:<3} {:>8.4} {:>11.5} ± {:<8.5} {:>8.3} % {:>10.3} %   {paper_text}",
                truth[j],
                row.mean[j],
                row.std[j],
                100.0 * row.relative_error[j],
                100.0 * row.mean_abs_relative_error[j],
            );
        }
        let _ = writeln!(
            text,
            "  samples: mean |relative error| c1 c2 c3 L [%] (all; identified only), \
             identified, compute median [ms]"
        );
        for r in &result.by_samples {
            let e = r.mean_abs_relative_error.map(|v| 100.0 * v);
            let t = r.mean_abs_relative_error_identified.map(|v| 100.0 * v);
            let _ = writeln!(
                text,
                "  {:>3}: {:>7.3} {:>7.3} {:>7.3} {:>7.3};  {:>7.3} {:>7.3} {:>7.3} {:>7.3}   \
                 {:>2}/{}   {:>8.1}",
                r.samples,
                e[0],
                e[1],
                e[2],
                e[3],
                t[0],
                t[1],
                t[2],
                t[3],
                r.identified,
                summary.trials,
                median_ms(w, r.samples)
            );
        }
        if let Some(until) = result.until.as_ref() {
            until_line(&mut text, until);
        }
        if let Some(density) = row.linear_density.as_ref() {
            let _ = writeln!(
                text,
                "  linear density ({} samples): true {:.5} kg/m, estimated {:.5} ± {:.5}, \
                 mean |err| {:.2} %",
                row.samples,
                result.wire.linear_density,
                density.mean,
                density.std,
                100.0 * density.mean_abs_relative_error
            );
        }
    }
    for other in summary.by_model.iter().skip(1) {
        let _ = writeln!(
            text,
            "\nthe same data through the {} model (mean |relative error| c1 c2 c3 L [%], \
             identified):",
            other.model.name()
        );
        for result in &other.wires {
            if let Some(r) = result
                .by_samples
                .iter()
                .find(|r| r.samples == 3)
                .or_else(|| result.by_samples.first())
            {
                let e = r.mean_abs_relative_error.map(|v| 100.0 * v);
                let _ = writeln!(
                    text,
                    "  {} ({} samples): {:>7.3} {:>7.3} {:>7.3} {:>7.3}   {:>2}/{}",
                    result.wire.name,
                    r.samples,
                    e[0],
                    e[1],
                    e[2],
                    e[3],
                    r.identified,
                    summary.trials
                );
            }
        }
    }
    text
}

/// The `--until` line of one wire.
fn until_line(text: &mut String, until: &UntilSummary) {
    let e = until.max_abs_relative_error.map(|v| 100.0 * v);
    let _ = writeln!(
        text,
        "  --until {} %: {}/{} reached within {} samples; samples median {}, max {}; \
         largest |relative error| c1 c2 c3 L [%] {:.3} {:.3} {:.3} {:.3}",
        until.target_percent,
        until.reached,
        until.trials,
        until.limit,
        until.samples_median,
        until.samples_max,
        e[0],
        e[1],
        e[2],
        e[3]
    );
}
