//! `ftwire experiment identify`: paper §IV-B, Table I and Figs. 3–4. Identify `η = (c1, c2, c3,
//! L)` of the nitinol wires from random motion of the second gripper, over trials and numbers of
//! samples.
//!
//! Per wire and trial, in the simulator (the true wire is given to the simulator only):
//! 1. the operator places the wire at a random start configuration `a0` (normalised within
//!    `[−5, 5]⁶`, stable for the true wire; [`place_wire`]) and the robot tares its sensor
//!    before the pick-up ([`tare`]);
//! 2. the second gripper follows the library's identification [`MotionPlan`] (seeded; its
//!    twist about the wire's tangent is `--twist`, default 40°), and at
//!    each rest the robot records `(ã, b̃)`: `ã` from the tared reading averaged over `--rest-samples` samples ([`measure_over`]) through
//!    the learnt calibration by default (`--pipeline calibrated`: `--calibration FILE`, or a
//!    calibration run first on the known wire with this run's gravity and seed and cached as
//!    `calibration.json`, [`load_or_run`]), or through the sensor's mounting only
//!    (`--pipeline mounting`, [`mounting`]: the sensor's gain error and cross-talk of about
//!    1 % stay in `ã`; for comparison, and with `--sensor undistorted` what a perfect
//!    calibration gives); `b̃` the believed pose;
//! 3. for every sample count `n` of `--samples`, `η` is identified from the first `n` samples
//!    with the swarm seeded by `--seed` (a fresh generator per identification, as
//!    `ftwire identify --log` does, so the log command reproduces each estimate), with the
//!    model of `--model`: `kirchhoff`, the paper's, or `loaded` (default with gravity on),
//!    which also identifies the wire's linear density `λ` under the known gravity
//!    (`ftwire identify --log --gravity 0,0,-9.81` replays it). With gravity on, the other
//!    model identifies from the same data as well, reported beside it.
//!
//! Results folder (`--out`, default `results/identify`):
//! - `summary.json`: the run header, then `model`, `form`, `gravity`, `sensor`, `pipeline`
//!   (`calibrated` or `mounting`), `calibration` (the `--calibration` path, `"cached"` when one
//!   was run and cached, `null` for the mounting pipeline), `trials`, `sample_counts`;
//!   `wires`: a list of `{wire: {name, c, length, linear_density}, by_samples}` of `--model`;
//!   `wire` and `by_samples` repeated at the top level for the first wire (issue 13's
//!   contract); and `by_model`, a list of `{model, wires}` for every model run, `--model`
//!   first. Each `by_samples` row is `{samples, estimated, identified, mean[4], std[4],
//!   relative_error[4], mean_abs_relative_error[4], mean_abs_relative_error_identified[4],
//!   evaluations_median, linear_density}` over `(c1, c2, c3, L)`, with
//!   `linear_density` `{mean, std, mean_abs_relative_error}` for the loaded model (`null`
//!   otherwise):
//!   `relative_error` is that of the mean over trials (Table I), `mean_abs_relative_error` the
//!   mean of each trial's absolute relative error, both as fractions (0.005 is 0.5 %), over
//!   the trials that returned an estimate (`estimated`), flagged ones included; `identified`
//!   counts the trials whose estimate was not flagged, and `mean_abs_relative_error_identified`
//!   is the mean over those only (`null` if none): what a user who heeds the flags gets.
//!   Every value is the same for the same seed: the wall-clock times are in `timings.json`.
//! - `timings.json`: `calibration_s`, every identification's `compute_ms`, and
//!   `compute_ms_median`, a list of `{model, wire, samples, compute_ms_median}` over the trials.
//! - `identify.csv`: one row per model, wire, trial and sample count (estimate, relative
//!   errors, `χ²/dof`, flags, `model`, `linear_density`).
//! - `error_vs_samples_<wire>.{png,svg}` (Fig. 3, log y, one per wire) and
//!   `time_vs_samples.{png,svg}` (Fig. 4, from `timings.json`; a timing figure, left out of
//!   `report.md` and `report.html`, [`ftwire_lab::report::TIMING_FIGURES`]).
//! - with `--save-log`, `logs/<wire>-trial<k>.jsonl`: each trial's records
//!   `{time, a, b}` in the format of `ftwire_estimate::log`, with `a` the configuration as
//!   identified from (tared, through `--pipeline`), `time` the rig's clock.
//! - `calibration.json`: the weights, when a calibration was run (no `--calibration`);
//!   its time is `calibration_s` in `timings.json`.

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use ftwire_core::{Pose, Rig};
use ftwire_estimate::calibration::Calibration;
use ftwire_estimate::ft::{FtCalibration, FtPipeline};
use ftwire_estimate::identify::{IdentifyConfig, MotionPlan};
use ftwire_estimate::log::{LogPose, LogRecord, to_line};
use ftwire_lab::csv_table::{Cell, CsvTable, text, value};
use ftwire_lab::error::{LabError, from_estimate, from_rod, from_sim};
use ftwire_lab::experiment::Gravity;
use ftwire_lab::experiment::calibration::load_or_run;
use ftwire_lab::experiment::rig::{
    believed_tip, measure_over, mounting, pipeline, place_wire, tare,
};
use ftwire_lab::header::RunHeader;
use ftwire_lab::paper::TABLE_I;
use ftwire_lab::results::{OutGuard, ResultsFolder};
use ftwire_lab::setup::SimSetup;
use ftwire_lab::wire::{WireSpec, file_stem};
use ftwire_report::{LineChart, Series};
use ftwire_rod::{Rod, from_normalised};
use ftwire_sim::{RigConfig, SimRig};
use nalgebra::Vector6;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::Serialize;

