//! `ftwire calibrate --log`: the paper's §IV-A calibration learnt from a rig's own recording.
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
//!    when not. A record without `raw`, with fewer than [`MIN_MARKERS`] markers, whose fit
//!    fails, or whose fit leaves the markers more than `max_label_rms` off (RMS) is rejected
//!    and counted by reason: a marker swap or a dropout burst must not teach the network.
//! 3. **Split by blocks of time** (`SplitOrder::Time`): the first 70 % of the labelled
//!    records train, the next 15 % validate (early stopping), the last 15 % test. A real
//!    sensor drifts, and a random split would put neighbours in time on both sides and hide it.
//! 4. **The map**: `Calibration::train` (a least-squares affine map from the reading to the
//!    label, which holds the mounting's lever arm and rotation, the gain, cross-talk and the
//!    offsets, plus a small network on what it leaves, starting at zero and stopped early on
//!    the validation block), in the format every `--calibration` loads.
//! 5. **Test**: on the test block, each inner marker's distance to `Φ(ã)` (the paper's
//!    metric, Fig. 5; the first marker is at the clamp and the last at the gripper, so they
//!    say nothing), for the reading through the mounting alone and through the calibration.
//!
//! Guarded by `tests/log_calibrate.rs` (a simulated recording of the `distorted` and
//! `real-like` sensors, bad logs).

use std::path::PathBuf;
use std::time::Instant;

use ftwire_estimate::calibration::{
    Calibration, CalibrationInput, Dataset, LabelModel, SplitOrder, TrainParams,
};
use ftwire_estimate::ft::{Mounting, MountingSpec};
use ftwire_estimate::log::LogRecord;
use ftwire_estimate::shape::{
    Correspondence, FitParams, Markers, ShapeFitter, evenly_spaced_fractions, marker_distances,
};
use ftwire_estimate::{KirchhoffModel, WireModel};
use ftwire_report::{LineChart, Series};
use nalgebra::{Point3, Vector3, Vector6};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::Serialize;

use crate::csv_table::{CsvTable, text, value};
use crate::error::{LabError, from_estimate};
use crate::experiment::{ModelKind, Progress, known_model_under};
use crate::results::ResultsFolder;
use crate::wire::WireSpec;

mod drift;
mod labelled;

