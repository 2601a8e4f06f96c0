//! The shape experiment (paper Table II, Fig. 5): the shape seen from the F/T sensor alone,
//! against the simulator's true centreline, over configurations of `A_free`.
//!
//! Per wire (default: the four presets; `common.wire` replaces them), `configs` (default 50)
//! seeded configurations of `A_free` of the true wire. For each, the operator places the wire
//! there anew and the robot tares before it grips it (as in
//! [`crate::experiment::calibration`]); `ã` is measured through the learnt calibration
//! (`calibration`, or a calibration run first on the known wire and cached as
//! `calibration.json`, labelled with the same model), and `ShapeEstimator` gives the shape
//! with the true wire's parameters (the wire is known, as in the paper's Table II) and the
//! estimators' model: `kirchhoff`, the paper's, or `loaded` (default with gravity on: the
//! wire's weight and rest curvature). Metrics: `mean_mm` (100 matched arc lengths),
//! `marker_mean_mm` (the paper's metric: each observed inner marker to the closest point of the
//! estimate, [`ftwire_rig::shape::inner_marker_mean`]), the same
//! mean for the tared mounting-only pipeline (`mounting_mean_mm`), both models' `mean_mm` from
//! the same `ã` (`kirchhoff_mean_mm`, `loaded_mean_mm`), the relative error of `ã`'s torque
//! and force against the true base wrench (`torque_rel`, `force_rel`: how well the
//! calibration, trained on another wire, carries over); the time of one shape estimate is in
//! the timings (`estimate_us_median`, per wire) and `configs.csv` (`estimate_us`).
//! Beside them, `fused_mean_mm`: the shape of the same model at `ã` fused with the gripper's
//! reported pose (`ftwire_control::BiasObserver` with `fuse_rest`, one rest after the tare,
//! the robot's repeatability as the pose's prior): what a robot that knows where its gripper
//! is gets from the same rest. `mean_mm` stays the F/T sensor's alone, as in Table II.
//! The error bars `σ(s)` (`sigma_mean_mm`, `coverage_2sigma`) carry to the shape, to first
//! order, the covariance of `ã` from the sensor's data sheet (the rest's noise, the tare's,
//! the drift since the tare), the learnt calibration's gain error, and the model's own error
//! against the simulated rod.
//!
//! [`run`] writes `configs.csv`, `calibration.json` (when it ran one), figures
//! `shape_<wire>` (the first configuration, estimate against truth and markers, 3-D;
//! `<wire>` as [`crate::wire::file_stem`] makes it) and `error_per_wire`, and with `save_log`
//! the JSON Lines log `logs/<wire>.jsonl` that `ftwire shape --log` reads: `raw` is the
//! **tared** reading averaged at rest (the calibration's input), `b` the believed tip pose,
//! `markers` the frame in the base clamp frame. The caller writes `summary.json`
//! ([`ShapeRun::summary`], the same for the same seed) and `timings.json`
//! ([`ShapeRun::timings`]), and may print [`ShapeRun::text`], the rows as text beside
//! Table II. Guarded by `tests/experiments.rs` and the recorded summary of
//! `crates/ftwire/tests/names_and_timings_cli.rs`.

mod text;

use std::path::PathBuf;
use std::time::Instant;

use ftwire_control::{BiasObserver, BiasObserverParams, NoiseModel};
use ftwire_core::Rig;
use ftwire_estimate::calibration::Calibration;
use ftwire_estimate::identify::MeasurementNoise;
use ftwire_estimate::log::{LogPose, LogRecord, to_line};
use ftwire_estimate::shape::{
    DEFAULT_METRIC_SAMPLES, ModelError, ShapeEstimator, centreline_distance,
};
use ftwire_estimate::{KirchhoffModel, WireModel};
use ftwire_report::{Chart3d, LineChart, Series, SeriesKind};
use ftwire_rod::Rod;
use ftwire_rod::sampling::Sampler;
use ftwire_sim::RigParams;
use nalgebra::{Point3, Vector3, Vector6};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::Serialize;