use super::stats::median;
use crate::cli::experiment::{IdentifyExperimentArgs, IdentifyPipeline, ModelArg};
use crate::cli::identify::FormArg;
use crate::commands::identify::{flag_name, run_identification};

/// The wires of Table I: 2 mm / 630 mm and 3 mm / 820 mm nitinol.
const DEFAULT_WIRES: [&str; 2] = ["nitinol-2mm-630", "nitinol-3mm-820"];

/// Trials per wire (Table I: 10).
const DEFAULT_TRIALS: usize = 10;

/// Sample counts identified from, a subset of the paper's 2 to 30 (Figs. 3–4) that keeps the
/// full run to a few minutes.
const DEFAULT_SAMPLES: [usize; 9] = [2, 3, 4, 5, 7, 10, 15, 20, 30];

/// The most samples a trial records (`--samples` above it is bad input).
const MAX_SAMPLES: usize = 500;

/// Half-width of the box of normalised start configurations (`to_normalised` units): a
/// moderate load, well inside `A_stable` for most draws.
const START_BOX: f64 = 5.0;

/// Start configurations tried per trial before giving up (unstable draws, or a start the
/// simulator cannot hold).
const START_ATTEMPTS: usize = 20;

/// Names of the four parameters, in the order of every `[4]` array.
const PARAMETERS: [&str; 4] = ["c1", "c2", "c3", "L"];

/// One recorded sample of a trial.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Recorded {
    /// The rig's clock \[s\].
    pub(crate) time: f64,
    /// `ã` (tared, through the pipeline; torque first, base clamp frame).
    pub(crate) a: Vector6<f64>,
    /// `b̃`, the believed second-gripper pose relative to the base clamp.
    pub(crate) b: Pose,
}

/// One identification: a wire, a trial, a sample count.
#[derive(Debug, Clone)]
struct Row {
    /// The estimator's model.
    model: ModelArg,
    wire: usize,
    trial: usize,
    samples: usize,
    /// `(c1, c2, c3, L)`, or `None` when identification returned an error.
    eta: Option<[f64; 4]>,
    /// The identified linear density \[kg/m\] (the loaded model only).
    linear_density: Option<f64>,
    chi2_per_dof: f64,
    /// Flag name, `"error"`, or `None` when identified.
    flag: Option<&'static str>,
    evaluations: usize,
    compute_ms: f64,
}

/// A wire in `summary.json`.
#[derive(Debug, Serialize)]
struct WireOut {
    name: String,
    c: [f64; 3],
    length: f64,
    /// The true linear density `ρ π r²` \[kg/m\] (what the loaded model identifies).
    linear_density: f64,
}

/// One row of `by_samples`.
#[derive(Debug, Serialize)]
struct BySamples {
    samples: usize,
    estimated: usize,
    identified: usize,
    mean: [f64; 4],
    std: [f64; 4],
    relative_error: [f64; 4],
    mean_abs_relative_error: [f64; 4],
    mean_abs_relative_error_identified: [f64; 4],
    evaluations_median: f64,
    /// The identified linear density over the trials (the loaded model only).
    linear_density: Option<DensityStats>,
}

/// The identified linear density over trials.
#[derive(Debug, Serialize)]
struct DensityStats {
    mean: f64,
    std: f64,
    mean_abs_relative_error: f64,
}

/// One model's results over the wires.
#[derive(Debug, Serialize)]
struct ModelResults {
    model: ModelArg,
    wires: Vec<WireResults>,
}

/// A wire's results.
#[derive(Debug, Serialize)]
struct WireResults {
    wire: WireOut,
    by_samples: Vec<BySamples>,
}

/// `summary.json`'s body.
#[derive(Debug, Serialize)]
struct Summary<'a> {
    /// The estimator's model (`--model`); `wire`, `by_samples` and `wires` are its results.
    model: ModelArg,
    form: FormArg,
    gravity: Gravity,
    /// `--sensor`: a preset's name or the sensor file as given.
    sensor: &'a str,
    pipeline: IdentifyPipeline,
    /// The `--calibration` path, `"cached"` when one was run, `None` for the mounting pipeline.
    calibration: Option<String>,
    trials: usize,
    sample_counts: &'a [usize],
    wire: &'a WireOut,
    by_samples: &'a [BySamples],
    wires: &'a [WireResults],
    /// Every model run on the same data (with gravity on, both), `--model` first.
    by_model: &'a [ModelResults],
}

