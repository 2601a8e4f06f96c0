//! `ftwire experiment shape` (paper Table II, Fig. 5): the shape seen from the F/T sensor
//! alone, against the simulator's true centreline, over configurations of `A_free`.
//!
//! Per wire (default: the four presets; `--wire` replaces them), `--configs N` (default 50)
//! seeded configurations of `A_free` of the true wire. For each, the operator places the wire
//! there anew and the robot tares before it grips it (as in
//! [`ftwire_lab::experiment::calibration`]); `ã` is measured through the learnt calibration
//! (`--calibration FILE`, or a calibration run first on the known wire and cached as
//! `calibration.json`, labelled with the same `--model`), and `ShapeEstimator` gives the shape
//! with the true wire's parameters (the wire is known, as in the paper's Table II) and the
//! model of `--model`: `kirchhoff`, the paper's, or `loaded` (default with gravity on: the
//! wire's weight and rest curvature). Metrics: `mean_mm` (100 matched arc lengths),
//! `marker_mean_mm` (each observed marker to the closest point of the estimate), the same
//! mean for the tared mounting-only pipeline (`mounting_mean_mm`), both models' `mean_mm` from
//! the same `ã` (`kirchhoff_mean_mm`, `loaded_mean_mm`), the relative error of `ã`'s torque
//! and force against the true base wrench (`torque_rel`, `force_rel`: how well the
//! calibration, trained on another wire, carries over); the time of one shape estimate is in
//! `timings.json` (`estimate_us_median`, per wire) and `configs.csv` (`estimate_us`).
//! Beside them, `fused_mean_mm`: the shape of the same model at `ã` fused with the gripper's
//! reported pose (`ftwire_control::BiasObserver` with `fuse_rest`, one rest after the tare,
//! the robot's repeatability as the pose's prior): what a robot that knows where its gripper
//! is gets from the same rest. `mean_mm` stays the F/T sensor's alone, as in Table II.
//!
//! Writes `summary.json` (the same for the same seed), `configs.csv`, `timings.json`
//! (`calibration_s`, `experiment_s`, and `estimate_us_median`: `[wire, µs]` pairs),
//! `calibration.json` (when it ran one), figures `shape_<wire>` (the first configuration,
//! estimate against truth and markers, 3-D; `<wire>` as [`ftwire_lab::wire::file_stem`] makes it)
//! and `error_per_wire`, and with `--save-log` the JSON Lines log `logs/<wire>.jsonl` that
//! `ftwire shape --log` reads: `raw` is the **tared** reading averaged at rest (the
//! calibration's input), `b` the believed tip pose, `markers` the frame in the base clamp frame.

use std::time::Instant;

use ftwire_control::{BiasObserver, BiasObserverSettings, NoiseModel};
use ftwire_core::Rig;
use ftwire_estimate::calibration::Calibration;
use ftwire_estimate::log::{LogPose, LogRecord, to_line};
use ftwire_estimate::shape::{
    DEFAULT_METRIC_SAMPLES, ShapeEstimator, centreline_distance, marker_distances,
};
use ftwire_estimate::{KirchhoffModel, WireModel};
use ftwire_lab::csv_table::{CsvTable, text, value};
use ftwire_lab::error::from_estimate;
use ftwire_lab::error::{LabError, from_rod};
use ftwire_lab::experiment::calibration::{load_or_run_into, rig_seed};
use ftwire_lab::experiment::rig::{
    believed_tip, bias_observer, measure_over, mounting, pipeline, place_wire, tare,
    true_centreline,
};
use ftwire_lab::experiment::{ModelKind, known_model};
use ftwire_lab::header::RunHeader;
use ftwire_lab::results::OutGuard;
use ftwire_lab::wire::{PRESETS, WireSpec, file_stem};
use ftwire_report::{Chart3d, LineChart, Series, SeriesKind};
use ftwire_rod::Rod;
use ftwire_rod::sampling::Sampler;
use ftwire_sim::RigConfig;
use nalgebra::{Point3, Vector3, Vector6};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::Serialize;

use super::stats::median;
use crate::cli::experiment::ShapeExperimentArgs;

/// Configurations per wire by default (the paper's 50).
const DEFAULT_CONFIGS: usize = 50;

