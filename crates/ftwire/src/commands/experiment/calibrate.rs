//! `ftwire experiment calibrate` (paper §IV-A): collect F/T readings and markers on a known
//! wire, label them by shape fitting (eq. 15), train the calibration network, and compare it
//! with the tared mounting-only pipeline on the test split.
//!
//! The procedure is [`ftwire_lab::experiment::calibration`]'s. `--wire` replaces the known wire
//! (default [`KNOWN_WIRE`]); `--trials` is the number of configurations collected (default
//! [`DEFAULT_SAMPLES`]). Writes `summary.json`, `calibration.json` (the weights, in the format
//! `--calibration` loads), `samples.csv` (one row per configuration) and `timings.json`.

use ftwire_lab::csv_table::{CsvTable, text, value};
use ftwire_lab::error::{LabError, from_estimate};
use ftwire_lab::experiment::calibration::{DEFAULT_SAMPLES, KNOWN_WIRE, run as calibrate};
use ftwire_lab::header::RunHeader;
use ftwire_lab::results::OutGuard;
use ftwire_lab::wire::WireSpec;

use crate::cli::experiment::CalibrateExperimentArgs;

/// Runs the experiment.
pub fn run(args: CalibrateExperimentArgs) -> Result<(), LabError> {
    let common = &args.common;
    let wire_name = common.wire.clone().unwrap_or_else(|| KNOWN_WIRE.to_owned());
    let wire = WireSpec::load(&wire_name).map_err(|e| LabError::bad_input(e.to_string()))?;
    let count = common.trials.unwrap_or(DEFAULT_SAMPLES);
    let setup = common.setup.load()?;
    let folder = common.open_results("calibrate", OutGuard::default())?;
    let header = RunHeader::new("experiment calibrate", Some(common.seed.seed), &args)?;
    eprintln!(
        "calibrating on {} ({count} configurations, gravity {:?})",
        wire.name, common.gravity
    );
    let result = calibrate(
        &wire,
        (common.gravity, common.model()),
        &setup,
        count,
        common.seed.seed,
        |k| {
            if (k + 1) % 50 == 0 {
                eprintln!("  {} / {count}", k + 1);
            }
        },
    )?;
    let json = result
        .calibration
        .to_json()
        .map_err(|e| from_estimate(e, "writing the calibration weights"))?;
    folder.write("calibration.json", json)?;
    let mut csv = CsvTable::new(
        "samples.csv",
        &[
            "sample",
            "split",
            "label_rms_mm",
            "t1",
            "t2",
            "t3",
            "f1",
            "f2",
            "f3",
            "label_t1",
            "label_t2",
            "label_t3",
            "label_f1",
            "label_f2",
            "label_f3",
        ],
    )?;
    for (i, sample) in result.samples.iter().enumerate() {
        let split = if result.split.train.contains(&i) {
            "train"
        } else if result.split.validation.contains(&i) {
            "validation"
        } else {
            "test"
        };
        let mut cells = vec![value(i), text(split), value(1e3 * sample.label_rms)];
        cells.extend(
            sample
                .true_wrench
                .iter()
                .chain(sample.label.iter())
                .map(|&v| value(v)),
        );
        csv.row(cells)?;
    }
    folder.write("samples.csv", csv.into_bytes()?)?;
    folder.write_json("timings.json", &result.timings)?;
    let s = &result.summary;
    let target = folder.finish(&header, s)?;
    println!(
        "calibration on {} ({} train, {} validation, {} test; skipped {:?})",
        wire.name, s.samples.train, s.samples.validation, s.samples.test, s.skipped
    );
    println!("                 torque_rel  force_rel  shape_mm");
    for (name, e) in [("raw (mounting)", &s.raw), ("calibrated", &s.calibrated)] {
        println!(
            "{name:<16} {:>10.4} {:>10.4} {:>9.2}",
            e.torque_rel, e.force_rel, e.shape_mm
        );
    }
    println!(
        "labels: marker RMS {:.3} mm, shape vs truth {:.2} mm",
        s.label_fit_mm, s.label_shape_mm
    );
    println!(
        "collect {:.1} s, train {:.1} s; results in {}",
        result.timings.collect_s,
        result.timings.train_s,
        target.display()
    );
    Ok(())
}