/// `timings.json`.
#[derive(Debug, Serialize)]
struct Timings<'a> {
    /// The calibration run \[s\] (0 when loaded or not needed).
    calibration_s: f64,
    /// Every identification.
    identifications: Vec<Timing<'a>>,
    /// The median over the trials of each model, wire and sample count (Fig. 4).
    compute_ms_median: Vec<MedianTiming<'a>>,
}

/// The median identification time of a model, wire and sample count in `timings.json`.
#[derive(Debug, Serialize)]
struct MedianTiming<'a> {
    model: ModelArg,
    wire: &'a str,
    samples: usize,
    compute_ms_median: f64,
}

/// One identification's timing in `timings.json`.
#[derive(Debug, Serialize)]
struct Timing<'a> {
    model: ModelArg,
    wire: &'a str,
    trial: usize,
    samples: usize,
    compute_ms: f64,
}

/// Runs the experiment.
pub fn run(args: IdentifyExperimentArgs) -> Result<(), LabError> {
    let wires = wires(&args)?;
    let trials = args.common.trials.unwrap_or(DEFAULT_TRIALS);
    let counts = sample_counts(args.samples.as_deref())?;
    let config = args.settings.config()?;
    let setup = args.common.setup.load()?;
    check_pipeline(&args, &setup)?;
    let gravity = args.common.gravity;
    let model = args.common.model();
    // Both models identify from the same data, `--model` first. Without gravity the loaded
    // model of these straight-at-rest wires is the paper's, so it runs alone.
    let settings = |kind| match kind {
        ModelArg::Loaded => loaded_config(&config, gravity),
        ModelArg::Weightless => config.clone(),
    };
    let models: Vec<(ModelArg, IdentifyConfig)> = match gravity {
        Gravity::Off => vec![(model, settings(model))],
        Gravity::On => vec![
            (model, settings(model)),
            (model.other(), settings(model.other())),
        ],
    };
    let folder = args.common.open_results(
        "identify",
        OutGuard::default().input_opt("--calibration", args.calibration.as_deref()),
    )?;
    let seed = args.common.seed.seed;
    let recorded = counts.last().copied().unwrap_or(2);
    // The start pose and `recorded − 1` moves.
    let plan = MotionPlan {
        moves: recorded - 1,
        twist: args.twist.to_radians(),
        ..MotionPlan::default()
    };
    plan.validate()
        .map_err(|e| LabError::bad_input(format!("--twist {}: {e}", args.twist)))?;
    let protocol = Protocol {
        plan,
        rest_samples: args.rest_samples,
    };
    let (learnt, calibration, calibration_s) = match args.pipeline {
        IdentifyPipeline::Mounting => (None, None, 0.0),
        IdentifyPipeline::Calibrated => {
            if args.calibration.is_none() {
                eprintln!("identify: no --calibration: calibrating on the known wire first");
            }
            let start = Instant::now();
            let (learnt, _) = load_or_run(
                args.calibration.as_deref(),
                (gravity, model),
                &setup,
                seed,
                |_| {},
            )?;
            match &args.calibration {
                Some(path) => (Some(learnt), Some(path.display().to_string()), 0.0),
                None => {
                    let seconds = start.elapsed().as_secs_f64();
                    let json = learnt
                        .to_json()
                        .map_err(|e| from_estimate(e, "writing the calibration weights"))?;
                    folder.write("calibration.json", json)?;
                    (Some(learnt), Some("cached".to_owned()), seconds)
                }
            }
        }
    };
    let map = learnt.as_ref().map_or(Map::Mounting, Map::Learnt);

    let mut rows = Vec::new();
    for (w, wire) in wires.iter().enumerate() {
        for trial in 0..trials {
            let stream = ((w as u64) << 32) | trial as u64;
            let samples = record_trial(wire, gravity, &setup, map, seed, stream, &protocol)
                .map_err(|e| e.context(format!("wire {} trial {trial}", wire.name)))?;
            for (model, config) in &models {
                let line = identify_trial(
                    &samples,
                    &counts,
                    (*model, config),
                    seed,
                    (w, trial),
                    &mut rows,
                );
                eprintln!(
                    "identify: {} trial {trial} ({} model): {line}",
                    wire.name,
                    model.name()
                );
            }
            if args.save_log {
                folder.write(
                    &format!("logs/{}", log_name(&wire.name, trial)),
                    log_text(&samples)?,
                )?;
            }
        }
    }

    let by_model: Vec<ModelResults> = models
        .iter()
        .map(|(model, _)| ModelResults {
            model: *model,
            wires: wires
                .iter()
                .enumerate()
                .map(|(w, wire)| WireResults {
                    wire: WireOut {
                        name: wire.name.clone(),
                        c: wire.c,
                        length: wire.length,
                        linear_density: linear_density(wire),
                    },
                    by_samples: counts
                        .iter()
                        .map(|&n| {
                            aggregate(
                                wire,
                                rows.iter()
                                    .filter(|r| r.model == *model && r.wire == w && r.samples == n),
                                n,
                            )
                        })
                        .collect(),
                })
                .collect(),
        })
        .collect();
    let results = by_model
        .first()
        .map(|m| m.wires.as_slice())
        .unwrap_or_default();
    let first = results
        .first()
        .ok_or_else(|| LabError::bad_input("no wire to identify"))?;
    let summary = Summary {
        model,
        form: args.settings.form,
        gravity,
        sensor: &setup.sensor.name,
        pipeline: args.pipeline,
        calibration,
        trials,
        sample_counts: &counts,
        wire: &first.wire,
        by_samples: &first.by_samples,
        wires: results,
        by_model: &by_model,
    };
    let mut medians = Vec::new();
    for &(model, _) in &models {
        for (w, wire) in wires.iter().enumerate() {
            for &samples in &counts {
                medians.push(MedianTiming {
                    model,
                    wire: &wire.name,
                    samples,
                    compute_ms_median: compute_ms_median(&rows, model, w, samples),
                });
            }
        }
    }
    let timings = Timings {
        calibration_s,
        compute_ms_median: medians,
        identifications: rows
            .iter()
            .map(|r| Timing {
                model: r.model,
                wire: &wires[r.wire].name,
                trial: r.trial,
                samples: r.samples,
                compute_ms: r.compute_ms,
            })
            .collect(),
    };
    folder.write("identify.csv", csv(&wires, &rows)?)?;
    folder.write_json("timings.json", &timings)?;
    let median_ms = |w: usize, n: usize| compute_ms_median(&rows, model, w, n);
    write_figures(&folder, results, &median_ms)?;
    let header = RunHeader::new("experiment identify", Some(seed), &args)?;
    let target = folder.finish(&header, &summary)?;
    print!("{}", table(&summary, &target, &median_ms));
    Ok(())
}