use crate::csv_table::{CsvTable, text, value};
use crate::error::{LabError, from_estimate, from_rod, from_sim};
use crate::experiment::calibration::{load_or_run_reporting, rig_seed};
use crate::experiment::coverage::{SigmaCheck, check_sigma};
use crate::experiment::rig::{
    LEARNT_GAIN_ERROR, SAMPLES_PER_REST, SIM_MODEL_ERROR_MM, believed_tip, bias_observer,
    identification_noise, measure_over, mounting, pipeline, place_wire, tare, true_centreline,
};
use crate::experiment::stats::median;
use crate::experiment::{CommonParams, Gravity, ModelKind, Progress, known_model};
use crate::results::ResultsFolder;
use crate::setup::SimSetup;
use crate::wire::{PRESETS, WireSpec, file_stem};

/// Configurations per wire by default (the paper's 50).
pub const DEFAULT_CONFIGS: usize = 50;

/// Draws of `A_free` per requested configuration before the experiment gives up on a wire.
const MAX_DRAWS_PER_CONFIG: usize = 3;

/// Calls of the shape estimate timed per configuration (their median is reported).
const TIMED_REPEATS: usize = 9;

/// The settings of the shape experiment.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ShapeParams {
    /// The settings every experiment takes (`trials` is not used: see `configs`).
    pub common: CommonParams,
    /// Configurations of `A_free` per wire, at least 1; `None`: [`DEFAULT_CONFIGS`].
    pub configs: Option<usize>,
    /// Learnt calibration weights (`ftwire_estimate::calibration` JSON); `None`: a
    /// calibration is first run on the known wire and cached in the results folder.
    pub calibration: Option<PathBuf>,
    /// Write the samples as JSON Lines logs (`logs/<wire>.jsonl`).
    pub save_log: bool,
    /// F/T samples averaged at each configuration (at the simulated sensor's 1 kHz, the
    /// default [`SAMPLES_PER_REST`] is the 0.1 s of the paper's protocol).
    pub rest_samples: usize,
}

impl Default for ShapeParams {
    fn default() -> Self {
        Self {
            common: CommonParams::default(),
            configs: None,
            calibration: None,
            save_log: false,
            rest_samples: SAMPLES_PER_REST,
        }
    }
}

impl ShapeParams {
    /// The wires: `common.wire`, or the four presets.
    ///
    /// # Errors
    /// Bad input for an unknown preset or a bad wire file.
    pub fn wires(&self) -> Result<Vec<WireSpec>, LabError> {
        Ok(match &self.common.wire {
            Some(given) => {
                vec![WireSpec::load(given).map_err(|e| LabError::bad_input(e.to_string()))?]
            }
            None => PRESETS
                .iter()
                .filter_map(|name| WireSpec::preset(name))
                .collect(),
        })
    }

    /// The configurations per wire: `configs`, or [`DEFAULT_CONFIGS`].
    ///
    /// # Errors
    /// Bad input for 0.
    pub fn configs(&self) -> Result<usize, LabError> {
        match self.configs.unwrap_or(DEFAULT_CONFIGS) {
            0 => Err(LabError::bad_input("--configs 0: give at least 1")),
            n => Ok(n),
        }
    }

    /// Checks the settings as [`run`] does before any work (the sensor and rig files, the
    /// wires, the count), so that a caller can refuse bad input before it opens a results
    /// folder.
    ///
    /// # Errors
    /// Bad input naming what is wrong.
    pub fn check(&self) -> Result<(), LabError> {
        fusion(&self.common.setup()?)?;
        self.wires()?;
        self.configs()?;
        Ok(())
    }
}

/// The bias observer's settings that fuse a rest with the gripper's reported pose.
fn fusion(setup: &SimSetup) -> Result<BiasObserverParams, LabError> {
    bias_observer(setup, NoiseModel::None, true)
        .ok_or_else(|| LabError::bad_input("no bias observer for a robot that knows its pose"))
}

