//! The identification experiment (paper §IV-B, Table I and Figs. 3–4): identify
//! `η = (c1, c2, c3, L)` of the nitinol wires from random motion of the second gripper, over
//! trials and numbers of samples.
//!
//! Per wire and trial, in the simulator (the true wire is given to the simulator only):
//! 1. the operator places the wire at a random start configuration `a0` (normalised within
//!    `[−5, 5]⁶`, stable for the true wire; [`crate::experiment::rig::place_wire`]) and the
//!    robot tares its sensor before the pick-up ([`crate::experiment::rig::tare`]);
//! 2. the second gripper follows the library's identification [`MotionPlan`] (seeded; its
//!    twist about the wire's tangent is [`IdentifyParams::twist`], default 40°), and at each
//!    rest the robot records `(ã, b̃)` ([`record_trial`]): `ã` from the tared reading averaged
//!    over [`IdentifyParams::rest_samples`] samples through the learnt calibration by default
//!    ([`Pipeline::Calibrated`]: a calibration file, or a calibration run first on the known
//!    wire with this run's gravity and seed and cached as `calibration.json`), or through the
//!    sensor's mounting only ([`Pipeline::Mounting`]: the sensor's gain error and cross-talk
//!    of about 1 % stay in `ã`; for comparison, and with the undistorted sensor what a perfect
//!    calibration gives); `b̃` the believed pose;
//! 3. for every sample count `n`, `η` is identified from the first `n` samples with the swarm
//!    seeded by the run's seed (a fresh generator per identification, as
//!    `ftwire identify --log` does, so the log command reproduces each estimate;
//!    [`run_identification`]), with the estimators' model: `kirchhoff`, the paper's, or
//!    `loaded` (default with gravity on), which also identifies the wire's linear density `λ`
//!    under the known gravity ([`loaded_config`]). With gravity on, the other model
//!    identifies from the same data as well, reported beside it.
//!
//! [`run`] writes into the results folder:
//! - `identify.csv`: one row per model, wire, trial and sample count (estimate, relative
//!   errors, `χ²/dof`, flags, `model`, `linear_density`);
//! - `error_vs_samples_<wire>.{png,svg}` (Fig. 3, log y, one per wire) and
//!   `time_vs_samples.{png,svg}` (Fig. 4, from the timings; a timing figure, left out of
//!   `report.md` and `report.html`, [`crate::report::TIMING_FIGURES`]);
//! - with `save_log`, `logs/<wire>-trial<k>.jsonl`: each trial's records `{time, a, b}` in
//!   the format of `ftwire_estimate::log`, with `a` the configuration as identified from
//!   (tared, through the pipeline), `time` the rig's clock;
//! - `calibration.json`: the weights, when a calibration was run.
//!
//! The caller writes `summary.json` ([`IdentifySummary`]: every value the same for the same
//! seed) and `timings.json` ([`IdentifyTimings`]), and may print [`IdentifyRun::text`], the
//! results as text beside Table I. In each `by_samples` row, `relative_error`
//! is that of the mean over trials (Table I), `mean_abs_relative_error` the mean of each
//! trial's absolute relative error, both over the trials that returned an estimate
//! (`estimated`), flagged ones included; `identified` counts the trials whose estimate was not
//! flagged, and `mean_abs_relative_error_identified` is the mean over those only. Guarded by
//! `tests/experiments.rs` and the recorded summary of
//! `crates/ftwire/tests/names_and_timings_cli.rs`.

mod estimate;
mod method;
mod summary;
pub mod text;
mod trial;
pub mod until;

use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Instant;

use ftwire_estimate::calibration::Calibration;
use ftwire_estimate::identify::{IdentifierParams, Sample};
use serde::Serialize;