/// `--pipeline` against `--sensor` and `--calibration`: the undistorted sensor is what a
/// perfect calibration gives, so a learnt one on top of it is not meant; weights given to the
/// mounting pipeline would be silently unused.
fn check_pipeline(args: &IdentifyExperimentArgs, setup: &SimSetup) -> Result<(), LabError> {
    match args.pipeline {
        IdentifyPipeline::Calibrated if setup.sensor.is_undistorted() => Err(LabError::bad_input(
            "--sensor undistorted already removes what the calibration learns (and the \
                 calibration is learnt on the distorted sensor): use it with --pipeline mounting",
        )),
        IdentifyPipeline::Mounting if args.calibration.is_some() => Err(LabError::bad_input(
            "--calibration is for --pipeline calibrated; --pipeline mounting uses no weights",
        )),
        _ => Ok(()),
    }
}

/// The map from the tared reading to `ã`: the sensor's mounting (built per trial from the
/// rig's configuration), or the learnt calibration.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Map<'a> {
    /// `--pipeline mounting`.
    Mounting,
    /// `--pipeline calibrated`.
    Learnt(&'a Calibration),
}

/// The wires: `--wire`, or Table I's.
fn wires(args: &IdentifyExperimentArgs) -> Result<Vec<WireSpec>, LabError> {
    let names: Vec<&str> = match &args.common.wire {
        Some(given) => vec![given.as_str()],
        None => DEFAULT_WIRES.to_vec(),
    };
    names
        .into_iter()
        .map(|name| WireSpec::load(name).map_err(|e| LabError::bad_input(format!("--wire: {e}"))))
        .collect()
}

/// The sample counts, sorted, each in `[2, MAX_SAMPLES]`.
fn sample_counts(given: Option<&[usize]>) -> Result<Vec<usize>, LabError> {
    let mut counts = given.map_or_else(|| DEFAULT_SAMPLES.to_vec(), <[usize]>::to_vec);
    if counts.is_empty() {
        return Err(LabError::bad_input("--samples: give at least one count"));
    }
    if let Some(bad) = counts.iter().find(|&&n| !(2..=MAX_SAMPLES).contains(&n)) {
        return Err(LabError::bad_input(format!(
            "--samples: {bad} is not allowed: each count must be in [2, {MAX_SAMPLES}] \
             (identification needs motion, so at least two samples)"
        )));
    }
    counts.sort_unstable();
    counts.dedup();
    Ok(counts)
}

