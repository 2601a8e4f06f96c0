//! `ftwire calibrate --log`: the F/T calibration learnt from a rig's recording
//! ([`ftwire_lab::log::calibrate`]: labels by shape fitting the markers, a split by blocks of
//! time, the map fitted on the shape or on the labels and chosen on the validation block, the
//! test block's marker errors). Writes
//! `calibration.json`, `summary.json`, `labels.csv`, `test.csv`, the figures and the report.

use ftwire_lab::error::LabError;
use ftwire_lab::header::RunHeader;
use ftwire_lab::log::calibrate::{self, DEFAULT_MAX_LABEL_RMS, LogCalibrateParams, MapLoss};
use ftwire_lab::results::OutGuard;
use ftwire_lab::wire::WireSpec;

use crate::cli::calibrate::CalibrateArgs;

/// The lab's settings of `args`.
fn params(args: &CalibrateArgs) -> Result<LogCalibrateParams, LabError> {
    let mut train = calibrate::default_train_params();
    train.hidden = args.hidden.iter().copied().filter(|&w| w > 0).collect();
    train.max_epochs = args.epochs;
    train.patience = args.patience;
    let max_label_rms = if args.max_label_rms_mm > 0.0 {
        1e-3 * args.max_label_rms_mm
    } else {
        return Err(LabError::bad_input(format!(
            "--max-label-rms-mm {}: must be > 0 (default {} mm)",
            args.max_label_rms_mm,
            1e3 * DEFAULT_MAX_LABEL_RMS
        )));
    };
    Ok(LogCalibrateParams {
        log: args.log.clone(),
        wire: WireSpec::load(&args.wire)
            .map_err(|e| LabError::bad_input(format!("--wire: {e}")))?,
        mounting: args.mounting.load()?,
        gravity: args.gravity.given(),
        marker_fractions: (!args.marker_fractions.is_empty())
            .then(|| args.marker_fractions.clone()),
        max_label_rms,
        train,
        drift: !args.no_drift,
        seed: args.seed.seed,
        loss: MapLoss::from_name(&args.loss).ok_or_else(|| {
            LabError::bad_input(format!(
                "--loss {}: one of {}",
                args.loss,
                MapLoss::NAMES.join(", ")
            ))
        })?,
        fit_gravity: args.fit_gravity.then_some(args.gravity_norm),
        rest_tolerance: 1e-3 * args.rest_tolerance_mm,
        shape: ftwire_estimate::calibration::shape_loss::ShapeLossParams {
            label_weight: args.label_weight,
            ..Default::default()
        },
    })
}

/// `shape` or `labels`.
fn loss_name(loss: MapLoss) -> &'static str {
    match loss {
        MapLoss::Shape => "shape",
        MapLoss::Labels => "labels",
    }
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
    let run = calibrate::run(&params, &folder, &mut |line| eprintln!("{line}"))?;
    let target = folder.finish_run(&header, &run.summary, &run.timings)?;
    let s = &run.summary;
    println!(
        "labels: {} of {} records fitted ({} rejected), marker RMS {:.2} mm",
        s.labels.fitted, s.labels.records, s.labels.rejected, s.labels.marker_rms_mm
    );
    println!(
        "split by time: {} train, {} validation, {} test",
        s.split.train, s.split.validation, s.split.test
    );
    println!(
        "map: {} fitted on the {} ({})",
        s.fit.map,
        loss_name(s.fit.loss),
        s.fit.chosen_by
    );
    if let Some(g) = s.fit.gravity_in_clamp {
        println!(
            "gravity in the clamp frame: {:.3}, {:.3}, {:.3} m/s²",
            g[0], g[1], g[2]
        );
    }
    let t = &s.test;
    println!(
        "test block, mean inner-marker distance: {:.2} mm uncalibrated, {:.2} mm calibrated{} \
         (map fitted on the labels {:.2} mm; labels {:.2} mm)",
        t.raw_marker_mean_mm,
        t.calibrated_marker_mean_mm,
        t.affine_marker_mean_mm
            .map_or_else(String::new, |a| format!(
                ", {a:.2} mm its affine part alone"
            )),
        t.label_map_marker_mean_mm,
        t.label_marker_mean_mm
    );
    println!(
        "test block, mean distance along the wire to the labels' shapes: {:.2} mm calibrated",
        t.calibrated_wire_mean_mm
    );
    println!(
        "labels {:.1} s, training {:.1} s, shape fit {:.1} s; results in {}",
        run.timings.label_s,
        run.timings.train_s,
        run.timings.fit_s,
        target.display()
    );
    Ok(())
}
