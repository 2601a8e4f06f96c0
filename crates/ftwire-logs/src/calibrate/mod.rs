//! `ftwire calibrate --log`: the F/T calibration learnt from a rig's own recording (the
//! paper's §IV-A, and the map fitted on the shape).
//!
//! The recording is a JSON Lines log (`ftwire_estimate::log`) whose records carry `raw` (the
//! reading averaged at rest, force first, sensor frame, not tared) and `markers` (base clamp
//! frame); `b` is not needed. On a known wire:
//!
//! 1. **Inputs.** The tool's weight below the sensor is taken out of each reading
//!    (`ftwire_estimate::ft::MountingSpec::compensate`, with the record's `gravity`).
//! 2. **Labels** by shape fitting (eq. 15): `ShapeFitter` fits the model's centreline to the
//!    record's markers, a global search then Levenberg–Marquardt, at the markers' arc lengths
//!    when they are given (`marker_fractions`) or at their closest points (the paper's form)
//!    when not. Consecutive records at one rest (markers moved less than `rest_tolerance`)
//!    are fitted on the rest's mean markers ([`Pooling`]). A record without `raw`, with fewer
//!    than [`MIN_MARKERS`] markers, whose fit fails, or whose fit leaves the markers more than
//!    `max_label_rms` off (RMS) is rejected and counted by reason: a marker swap or a dropout
//!    burst must not teach the map.
//! 3. **Split by blocks of time** (`SplitOrder::Time`): the first 70 % of the labelled
//!    records train, the next 15 % validate, the last 15 % test. A real sensor drifts, and a
//!    random split would put neighbours in time on both sides and hide it.
//! 4. **The map fitted on the labels**: `Calibration::train` (a least-squares affine map from
//!    the reading to the label, which holds the mounting's lever arm and rotation, the gain,
//!    cross-talk and the offsets, plus a small network on what it leaves, starting at zero and
//!    stopped early on the validation block): the paper's map, and with [`MapLoss::Labels`]
//!    the one kept.
//! 5. **The map fitted on the shape** ([`MapLoss::Shape`]):
//!    `ftwire_estimate::calibration::shape_loss::fit_on_shape` fits the affine map and affine
//!    maps with a polynomial part on Huber's loss of the markers' distance to `Φ(map(raw))`,
//!    through the model's Jacobian, the labels starting it and keeping a weak pull
//!    (`label_weight`), gravity's direction with it when asked (`fit_gravity`). The candidate
//!    whose validation records' markers lie closest to their shapes is kept, the map of 4
//!    among the candidates.
//! 6. **Test**: on the test block, each inner marker's distance to `Φ(ã)` (the paper's
//!    metric, Fig. 5; the first marker is at the clamp and the last at the gripper, so they
//!    say nothing) and the mean distance along the wire to the label's shape, for the reading
//!    through the mounting alone, the kept map, its affine part and the map of 4; a
//!    calibration worse than the mounting alone is said (`worse_than_raw`, and on stderr).
//!
//! Pieces, one per file, in the order the run uses them: `params` the settings and
//! their checks; `labelling` the recording read and each record's label; `rests` the records
//! of one rest pooled; `labelled` one labelled record; `drift` the drift term; `map_fit` the
//! maps fitted on the labels and on the shape; `test_block` the test block's errors, table
//! and figures; `summary` what the run reports. This file runs them in turn ([`run`]).
//!
//! Guarded by `tests/log_calibrate.rs` (a simulated recording of the `distorted` and
//! `real-like` sensors, bad logs).

use std::time::Instant;

use ftwire_estimate::calibration::Drift;

use ftwire_app::Progress;
use ftwire_app::error::{LabError, from_estimate};
use ftwire_app::results::ResultsFolder;

mod drift;
mod labelled;
mod labelling;
mod map_fit;
mod params;
mod rests;
mod summary;
mod test_block;