pub use drift::DRIFT_T_STATISTIC;
use drift::choose_drift;
use labelled::Labelled;

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
}

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

    /// The model the labels and the test shapes are solved with.
    fn model(&self) -> Result<KirchhoffModel, LabError> {
        match self.gravity {
            None => known_model_under(&self.wire, Vector3::zeros(), ModelKind::Weightless),
            Some(g) => known_model_under(&self.wire, Vector3::from(g), ModelKind::Loaded),
        }
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

/// The test block's errors \[mm\]: each inner marker's distance to the shape, averaged.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TestErrors {
    /// The reading through the mounting alone, as the model would take it uncalibrated.
    pub raw_marker_mean_mm: f64,
    /// The reading through the learnt calibration.
    pub calibrated_marker_mean_mm: f64,
    /// The labels' own shapes: the floor any calibration can reach against these markers.
    pub label_marker_mean_mm: f64,
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
    /// Training the network.
    pub train_s: f64,
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
    let model = params.model()?;
    let mounting = params
        .mounting
        .mounting()
        .map_err(|e| LabError::bad_input(format!("--mounting: {e}")))?;
    progress(&format!(
        "labelling {} records by shape fitting on {}",
        records.len(),
        params.wire.name
    ));
    let start = Instant::now();
    let (labelled, labels, csv) = label_all(params, &model, (&records, &lines), progress)?;
    let label_s = start.elapsed().as_secs_f64();
    folder.write("labels.csv", csv)?;
    let start = Instant::now();
    let drift = if params.drift {
        choose_drift(&labelled, &params.train)
    } else {
        None
    };
    let at_reference = |l: &Labelled| match &drift {
        Some(d) => l.label - d.rate * (l.time - d.reference_time),
        None => l.label,
    };
    let data = Dataset::new(
        labelled.iter().map(|l| l.raw).collect(),
        labelled.iter().map(at_reference).collect(),
    )
    .map_err(|e| from_estimate(e, "the labelled records"))?;
    let mut calibration = Calibration::train(&data, &params.train, params.seed).map_err(|e| {
        LabError::bad_input(format!(
            "training on {} labelled records of {}: {e}",
            labelled.len(),
            params.log.display()
        ))
    })?;
    if let Some(d) = drift {
        calibration = calibration
            .with_drift(d)
            .map_err(|e| from_estimate(e, "the drift term"))?;
    }
    // The labels' model, and the input: the log's readings as they were, never tared.
    let label_model = params
        .gravity
        .map_or(Ok(LabelModel::WEIGHTLESS), LabelModel::loaded)
        .map_err(|e| LabError::bad_input(format!("--gravity-in-clamp: {e}")))?;
    calibration = calibration
        .with_provenance(label_model, CalibrationInput::Raw)
        .map_err(|e| from_estimate(e, "the calibration's model"))?;
    let train_s = start.elapsed().as_secs_f64();
    let split = data
        .split(
            &params.train.split,
            &mut ChaCha8Rng::seed_from_u64(params.seed),
        )
        .map_err(|e| from_estimate(e, "the split"))?;
    let test_rows = test_errors(&model, &mounting, &calibration, &labelled, &split.test)?;
    let test = mean_errors(&test_rows);
    folder.write("test.csv", test_csv(&test_rows)?)?;
    let json = calibration
        .to_json()
        .map_err(|e| from_estimate(e, "writing the calibration weights"))?;
    folder.write("calibration.json", json)?;
    write_figures(folder, &labelled, &test_rows)?;
    let drift = calibration.drift().map(|d| DriftOut {
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
        },
        timings: LogCalibrateTimings { label_s, train_s },
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
    Ok(Ok(Labelled {
        line: 0,
        time: record.time,
        raw,
        label: fit.a,
        rms: fit.rms,
        inner,
    }))
}

/// One test record's errors \[m\].
struct TestRow {
    line: usize,
    time: f64,
    raw: f64,
    calibrated: f64,
    label: f64,
}

/// The mean distance of the inner markers to `Φ(a)` \[m\].
fn inner_marker_mean(
    model: &KirchhoffModel,
    a: &Vector6<f64>,
    markers: &[Point3<f64>],
) -> Result<f64, LabError> {
    let shape = model
        .shape(a, SHAPE_NODES)
        .map_err(|e| from_estimate(e, "the shape of a test record"))?;
    let inner = markers
        .get(1..markers.len().saturating_sub(1))
        .unwrap_or(&[]);
    let d = marker_distances(inner, &shape.positions)
        .map_err(|e| from_estimate(e, "the marker distances"))?;
    #[allow(clippy::cast_precision_loss)] // a handful of markers
    Ok(d.iter().sum::<f64>() / d.len().max(1) as f64)
}

/// The test block's errors, record by record.
fn test_errors(
    model: &KirchhoffModel,
    mounting: &Mounting,
    calibration: &Calibration,
    labelled: &[Labelled],
    test: &[usize],
) -> Result<Vec<TestRow>, LabError> {
    test.iter()
        .filter_map(|&i| labelled.get(i))
        .map(|l| {
            Ok(TestRow {
                line: l.line,
                time: l.time,
                raw: inner_marker_mean(model, &mounting.to_configuration(&l.raw), &l.inner)?,
                calibrated: inner_marker_mean(
                    model,
                    &calibration.apply_at(&l.raw, l.time),
                    &l.inner,
                )?,
                label: inner_marker_mean(model, &l.label, &l.inner)?,
            })
        })
        .collect()
}

/// The test block's means \[mm\] (zero for an empty block).
fn mean_errors(rows: &[TestRow]) -> TestErrors {
    #[allow(clippy::cast_precision_loss)] // counts far below 2⁵²
    let n = rows.len().max(1) as f64;
    let mean = |f: fn(&TestRow) -> f64| 1e3 * rows.iter().map(f).sum::<f64>() / n;
    TestErrors {
        raw_marker_mean_mm: mean(|r| r.raw),
        calibrated_marker_mean_mm: mean(|r| r.calibrated),
        label_marker_mean_mm: mean(|r| r.label),
    }
}

/// `test.csv`.
fn test_csv(rows: &[TestRow]) -> Result<Vec<u8>, LabError> {
    let mut csv = CsvTable::new(
        "test.csv",
        &["line", "time", "raw_mm", "calibrated_mm", "label_mm"],
    )?;
    for r in rows {
        csv.row(vec![
            value(r.line),
            value(r.time),
            value(1e3 * r.raw),
            value(1e3 * r.calibrated),
            value(1e3 * r.label),
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
        rows.iter().map(|r| (r.time, 1e3 * r.raw)).collect(),
    ))
    .with_series(Series::points(
        "calibrated",
        rows.iter().map(|r| (r.time, 1e3 * r.calibrated)).collect(),
    ))
    .with_series(Series::points(
        "label (floor)",
        rows.iter().map(|r| (r.time, 1e3 * r.label)).collect(),
    ));
    folder.write_figure("test_errors", |dir| errors.write(dir, "test_errors"))
}