/// Places the wire, tares, follows the motion plan, and records a sample at the start pose and
/// after each of the plan's moves. A start the simulator cannot hold or a move it cannot follow
/// (no answer) starts the trial again from another `a0`.
pub(crate) fn record_trial(
    wire: &WireSpec,
    gravity: Gravity,
    setup: &SimSetup,
    map: Map<'_>,
    seed: u64,
    stream: u64,
    protocol: &Protocol,
) -> Result<Vec<Recorded>, LabError> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(stream);
    let params = wire
        .wire_params()
        .map_err(|e| LabError::bad_input(format!("wire {}: {e}", wire.name)))?;
    let truth = Rod::new(params);
    let mut last = LabError::no_answer(format!(
        "no stable start configuration in [−{START_BOX}, {START_BOX}]⁶ (normalised) after \
         {START_ATTEMPTS} draws"
    ));
    for _ in 0..START_ATTEMPTS {
        let z = Vector6::from_fn(|_, _| rng.random_range(-START_BOX..START_BOX));
        let a0 = from_normalised(&params, &z);
        if !truth
            .is_stable(&a0)
            .map_err(|e| from_rod(e, "checking the start configuration"))?
        {
            continue;
        }
        let config = setup.rig_config(rng.random());
        match follow_plan(wire, gravity, &a0, config, map, protocol, &mut rng) {
            Ok(samples) => return Ok(samples),
            Err(e) if e.exit_code() == ftwire_lab::error::EXIT_NO_ANSWER => last = e,
            Err(e) => return Err(e),
        }
    }
    Err(last)
}

/// One attempt of a trial from `a0`: places the wire, tares, and follows the plan through
/// `map`.
fn follow_plan(
    wire: &WireSpec,
    gravity: Gravity,
    a0: &Vector6<f64>,
    config: RigConfig,
    map: Map<'_>,
    protocol: &Protocol,
    rng: &mut ChaCha8Rng,
) -> Result<Vec<Recorded>, LabError> {
    let mut rig = place_wire(wire, gravity, a0, config.clone())?;
    let tared = tare(&mut rig)?;
    match map {
        Map::Mounting => {
            let pipeline = pipeline(tared, mounting(&config)?)?;
            follow(&mut rig, &pipeline, protocol, rng)
        }
        Map::Learnt(learnt) => {
            let pipeline = pipeline(tared, learnt.clone())?;
            follow(&mut rig, &pipeline, protocol, rng)
        }
    }
}

/// How a trial moves and measures: the library's motion plan, and the F/T samples averaged at
/// each rest.
pub(crate) struct Protocol {
    /// The library's identification motion.
    pub(crate) plan: MotionPlan,
    /// F/T samples averaged at each rest.
    pub(crate) rest_samples: usize,
}

/// Records the sample at the current rest, then one after each move of the plan.
fn follow<C: FtCalibration>(
    rig: &mut SimRig,
    pipeline: &FtPipeline<C>,
    protocol: &Protocol,
    rng: &mut ChaCha8Rng,
) -> Result<Vec<Recorded>, LabError> {
    let b0 = believed_tip(rig)?;
    let poses = protocol.plan.poses(&b0, rng);
    let mut samples = Vec::with_capacity(poses.len() + 1);
    samples.push(record(rig, pipeline, protocol.rest_samples)?);
    for b in poses {
        let base = rig
            .gripper_poses()
            .map_err(|e| from_sim(e, "reading the gripper poses"))?
            .base;
        rig.move_tip(base * b)
            .map_err(|e| from_sim(e, "moving the second gripper"))?;
        samples.push(record(rig, pipeline, protocol.rest_samples)?);
    }
    Ok(samples)
}

/// One sample at the rig's current rest.
fn record<C: FtCalibration>(
    rig: &mut SimRig,
    pipeline: &FtPipeline<C>,
    rest_samples: usize,
) -> Result<Recorded, LabError> {
    let a = measure_over(rig, pipeline, rest_samples)?.a;
    Ok(Recorded {
        time: rig.time(),
        a,
        b: believed_tip(rig)?,
    })
}

/// Identifies from the first `n` samples for each count with one model and its settings;
/// pushes the rows (tagged with the model, the wire's index and the trial) and returns a
/// progress line.
fn identify_trial(
    samples: &[Recorded],
    counts: &[usize],
    (model, config): (ModelArg, &IdentifyConfig),
    seed: u64,
    (wire, trial): (usize, usize),
    rows: &mut Vec<Row>,
) -> String {
    let pairs: Vec<(Vector6<f64>, Pose)> = samples.iter().map(|s| (s.a, s.b)).collect();
    let mut line = String::new();
    for &n in counts {
        let Some(prefix) = pairs.get(..n) else {
            continue;
        };
        let start = Instant::now();
        let result = run_identification(prefix, config, seed);
        let compute_ms = start.elapsed().as_secs_f64() * 1e3;
        let row = match result {
            Ok(estimate) => Row {
                model,
                wire,
                trial,
                samples: n,
                eta: Some([estimate.c[0], estimate.c[1], estimate.c[2], estimate.length]),
                linear_density: estimate.linear_density,
                chi2_per_dof: estimate.chi2_per_dof,
                flag: flag_name(estimate.unidentified.as_ref()),
                evaluations: estimate.evaluations,
                compute_ms,
            },
            Err(e) => {
                eprintln!("identify: trial {trial}, {n} samples: {e}");
                Row {
                    model,
                    wire,
                    trial,
                    samples: n,
                    eta: None,
                    linear_density: None,
                    chi2_per_dof: f64::NAN,
                    flag: Some("error"),
                    evaluations: 0,
                    compute_ms,
                }
            }
        };
        let _ = write!(
            line,
            "{n}:{} ",
            row.flag
                .map_or("ok", |f| if f == "error" { "err" } else { "flag" })
        );
        rows.push(row);
    }
    line
}