pub use self::estimate::loaded_config;
pub use self::method::Pipeline;
use self::summary::Row;
pub use self::summary::{
    BySamples, DensityStats, IdentifySummary, IdentifyTimings, MedianTiming, ModelResults,
    NoiseOut, PARAMETERS, Timing, WireOut, WireResults, linear_density, truth,
};
pub use self::trial::{Map, Protocol, Recorded, record_trial};
use crate::error::{LabError, from_estimate};
use crate::experiment::calibration::load_or_run;
use crate::experiment::{CommonParams, Gravity, ModelKind, Progress};
use crate::results::ResultsFolder;
use crate::setup::SimSetup;
use crate::wire::WireSpec;
pub use ftwire_estimate::identify::MotionPlan;
pub use ftwire_logs::identification::{
    Form, ResidualParams, TEMPLATE_RADIUS, data_sheet_noise, flag_name, identifier,
    run_identification, template_model,
};

/// The wires of Table I: 2 mm / 630 mm and 3 mm / 820 mm nitinol.
pub const DEFAULT_WIRES: [&str; 2] = ["nitinol-2mm-630", "nitinol-3mm-820"];

/// Trials per wire (Table I: 10).
pub const DEFAULT_TRIALS: usize = 10;

/// Sample counts identified from, a subset of the paper's 2 to 30 (Figs. 3–4) that keeps the
/// full run to a few minutes.
pub const DEFAULT_SAMPLES: [usize; 9] = [2, 3, 4, 5, 7, 10, 15, 20, 30];

/// The most samples a trial records (a larger sample count is bad input).
pub const MAX_SAMPLES: usize = 500;

/// The twist of each identification move about the wire's tangent by default \[degrees\].
pub const DEFAULT_TWIST: f64 = 40.0;

/// F/T samples averaged at each rest of the identification motion by default. At the
/// simulated sensor's 1 kHz, 400 is a 0.4 s rest: the white noise of `ã` falls as `1/√N`,
/// while the sensor's bias drifts on for the time the rests take; the two balance near
/// `σ √f / q ≈ 800` for the default sensor (noise σ, rate f, drift intensity q), and of 100,
/// 400 and 1000 the unseen-wire survey (`crates/ftwire/tests/identify_unseen.rs`) measured
/// 400 best.
pub const REST_SAMPLES: usize = 400;

/// The settings of the identification experiment.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct IdentifyParams {
    /// The settings every experiment takes (`wire` replaces [`DEFAULT_WIRES`], `trials`
    /// [`DEFAULT_TRIALS`]).
    pub common: CommonParams,
    /// Write each trial's samples as a JSON Lines log (`logs/`).
    pub save_log: bool,
    /// Sample counts to identify from, each from the first N samples of every trial, each in
    /// `[2, MAX_SAMPLES]`; `None`: [`DEFAULT_SAMPLES`].
    pub samples: Option<Vec<usize>>,
    /// The residual form and the known relations between the parameters.
    pub settings: ResidualParams,
    /// The twist of each identification move about the wire's tangent at the second gripper
    /// \[degrees\] (default [`DEFAULT_TWIST`]; see `MotionPlan`).
    pub twist: f64,
    /// F/T samples averaged at each rest of the motion (default [`REST_SAMPLES`]).
    pub rest_samples: usize,
    /// How `ã` is computed from the tared reading.
    pub pipeline: Pipeline,
    /// Learnt calibration weights for [`Pipeline::Calibrated`]; `None`: a calibration is first
    /// run on the known wire (with this run's gravity and seed) and cached in the folder.
    pub calibration: Option<PathBuf>,
    /// Identify with what the samples share modelled: the tare's offset and its drift
    /// ([`crate::experiment::rig::identification_noise`]) and the map's gain error
    /// ([`crate::experiment::rig::simulated_rig_errors`]), estimated with the wire; `false`
    /// treats the errors of the samples as independent.
    pub bias_model: bool,
    /// Sample each trial until every parameter's 95 % half-width is within this percentage of
    /// its value, up to the largest sample count ([`until`]); `None`: off.
    pub until: Option<f64>,
}

impl Default for IdentifyParams {
    fn default() -> Self {
        Self {
            common: CommonParams::default(),
            save_log: false,
            samples: None,
            settings: ResidualParams::default(),
            twist: DEFAULT_TWIST,
            rest_samples: REST_SAMPLES,
            pipeline: Pipeline::default(),
            calibration: None,
            bias_model: true,
            until: None,
        }
    }
}

