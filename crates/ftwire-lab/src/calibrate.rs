//! The calibration experiment (paper §IV-A): collect F/T readings and markers on a known
//! wire, label them by shape fitting (eq. 15), train the calibration network, and compare it
//! with the tared mounting-only pipeline on the test split.
//!
//! The procedure is [`crate::experiment::calibration`]'s; this module runs it as an
//! experiment writing a results folder: `calibration.json` (the weights, in the format the
//! other experiments' `--calibration` loads) and `samples.csv` (one row per configuration).
//! The caller writes `summary.json` ([`CalibrateRun::summary`]) and `timings.json`
//! ([`CalibrateRun::timings`]), and may print [`CalibrateRun::text`], the results as text.
//! Guarded by the tests of `tests/experiments.rs` and by the
//! recorded summary of `crates/ftwire/tests/calibrate_experiment.rs`.

use std::fmt::Write as _;
use std::path::Path;

use serde::Serialize;

use crate::csv_table::{CsvTable, text, value};
use crate::error::{LabError, from_estimate};
use crate::experiment::calibration::{
    self, CalibrationRun, CalibrationSummary, CalibrationTimings, DEFAULT_SAMPLES, KNOWN_WIRE,
    RecordedRest,
};
use crate::experiment::{CommonParams, Progress};
use crate::results::ResultsFolder;
use crate::wire::WireSpec;

/// Configurations between two progress lines.
const PROGRESS_EVERY: usize = 50;

/// The settings of the calibration experiment: only the common ones. `common.wire` replaces
/// the known wire (default [`KNOWN_WIRE`]); `common.trials` is the number of configurations
/// collected (default [`DEFAULT_SAMPLES`]).
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct CalibrateParams {
    /// The settings every experiment takes.
    pub common: CommonParams,
    /// Also write the session as a rig records it: `logs/recording.jsonl` (the log format of
    /// `ftwire_estimate::log`: `time`, the raw reading not tared, the markers; no `b`) and
    /// `logs/truth.jsonl` (the simulator's centreline of each of its lines).
    pub save_log: bool,
}

impl CalibrateParams {
    /// The known wire: `common.wire`, or [`KNOWN_WIRE`].
    ///
    /// # Errors
    /// Bad input for an unknown preset or a bad wire file.
    pub fn wire(&self) -> Result<WireSpec, LabError> {
        self.common.wire_or(KNOWN_WIRE)
    }

    /// The configurations collected: `common.trials`, or [`DEFAULT_SAMPLES`].
    pub fn count(&self) -> usize {
        self.common.trials.unwrap_or(DEFAULT_SAMPLES)
    }

    /// Checks the settings as [`run`] does before any work (the wire, the sensor and the rig
    /// files), so that a caller can refuse bad input before it opens a results folder.
    ///
    /// # Errors
    /// Bad input naming what is wrong.
    pub fn check(&self) -> Result<(), LabError> {
        self.wire()?;
        self.common.setup()?;
        Ok(())
    }
}

/// A finished calibration experiment.
#[derive(Debug, Clone)]
pub struct CalibrateRun {
    /// `summary.json`'s body (after the run header).
    pub summary: CalibrationSummary,
    /// `timings.json`: the wall-clock times of collection and training.
    pub timings: CalibrationTimings,
}

impl CalibrateRun {
    /// The results as text: the split, the raw (mounting) and calibrated errors of the test
    /// split (relative errors of `ã`'s torque and force, shape error \[mm\]), the labels' fit,
    /// then the wall times and `results`, the folder the run was written to.
    pub fn text(&self, results: &Path) -> String {
        let s = &self.summary;
        let mut text = String::new();
        let _ = writeln!(
            text,
            "calibration on {} ({} train, {} validation, {} test; skipped {:?})",
            s.wire.name, s.samples.train, s.samples.validation, s.samples.test, s.skipped
        );
        let _ = writeln!(text, "                 torque_rel  force_rel  shape_mm");
        for (name, e) in [("raw (mounting)", &s.raw), ("calibrated", &s.calibrated)] {
            let _ = writeln!(
                text,
                "{name:<16} {:>10.4} {:>10.4} {:>9.2}",
                e.torque_rel, e.force_rel, e.shape_mm
            );
        }
        let _ = writeln!(
            text,
            "labels: marker RMS {:.3} mm, shape vs truth {:.2} mm",
            s.label_fit_mm, s.label_shape_mm
        );
        let _ = writeln!(
            text,
            "collect {:.1} s, train {:.1} s; results in {}",
            self.timings.collect_s,
            self.timings.train_s,
            results.display()
        );
        text
    }
}