/// The settings of the loaded model: `config` with the wire's linear density identified under
/// the experiment's gravity. The rig's base clamp sits at the world origin with the world's
/// axes ([`place_wire`]), so gravity in the base clamp frame is the world's.
pub(crate) fn loaded_config(config: &IdentifyConfig, gravity: Gravity) -> IdentifyConfig {
    let mut loaded = config.clone();
    if gravity == Gravity::On {
        loaded.constraints.weight = Some(gravity.vector());
    }
    loaded
}

/// The wire's true linear density `ρ π r²` \[kg/m\].
pub(crate) fn linear_density(wire: &WireSpec) -> f64 {
    wire.density * std::f64::consts::PI * wire.radius * wire.radius
}

/// The true `(c1, c2, c3, L)`.
pub(crate) fn truth(wire: &WireSpec) -> [f64; 4] {
    [wire.c[0], wire.c[1], wire.c[2], wire.length]
}

/// The mean of `|e[j] − truth| / truth` over `estimates` (NaN for none).
fn mean_abs_relative(estimates: &[[f64; 4]], j: usize, truth: f64) -> f64 {
    estimates
        .iter()
        .map(|e| (e[j] - truth).abs() / truth)
        .sum::<f64>()
        / estimates.len() as f64
}

/// One `by_samples` row from the rows of a wire and a sample count.
fn aggregate<'a>(wire: &WireSpec, rows: impl Iterator<Item = &'a Row>, n: usize) -> BySamples {
    let rows: Vec<&Row> = rows.collect();
    let truth = truth(wire);
    let estimates: Vec<[f64; 4]> = rows.iter().filter_map(|r| r.eta).collect();
    let count = estimates.len() as f64;
    let mut mean = [f64::NAN; 4];
    let mut std = [f64::NAN; 4];
    let mut relative_error = [f64::NAN; 4];
    let mut mean_abs_relative_error = [f64::NAN; 4];
    let trusted: Vec<[f64; 4]> = rows
        .iter()
        .filter(|r| r.flag.is_none())
        .filter_map(|r| r.eta)
        .collect();
    let mean_abs_relative_error_identified =
        std::array::from_fn(|j| mean_abs_relative(&trusted, j, truth[j]));
    if !estimates.is_empty() {
        for j in 0..4 {
            let m = estimates.iter().map(|e| e[j]).sum::<f64>() / count;
            let var = if estimates.len() > 1 {
                estimates.iter().map(|e| (e[j] - m).powi(2)).sum::<f64>() / (count - 1.0)
            } else {
                0.0
            };
            mean[j] = m;
            std[j] = var.sqrt();
            relative_error[j] = (m - truth[j]).abs() / truth[j];
            mean_abs_relative_error[j] = mean_abs_relative(&estimates, j, truth[j]);
        }
    }
    let densities: Vec<f64> = rows.iter().filter_map(|r| r.linear_density).collect();
    let linear_density = (!densities.is_empty()).then(|| {
        let count = densities.len() as f64;
        let mean = densities.iter().sum::<f64>() / count;
        let truth = self::linear_density(wire);
        let var =
            densities.iter().map(|d| (d - mean).powi(2)).sum::<f64>() / (count - 1.0).max(1.0);
        DensityStats {
            mean,
            std: var.sqrt(),
            mean_abs_relative_error: densities
                .iter()
                .map(|d| (d - truth).abs() / truth)
                .sum::<f64>()
                / count,
        }
    });
    BySamples {
        linear_density,
        samples: n,
        estimated: estimates.len(),
        identified: rows.iter().filter(|r| r.flag.is_none()).count(),
        mean,
        std,
        relative_error,
        mean_abs_relative_error,
        mean_abs_relative_error_identified,
        evaluations_median: median(
            &rows
                .iter()
                .map(|r| r.evaluations as f64)
                .collect::<Vec<_>>(),
        ),
    }
}

/// `identify.csv`.
fn csv(wires: &[WireSpec], rows: &[Row]) -> Result<Vec<u8>, LabError> {
    let mut table = CsvTable::new(
        "identify.csv",
        &[
            "wire",
            "trial",
            "samples",
            "c1",
            "c2",
            "c3",
            "L",
            "rel_err_c1",
            "rel_err_c2",
            "rel_err_c3",
            "rel_err_L",
            "chi2_per_dof",
            "evaluations",
            "identified",
            "flag",
            "model",
            "linear_density",
        ],
    )?;
    for row in rows {
        let Some(wire) = wires.get(row.wire) else {
            continue;
        };
        let truth = truth(wire);
        let eta = row.eta.unwrap_or([f64::NAN; 4]);
        let mut cells = vec![text(&wire.name), value(row.trial), value(row.samples)];
        cells.extend(eta.iter().map(|&v| value(v)));
        cells.extend(
            eta.iter()
                .zip(truth)
                .map(|(v, true_value)| value((v - true_value) / true_value)),
        );
        cells.extend([
            value(row.chi2_per_dof),
            value(row.evaluations),
            value(row.flag.is_none()),
            text(row.flag.unwrap_or("")),
            text(row.model.name()),
            row.linear_density.map_or_else(Cell::empty, value),
        ]);
        table.row(cells)?;
    }
    table.into_bytes()
}