/// Draws of `A_free` per requested configuration before the experiment gives up on a wire.
const MAX_DRAWS_PER_CONFIG: usize = 3;

/// Calls of the shape estimate timed per configuration (their median is reported).
const TIMED_REPEATS: usize = 9;

/// Paper Table II: mean shape error \[mm\] of the real wires, for the printed comparison.
pub(crate) const TABLE_II: [(&str, f64); 4] = [
    ("nitinol-2mm-630", 5.72),
    ("nitinol-3mm-910", 7.42),
    ("nitinol-3mm-820", 6.55),
    ("cable-3mm-920", 52.3),
];

/// One wire's row of `summary.json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
struct WireResult {
    name: String,
    configs: usize,
    mean_mm: f64,
    std_mm: f64,
    marker_mean_mm: f64,
    /// The tared mounting-only pipeline's `mean_mm`, for comparison.
    mounting_mean_mm: f64,
    /// `mean_mm` of each model from the same `ã` (`--model`'s is `mean_mm`).
    kirchhoff_mean_mm: f64,
    /// As `kirchhoff_mean_mm`, the loaded model (the wire's weight and rest curvature).
    loaded_mean_mm: f64,
    /// `--model`'s shape at `ã` fused with the reported gripper pose (module docs).
    fused_mean_mm: f64,
    /// Mean of `‖τ̃ − τ‖ / ‖τ‖` of the measured `ã` against the simulator's true base wrench:
    /// the calibration's error on this wire (it was trained on another one).
    torque_rel: f64,
    /// As `torque_rel`, the force.
    force_rel: f64,
    /// Configurations the estimator did not flag as confident.
    not_confident: usize,
    /// Configurations skipped (and replaced by another draw) because the simulator could not
    /// place the wire, too few F/T samples survived, or the model could not solve at `ã`.
    skipped: usize,
}

#[derive(Serialize)]
struct ShapeSummary {
    /// The estimator's model (`--model`).
    model: ModelKind,
    wires: Vec<WireResult>,
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
}

fn mean(values: &[f64]) -> f64 {
    values.iter().sum::<f64>() / values.len().max(1) as f64
}

/// What the robot reads a rest through: the learnt calibration, and the bias observer's
/// settings that fuse the rest with the gripper's reported pose.
struct Readout<'a> {
    calibration: &'a Calibration,
    fusion: BiasObserverSettings,
}

/// Runs one configuration `k` of `wire` at `placed`.
fn run_config(
    wire: &WireSpec,
    args: &ShapeExperimentArgs,
    readout: &Readout<'_>,
    estimator: &mut ShapeEstimator<KirchhoffModel>,
    other: &KirchhoffModel,
    placed: &Vector6<f64>,
    config: RigConfig,
) -> Result<Option<ConfigResult>, LabError> {
    let Ok(mut rig) = place_wire(wire, args.common.gravity, placed, config.clone()) else {
        return Ok(None);
    };
    let tared = pipeline(tare(&mut rig)?, readout.calibration.clone())?;
    let Ok(measured) = measure_over(&mut rig, &tared, args.rest_samples) else {
        return Ok(None);
    };
    let raw = tared.tare().apply(&measured.raw.mean);
    let a_tilde = measured.a;
    let frame = rig
        .observe_markers()
        .map_err(|e| ftwire_lab::error::from_sim(e, "observing the markers"))?;
    let true_wrench = rig.equilibrium().base_wrench.to_vector();
    let relative = |start: usize| {
        let t = true_wrench.fixed_rows::<3>(start);
        (a_tilde.fixed_rows::<3>(start) - t).norm() / t.norm().max(f64::MIN_POSITIVE)
    };
    let wrench_rel = (relative(0), relative(3));
    let truth = true_centreline(&rig);
    // The time of one estimate: the median of TIMED_REPEATS calls (each a fresh sample).
    let mut times = [0.0; TIMED_REPEATS];
    for time in &mut times {
        estimator.reset();
        let start = Instant::now();
        let estimate = estimator.estimate(&a_tilde);
        *time = start.elapsed().as_secs_f64() * 1e6;
        std::hint::black_box(estimate.is_ok());
    }
    let estimate_us = median(&times);
    estimator.reset();
    let Ok(estimate) = estimator.estimate(&a_tilde) else {
        return Ok(None);
    };
    let positions = estimate.shape.positions.clone();
    let distance = |shape: &[Vector3<f64>]| {
        centreline_distance(shape, &truth, DEFAULT_METRIC_SAMPLES)
            .map_err(|e| from_estimate(e, "the shape error"))
    };
    let centreline_mean = distance(&positions)?;
    let other_mean = match other.shape(&a_tilde, positions.len()) {
        Ok(shape) => distance(&shape.positions)?,
        Err(_) => f64::NAN,
    };
    let mounting_a = mounting(&config)?.to_configuration(&raw);
    let mounting_mean = match estimator.model().shape(&mounting_a, positions.len()) {
        Ok(shape) => distance(&shape.positions)?,
        Err(_) => f64::NAN,
    };
    // One rest after the tare, fused with where the robot reports its gripper.
    let mut fusion = BiasObserver::new(*estimator.model(), readout.fusion)
        .map_err(|e| LabError::bad_input(e.to_string()))?;
    let fused = fusion.update(
        &a_tilde,
        &measured.a_std_error,
        &believed_tip(&rig)?,
        rig.time(),
    );
    let fused_mean = match estimator.model().shape(&fused, positions.len()) {
        Ok(shape) => distance(&shape.positions)?,
        Err(_) => f64::NAN,
    };
    let seen: Vec<Point3<f64>> = frame.positions.iter().flatten().copied().collect();
    let marker_mean =
        mean(&marker_distances(&seen, &positions).map_err(|e| from_estimate(e, "marker errors"))?);
    let record = LogRecord {
        time: rig.time(),
        raw: Some(raw.into()),
        a: None,
        b: LogPose::from_pose(&believed_tip(&rig)?),
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
    }))
}