/// One wire's row of the summary (the errors are means over its configurations).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WireResult {
    /// The wire's name.
    pub name: String,
    /// Configurations measured.
    pub configs: usize,
    /// Mean distance \[mm\] between the shape from `ã` and the true centreline (100 matched
    /// arc lengths), with the estimators' model.
    pub mean_mm: f64,
    /// Sample standard deviation of `mean_mm` over the configurations \[mm\].
    pub std_mm: f64,
    /// Mean distance \[mm\] of each observed inner marker to the closest point of the estimate.
    pub marker_mean_mm: f64,
    /// The tared mounting-only pipeline's `mean_mm` \[mm\], for comparison.
    pub mounting_mean_mm: f64,
    /// `mean_mm` of the paper's weightless model from the same `ã` \[mm\].
    pub kirchhoff_mean_mm: f64,
    /// As `kirchhoff_mean_mm`, the loaded model (the wire's weight and rest curvature).
    pub loaded_mean_mm: f64,
    /// The estimators' model's shape at `ã` fused with the reported gripper pose \[mm\]
    /// (module docs).
    pub fused_mean_mm: f64,
    /// Mean of `‖τ̃ − τ‖ / ‖τ‖` of the measured `ã` against the simulator's true base wrench:
    /// the calibration's error on this wire (it was trained on another one).
    pub torque_rel: f64,
    /// As `torque_rel`, the force.
    pub force_rel: f64,
    /// Configurations the estimator did not flag as confident.
    pub not_confident: usize,
    /// Configurations skipped (and replaced by another draw) because the simulator could not
    /// place the wire, too few F/T samples survived, or the model could not solve at `ã`.
    pub skipped: usize,
    /// The mean `σ(s)` of the estimate along the wire \[mm\] (from the sensor's data sheet,
    /// the calibration's gain error and the model's error), over the configurations; left out
    /// where the simulator's wire has too few nodes to match.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sigma_mean_mm: Option<f64>,
    /// The share of the true centreline's points (at the simulator's nodes, the base clamp
    /// left out) within `2σ(s)` of the estimate, over the configurations; left out as
    /// [`Self::sigma_mean_mm`] is.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub coverage_2sigma: Option<f64>,
}

/// `summary.json`'s body.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ShapeSummary {
    /// The estimators' model.
    pub model: ModelKind,
    /// One row per wire.
    pub wires: Vec<WireResult>,
}

/// `timings.json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ShapeTimings {
    /// Loading or running the calibration \[s\].
    pub calibration_s: f64,
    /// The experiment after the calibration \[s\].
    pub experiment_s: f64,
    /// The median time of one shape estimate per wire, `(wire, µs)`.
    pub estimate_us_median: Vec<(String, f64)>,
}

/// A finished shape experiment.
#[derive(Debug, Clone)]
pub struct ShapeRun {
    /// `summary.json`'s body (after the run header).
    pub summary: ShapeSummary,
    /// `timings.json`.
    pub timings: ShapeTimings,
}

/// One configuration's result.
struct ConfigResult {
    a_tilde: Vector6<f64>,
    mean: f64,
    /// The other model's `mean` from the same `ã`.
    other_mean: f64,
    /// Relative errors of `ã`'s torque and force against the true base wrench.
    wrench_rel: (f64, f64),
    mounting_mean: f64,
    /// The shape error at `ã` fused with the reported pose.
    fused_mean: f64,
    marker_mean: f64,
    estimate_us: f64,
    confident: bool,
    estimate: Vec<Vector3<f64>>,
    truth: Vec<Vector3<f64>>,
    markers: Vec<Option<Point3<f64>>>,
    record: LogRecord,
    /// The error bars against the truth, from the sensor's and the calibration's error.
    sigma: Option<SigmaCheck>,
}

fn mean(values: &[f64]) -> f64 {
    values.iter().sum::<f64>() / values.len().max(1) as f64
}

/// What the robot reads a rest through: the learnt calibration, the bias observer's
/// settings that fuse the rest with the gripper's reported pose, and the samples averaged.
struct Readout<'a> {
    calibration: &'a Calibration,
    fusion: BiasObserverParams,
    rest_samples: usize,
    /// The error of `ã` the error bars are drawn from: the sensor's data sheet (the rest's
    /// noise, the tare's, the drift since the tare) and the learnt calibration's gain error
    /// ([`crate::experiment::rig::identification_noise`], [`LEARNT_GAIN_ERROR`]).
    noise: MeasurementNoise,
}