/// The median wall time \[ms\] of `model`'s identifications of wire `wire` (its index) from
/// `samples` samples, over the trials (NaN for none).
fn compute_ms_median(rows: &[Row], model: ModelArg, wire: usize, samples: usize) -> f64 {
    let times: Vec<f64> = rows
        .iter()
        .filter(|r| r.model == model && r.wire == wire && r.samples == samples)
        .map(|r| r.compute_ms)
        .collect();
    median(&times)
}

/// Figs. 3 and 4 into the results folder: the errors of `results`, and the time of each wire
/// (its index) and sample count from `median_ms`.
fn write_figures(
    folder: &ResultsFolder,
    results: &[WireResults],
    median_ms: &dyn Fn(usize, usize) -> f64,
) -> Result<(), LabError> {
    let mut charts = Vec::new();
    let mut time = LineChart::new(
        "identification time against samples (Fig. 4)",
        "samples",
        "compute time, median over trials [ms]",
    );
    for (w, result) in results.iter().enumerate() {
        let mut error = LineChart::new(
            format!(
                "{}: identification error against samples (Fig. 3)",
                result.wire.name
            ),
            "samples",
            "mean |relative error| [%]",
        )
        .with_log_y();
        for (j, parameter) in PARAMETERS.iter().enumerate() {
            let points = result
                .by_samples
                .iter()
                .map(|r| (r.samples as f64, 100.0 * r.mean_abs_relative_error[j]))
                .collect();
            error = error.with_series(Series::line_points(*parameter, points));
        }
        charts.push((
            error,
            format!("error_vs_samples_{}", file_stem(&result.wire.name)),
        ));
        let points = result
            .by_samples
            .iter()
            .map(|r| (r.samples as f64, median_ms(w, r.samples)))
            .collect();
        time = time.with_series(Series::line_points(result.wire.name.clone(), points));
    }
    charts.push((time, ftwire_lab::report::TIMING_FIGURES[0].to_owned()));
    for (chart, stem) in &charts {
        match chart.write(folder.dir(), stem) {
            // A figure without a drawable point (every estimate failed) is left out.
            Ok(_) | Err(ftwire_report::ReportError::Empty { .. }) => {}
            Err(e) => return Err(LabError::no_answer(format!("drawing {stem}: {e}"))),
        }
    }
    Ok(())
}

/// `<wire>-trial<k>.jsonl` (see [`file_stem`]).
fn log_name(wire: &str, trial: usize) -> String {
    format!("{}-trial{trial}.jsonl", file_stem(wire))
}

/// A trial's JSON Lines log.
fn log_text(samples: &[Recorded]) -> Result<String, LabError> {
    let mut text = String::new();
    for sample in samples {
        let record = LogRecord {
            time: sample.time,
            raw: None,
            a: Some(sample.a.into()),
            b: LogPose::from_pose(&sample.b),
            markers: None,
        };
        let line = to_line(&record).map_err(|e| LabError::no_answer(e.to_string()))?;
        text.push_str(&line);
        text.push('\n');
    }
    Ok(text)
}

