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
//! Guarded by `tests/log_calibrate.rs` (a simulated recording of the `distorted` and
//! `real-like` sensors, bad logs).

use std::path::PathBuf;
use std::time::Instant;

use ftwire_estimate::calibration::shape_loss::{
    Candidate, GravityFit, GravityStart, ShapeLossParams, ShapeSample, fit_on_shape, marker_mean,
};
use ftwire_estimate::calibration::{
    Calibration, CalibrationInput, Dataset, Drift, LabelModel, SplitOrder, TrainParams,
};
use ftwire_estimate::ft::{Mounting, MountingSpec};
use ftwire_estimate::log::LogRecord;
use ftwire_estimate::shape::{
    Correspondence, FitParams, Markers, ShapeFitter, centreline_distance, evenly_spaced_fractions,
    marker_distances,
};
use ftwire_estimate::{KirchhoffModel, WireModel};
use ftwire_report::{LineChart, Series};
use nalgebra::{Point3, Vector3, Vector6};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::Serialize;

use ftwire_app::Progress;
use ftwire_app::config::wire::WireSpec;
use ftwire_app::csv_table::{CsvTable, text, value};
use ftwire_app::error::{LabError, from_estimate};
use ftwire_app::results::ResultsFolder;

mod drift;
mod labelled;
mod rests;

pub use drift::DRIFT_T_STATISTIC;
use drift::choose_drift;
use labelled::Labelled;
pub use rests::Pooling;

/// Fewest markers a record needs for a label: the fit has six unknowns and three numbers per
/// marker, and the clamp's marker says nothing.
pub const MIN_MARKERS: usize = 4;

/// Default largest RMS marker residual of a label's fit \[m\]: a few times the about 1 mm of a
/// real rig's markers against its own fitted wire.
pub const DEFAULT_MAX_LABEL_RMS: f64 = 3e-3;

/// Nodes of the shapes compared with the markers.
const SHAPE_NODES: usize = 101;

/// Records between two progress lines.
const PROGRESS_EVERY: usize = 100;

/// The training settings for a recording: a small network (a few hundred records), the split
/// by blocks of time, patience for a small validation block.
pub fn default_train_params() -> TrainParams {
    let mut train = TrainParams {
        hidden: vec![16, 16],
        patience: 200,
        ..TrainParams::default()
    };
    train.split.order = SplitOrder::Time;
    train
}

/// The settings of `calibrate --log`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LogCalibrateParams {
    /// The recording.
    pub log: PathBuf,
    /// The known wire of the recording.
    pub wire: WireSpec,
    /// The sensor's mounting (and tool).
    pub mounting: MountingSpec,
    /// Gravity in the base clamp frame \[m/s²\] for the loaded model; `None`: the paper's
    /// weight-free model.
    pub gravity: Option<[f64; 3]>,
    /// The markers' arc lengths as fractions of the wire's length, in the log's order; `None`:
    /// matched at their closest points.
    pub marker_fractions: Option<Vec<f64>>,
    /// Largest RMS marker residual of a kept label \[m\].
    pub max_label_rms: f64,
    /// How the network is trained (the split is by blocks of time unless set otherwise).
    pub train: TrainParams,
    /// Offer the map a drift term (an offset linear in time, fitted on the training block);
    /// it is kept only when it predicts the validation block better.
    pub drift: bool,
    /// Seed of the fits' global search and of the network's initial weights.
    pub seed: u64,
    /// What the map is fitted on.
    pub loss: MapLoss,
    /// Fit gravity's direction in the clamp frame with the map, of this norm \[m/s²\]
    /// (`--fit-gravity`, `--gravity-norm`); `gravity`, when given, is where it starts. Only
    /// with [`MapLoss::Shape`].
    pub fit_gravity: Option<f64>,
    /// Consecutive records whose markers moved less than this \[m\] are one rest, and their
    /// labels are fitted to the rest's mean markers; zero: every record alone.
    pub rest_tolerance: f64,
    /// The shape fit's candidate maps and iterations (with [`MapLoss::Shape`]).
    pub shape: ShapeLossParams,
}