/// The median time \[µs\] of [`TIMED_REPEATS`] shape estimates at `a_tilde` (each a fresh
/// start).
fn time_estimate(estimator: &mut ShapeEstimator<KirchhoffModel>, a_tilde: &Vector6<f64>) -> f64 {
    let mut times = [0.0; TIMED_REPEATS];
    for time in &mut times {
        estimator.reset();
        let start = Instant::now();
        let estimate = estimator.estimate(a_tilde);
        *time = start.elapsed().as_secs_f64() * 1e6;
        std::hint::black_box(estimate.is_ok());
    }
    median(&times)
}

/// Runs one configuration of `wire` at `placed`; `None` when it is skipped.
fn run_config(
    (wire, gravity): (&WireSpec, Gravity),
    readout: &Readout<'_>,
    estimator: &mut ShapeEstimator<KirchhoffModel>,
    other: &KirchhoffModel,
    placed: &Vector6<f64>,
    config: RigParams,
) -> Result<Option<ConfigResult>, LabError> {
    let Ok(mut rig) = place_wire(wire, gravity, placed, config.clone()) else {
        return Ok(None);
    };
    let tared = pipeline(tare(&mut rig)?, readout.calibration.clone())?;
    let tared_at = rig.time();
    let Ok(measured) = measure_over(&mut rig, &tared, readout.rest_samples) else {
        return Ok(None);
    };
    let since_tare = rig.time() - tared_at;
    let raw = tared.tare().apply(&measured.raw.mean);
    let a_tilde = measured.a;
    let frame = rig
        .observe_markers()
        .map_err(|e| from_sim(e, "observing the markers"))?;
    let true_wrench = rig.equilibrium().base_wrench.to_vector();
    let relative = |start: usize| {
        let t = true_wrench.fixed_rows::<3>(start);
        (a_tilde.fixed_rows::<3>(start) - t).norm() / t.norm().max(f64::MIN_POSITIVE)
    };
    let wrench_rel = (relative(0), relative(3));
    let truth = true_centreline(&rig);
    let estimate_us = time_estimate(estimator, &a_tilde);
    estimator.reset();
    let Ok(estimate) = estimator.estimate(&a_tilde) else {
        return Ok(None);
    };
    let positions = estimate.shape.positions.clone();
    let distance = |shape: &[Vector3<f64>]| {
        centreline_distance(shape, &truth, DEFAULT_METRIC_SAMPLES)
            .map_err(|e| from_estimate(e, "the shape error"))
    };
    // The mean distance of `model`'s shape at `a`, NaN where the model cannot solve there.
    let shape_mean =
        |model: &KirchhoffModel, a: &Vector6<f64>| match model.shape(a, positions.len()) {
            Ok(shape) => distance(&shape.positions),
            Err(_) => Ok(f64::NAN),
        };
    let centreline_mean = distance(&positions)?;
    let other_mean = shape_mean(other, &a_tilde)?;
    let mounting_a = mounting(&config)?.to_configuration(&raw);
    let mounting_mean = shape_mean(estimator.model(), &mounting_a)?;
    // One rest after the tare, fused with where the robot reports its gripper.
    let mut fusion = BiasObserver::new(*estimator.model(), readout.fusion)
        .map_err(|e| LabError::bad_input(e.to_string()))?;
    let fused = fusion.update(
        &a_tilde,
        &measured.a_std_error,
        &believed_tip(&rig)?,
        rig.time(),
    );
    let fused_mean = shape_mean(estimator.model(), &fused)?;
    let covariance = readout.noise.sample_covariance(&a_tilde, since_tare);
    let model_error = ModelError::new(1e-3 * SIM_MODEL_ERROR_MM / wire.length)
        .map_err(|e| from_estimate(e, "the model error"))?;
    let sigma = check_sigma(
        estimator.model(),
        &a_tilde,
        &covariance,
        Some(&model_error),
        &truth,
    )
    .map_err(|e| from_estimate(e, "the error bars"))?;
    let markers: Vec<Option<[f64; 3]>> = frame
        .positions
        .iter()
        .map(|p| p.map(|p| [p.x, p.y, p.z]))
        .collect();
    let marker_mean = ftwire_rig::shape::inner_marker_mean(estimator.model(), &a_tilde, &markers)
        .map_err(|e| LabError::bad_input(format!("marker errors: {e}")))?
        .unwrap_or(f64::NAN);
    let record = LogRecord {
        time: rig.time(),
        raw: Some(raw.into()),
        a: None,
        b: Some(LogPose::from_pose(&believed_tip(&rig)?)),
        gravity: None,
        markers: Some(
            frame
                .positions
                .iter()
                .map(|p| p.map(|p| [p.x, p.y, p.z]))
                .collect(),
        ),
    };
    Ok(Some(ConfigResult {
        a_tilde,
        mean: centreline_mean,
        other_mean,
        wrench_rel,
        mounting_mean,
        fused_mean,
        marker_mean,
        estimate_us,
        confident: estimate.confidence.is_confident(),
        estimate: positions,
        truth,
        markers: frame.positions,
        record,
        sigma,
    }))
}