/// The printed table: per wire, the 3-sample row (or the smallest count) beside Table I, and
/// one line per sample count with its median time from `median_ms` (of the wire's index and
/// the count).
fn table(summary: &Summary<'_>, target: &Path, median_ms: &dyn Fn(usize, usize) -> f64) -> String {
    let mut text = String::new();
    let _ = writeln!(
        text,
        "identify: gravity {:?}, {} model, {} sensor, {:?} pipeline{}, {:?} residual, {} \
         trials; results in {}",
        summary.gravity,
        summary.model.name(),
        summary.sensor,
        summary.pipeline,
        summary
            .calibration
            .as_ref()
            .map_or_else(String::new, |c| format!(" ({c})")),
        summary.form,
        summary.trials,
        target.display()
    );
    for (w, result) in summary.wires.iter().enumerate() {
        let paper = TABLE_I
            .iter()
            .find(|(name, _)| *name == result.wire.name)
            .map(|(_, rows)| rows);
        let Some(row) = result
            .by_samples
            .iter()
            .find(|r| r.samples == 3)
            .or_else(|| result.by_samples.first())
        else {
            continue;
        };
        let _ = writeln!(
            text,
            "\n{} ({} samples; {} of {} trials identified)",
            result.wire.name, row.samples, row.identified, summary.trials
        );
        let _ = writeln!(
            text,
            "  {:<3} {:>8} {:>22} {:>10} {:>12}   paper (Table I, 3 samples)",
            "", "true", "estimated", "err(mean)", "mean|err|"
        );
        let truth = [
            result.wire.c[0],
            result.wire.c[1],
            result.wire.c[2],
            result.wire.length,
        ];
        for (j, parameter) in PARAMETERS.iter().enumerate() {
            let paper_text = paper.map_or_else(
                || "—".to_owned(),
                |rows| {
                    let (_, estimate, pm, error) = rows[j];
                    format!("{estimate:.3} ± {pm:.3}, {error:.1} %")
                },
            );
            let _ = writeln!(
                text,
                "  {parameter:<3} {:>8.4} {:>11.5} ± {:<8.5} {:>8.3} % {:>10.3} %   {paper_text}",
                truth[j],
                row.mean[j],
                row.std[j],
                100.0 * row.relative_error[j],
                100.0 * row.mean_abs_relative_error[j],
            );
        }
        let _ = writeln!(
            text,
            "  samples: mean |relative error| c1 c2 c3 L [%] (all; identified only), \
             identified, compute median [ms]"
        );
        for r in &result.by_samples {
            let e = r.mean_abs_relative_error.map(|v| 100.0 * v);
            let t = r.mean_abs_relative_error_identified.map(|v| 100.0 * v);
            let _ = writeln!(
                text,
                "  {:>3}: {:>7.3} {:>7.3} {:>7.3} {:>7.3};  {:>7.3} {:>7.3} {:>7.3} {:>7.3}   \
                 {:>2}/{}   {:>8.1}",
                r.samples,
                e[0],
                e[1],
                e[2],
                e[3],
                t[0],
                t[1],
                t[2],
                t[3],
                r.identified,
                summary.trials,
                median_ms(w, r.samples)
            );
        }
        if let Some(density) = row.linear_density.as_ref() {
            let _ = writeln!(
                text,
                "  linear density ({} samples): true {:.5} kg/m, estimated {:.5} ± {:.5}, \
                 mean |err| {:.2} %",
                row.samples,
                result.wire.linear_density,
                density.mean,
                density.std,
                100.0 * density.mean_abs_relative_error
            );
        }
    }
    for other in summary.by_model.iter().skip(1) {
        let _ = writeln!(
            text,
            "\nthe same data through the {} model (mean |relative error| c1 c2 c3 L [%], \
             identified):",
            other.model.name()
        );
        for result in &other.wires {
            if let Some(r) = result
                .by_samples
                .iter()
                .find(|r| r.samples == 3)
                .or_else(|| result.by_samples.first())
            {
                let e = r.mean_abs_relative_error.map(|v| 100.0 * v);
                let _ = writeln!(
                    text,
                    "  {} ({} samples): {:>7.3} {:>7.3} {:>7.3} {:>7.3}   {:>2}/{}",
                    result.wire.name,
                    r.samples,
                    e[0],
                    e[1],
                    e[2],
                    e[3],
                    r.identified,
                    summary.trials
                );
            }
        }
    }
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sample_counts_are_sorted_and_checked() {
        assert_eq!(sample_counts(Some(&[5, 2, 5])).ok(), Some(vec![2, 5]));
        assert_eq!(sample_counts(None).ok(), Some(DEFAULT_SAMPLES.to_vec()));
        for bad in [&[1][..], &[], &[2, MAX_SAMPLES + 1]] {
            assert_eq!(sample_counts(Some(bad)).map_err(|e| e.exit_code()), Err(2));
        }
    }

    #[test]
    fn statistics_are_of_the_mean_and_of_each_trial() {
        let wire = WireSpec::preset("nitinol-2mm-630").expect("a preset");
        let t = truth(&wire);
        let row = |trial, scale: f64| Row {
            model: ModelArg::Weightless,
            linear_density: None,
            wire: 0,
            trial,
            samples: 3,
            eta: Some(t.map(|v| v * scale)),
            chi2_per_dof: 1.0,
            flag: None,
            evaluations: 10,
            compute_ms: trial as f64,
        };
        // +1 % and −1 %: the mean is exact, each trial is 1 % off.
        let rows = [row(0, 1.01), row(1, 0.99), row(2, 1.0)];
        let out = aggregate(&wire, rows.iter(), 3);
        for (j, true_value) in t.iter().enumerate() {
            assert!(out.relative_error[j] < 1e-12);
            assert!((out.mean_abs_relative_error[j] - 0.02 / 3.0).abs() < 1e-12);
            assert!((out.std[j] - 0.01 * true_value).abs() < 1e-12);
        }
        assert_eq!(out.identified, 3);
        let mut flagged = rows.to_vec();
        flagged[0].flag = Some("residual_above_noise");
        let out = aggregate(&wire, flagged.iter(), 3);
        assert_eq!(out.identified, 2);
        assert!((out.mean_abs_relative_error_identified[3] - 0.005).abs() < 1e-12);
        assert!((out.mean_abs_relative_error[3] - 0.02 / 3.0).abs() < 1e-12);
        assert!((compute_ms_median(&rows, ModelArg::Weightless, 0, 3) - 1.0).abs() < 1e-12);
        assert!(compute_ms_median(&rows, ModelArg::Loaded, 0, 3).is_nan());
        assert_eq!(log_name("a b/c", 4), "a_b_c-trial4.jsonl");
    }
}