/// What `calibrate --log` fits the map on (`--loss`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum MapLoss {
    /// The markers' distance to the model's shape of the map's `a` (Huber's loss), through
    /// the model's Jacobian; the labels start it and keep a weak pull
    /// (`ftwire_estimate::calibration::shape_loss`); the map fitted on the labels is one more
    /// candidate.
    #[default]
    Shape,
    /// The labels in `a` (least squares, the affine map and the network): the paper's §IV-A.
    Labels,
}

impl MapLoss {
    /// The names `--loss` takes.
    pub const NAMES: [&'static str; 2] = ["shape", "labels"];

    /// The loss of a name of [`Self::NAMES`].
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "shape" => Some(Self::Shape),
            "labels" => Some(Self::Labels),
            _ => None,
        }
    }
}

/// Default rest tolerance \[m\]: a few times a motion-capture system's jitter, well below
/// a rig's steps between rests (about 17 mm).
pub const DEFAULT_REST_TOLERANCE: f64 = 2e-3;

/// Default `|g|` of `--fit-gravity` \[m/s²\].
pub const STANDARD_GRAVITY: f64 = 9.81;

impl LogCalibrateParams {
    /// Checks the settings before any work.
    ///
    /// # Errors
    /// Bad input naming the value.
    pub fn check(&self) -> Result<(), LabError> {
        self.mounting
            .validate()
            .map_err(|e| LabError::bad_input(format!("--mounting: {e}")))?;
        self.wire
            .wire_params()
            .map_err(|e| LabError::bad_input(format!("--wire {}: {e}", self.wire.name)))?;
        if !(self.max_label_rms.is_finite() && self.max_label_rms > 0.0) {
            return Err(LabError::bad_input(format!(
                "--max-label-rms-mm {}: must be a finite distance > 0",
                1e3 * self.max_label_rms
            )));
        }
        if let Some(g) = &self.gravity
            && g.iter().any(|v| !v.is_finite())
        {
            return Err(LabError::bad_input(format!(
                "gravity {g:?}: every component must be finite"
            )));
        }
        if let Some(norm) = self.fit_gravity
            && !(norm.is_finite() && norm > 0.0 && norm <= LabelModel::MAX_GRAVITY)
        {
            return Err(LabError::bad_input(format!(
                "--gravity-norm {norm}: must be a finite acceleration in (0, 100] m/s²"
            )));
        }
        if self.fit_gravity.is_some() && self.loss == MapLoss::Labels {
            return Err(LabError::bad_input(
                "--fit-gravity fits gravity with the map on the shape: it needs --loss shape"
                    .to_owned(),
            ));
        }
        if !(self.rest_tolerance.is_finite() && self.rest_tolerance >= 0.0) {
            return Err(LabError::bad_input(format!(
                "--rest-tolerance-mm {}: must be a finite distance ≥ 0 (0: no pooling)",
                1e3 * self.rest_tolerance
            )));
        }
        if let Some(fractions) = &self.marker_fractions
            && let Some(bad) = fractions
                .iter()
                .find(|f| !(f.is_finite() && (0.0..=1.0).contains(*f)))
        {
            return Err(LabError::bad_input(format!(
                "--marker-fractions: {bad} is not a fraction of the length in [0, 1]"
            )));
        }
        Ok(())
    }

    /// The model the labels are solved with.
    fn model(&self) -> Result<KirchhoffModel, LabError> {
        self.model_under(self.gravity)
    }

    /// The model under `gravity` in the clamp frame (`None`: weight-free).
    fn model_under(&self, gravity: Option<[f64; 3]>) -> Result<KirchhoffModel, LabError> {
        crate::shape::wire_model(&self.wire, gravity)
    }
}

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
    /// Rejected: fewer than [`MIN_MARKERS`] markers.
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