impl IdentifyParams {
    /// The wires: `common.wire`, or Table I's.
    ///
    /// # Errors
    /// Bad input for an unknown preset or a bad wire file.
    pub fn wires(&self) -> Result<Vec<WireSpec>, LabError> {
        let names: Vec<&str> = match &self.common.wire {
            Some(given) => vec![given.as_str()],
            None => DEFAULT_WIRES.to_vec(),
        };
        names
            .into_iter()
            .map(|name| {
                WireSpec::load(name).map_err(|e| LabError::bad_input(format!("--wire: {e}")))
            })
            .collect()
    }

    /// The sample counts, sorted and without repeats, each in `[2, MAX_SAMPLES]`.
    ///
    /// # Errors
    /// Bad input for no count or a count out of range.
    pub fn sample_counts(&self) -> Result<Vec<usize>, LabError> {
        sample_counts(self.samples.as_deref())
    }

    /// The motion plan of a trial recording `recorded` samples: the start pose and
    /// `recorded − 1` moves, each twisted by [`IdentifyParams::twist`].
    ///
    /// # Errors
    /// Bad input for a twist the plan refuses.
    pub fn plan(&self, recorded: usize) -> Result<MotionPlan, LabError> {
        let plan = MotionPlan {
            moves: recorded.saturating_sub(1),
            twist: self.twist.to_radians(),
            ..MotionPlan::default()
        };
        plan.validate()
            .map_err(|e| LabError::bad_input(format!("--twist {}: {e}", self.twist)))?;
        Ok(plan)
    }

    /// Checks the settings as [`run`] does before any work (the wires, the counts, the
    /// identification settings, the sensor and rig files, the pipeline against the sensor and
    /// the calibration, the twist), so that a caller can refuse bad input before it opens a results
    /// folder.
    ///
    /// # Errors
    /// Bad input naming what is wrong.
    pub fn check(&self) -> Result<(), LabError> {
        self.prepare().map(|_| ())
    }

    /// The checked settings: the wires, the sample counts, the settings of each model run
    /// (the estimators' model first) and the simulated setup.
    fn prepare(&self) -> Result<Prepared, LabError> {
        if let Some(target) = self.until
            && !(until::MIN_TARGET_PERCENT..=until::MAX_TARGET_PERCENT).contains(&target)
        {
            return Err(LabError::bad_input(format!(
                "--until {target}: give a percentage from {} to {}",
                until::MIN_TARGET_PERCENT,
                until::MAX_TARGET_PERCENT
            )));
        }
        let wires = self.wires()?;
        let counts = self.sample_counts()?;
        let setup = self.common.setup()?;
        let mut config = self.settings.config()?;
        if self.bias_model {
            config.noise = crate::experiment::rig::identification_noise(&setup, self.rest_samples)?;
        }
        // The simulated rig's own pose noise and, with the shared errors modelled, the map's
        // gain error, unless given.
        let (pose, gain) = crate::experiment::rig::simulated_rig_errors(
            &setup,
            self.pipeline == Pipeline::Calibrated,
        );
        config.noise.rotation = pose[0];
        config.noise.translation = pose[1];
        if self.bias_model {
            config.noise.torque_gain = Some(gain[0]);
            config.noise.gain = gain[1];
        }
        config.noise = self.settings.with_noise_settings(config.noise)?;
        // The wire model against the simulated rod, unless given.
        self.settings.with_model_floor(
            &mut config,
            crate::experiment::rig::SIM_MODEL_PARAMETER_ERROR,
        )?;
        self.check_pipeline(&setup)?;
        let plan = self.plan(counts.last().copied().unwrap_or(2))?;
        let gravity = self.common.gravity;
        let model = self.common.model();
        // Both models identify from the same data, the estimators' first. Without gravity
        // the loaded model of these straight-at-rest wires is the paper's, so it runs alone.
        let settings = |kind| match kind {
            ModelKind::Loaded => loaded_config(&config, gravity),
            ModelKind::Weightless => config.clone(),
        };
        let models = match gravity {
            Gravity::Off => vec![(model, settings(model))],
            Gravity::On => vec![
                (model, settings(model)),
                (model.other(), settings(model.other())),
            ],
        };
        Ok(Prepared {
            wires,
            counts,
            models,
            setup,
            plan,
        })
    }