pub use drift::DRIFT_T_STATISTIC;
use labelling::{label_all, read};
use map_fit::Training;
pub use params::{
    DEFAULT_MAX_LABEL_RMS, DEFAULT_REST_TOLERANCE, LogCalibrateParams, MIN_MARKERS, MapLoss,
    STANDARD_GRAVITY, default_train_params,
};
pub use rests::Pooling;
pub use summary::{
    CandidateOut, DriftOut, FitOut, Labels, LogCalibrateRun, LogCalibrateSummary,
    LogCalibrateTimings, SplitSizes, TestErrors,
};
use test_block::{TestMaps, TestModels, mean_errors, test_csv, test_errors, write_figures};

/// Learns the calibration from the recording into `folder`: `calibration.json`, `labels.csv`
/// (every record: line, time, status, fit RMS, label), `test.csv` (each test record's errors),
/// and the figures `label_fit` and `test_errors`. Returns the summary and timings for the
/// caller to write.
///
/// # Errors
/// Bad input for bad settings, an unreadable log, a log without markers or raw readings, too
/// few labels for the split; no answer when training fails.
pub fn run(
    params: &LogCalibrateParams,
    folder: &ResultsFolder,
    progress: Progress<'_>,
) -> Result<LogCalibrateRun, LabError> {
    params.check()?;
    let (records, lines) = read(&params.log)?;
    let (records, pooling) = rests::pool(&records, params.rest_tolerance);
    let label_model = params.model()?;
    let mounting = params
        .mounting
        .mounting()
        .map_err(|e| LabError::bad_input(format!("--mounting: {e}")))?;
    progress(&format!(
        "labelling {} records ({} rests) by shape fitting on {}",
        records.len(),
        pooling.rests,
        params.wire.name
    ));
    let start = Instant::now();
    let (labelled, mut labels, csv) =
        label_all(params, &label_model, (&records, &lines), progress)?;
    labels.rests = pooling.rests;
    labels.pooled_records = pooling.pooled_records;
    let label_s = start.elapsed().as_secs_f64();
    folder.write("labels.csv", csv)?;
    let start = Instant::now();
    let training = Training::new(params, &labelled)?;
    let label_map = training.label_map(params)?;
    let train_s = start.elapsed().as_secs_f64();
    let start = Instant::now();
    let (calibration, affine, fit) = training.fit(params, &label_model, &label_map, progress)?;
    let fit_s = start.elapsed().as_secs_f64();
    let models = TestModels {
        labels: &label_model,
        fitted: &params.model_under(fit.gravity_in_clamp)?,
    };
    let maps = TestMaps {
        mounting: &mounting,
        calibration: &calibration,
        affine: affine.as_ref(),
        label_map: &label_map,
    };
    let test_rows = test_errors(&models, &maps, &labelled, &training.split.test)?;
    let test = mean_errors(&test_rows);
    if test.worse_than_raw {
        progress(&format!(
            "warning: the calibration is worse on the test block ({:.2} mm at the inner \
             markers) than the reading through the mounting alone ({:.2} mm): check the \
             recording (time order, units, markers' order) and the settings",
            test.calibrated_marker_mean_mm, test.raw_marker_mean_mm
        ));
    }
    folder.write("test.csv", test_csv(&test_rows)?)?;
    let json = calibration
        .to_json()
        .map_err(|e| from_estimate(e, "writing the calibration weights"))?;
    folder.write("calibration.json", json)?;
    write_figures(folder, &labelled, &test_rows)?;
    let drift = calibration.drift().map(|d: &Drift| DriftOut {
        reference_time: d.reference_time,
        rate: d.rate.into(),
    });
    Ok(LogCalibrateRun {
        calibration,
        summary: LogCalibrateSummary {
            wire: params.wire.clone(),
            labels,
            split: SplitSizes {
                train: training.split.train.len(),
                validation: training.split.validation.len(),
                test: training.split.test.len(),
            },
            test,
            drift,
            fit,
        },
        timings: LogCalibrateTimings {
            label_s,
            train_s,
            fit_s,
        },
    })
}