/// A polynomial degree's name in `fit.map`.
fn map_name(degree: usize) -> &'static str {
    match degree {
        1 => "affine",
        2 => "affine+quadratic",
        _ => "affine+cubic",
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
    let drift = if params.drift {
        choose_drift(&labelled, &params.train)
    } else {
        None
    };
    let offset = |l: &Labelled| drift.as_ref().map_or(Vector6::zeros(), |d| d.at(l.time));
    let data = Dataset::new(
        labelled.iter().map(|l| l.raw).collect(),
        labelled.iter().map(|l| l.label - offset(l)).collect(),
    )
    .map_err(|e| from_estimate(e, "the labelled records"))?;
    let split = data
        .split(
            &params.train.split,
            &mut ChaCha8Rng::seed_from_u64(params.seed),
        )
        .map_err(|e| {
            LabError::bad_input(format!(
                "training on {} labelled records of {}: {e}",
                labelled.len(),
                params.log.display()
            ))
        })?;
    // The labels' model, and the input: the log's readings as they were, never tared.
    let given_model = params
        .gravity
        .map_or(Ok(LabelModel::WEIGHTLESS), LabelModel::loaded)
        .map_err(|e| LabError::bad_input(format!("--gravity-in-clamp: {e}")))?;
    let finish = |c: Calibration, model: LabelModel| {
        let c = match drift {
            Some(d) => c
                .with_drift(d)
                .map_err(|e| from_estimate(e, "the drift term"))?,
            None => c,
        };
        c.with_provenance(model, CalibrationInput::Raw)
            .map_err(|e| from_estimate(e, "the calibration's model"))
    };
    let label_map = Calibration::train(&data, &params.train, params.seed).map_err(|e| {
        LabError::bad_input(format!(
            "training on {} labelled records of {}: {e}",
            labelled.len(),
            params.log.display()
        ))
    })?;
    let label_map = finish(label_map, given_model)?;
    let train_s = start.elapsed().as_secs_f64();
    let start = Instant::now();
    let (calibration, affine, fit) = match params.loss {
        MapLoss::Labels => {
            let fit = FitOut {
                loss: MapLoss::Labels,
                map: if params.train.hidden.is_empty() {
                    "affine".to_owned()
                } else {
                    "affine+network".to_owned()
                },
                chosen_by: "validation_loss".to_owned(),
                gravity_in_clamp: params.gravity,
                degree: None,
                ridge: None,
                validation_marker_mean_mm: None,
                huber_mm: None,
                candidates: Vec::new(),
                label_map_validation_marker_mean_mm: None,
                gravity_starts: Vec::new(),
                train_failures: 0,
            };
            (label_map.clone(), None, fit)
        }
        MapLoss::Shape => {
            progress(&format!(
                "fitting the map on the shape: {} training and {} validation records",
                split.train.len(),
                split.validation.len()
            ));
            let samples = |indices: &[usize]| -> Vec<ShapeSample> {
                indices
                    .iter()
                    .filter_map(|&i| labelled.get(i))
                    .map(|l| ShapeSample {
                        raw: l.raw,
                        offset: offset(l),
                        markers: l.loss_markers.clone(),
                        fractions: l.loss_fractions.clone(),
                    })
                    .collect()
            };
            let train_labels: Vec<Vector6<f64>> = split
                .train
                .iter()
                .filter_map(|&i| data.labels().get(i).copied())
                .collect();
            let mut shape = params.shape.clone();
            shape.gravity = params.fit_gravity.map(|norm| GravityFit {
                mass_per_length: params.wire.density
                    * std::f64::consts::PI
                    * params.wire.radius.powi(2),
                norm,
                start: params.gravity,
            });
            let fitted = fit_on_shape(
                &label_model,
                &samples(&split.train),
                &train_labels,
                &samples(&split.validation),
                &shape,
            )
            .map_err(|e| from_estimate(e, "fitting the map on the shape"))?;
            let gravity = fitted.gravity_in_clamp.or(params.gravity);
            let model = gravity
                .map_or(Ok(LabelModel::WEIGHTLESS), LabelModel::loaded)
                .map_err(|e| from_estimate(e, "the fitted gravity"))?;
            let chosen = &fitted.candidates[fitted.chosen];
            // The map fitted on the labels is one more candidate, judged the same way.
            let (label_map_validation, label_map_failures) = marker_mean(
                &label_model,
                &label_map,
                &samples(&split.validation),
                shape.nodes,
            )
            .map_err(|e| from_estimate(e, "judging the map fitted on the labels"))?;
            let shape_wins = (chosen.validation_failures, chosen.validation_marker_mean)
                <= (label_map_failures, label_map_validation);
            let fit = FitOut {
                loss: MapLoss::Shape,
                map: if shape_wins {
                    map_name(chosen.degree).to_owned()
                } else {
                    "affine+network (fitted on the labels)".to_owned()
                },
                chosen_by: "validation_marker_mean".to_owned(),
                gravity_in_clamp: if shape_wins { gravity } else { params.gravity },
                degree: shape_wins.then_some(chosen.degree),
                ridge: shape_wins.then_some(chosen.ridge),
                validation_marker_mean_mm: Some(
                    1e3 * chosen.validation_marker_mean.min(label_map_validation),
                ),
                huber_mm: Some(1e3 * fitted.huber),
                candidates: fitted.candidates.iter().map(CandidateOut::from).collect(),
                label_map_validation_marker_mean_mm: Some(1e3 * label_map_validation),
                gravity_starts: fitted.gravity_starts.clone(),
                train_failures: fitted.train_failures,
            };
            let calibration = if shape_wins {
                finish(fitted.calibration, model)?
            } else {
                label_map.clone()
            };
            (calibration, Some(finish(fitted.affine, model)?), fit)
        }
    };
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
    let test_rows = test_errors(&models, &maps, &labelled, &split.test)?;
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
                train: split.train.len(),
                validation: split.validation.len(),
                test: split.test.len(),
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

/// Reads the log; refuses one without raw readings or markers.
fn read(path: &std::path::Path) -> Result<(Vec<LogRecord>, Vec<usize>), LabError> {
    let (lines, records): (Vec<usize>, Vec<LogRecord>) = super::read_log(path)?
        .into_iter()
        .map(|l| (l.line, l.record))
        .unzip();
    if !records.iter().any(|r| r.raw.is_some()) {
        return Err(LabError::bad_input(format!(
            "--log {}: no record has a raw F/T reading (`raw`): there is nothing to calibrate",
            path.display()
        )));
    }
    if !records.iter().any(|r| r.markers.is_some()) {
        return Err(LabError::bad_input(format!(
            "--log {}: no record has markers (`markers`): the labels come from fitting the \
             wire to them",
            path.display()
        )));
    }
    Ok((records, lines))
}

/// Why a record got no label.
enum Rejection {
    NoRaw,
    FewMarkers,
    FitFailed,
    OffMarkers(f64),
}

/// Labels every record; returns the labelled ones, the counts and `labels.csv`.
fn label_all(
    params: &LogCalibrateParams,
    model: &KirchhoffModel,
    (records, lines): (&[LogRecord], &[usize]),
    progress: Progress<'_>,
) -> Result<(Vec<Labelled>, Labels, Vec<u8>), LabError> {
    let fitter = fitter(model, params.marker_fractions.is_some())?;
    let outcomes = fit_in_parallel(params, &fitter, records, progress)?;
    let mut counts = Labels {
        records: records.len(),
        ..Labels::default()
    };
    let mut csv = CsvTable::new(
        "labels.csv",
        &[
            "line", "time", "status", "rms_mm", "a1", "a2", "a3", "a4", "a5", "a6",
        ],
    )?;
    let mut labelled = Vec::new();
    for ((record, &line), outcome) in records.iter().zip(lines).zip(outcomes) {
        match outcome {
            Ok(l) => {
                let mut cells = vec![value(line), value(record.time), text("fitted")];
                cells.push(value(1e3 * l.rms));
                cells.extend(l.label.iter().map(|&v| value(v)));
                csv.row(cells)?;
                labelled.push(Labelled { line, ..l });
            }
            Err(why) => {
                let (status, rms, count) = match why {
                    Rejection::NoRaw => ("no_raw", None, &mut counts.no_raw),
                    Rejection::FewMarkers => ("few_markers", None, &mut counts.few_markers),
                    Rejection::FitFailed => ("fit_failed", None, &mut counts.fit_failed),
                    Rejection::OffMarkers(rms) => {
                        ("off_markers", Some(rms), &mut counts.off_markers)
                    }
                };
                *count += 1;
                let mut cells = vec![value(line), value(record.time), text(status)];
                cells.push(rms.map_or_else(|| text(""), |r| value(1e3 * r)));
                cells.extend((0..6).map(|_| text("")));
                csv.row(cells)?;
            }
        }
    }
    counts.fitted = labelled.len();
    counts.rejected = counts.records - counts.fitted;
    if labelled.is_empty() {
        return Err(LabError::bad_input(format!(
            "--log {}: every record was rejected ({} without raw, {} with fewer than \
             {MIN_MARKERS} markers, {} fits failed, {} fits more than {:.1} mm RMS off their \
             markers): nothing to learn from",
            params.log.display(),
            counts.no_raw,
            counts.few_markers,
            counts.fit_failed,
            counts.off_markers,
            1e3 * params.max_label_rms
        )));
    }
    #[allow(clippy::cast_precision_loss)] // counts far below 2⁵²
    let n = labelled.len() as f64;
    counts.marker_rms_mm = 1e3 * labelled.iter().map(|l| l.rms).sum::<f64>() / n;
    Ok((labelled, counts, csv.into_bytes()?))
}

/// Every record's label or rejection, fitted on every core: record `k` (0-based) draws from
/// its own generator seeded by `seed` and `k`, so the labels do not depend on the number of
/// threads.
fn fit_in_parallel(
    params: &LogCalibrateParams,
    fitter: &ShapeFitter<KirchhoffModel>,
    records: &[LogRecord],
    progress: Progress<'_>,
) -> Result<Vec<Result<Labelled, Rejection>>, LabError> {
    let threads = std::thread::available_parallelism().map_or(1, std::num::NonZero::get);
    let chunk = records.len().div_ceil(threads).max(1);
    let done = std::sync::atomic::AtomicUsize::new(0);
    let results: Vec<Result<Vec<_>, LabError>> = std::thread::scope(|scope| {
        let handles: Vec<_> = records
            .chunks(chunk)
            .enumerate()
            .map(|(c, part)| {
                let done = &done;
                scope.spawn(move || {
                    part.iter()
                        .enumerate()
                        .map(|(j, record)| {
                            let k = c * chunk + j;
                            let mut rng = ChaCha8Rng::seed_from_u64(
                                params.seed.wrapping_mul(1_000_003).wrapping_add(k as u64),
                            );
                            done.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                            label_one(params, fitter, record, &mut rng)
                        })
                        .collect::<Result<Vec<_>, LabError>>()
                })
            })
            .collect();
        let mut reported = 0;
        while handles.iter().any(|h| !h.is_finished()) {
            std::thread::sleep(std::time::Duration::from_millis(200));
            let now = done.load(std::sync::atomic::Ordering::Relaxed) / PROGRESS_EVERY;
            if now > reported {
                reported = now;
                progress(&format!("  {} / {}", now * PROGRESS_EVERY, records.len()));
            }
        }
        handles
            .into_iter()
            .map(|h| {
                h.join()
                    .unwrap_or_else(|_| Err(LabError::no_answer("a labelling thread panicked")))
            })
            .collect()
    });
    let mut all = Vec::with_capacity(records.len());
    for part in results {
        all.extend(part?);
    }
    Ok(all)
}

/// The shape fitter: at the markers' arc lengths, or at their closest points.
fn fitter(
    model: &KirchhoffModel,
    arc_lengths: bool,
) -> Result<ShapeFitter<KirchhoffModel>, LabError> {
    let config = FitParams {
        correspondence: if arc_lengths {
            Correspondence::ArcLength
        } else {
            Correspondence::ClosestPoint
        },
        ..FitParams::default()
    };
    ShapeFitter::new(*model)
        .with_config(config)
        .map_err(|e| from_estimate(e, "the shape fitter"))
}

/// One record's label, or why it has none.
fn label_one(
    params: &LogCalibrateParams,
    fitter: &ShapeFitter<KirchhoffModel>,
    record: &LogRecord,
    rng: &mut ChaCha8Rng,
) -> Result<Result<Labelled, Rejection>, LabError> {
    let Some(raw) = record.raw() else {
        return Ok(Err(Rejection::NoRaw));
    };
    let gravity = record.gravity.map(Vector3::from);
    let raw = params
        .mounting
        .compensate(&raw, gravity.as_ref())
        .map_err(|e| {
            LabError::bad_input(format!("--log: the record at time {}: {e}", record.time))
        })?;
    let seen: Vec<Option<Point3<f64>>> = record.markers().unwrap_or_default();
    let observed: Vec<Point3<f64>> = seen.iter().flatten().copied().collect();
    // The inner markers, by their place in the list: not the first (at the clamp) nor the
    // last (at the gripper), whether or not those were seen.
    let inner: Vec<Point3<f64>> = seen
        .get(1..seen.len().saturating_sub(1))
        .unwrap_or(&[])
        .iter()
        .flatten()
        .copied()
        .collect();
    if observed.len() < MIN_MARKERS {
        return Ok(Err(Rejection::FewMarkers));
    }
    let fractions = match &params.marker_fractions {
        Some(f) if f.len() == seen.len() => f.clone(),
        Some(f) => {
            return Err(LabError::bad_input(format!(
                "--marker-fractions has {} fractions but the record at time {} has {} markers",
                f.len(),
                record.time,
                seen.len()
            )));
        }
        // Closest-point matching does not use the fractions; any valid ones do.
        None => evenly_spaced_fractions(seen.len()),
    };
    let fit = Markers::new(&fractions, &seen).and_then(|m| fitter.fit(&m, rng));
    let Ok(fit) = fit else {
        return Ok(Err(Rejection::FitFailed));
    };
    if fit.rms.is_nan() || fit.rms > params.max_label_rms {
        return Ok(Err(Rejection::OffMarkers(fit.rms)));
    }
    let (loss_markers, loss_fractions): (Vec<Point3<f64>>, Vec<f64>) = seen
        .iter()
        .zip(&fractions)
        .skip(1)
        .filter_map(|(p, f)| p.map(|p| (p, *f)))
        .unzip();
    Ok(Ok(Labelled {
        line: 0,
        time: record.time,
        raw,
        label: fit.a,
        rms: fit.rms,
        inner,
        loss_markers,
        loss_fractions: params.marker_fractions.is_some().then_some(loss_fractions),
    }))
}

/// One test record's errors \[m\]: at the inner markers, and along the wire against the
/// label's shape.
struct TestRow {
    line: usize,
    time: f64,
    raw: [f64; 2],
    calibrated: [f64; 2],
    affine: Option<[f64; 2]>,
    label_map: [f64; 2],
    label: f64,
}

/// The models of the test: the labels' and the one the map was fitted with (the loaded
/// model under a fitted gravity).
struct TestModels<'a> {
    labels: &'a KirchhoffModel,
    fitted: &'a KirchhoffModel,
}