/// Runs the calibration experiment into `folder`: writes `calibration.json` and
/// `samples.csv`, reports a line to `progress` when it starts and every 50 configurations,
/// and returns the summary and timings for the caller to write (it does not finish the
/// folder).
///
/// # Errors
/// Bad input for bad settings ([`CalibrateParams::check`]) or too few usable samples for the
/// split; no answer when the collection fails; I/O errors writing the folder.
pub fn run(
    settings: &CalibrateParams,
    folder: &ResultsFolder,
    progress: Progress<'_>,
) -> Result<CalibrateRun, LabError> {
    let common = &settings.common;
    let wire = settings.wire()?;
    let count = settings.count();
    let setup = common.setup()?;
    progress(&format!(
        "calibrating on {} ({count} configurations, gravity {:?})",
        wire.name, common.gravity
    ));
    let result = calibration::run(
        &wire,
        (common.gravity, common.model()),
        &setup,
        count,
        common.seed,
        |k| {
            if (k + 1) % PROGRESS_EVERY == 0 {
                progress(&format!("  {} / {count}", k + 1));
            }
        },
    )?;
    let json = result
        .calibration
        .to_json()
        .map_err(|e| from_estimate(e, "writing the calibration weights"))?;
    folder.write("calibration.json", json)?;
    folder.write("samples.csv", samples_csv(&result)?)?;
    if settings.save_log {
        let (log, truth) = recording_lines(&result.recording)?;
        folder.write("logs/recording.jsonl", log)?;
        folder.write("logs/truth.jsonl", truth)?;
    }
    Ok(CalibrateRun {
        summary: result.summary,
        timings: result.timings,
    })
}

/// One line of `logs/recording.jsonl`, in the log format of `ftwire_estimate::log`.
#[derive(Serialize)]
struct RecordLine<'a> {
    time: f64,
    raw: [f64; 6],
    markers: &'a [Option<[f64; 3]>],
}

/// One line of `logs/truth.jsonl`: the recording's line (1-based) and the true centreline
/// \[m\], base clamp frame.
#[derive(Serialize)]
struct TruthLine {
    line: usize,
    points: Vec<[f64; 3]>,
}

/// The recording and its truth as JSON Lines.
fn recording_lines(recording: &[RecordedRest]) -> Result<(Vec<u8>, Vec<u8>), LabError> {
    let json =
        |e: serde_json::Error| LabError::bad_input(format!("cannot serialise the recording: {e}"));
    let (mut log, mut truth) = (Vec::new(), Vec::new());
    for (i, rest) in recording.iter().enumerate() {
        let markers: Vec<Option<[f64; 3]>> = rest
            .markers
            .iter()
            .map(|m| m.map(|p| [p.x, p.y, p.z]))
            .collect();
        let line = RecordLine {
            time: rest.time,
            raw: rest.raw.into(),
            markers: &markers,
        };
        serde_json::to_writer(&mut log, &line).map_err(json)?;
        log.push(b'\n');
        let points = rest.truth.iter().map(|p| [p.x, p.y, p.z]).collect();
        serde_json::to_writer(
            &mut truth,
            &TruthLine {
                line: i + 1,
                points,
            },
        )
        .map_err(json)?;
        truth.push(b'\n');
    }
    Ok((log, truth))
}

/// `samples.csv`: one row per used configuration, its split, the label's marker residual,
/// the true wrench and the label (torque first).
fn samples_csv(result: &CalibrationRun) -> Result<Vec<u8>, LabError> {
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
    csv.into_bytes()
}
