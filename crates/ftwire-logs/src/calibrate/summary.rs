//! What `calibrate --log` reports: `summary.json`'s parts (the labels' counts, the split,
//! the test block's errors, the drift term, how the map was fitted and chosen), the timings
//! and the finished run. Plain data, filled in by the steps that compute it.

use ftwire_estimate::calibration::Calibration;
use ftwire_estimate::calibration::shape_loss::{Candidate, GravityStart};
use serde::Serialize;

use ftwire_app::config::wire::WireSpec;

use super::params::MapLoss;

/// Records by what became of them.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct Labels {
    /// Records in the log.
    pub records: usize,
    /// Records labelled (kept for training and testing).
    pub fitted: usize,
    /// Records rejected (the sum of the reasons below).
    pub rejected: usize,
    /// Mean RMS marker residual of the kept labels' fits \[mm\].
    pub marker_rms_mm: f64,
    /// Rejected: no `raw` reading.
    pub no_raw: usize,
    /// Rejected: a reading far outside the session's (`labelling::OUTLIER_SCALES` robust
    /// standard deviations from its median in some channel).
    pub outlier_readings: usize,
    /// Rejected: fewer than [`MIN_MARKERS`](super::MIN_MARKERS) markers.
    pub few_markers: usize,
    /// Rejected: the fit failed.
    pub fit_failed: usize,
    /// Rejected: the fit's RMS marker residual was above the limit.
    pub off_markers: usize,
    /// Rests found (consecutive records whose markers moved less than the rest tolerance).
    pub rests: usize,
    /// Records that shared their rest with another and were labelled on its mean markers.
    pub pooled_records: usize,
}

/// The split sizes (blocks of time).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SplitSizes {
    /// Training records (the first block).
    pub train: usize,
    /// Validation records (the next block).
    pub validation: usize,
    /// Test records (the last block).
    pub test: usize,
}

/// The test block's errors \[mm\]: each inner marker's distance to the shape, averaged
/// (`*_marker_mean_mm`, the paper's metric), and the mean distance along the wire to the
/// label's shape at equal arc lengths (`*_wire_mean_mm`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TestErrors {
    /// The reading through the mounting alone, as the model would take it uncalibrated.
    pub raw_marker_mean_mm: f64,
    /// The reading through the learnt calibration.
    pub calibrated_marker_mean_mm: f64,
    /// The labels' own shapes: the floor any calibration can reach against these markers.
    pub label_marker_mean_mm: f64,
    /// The affine part alone, fitted on the shape (with `--loss shape`).
    pub affine_marker_mean_mm: Option<f64>,
    /// The map fitted to the labels in `a` (the affine map and the network, §IV-A).
    pub label_map_marker_mean_mm: f64,
    /// Along the wire, the reading through the mounting alone.
    pub raw_wire_mean_mm: f64,
    /// Along the wire, the learnt calibration.
    pub calibrated_wire_mean_mm: f64,
    /// Along the wire, the affine part alone (with `--loss shape`).
    pub affine_wire_mean_mm: Option<f64>,
    /// Along the wire, the map fitted to the labels.
    pub label_map_wire_mean_mm: f64,
    /// The calibration is worse on the test block than the reading through the mounting
    /// alone: something is wrong with the recording or the settings (also said on stderr).
    pub worse_than_raw: bool,
}

/// How the map was fitted and chosen (`summary.json`'s `fit`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FitOut {
    /// `shape` (the markers' distance to the shape, Huber's loss) or `labels`.
    pub loss: MapLoss,
    /// The chosen map: `affine`, `affine+quadratic`, `affine+cubic` or `affine+network`.
    pub map: String,
    /// What chose it: `validation_marker_mean` (the candidate whose validation records'
    /// markers lie closest to their shapes) or `validation_loss` (early stopping in `a`).
    pub chosen_by: String,
    /// Gravity in the clamp frame of the model the map was fitted with \[m/s²\] (fitted with
    /// `--fit-gravity`); `None`: weight-free.
    pub gravity_in_clamp: Option<[f64; 3]>,
    /// The chosen polynomial degree (1: affine) and ridge (with `--loss shape`).
    pub degree: Option<usize>,
    /// The chosen ridge weight, relative (with `--loss shape`).
    pub ridge: Option<f64>,
    /// The chosen map's validation mean marker distance \[mm\] (with `--loss shape`).
    pub validation_marker_mean_mm: Option<f64>,
    /// Huber's threshold \[mm\] (with `--loss shape`).
    pub huber_mm: Option<f64>,
    /// Every candidate fitted on the shape, the affine map first (with `--loss shape`).
    pub candidates: Vec<CandidateOut>,
    /// The validation mean marker distance \[mm\] of the map fitted on the labels, the
    /// last candidate (with `--loss shape`): kept when it is the closest.
    pub label_map_validation_marker_mean_mm: Option<f64>,
    /// Gravity's starts and where the affine fit took each (with `--fit-gravity` and no
    /// `--gravity-in-clamp`): a well-determined direction ends the same from each.
    pub gravity_starts: Vec<GravityStart>,
    /// Training records left out because their start shape could not be solved.
    pub train_failures: usize,
}

/// One candidate map of the shape fit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CandidateOut {
    /// Polynomial degree (1: affine).
    pub degree: usize,
    /// Relative ridge weight of the polynomial part.
    pub ridge: f64,
    /// Gauss–Newton iterations.
    pub iterations: usize,
    /// Training records' mean marker distance \[mm\].
    pub train_marker_mean_mm: f64,
    /// Validation records' mean marker distance \[mm\].
    pub validation_marker_mean_mm: f64,
    /// Validation records whose shape could not be solved.
    pub validation_failures: usize,
    /// Gravity in the clamp frame it ended with \[m/s²\].
    pub gravity_in_clamp: Option<[f64; 3]>,
}

impl From<&Candidate> for CandidateOut {
    fn from(c: &Candidate) -> Self {
        Self {
            degree: c.degree,
            ridge: c.ridge,
            iterations: c.iterations,
            train_marker_mean_mm: 1e3 * c.train_marker_mean,
            validation_marker_mean_mm: 1e3 * c.validation_marker_mean,
            validation_failures: c.validation_failures,
            gravity_in_clamp: c.gravity_in_clamp,
        }
    }
}

/// `summary.json` of `calibrate --log`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LogCalibrateSummary {
    /// The known wire.
    pub wire: WireSpec,
    /// The labels.
    pub labels: Labels,
    /// The split.
    pub split: SplitSizes,
    /// The test block's errors.
    pub test: TestErrors,
    /// The drift term, when the validation block chose one.
    pub drift: Option<DriftOut>,
    /// How the map was fitted and chosen.
    pub fit: FitOut,
}

/// The drift term of the map.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct DriftOut {
    /// The time the map is exact at \[s\] (the last training record's).
    pub reference_time: f64,
    /// The drift of `a` per second, torque first \[N·m/s, N/s\].
    pub rate: [f64; 6],
}

/// Wall-clock times \[s\].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LogCalibrateTimings {
    /// Fitting the labels.
    pub label_s: f64,
    /// Training the network on the labels.
    pub train_s: f64,
    /// Fitting the map on the shape (zero with `--loss labels`).
    pub fit_s: f64,
}

/// A finished `calibrate --log`.
#[derive(Debug, Clone)]
pub struct LogCalibrateRun {
    /// The learnt calibration (also written as `calibration.json`).
    pub calibration: Calibration,
    /// `summary.json`'s body.
    pub summary: LogCalibrateSummary,
    /// `timings.json`.
    pub timings: LogCalibrateTimings,
}