/// The maps compared on the test block.
struct TestMaps<'a> {
    mounting: &'a Mounting,
    calibration: &'a Calibration,
    affine: Option<&'a Calibration>,
    label_map: &'a Calibration,
}

/// The mean distance of the inner markers to `Φ(a)`, and the mean distance along the wire
/// from `Φ(a)` to the label's shape \[m\].
fn distances(
    model: &KirchhoffModel,
    a: &Vector6<f64>,
    l: &Labelled,
    label_shape: &[Vector3<f64>],
) -> Result<[f64; 2], LabError> {
    let shape = model
        .shape(a, SHAPE_NODES)
        .map_err(|e| from_estimate(e, "the shape of a test record"))?;
    let d = marker_distances(&l.inner, &shape.positions)
        .map_err(|e| from_estimate(e, "the marker distances"))?;
    #[allow(clippy::cast_precision_loss)] // a handful of markers
    let markers = d.iter().sum::<f64>() / d.len().max(1) as f64;
    let wire = centreline_distance(&shape.positions, label_shape, SHAPE_NODES)
        .map_err(|e| from_estimate(e, "the distance along the wire"))?;
    Ok([markers, wire])
}

/// The test block's errors, record by record.
fn test_errors(
    models: &TestModels<'_>,
    maps: &TestMaps<'_>,
    labelled: &[Labelled],
    test: &[usize],
) -> Result<Vec<TestRow>, LabError> {
    test.iter()
        .filter_map(|&i| labelled.get(i))
        .map(|l| {
            let label_shape = models
                .labels
                .shape(&l.label, SHAPE_NODES)
                .map_err(|e| from_estimate(e, "the shape of a label"))?
                .positions;
            let fitted = |a: &Vector6<f64>| distances(models.fitted, a, l, &label_shape);
            Ok(TestRow {
                line: l.line,
                time: l.time,
                raw: fitted(&maps.mounting.to_configuration(&l.raw))?,
                calibrated: fitted(&maps.calibration.apply_at(&l.raw, l.time))?,
                affine: maps
                    .affine
                    .map(|c| fitted(&c.apply_at(&l.raw, l.time)))
                    .transpose()?,
                label_map: distances(
                    models.labels,
                    &maps.label_map.apply_at(&l.raw, l.time),
                    l,
                    &label_shape,
                )?,
                label: distances(models.labels, &l.label, l, &label_shape)?[0],
            })
        })
        .collect()
}