    /// The pipeline against the sensor and the calibration: the undistorted sensor is what a
    /// perfect calibration gives, so a learnt one on top of it is not meant; weights given to
    /// the mounting pipeline would be silently unused.
    fn check_pipeline(&self, setup: &SimSetup) -> Result<(), LabError> {
        match self.pipeline {
            Pipeline::Calibrated if setup.sensor.is_undistorted() => Err(LabError::bad_input(
                "--sensor undistorted already removes what the calibration learns (and the \
                 calibration is learnt on the distorted sensor): use it with --pipeline mounting",
            )),
            Pipeline::Mounting if self.calibration.is_some() => Err(LabError::bad_input(
                "--calibration is for --pipeline calibrated; --pipeline mounting uses no weights",
            )),
            _ => Ok(()),
        }
    }
}

/// The settings of a run, checked.
struct Prepared {
    wires: Vec<WireSpec>,
    counts: Vec<usize>,
    /// Each model run and its identification settings, the estimators' model first.
    models: Vec<(ModelKind, IdentifierParams)>,
    setup: SimSetup,
    /// The motion of every trial.
    plan: MotionPlan,
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

/// A finished identification experiment.
#[derive(Debug, Clone)]
pub struct IdentifyRun {
    /// `summary.json`'s body (after the run header).
    pub summary: IdentifySummary,
    /// `timings.json`.
    pub timings: IdentifyTimings,
}

/// Runs the identification experiment into `folder` (see the module docs for what it
/// writes), reports a line per trial and model (and each failed identification) to
/// `progress`, and returns the summary and timings for the caller to write (it does not
/// finish the folder).
///
/// # Errors
/// Bad input for bad settings ([`IdentifyParams::check`]) or a bad calibration file; no answer
/// when a trial finds no start it can follow or a figure cannot be drawn; I/O errors writing
/// the folder.
pub fn run(
    settings: &IdentifyParams,
    folder: &ResultsFolder,
    progress: Progress<'_>,
) -> Result<IdentifyRun, LabError> {
    let Prepared {
        wires,
        counts,
        models,
        setup,
        plan,
    } = settings.prepare()?;
    let common = &settings.common;
    let (gravity, seed) = (common.gravity, common.seed);
    let trials = common.trials.unwrap_or(DEFAULT_TRIALS);
    let protocol = Protocol {
        plan,
        rest_samples: settings.rest_samples,
    };
    let (learnt, calibration, calibration_s) = calibration(settings, &setup, folder, progress)?;
    let map = learnt.as_ref().map_or(Map::Mounting, Map::Learnt);

    let mut rows = Vec::new();
    let mut until_trials: Vec<Vec<until::UntilTrial>> = vec![Vec::new(); wires.len()];
    for (w, wire) in wires.iter().enumerate() {
        for trial in 0..trials {
            let stream = ((w as u64) << 32) | trial as u64;
            let samples = record_trial(wire, gravity, &setup, map, seed, stream, &protocol)
                .map_err(|e| e.context(format!("wire {} trial {trial}", wire.name)))?;
            for (model, config) in &models {
                let line = identify_trial(
                    &samples,
                    (&counts, seed),
                    (*model, config),
                    (w, trial),
                    &mut rows,
                    progress,
                );
                progress(&format!(
                    "identify: {} trial {trial} ({} model): {line}",
                    wire.name,
                    model.name()
                ));
            }
            if let (Some(target), Some((_, config))) = (settings.until, models.first()) {
                let timed: Vec<Sample> = samples.iter().map(Recorded::sample).collect();
                let t = until::sample_until(&timed, config, seed, target);
                progress(&format!(
                    "identify: {} trial {trial}: {} after {} samples (--until {target} %)",
                    wire.name,
                    if t.reached { "reached" } else { "not reached" },
                    t.samples
                ));
                until_trials[w].push(t);
            }
            if settings.save_log {
                folder.write(
                    &format!("logs/{}", trial::log_name(&wire.name, trial)),
                    trial::log_text(&samples)?,
                )?;
            }
        }
    }

    let by_model: Vec<ModelResults> = models
        .iter()
        .map(|(model, _)| summary::model_results(*model, &wires, &counts, &rows))
        .collect();
    let mut results = by_model
        .first()
        .map(|m| m.wires.clone())
        .unwrap_or_default();
    if let Some(target) = settings.until {
        let limit = counts.last().copied().unwrap_or(2);
        for ((result, wire), done) in results.iter_mut().zip(&wires).zip(&until_trials) {
            result.until = Some(until::UntilSummary::new(wire, target, limit, done));
        }
    }
    let first = results
        .first()
        .cloned()
        .ok_or_else(|| LabError::bad_input("no wire to identify"))?;
    let model = common.model();
    let summary = IdentifySummary {
        model,
        form: settings.settings.form,
        gravity,
        sensor: setup.sensor.name.clone(),
        pipeline: settings.pipeline,
        calibration,
        trials,
        noise: models.first().map_or_else(
            || summary::NoiseOut::new(&IdentifierParams::default()),
            |(_, c)| summary::NoiseOut::new(c),
        ),
        sample_counts: counts.clone(),
        wire: first.wire,
        by_samples: first.by_samples,
        until: first.until,
        wires: results,
        by_model,
    };
    let kinds: Vec<ModelKind> = models.iter().map(|(kind, _)| *kind).collect();
    let timings = summary::timings(calibration_s, &kinds, (&wires, &counts), &rows);
    folder.write("identify.csv", summary::csv(&wires, &rows)?)?;
    let median_ms = |w: usize, n: usize| summary::compute_ms_median(&rows, model, w, n);
    summary::write_figures(folder, &summary.wires, &median_ms)?;
    Ok(IdentifyRun { summary, timings })
}

/// The learnt calibration of the calibrated pipeline (loaded, or run and cached as
/// `calibration.json`), what the summary says of it (the file, `"cached"`, or `None` for the
/// mounting pipeline) and the time a run took \[s\] (0 when loaded).
fn calibration(
    settings: &IdentifyParams,
    setup: &SimSetup,
    folder: &ResultsFolder,
    progress: Progress<'_>,
) -> Result<(Option<Calibration>, Option<String>, f64), LabError> {
    if settings.pipeline == Pipeline::Mounting {
        return Ok((None, None, 0.0));
    }
    let common = &settings.common;
    if settings.calibration.is_none() {
        progress("identify: no --calibration: calibrating on the known wire first");
    }
    let start = Instant::now();
    let (learnt, _) = load_or_run(
        settings.calibration.as_deref(),
        (common.gravity, common.model()),
        setup,
        common.seed,
        |_| {},
    )?;
    match &settings.calibration {
        Some(path) => Ok((Some(learnt), Some(path.display().to_string()), 0.0)),
        None => {
            let seconds = start.elapsed().as_secs_f64();
            let json = learnt
                .to_json()
                .map_err(|e| from_estimate(e, "writing the calibration weights"))?;
            folder.write("calibration.json", json)?;
            Ok((Some(learnt), Some("cached".to_owned()), seconds))
        }
    }
}

/// Identifies from the first `n` samples for each count with one model and its settings;
/// pushes the rows (tagged with the model, the wire's index and the trial), reports each
/// failed identification to `progress`, and returns a progress line (`n:ok`, `n:flag` or
/// `n:err` per count).
fn identify_trial(
    samples: &[Recorded],
    (counts, seed): (&[usize], u64),
    (model, config): (ModelKind, &IdentifierParams),
    (wire, trial): (usize, usize),
    rows: &mut Vec<Row>,
    progress: Progress<'_>,
) -> String {
    let pairs: Vec<Sample> = samples.iter().map(Recorded::sample).collect();
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
                interval95: estimate
                    .interval95()
                    .and_then(|i| <[[f64; 2]; 4]>::try_from(&i[..4]).ok()),
                flag: flag_name(estimate.unidentified.as_ref()),
                evaluations: estimate.evaluations,
                compute_ms,
            },
            Err(e) => {
                progress(&format!("identify: trial {trial}, {n} samples: {e}"));
                Row {
                    model,
                    wire,
                    trial,
                    samples: n,
                    eta: None,
                    linear_density: None,
                    chi2_per_dof: f64::NAN,
                    interval95: None,
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
}