/// Runs the experiment.
pub fn run(args: ShapeExperimentArgs) -> Result<(), LabError> {
    let common = &args.common;
    let seed = common.seed.seed;
    let setup = common.setup.load()?;
    let fusion = bias_observer(&setup, NoiseModel::None, true)
        .ok_or_else(|| LabError::bad_input("no bias observer for a robot that knows its pose"))?;
    let wires: Vec<WireSpec> = match &common.wire {
        Some(given) => vec![WireSpec::load(given).map_err(|e| LabError::bad_input(e.to_string()))?],
        None => PRESETS
            .iter()
            .filter_map(|name| WireSpec::preset(name))
            .collect(),
    };
    let configs = args.configs.unwrap_or(DEFAULT_CONFIGS);
    if configs == 0 {
        return Err(LabError::bad_input("--configs 0: give at least 1"));
    }
    let folder = common.open_results(
        "shape",
        OutGuard::default().input_opt("--calibration", args.calibration.as_deref()),
    )?;
    let header = RunHeader::new("experiment shape", Some(seed), &args)?;
    let (calibration, calibration_s) = load_or_run_into(
        &folder,
        args.calibration.as_deref(),
        (common.gravity, common.model()),
        &setup,
        seed,
    )?;
    let readout = Readout {
        calibration: &calibration,
        fusion,
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
    // The median time of one estimate per wire \[µs\], for `timings.json`.
    let mut estimate_us_median: Vec<(String, f64)> = Vec::new();
    let mut logs: Vec<(String, String)> = Vec::new();
    let mut first_shapes = Vec::new();
    let start = Instant::now();
    for (w, wire) in wires.iter().enumerate() {
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
                wire,
                &args,
                &readout,
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
        logs.push((wire.name.clone(), log));
        let means: Vec<f64> = rows.iter().map(|r| 1e3 * r.mean).collect();
        let m = mean(&means);
        let other_m = mean(&rows.iter().map(|r| 1e3 * r.other_mean).collect::<Vec<_>>());
        let var = means.iter().map(|x| (x - m).powi(2)).sum::<f64>()
            / (means.len().saturating_sub(1).max(1)) as f64;
        let times: Vec<f64> = rows.iter().map(|r| r.estimate_us).collect();
        estimate_us_median.push((wire.name.clone(), median(&times)));
        results.push(WireResult {
            name: wire.name.clone(),
            configs: rows.len(),
            mean_mm: m,
            std_mm: var.sqrt(),
            marker_mean_mm: mean(&rows.iter().map(|r| 1e3 * r.marker_mean).collect::<Vec<_>>()),
            mounting_mean_mm: mean(
                &rows
                    .iter()
                    .map(|r| 1e3 * r.mounting_mean)
                    .collect::<Vec<_>>(),
            ),
            not_confident: rows.iter().filter(|r| !r.confident).count(),
            skipped,
            torque_rel: mean(&rows.iter().map(|r| r.wrench_rel.0).collect::<Vec<_>>()),
            force_rel: mean(&rows.iter().map(|r| r.wrench_rel.1).collect::<Vec<_>>()),
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
            fused_mean_mm: mean(&rows.iter().map(|r| 1e3 * r.fused_mean).collect::<Vec<_>>()),
        });
        if let Some(first) = rows.into_iter().next() {
            first_shapes.push((wire.name.clone(), first));
        }
    }
    let experiment_s = start.elapsed().as_secs_f64();
    folder.write("configs.csv", csv.into_bytes()?)?;
    folder.write_json(
        "timings.json",
        &serde_json::json!({
            "calibration_s": calibration_s,
            "experiment_s": experiment_s,
            "estimate_us_median": estimate_us_median,
        }),
    )?;
    let to_points = |v: &[Vector3<f64>]| v.iter().map(|p| [p.x, p.y, p.z]).collect::<Vec<_>>();
    for (name, row) in &first_shapes {
        let markers: Vec<[f64; 3]> = row
            .markers
            .iter()
            .flatten()
            .map(|p| [p.x, p.y, p.z])
            .collect();
        let chart = Chart3d::new(format!("{name}: shape from F/T against the truth"))
            .with_curve("truth (simulator)", to_points(&row.truth), SeriesKind::Line)
            .with_curve(
                "estimate from F/T",
                to_points(&row.estimate),
                SeriesKind::Line,
            )
            .with_curve("markers", markers, SeriesKind::Points);
        let stem = format!("shape_{}", file_stem(name));
        folder.write_figure(&stem, |dir| chart.write(dir, &stem))?;
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
    folder.write_figure("error_per_wire", |dir| chart.write(dir, "error_per_wire"))?;
    let summary = ShapeSummary {
        model: common.model(),
        wires: results,
    };
    if args.save_log {
        for (name, log) in &logs {
            folder.write(&format!("logs/{}.jsonl", file_stem(name)), log)?;
        }
    }
    let target = folder.finish(&header, &summary)?;
    println!(
        "shape: {} model (mean_mm), the {} model from the same ã beside it",
        summary.model.name(),
        summary.model.other().name()
    );
    println!(
        "{:<18} {:>7} {:>8} {:>7} {:>10} {:>8} {:>10} {:>10} {:>8} {:>9} {:>9} {:>9}",
        "wire",
        "configs",
        "mean_mm",
        "std_mm",
        summary.model.other().name(),
        "fused",
        "marker_mm",
        "mounting",
        "est_us",
        "Table II",
        "torque_%",
        "force_%"
    );
    for (r, (_, estimate_us)) in summary.wires.iter().zip(&estimate_us_median) {
        let paper = TABLE_II
            .iter()
            .find(|(n, _)| *n == r.name)
            .map_or_else(|| "-".to_owned(), |(_, v)| format!("{v:.2}"));
        let other = match summary.model {
            ModelKind::Weightless => r.loaded_mean_mm,
            ModelKind::Loaded => r.kirchhoff_mean_mm,
        };
        println!(
            "{:<18} {:>7} {:>8.2} {:>7.2} {:>10.2} {:>8.2} {:>10.2} {:>10.2} {:>8.1} {:>9} {:>9.3} {:>9.3}",
            r.name,
            r.configs,
            r.mean_mm,
            r.std_mm,
            other,
            r.fused_mean_mm,
            r.marker_mean_mm,
            r.mounting_mean_mm,
            estimate_us,
            paper,
            100.0 * r.torque_rel,
            100.0 * r.force_rel
        );
    }
    println!(
        "calibration {calibration_s:.1} s, experiment {experiment_s:.1} s; results in {}",
        target.display()
    );
    Ok(())
}