/// The test block's means \[mm\] (zero for an empty block).
fn mean_errors(rows: &[TestRow]) -> TestErrors {
    #[allow(clippy::cast_precision_loss)] // counts far below 2⁵²
    let n = rows.len().max(1) as f64;
    let mean = |f: &dyn Fn(&TestRow) -> f64| 1e3 * rows.iter().map(f).sum::<f64>() / n;
    let affine = |k: usize| {
        rows.iter()
            .all(|r| r.affine.is_some())
            .then(|| mean(&|r| r.affine.map_or(0.0, |a| a[k])))
            .filter(|_| !rows.is_empty())
    };
    let raw = mean(&|r| r.raw[0]);
    let calibrated = mean(&|r| r.calibrated[0]);
    TestErrors {
        raw_marker_mean_mm: raw,
        calibrated_marker_mean_mm: calibrated,
        label_marker_mean_mm: mean(&|r| r.label),
        affine_marker_mean_mm: affine(0),
        label_map_marker_mean_mm: mean(&|r| r.label_map[0]),
        raw_wire_mean_mm: mean(&|r| r.raw[1]),
        calibrated_wire_mean_mm: mean(&|r| r.calibrated[1]),
        affine_wire_mean_mm: affine(1),
        label_map_wire_mean_mm: mean(&|r| r.label_map[1]),
        worse_than_raw: calibrated > raw,
    }
}

