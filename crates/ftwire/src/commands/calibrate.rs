//! `ftwire calibrate --log`: the F/T calibration learnt from a rig's recording
//! ([`ftwire_lab::log::calibrate`]: labels by shape fitting the markers, a split by blocks of
//! time, the map fitted on the shape or on the labels and chosen on the validation block, the
//! test block's marker errors). Writes
//! `calibration.json`, `summary.json`, `labels.csv`, `test.csv`, the figures and the report, and
//! prints the results ([`ftwire_lab::log::calibrate::LogCalibrateRun::text`]).

use ftwire_lab::error::LabError;
use ftwire_lab::header::RunHeader;
use ftwire_lab::log::calibrate::{self, LogCalibrateParams};
use ftwire_lab::results::OutGuard;
use ftwire_lab::wire::WireSpec;

use crate::cli::calibrate::CalibrateArgs;

/// The lab's settings of `args`.
fn params(args: &CalibrateArgs) -> Result<LogCalibrateParams, LabError> {
    let mut train = calibrate::default_train_params();
    train.hidden = args.hidden.iter().copied().filter(|&w| w > 0).collect();
    train.max_epochs = args.epochs;
    train.patience = args.patience;
    Ok(LogCalibrateParams {
        log: args.log.clone(),
        wire: WireSpec::load(&args.wire)
            .map_err(|e| LabError::bad_input(format!("--wire: {e}")))?,
        mounting: args.mounting.load()?,
        gravity: args.gravity.given(),
        marker_fractions: (!args.marker_fractions.is_empty())
            .then(|| args.marker_fractions.clone()),
        max_label_rms: 1e-3 * args.max_label_rms_mm,
        train,
        drift: !args.no_drift,
        seed: args.seed.seed,
        loss: args.loss,
        fit_gravity: args.fit_gravity.then_some(args.gravity_norm),
        rest_tolerance: 1e-3 * args.rest_tolerance_mm,
        shape: ftwire_estimate::calibration::shape_loss::ShapeLossParams {
            label_weight: args.label_weight,
            ..Default::default()
        },
    })
}

/// Runs `calibrate --log`.
pub fn run(args: CalibrateArgs) -> Result<(), LabError> {
    let params = params(&args)?;
    params.check()?;
    let guard = OutGuard::default()
        .input("--log", &args.log)
        .input("--wire", &args.wire)
        .input_opt("--mounting", args.mounting.file.as_ref());
    let folder = args.results.open("calibrate-log", guard)?;
    let header = RunHeader::new("calibrate", Some(args.seed.seed), &args)?;
    let run = calibrate::run(&params, &folder, &mut |line| errln!("{line}"))?;
    let target = folder.finish_run(&header, &run.summary, &run.timings)?;
    out!("{}", run.text(&target));
    Ok(())
}
