//! `ftwire shape --log`: the wire's shape for every record of a rig log (paper §IV-C), as a
//! real rig would run the estimator offline. The work is [`ftwire_lab::log::shape`]'s; this
//! command prints each record's answer as soon as it has it, or with `--out DIR` writes the
//! results folder.
//!
//! Every record is the rig layer's one shape record ([`ftwire_rig::record`]). Without `--out`:
//! with `--json`, one such JSON object per line; without, one line of text. With `--out DIR`:
//! `DIR/shapes.jsonl` (the same records, [`ftwire_lab::log::shape::folder`]), `summary.json` (`records`, `not_stable`,
//! `not_confident`, `marker_mean_mm`, and `sigma_mean_mm` with error bars), `timings.json`
//! and the report; the summary is printed
//! (as JSON with `--json`). A record the model cannot solve gets an `error` instead, and the
//! command then exits 1 after the last record (the folder written). A bad or empty log, a
//! `raw` record with neither `--calibration` nor `--mounting`, or one without `gravity` when
//! the mounting has a tool, is bad input (exit 2) naming the line, before anything is written.

use std::io;

use ftwire_app::output;
use ftwire_lab::error::LabError;
use ftwire_lab::header::RunHeader;
use ftwire_lab::log::shape::{LogShapes, ShapeLog, ShapeLogParams};
use ftwire_lab::results::OutGuard;

use crate::cli::shape::ShapeArgs;

/// Runs the command.
pub fn run(args: ShapeArgs) -> Result<(), LabError> {
    let params = ShapeLogParams {
        log: args.log.clone(),
        wire: args.wire.clone(),
        calibration: args.calibration.file.clone(),
        mounting: args.mounting.given()?,
        gravity_in_clamp: args.gravity.given(),
        points: args.points,
        a_std: args.a_std.map(|s| s.0),
        model_error: args.model_error,
        sensor: args
            .sensor
            .as_deref()
            .map(|given| {
                ftwire_lab::log::identify::LogDrift::load(
                    given,
                    args.rest_samples,
                    args.tare_samples,
                    args.tare_time,
                )
            })
            .transpose()?,
        gain_error: args.gain_error.map(|pct| 1e-2 * pct),
    };
    if args.results.out.is_some() {
        return write_folder(&args, &params);
    }
    if args.results.force {
        return Err(LabError::bad_input(
            "--force replaces the --out folder: give --out DIR (without it each record is \
             printed and nothing is written)",
        ));
    }
    print_records(&args, &params)
}

/// Prints each record's shape as soon as it has it ([`LogShapes::write_all`]).
fn print_records(args: &ShapeArgs, params: &ShapeLogParams) -> Result<(), LabError> {
    let shapes = LogShapes::new(params)?;
    let stdout = io::stdout();
    shapes.write_all(&mut stdout.lock(), args.output.json)
}

/// Writes the results folder of `--out` and prints the summary.
fn write_folder(args: &ShapeArgs, params: &ShapeLogParams) -> Result<(), LabError> {
    let log = ShapeLog::load(params)?;
    let guard = OutGuard::default()
        .input("--log", &args.log)
        .input("--wire", &args.wire)
        .input_opt("--calibration", args.calibration.file.as_ref())
        .input_opt("--mounting", args.mounting.file.as_ref())
        .input_opt("--sensor", args.sensor.as_ref());
    let folder = args.results.open("shape-log", guard)?;
    let header = RunHeader::new("shape", None, args)?;
    let run = log.write(&folder, &mut |line| errln!("{line}"))?;
    let target = folder.finish_run(&header, &run.summary, &run.timings)?;
    output::print_display(&run.summary, args.output.json)?;
    if !args.output.json {
        outln!(
            "{:.0} records/s; results in {}",
            run.timings.records_per_s,
            target.display()
        );
    }
    run.all_shaped()
}