/// `test.csv`.
fn test_csv(rows: &[TestRow]) -> Result<Vec<u8>, LabError> {
    let mut csv = CsvTable::new(
        "test.csv",
        &[
            "line",
            "time",
            "raw_mm",
            "calibrated_mm",
            "label_mm",
            "affine_mm",
            "label_map_mm",
            "raw_wire_mm",
            "calibrated_wire_mm",
            "affine_wire_mm",
            "label_map_wire_mm",
        ],
    )?;
    let mm = |v: f64| value(1e3 * v);
    let opt = |v: Option<f64>| v.map_or_else(|| text(""), mm);
    for r in rows {
        csv.row(vec![
            value(r.line),
            value(r.time),
            mm(r.raw[0]),
            mm(r.calibrated[0]),
            mm(r.label),
            opt(r.affine.map(|a| a[0])),
            mm(r.label_map[0]),
            mm(r.raw[1]),
            mm(r.calibrated[1]),
            opt(r.affine.map(|a| a[1])),
            mm(r.label_map[1]),
        ])?;
    }
    csv.into_bytes()
}

/// `label_fit` (each label's RMS marker residual over time) and `test_errors` (the test
/// block's marker errors over time, uncalibrated and calibrated).
fn write_figures(
    folder: &ResultsFolder,
    labelled: &[Labelled],
    rows: &[TestRow],
) -> Result<(), LabError> {
    let fits = LineChart::new(
        "labels: RMS marker residual of each record's shape fit",
        "time [s]",
        "RMS marker residual [mm]",
    )
    .with_series(Series::points(
        "kept labels",
        labelled.iter().map(|l| (l.time, 1e3 * l.rms)).collect(),
    ));
    folder.write_figure("label_fit", |dir| fits.write(dir, "label_fit"))?;
    let errors = LineChart::new(
        "test block: mean inner-marker distance to the shape from F/T",
        "time [s]",
        "mean marker distance [mm]",
    )
    .with_log_y()
    .with_series(Series::points(
        "mounting only",
        rows.iter().map(|r| (r.time, 1e3 * r.raw[0])).collect(),
    ))
    .with_series(Series::points(
        "calibrated",
        rows.iter()
            .map(|r| (r.time, 1e3 * r.calibrated[0]))
            .collect(),
    ))
    .with_series(Series::points(
        "label (floor)",
        rows.iter().map(|r| (r.time, 1e3 * r.label)).collect(),
    ));
    folder.write_figure("test_errors", |dir| errors.write(dir, "test_errors"))
}
