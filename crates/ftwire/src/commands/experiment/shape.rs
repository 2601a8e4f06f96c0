//! `ftwire experiment shape` (paper Table II, Fig. 5): the shape seen from the F/T sensor
//! alone, against the simulator's true centreline, over configurations of `A_free`.
//!
//! The experiment, its metrics and its files are [`ftwire_lab::shape`]'s. This command maps
//! the options to [`ShapeParams`], writes `summary.json` (the same for the same seed) and
//! `timings.json` (`calibration_s`, `experiment_s`, and `estimate_us_median`: `[wire, µs]`
//! pairs), and prints each wire's row beside the paper's Table II.

use ftwire_lab::error::LabError;
use ftwire_lab::experiment::ModelKind;
use ftwire_lab::header::RunHeader;
use ftwire_lab::paper::TABLE_II;
use ftwire_lab::results::OutGuard;
use ftwire_lab::shape::{self, ShapeParams, ShapeRun};

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
    let run = shape::run(&params, &folder, &mut |line| eprintln!("{line}"))?;
    let target = folder.finish_run(&header, &run.summary, &run.timings)?;
    print_table(&run);
    println!(
        "calibration {:.1} s, experiment {:.1} s; results in {}",
        run.timings.calibration_s,
        run.timings.experiment_s,
        target.display()
    );
    Ok(())
}

/// Prints one row per wire beside the paper's Table II.
fn print_table(run: &ShapeRun) {
    let summary = &run.summary;
    println!(
        "shape: {} model (mean_mm), the {} model from the same ã beside it",
        summary.model.name(),
        summary.model.other().name()
    );
    println!(
        "{:<18} {:>7} {:>8} {:>7} {:>10} {:>8} {:>10} {:>10} {:>8} {:>9} {:>9} {:>9}",
        "wire",
        "configs",
        "mean_mm",
        "std_mm",
        summary.model.other().name(),
        "fused",
        "marker_mm",
        "mounting",
        "est_us",
        "Table II",
        "torque_%",
        "force_%"
    );
    for (r, (_, estimate_us)) in summary.wires.iter().zip(&run.timings.estimate_us_median) {
        let paper = TABLE_II
            .iter()
            .find(|(n, _)| *n == r.name)
            .map_or_else(|| "-".to_owned(), |(_, v)| format!("{v:.2}"));
        let other = match summary.model {
            ModelKind::Weightless => r.loaded_mean_mm,
            ModelKind::Loaded => r.kirchhoff_mean_mm,
        };
        println!(
            "{:<18} {:>7} {:>8.2} {:>7.2} {:>10.2} {:>8.2} {:>10.2} {:>10.2} {:>8.1} {:>9} {:>9.3} {:>9.3}",
            r.name,
            r.configs,
            r.mean_mm,
            r.std_mm,
            other,
            r.fused_mean_mm,
            r.marker_mean_mm,
            r.mounting_mean_mm,
            estimate_us,
            paper,
            100.0 * r.torque_rel,
            100.0 * r.force_rel
        );
    }
}