/// What one wire gives: its summary row, its log, the median time of one estimate \[µs\]
/// and its first configuration (for the figure).
struct WireOutcome {
    result: WireResult,
    log: String,
    estimate_us_median: f64,
    first: Option<ConfigResult>,
}

/// Measures `configs` configurations of wire `w` of the run and appends its rows to `csv`.
fn run_wire(
    (w, wire): (usize, &WireSpec),
    settings: &ShapeParams,
    (readout, setup): (&Readout<'_>, &SimSetup),
    configs: usize,
    csv: &mut CsvTable,
) -> Result<WireOutcome, LabError> {
    let common = &settings.common;
    let seed = common.seed;
    let kind = common.model();
    let model = known_model(wire, common.gravity, kind)?;
    let other = known_model(wire, common.gravity, kind.other())?;
    // Configurations are drawn from A_free of the weight-free model, whatever the
    // estimator's model, so that both models see the same placements.
    let rod = Rod::new(*model.wire());
    let mut estimator = ShapeEstimator::new(model);
    let mut rng = ChaCha8Rng::seed_from_u64(seed.wrapping_add(1 + w as u64));
    let mut rows: Vec<ConfigResult> = Vec::new();
    let mut skipped = 0;
    // The log's clock: each placement's rig starts its own clock at 0, so the log adds
    // them up, one placement after the other.
    let mut clock = 0.0;
    // A configuration the simulator cannot place is skipped and another one drawn, up to
    // MAX_DRAWS_PER_CONFIG draws per configuration in all.
    let mut k = 0;
    while rows.len() < configs && k < MAX_DRAWS_PER_CONFIG * configs {
        let placed = Sampler::default()
            .sample_free(&rod, &mut rng)
            .map_err(|e| from_rod(e, "sampling A_free"))?;
        let rig = rig_seed(seed.wrapping_add(1_000 * (w as u64 + 1)), k);
        k += 1;
        match run_config(
            (wire, common.gravity),
            readout,
            &mut estimator,
            &other,
            &placed,
            setup.rig_config(rig),
        )? {
            Some(mut row) => {
                clock += row.record.time;
                row.record.time = clock;
                rows.push(row);
            }
            None => skipped += 1,
        }
    }
    let mut log = String::new();
    for (k, row) in rows.iter().enumerate() {
        let mut cells = vec![
            text(&wire.name),
            value(k),
            value(1e3 * row.mean),
            value(1e3 * row.mounting_mean),
            value(1e3 * row.marker_mean),
            value(row.confident),
            value(row.estimate_us),
        ];
        cells.extend(row.a_tilde.iter().map(|&v| value(v)));
        cells.push(value(1e3 * row.fused_mean));
        csv.row(cells)?;
        log.push_str(&to_line(&row.record).map_err(|e| from_estimate(e, "the log"))?);
        log.push('\n');
    }
    let times: Vec<f64> = rows.iter().map(|r| r.estimate_us).collect();
    Ok(WireOutcome {
        result: wire_result(wire, kind, &rows, skipped),
        log,
        estimate_us_median: median(&times),
        first: rows.into_iter().next(),
    })
}

/// The summary row of `wire` from its configurations' results.
fn wire_result(
    wire: &WireSpec,
    kind: ModelKind,
    rows: &[ConfigResult],
    skipped: usize,
) -> WireResult {
    let mean_of = |f: &dyn Fn(&ConfigResult) -> f64| mean(&rows.iter().map(f).collect::<Vec<_>>());
    let means: Vec<f64> = rows.iter().map(|r| 1e3 * r.mean).collect();
    let m = mean(&means);
    let other_m = mean_of(&|r| 1e3 * r.other_mean);
    let var = means.iter().map(|x| (x - m).powi(2)).sum::<f64>()
        / (means.len().saturating_sub(1).max(1)) as f64;
    WireResult {
        name: wire.name.clone(),
        configs: rows.len(),
        mean_mm: m,
        std_mm: var.sqrt(),
        marker_mean_mm: mean_of(&|r| 1e3 * r.marker_mean),
        mounting_mean_mm: mean_of(&|r| 1e3 * r.mounting_mean),
        not_confident: rows.iter().filter(|r| !r.confident).count(),
        skipped,
        torque_rel: mean_of(&|r| r.wrench_rel.0),
        force_rel: mean_of(&|r| r.wrench_rel.1),
        kirchhoff_mean_mm: if kind == ModelKind::Weightless {
            m
        } else {
            other_m
        },
        loaded_mean_mm: if kind == ModelKind::Loaded {
            m
        } else {
            other_m
        },
        fused_mean_mm: mean_of(&|r| 1e3 * r.fused_mean),
        sigma_mean_mm: all_sigma(rows, |s| 1e3 * s.sigma_mean()),
        coverage_2sigma: all_sigma(rows, SigmaCheck::coverage_2sigma),
    }
}

/// The mean of `f` over the configurations' error bars; `None` unless every configuration
/// has them.
fn all_sigma(rows: &[ConfigResult], f: impl Fn(&SigmaCheck) -> f64) -> Option<f64> {
    let values: Option<Vec<f64>> = rows.iter().map(|r| r.sigma.as_ref().map(&f)).collect();
    values.filter(|v| !v.is_empty()).map(|v| mean(&v))
}

/// Runs the shape experiment into `folder` (see the module docs for what it writes), reports
/// when it calibrates first to `progress`, and returns the summary and timings for the caller
/// to write (it does not finish the folder).
///
/// # Errors
/// Bad input for bad settings ([`ShapeParams::check`]) or a bad calibration file; no answer
/// when `A_free` cannot be sampled or a figure cannot be drawn; I/O errors writing the folder.
pub fn run(
    settings: &ShapeParams,
    folder: &ResultsFolder,
    progress: Progress<'_>,
) -> Result<ShapeRun, LabError> {
    let common = &settings.common;
    let setup = common.setup()?;
    let fusion = fusion(&setup)?;
    let wires = settings.wires()?;
    let configs = settings.configs()?;
    let (calibration, calibration_s) = load_or_run_reporting(
        folder,
        settings.calibration.as_deref(),
        (common.gravity, common.model()),
        (&setup, common.seed),
        progress,
    )?;
    let noise = MeasurementNoise {
        torque_gain: Some(LEARNT_GAIN_ERROR[0]),
        gain: LEARNT_GAIN_ERROR[1],
        ..identification_noise(&setup, settings.rest_samples)?
    };
    let readout = Readout {
        calibration: &calibration,
        fusion,
        rest_samples: settings.rest_samples,
        noise,
    };
    let mut csv = CsvTable::new(
        "configs.csv",
        &[
            "wire",
            "config",
            "mean_mm",
            "mounting_mean_mm",
            "marker_mean_mm",
            "confident",
            "estimate_us",
            "a1",
            "a2",
            "a3",
            "a4",
            "a5",
            "a6",
            "fused_mm",
        ],
    )?;
    let mut results = Vec::new();
    let mut estimate_us_median = Vec::new();
    let mut logs = Vec::new();
    let mut first_shapes = Vec::new();
    let start = Instant::now();
    for (w, wire) in wires.iter().enumerate() {
        let outcome = run_wire((w, wire), settings, (&readout, &setup), configs, &mut csv)?;
        results.push(outcome.result);
        estimate_us_median.push((wire.name.clone(), outcome.estimate_us_median));
        logs.push((wire.name.clone(), outcome.log));
        if let Some(first) = outcome.first {
            first_shapes.push((wire.name.clone(), first));
        }
    }
    let experiment_s = start.elapsed().as_secs_f64();
    folder.write("configs.csv", csv.into_bytes()?)?;
    write_figures(folder, &first_shapes, &results)?;
    if settings.save_log {
        for (name, log) in &logs {
            folder.write(&format!("logs/{}.jsonl", file_stem(name)), log)?;
        }
    }
    Ok(ShapeRun {
        summary: ShapeSummary {
            model: common.model(),
            wires: results,
        },
        timings: ShapeTimings {
            calibration_s,
            experiment_s,
            estimate_us_median,
        },
    })
}

/// The figures: each wire's first configuration (estimate, truth and markers, 3-D) and the
/// mean error per wire (Fig. 5).
fn write_figures(
    folder: &ResultsFolder,
    first_shapes: &[(String, ConfigResult)],
    results: &[WireResult],
) -> Result<(), LabError> {
    let to_points = |v: &[Vector3<f64>]| v.iter().map(|p| [p.x, p.y, p.z]).collect::<Vec<_>>();
    for (name, row) in first_shapes {
        let markers: Vec<[f64; 3]> = row
            .markers
            .iter()
            .flatten()
            .map(|p| [p.x, p.y, p.z])
            .collect();
        let chart = Chart3d::new(format!("{name}: shape from F/T against the truth")).with_curve(
            "truth (simulator)",
            to_points(&row.truth),
            SeriesKind::Line,
        );
        let chart = match &row.sigma {
            Some(check) => chart.with_tube(
                "estimate from F/T, 2σ tube",
                to_points(&check.estimate),
                check.sigma.iter().map(|s| 2.0 * s).collect(),
                SeriesKind::Line,
            ),
            None => chart.with_curve(
                "estimate from F/T",
                to_points(&row.estimate),
                SeriesKind::Line,
            ),
        }
        .with_curve("markers", markers, SeriesKind::Points);
        let stem = format!("shape_{}", file_stem(name));
        folder.write_figure(&stem, |dir| chart.write(dir, &stem))?;
        if let Some(check) = &row.sigma {
            let stem = format!("shape_error_{}", file_stem(name));
            let chart = sigma_chart(name, check, row.truth.len());
            folder.write_figure(&stem, |dir| chart.write(dir, &stem))?;
        }
    }
    let points: Vec<(f64, f64)> = results
        .iter()
        .enumerate()
        .map(|(i, r)| (i as f64, r.mean_mm))
        .collect();
    let chart = LineChart::new(
        format!(
            "mean shape error per wire ({})",
            results
                .iter()
                .map(|r| r.name.as_str())
                .collect::<Vec<_>>()
                .join(", ")
        ),
        "wire (in the order of the title)",
        "mean error along the wire [mm]",
    )
    .with_series(
        Series::points("learnt calibration", points)
            .with_error_bars(results.iter().map(|r| r.std_mm).collect()),
    );
    folder.write_figure("error_per_wire", |dir| chart.write(dir, "error_per_wire"))
}

/// The error of the first configuration's estimate along the wire, with the `±2σ(s)` band
/// around zero: a point of the error curve inside the band is covered.
fn sigma_chart(name: &str, check: &SigmaCheck, points: usize) -> LineChart {
    // The simulator's points' arc lengths as fractions of L: the clamp points, and the
    // interior nodes at (k − ½)h with L = (N − 1)h, N = points − 1 (ftwire_sim's
    // wire_centreline).
    #[allow(clippy::cast_precision_loss)] // a few hundred points
    let s = |k: usize| -> f64 {
        if k == 0 {
            0.0
        } else if k + 1 >= points {
            1.0
        } else {
            (k as f64 - 0.5) / (points as f64 - 2.0)
        }
    };
    let error: Vec<(f64, f64)> = check
        .error
        .iter()
        .enumerate()
        .map(|(k, e)| (s(k), 1e3 * e))
        .collect();
    let zero: Vec<(f64, f64)> = (0..check.sigma.len()).map(|k| (s(k), 0.0)).collect();
    LineChart::new(
        format!("{name}: error along the wire and ±2σ"),
        "arc length s / L",
        "distance to the truth [mm]",
    )
    .with_series(
        Series::line("±2σ(s) (sensor, calibration and model error)", zero)
            .with_band(check.sigma.iter().map(|s| 2e3 * s).collect()),
    )
    .with_series(Series::line("‖estimate − truth‖", error))
}
