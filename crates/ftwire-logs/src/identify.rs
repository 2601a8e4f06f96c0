//! Identify a wire's `η = (c1, c2, c3, L)` from a recorded log (paper §III-B, eq. 12; the
//! library's `ftwire_estimate::identify`), through the one identification the live experiment
//! makes ([`crate::identification::run_identification`]: the model template, the swarm's random
//! generator), so that both give the same answer on the same data and seed.
//!
//! Records with `a` (tared and calibrated) are used as they are; records with `raw` go
//! through the learnt calibration ([`IdentifyLogParams::calibration`]) or the mounting
//! ([`IdentifyLogParams::mounting`]), as [`super::a_tilde`] says. Every record needs `b`, the
//! second gripper's pose. [`samples`] reads the log into `(ã, b̃)` pairs, [`estimate`]
//! identifies from them and gives the [`EstimateReport`] that `ftwire identify --log` prints.
//! Guarded by this module's tests, `tests/logs.rs` and `crates/ftwire/tests/identify_log.rs`
//! (a saved log gives the live run's estimate).

use std::fmt;
use std::path::{Path, PathBuf};
use std::time::Duration;

use ftwire_app::error::FrontEnd;
use ftwire_core::Pose;
use ftwire_estimate::ft::MountingSpec;
use ftwire_estimate::identify::{
    Estimate, IdentifierParams, MeasurementNoise, Sample, Unidentified,
};
use nalgebra::{Vector3, Vector6};
use serde::Serialize;

use super::{LogLine, RawMap, a_tilde, read_log};
use crate::identification::{Form, ResidualParams, flag_name, identifier};
use ftwire_app::Progress;
use ftwire_app::error::{LabError, from_estimate};
use ftwire_app::input::CountRange;

/// What to identify from: the log, how its records become `ã`, and how to identify.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct IdentifyLogParams {
    /// The JSON Lines log ([`ftwire_estimate::log`]).
    pub log: PathBuf,
    /// The learnt calibration's weights file, for records with `raw`.
    pub calibration: Option<PathBuf>,
    /// The sensor's mounting (`--mounting`): the tool's weight is taken out of `raw`, and
    /// without a calibration the mounting alone maps it; `None`: not given (records with
    /// `raw` then need the calibration).
    pub mounting: Option<MountingSpec>,
    /// Use only the first `n` records; `None`: all.
    pub samples: Option<usize>,
    /// The residual form and the known relations between the parameters.
    pub residual: ResidualParams,
    /// Gravity in the base clamp frame \[m/s²\]: identify with the loaded model, the wire's
    /// linear density as well as `c` and `L`; `None`: the paper's weightless model.
    pub gravity: Option<Vector3<f64>>,
    /// The seed of the particle swarm.
    pub seed: u64,
    /// The sensor's data sheet, to model the bias all records share (the tare's offset and its
    /// drift, estimated with the wire); `None`: the records' errors are independent.
    pub drift: Option<LogDrift>,
    /// Who calls, so that errors name the inputs as that front end spells them.
    #[serde(skip)]
    pub front_end: FrontEnd,
}

/// What `identify --log` needs to model the sensor's shared bias, and `shape --log` to draw
/// error bars ([`ftwire_rig::DataSheet::noise`]): the sensor's data sheet, how many readings
/// each record and the tare averaged, and when the tare was taken.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LogDrift {
    /// The sensor preset or file (`--sensor`), as given.
    pub sensor: String,
    /// Its settings: `noise_std`, `bias_random_walk`, `bias_time_constant` and, without
    /// `--mounting`, its clamp's place.
    #[serde(skip)]
    pub params: ftwire_rig::DataSheet,
    /// Readings averaged per record (`--rest-samples`).
    pub rest_samples: usize,
    /// Readings averaged by the tare (`--tare-samples`).
    pub tare_samples: usize,
    /// The tare's time on the log's clock \[s\] (`--tare-time`); `None`: the first record's.
    pub tare_time: Option<f64>,
}

impl LogDrift {
    /// The sensor preset or file `sensor` (`--sensor`, as given), with the readings averaged
    /// per record and by the tare and the tare's time.
    ///
    /// # Errors
    /// Bad input naming `--sensor` for an unknown preset or a bad sensor file.
    pub fn load(
        sensor: &str,
        rest_samples: usize,
        tare_samples: usize,
        tare_time: Option<f64>,
    ) -> Result<Self, LabError> {
        let spec = ftwire_app::config::sensor::DataSheetSpec::load(sensor)
            .map_err(|e| LabError::bad_input(format!("--sensor: {e}")))?;
        Ok(Self {
            sensor: sensor.to_owned(),
            params: spec.sheet,
            rest_samples,
            tare_samples,
            tare_time,
        })
    }

    /// The noise of `ã` from the data sheet, mapped by `mounting` (or else the sensor's own
    /// clamp), with the map's gain error `gain` (a fraction; `None`: none).
    ///
    /// # Errors
    /// Bad input naming `--sensor`, `--mounting` or `--gain-error`.
    pub fn noise(
        &self,
        mounting: Option<&MountingSpec>,
        gain: Option<f64>,
    ) -> Result<MeasurementNoise, LabError> {
        let mount = match mounting {
            Some(spec) => spec
                .mounting()
                .map_err(|e| LabError::bad_input(format!("--mounting: {e}")))?,
            None => ftwire_estimate::ft::Mounting::new(self.params.sensor_from_clamp())
                .map_err(|e| LabError::bad_input(format!("--sensor's mounting: {e}")))?,
        };
        crate::identification::data_sheet_noise(
            &self.params,
            &mount,
            (self.rest_samples, self.tare_samples),
            gain,
        )
    }
}

impl IdentifyLogParams {
    /// The library's settings: [`ResidualParams::config`] with the loaded model's weight when
    /// [`Self::gravity`] is given or the calibration's labels were made with the loaded model
    /// ([`super::model_gravity`]).
    ///
    /// # Errors
    /// Bad input for a torsion ratio that is not positive, a gravity the library refuses, a
    /// calibration that cannot be read, or a gravity that conflicts with the calibration's.
    pub fn config(&self) -> Result<IdentifierParams, LabError> {
        let mut config = self.residual.config()?;
        if let Some(drift) = &self.drift {
            config.noise = self
                .residual
                .with_noise_settings(drift.noise(self.mounting.as_ref(), None)?)?;
        }
        // The calibration's own label model unless the flag names the same one.
        let given = self.gravity.map(Into::into);
        let gravity = match &self.calibration {
            Some(path) => super::model_gravity(&super::raw_map(Some(path), None)?, given)?,
            None => given,
        };
        if let Some(g) = gravity.map(Vector3::from) {
            config.constraints.weight = Some(g);
            config
                .validate()
                .map_err(|e| LabError::bad_input(format!("--gravity-in-clamp: {e}")))?;
        }
        Ok(config)
    }

    /// Bad settings refused before the log is read ([`Self::config`]).
    ///
    /// # Errors
    /// As [`Self::config`].
    pub fn check(&self) -> Result<(), LabError> {
        self.config().map(|_| ())
    }
}

/// The log's samples `(ã, b̃)` and their times on the log's clock, in order, the first
/// [`IdentifyLogParams::samples`] of them.
///
/// # Errors
/// Bad input for a log [`read_log`] refuses, a calibration or mounting [`super::raw_map`]
/// refuses, a record [`samples_of`] refuses, or more samples asked for than the log holds.
pub fn samples(params: &IdentifyLogParams) -> Result<Vec<Sample>, LabError> {
    let map = super::raw_map(params.calibration.as_deref(), params.mounting.clone())?;
    let lines = read_log(&params.log)?;
    let pairs = samples_of(&lines, &map, &params.log)?;
    let mut samples: Vec<Sample> = pairs
        .into_iter()
        .zip(&lines)
        .map(|((a, b), line)| Sample {
            a,
            b,
            time: Some(line.record.time),
        })
        .collect();
    if let Some(n) = params.samples {
        if n > samples.len() {
            return Err(LabError::bad_input(format!(
                "{} {n}: {} holds only {} records",
                params.front_end.spell("--samples"),
                params.front_end.source(&params.log),
                samples.len()
            )));
        }
        samples.truncate(n);
    }
    Ok(samples)
}

/// The `(ã, b̃)` pairs of `lines` (read from the log at `path`, which the errors name), in
/// order: `ã` by [`a_tilde`].
///
/// # Errors
/// Bad input naming the log and the record's line and time: a record [`a_tilde`] refuses, one
/// whose `raw` the calibration maps to a value that is not finite, or one without `b`.
pub fn samples_of(
    lines: &[LogLine],
    map: &RawMap,
    path: &std::path::Path,
) -> Result<Vec<(Vector6<f64>, Pose)>, LabError> {
    let log = || format!("log {}", path.display());
    lines
        .iter()
        .map(|line| {
            let record = &line.record;
            let a = a_tilde(line, map).map_err(|e| e.context(log()))?;
            // A record's own `a` is used as it is; the calibration's output may not be finite.
            if record.a.is_none()
                && let Some(i) = a.iter().position(|v| !v.is_finite())
            {
                return Err(LabError::bad_input(format!(
                    "{}: line {} (time {}): the calibration maps raw = {:?} to a[{i}] = {}, \
                     not a finite number",
                    log(),
                    line.line,
                    record.time,
                    record.raw,
                    a[i]
                )));
            }
            let b = record.b.ok_or_else(|| {
                LabError::bad_input(format!(
                    "{}: line {} (time {}) has no `b`: identification needs the second \
                     gripper's pose on every record",
                    log(),
                    line.line,
                    record.time
                ))
            })?;
            Ok((a, b.to_pose()))
        })
        .collect()
}

/// `identify --samples` (and the readings of `--rest-samples`, `--tare-samples`): a window
/// of the log, whose records are all read in any case (a
/// million records of a few hundred bytes each).
pub const LOG_SAMPLES: CountRange = CountRange::new(1, 1_000_000);

/// How long the search runs between two progress lines.
pub const PROGRESS_TICK: Duration = Duration::from_millis(200);

/// Identifies the wire from `samples` ([`samples`]) with the swarm seeded by
/// [`IdentifyLogParams::seed`]: the same estimate as
/// [`crate::identification::run_identification`] for the same samples and seed (the search is cut
/// into steps of [`PROGRESS_TICK`] by [`crate::identification::identifier`], which the library's
/// streaming identifier makes independent of the cut). After each step `progress` gets where
/// the search is: the search round and the swarm iteration, or the refinement.
///
/// An estimate that does not identify the wire is an answer too: its report says why
/// ([`EstimateReport::reason`]).
///
/// # Errors
/// As [`IdentifyLogParams::config`] and [`crate::identification::run_identification`], with the
/// log named.
pub fn estimate(
    params: &IdentifyLogParams,
    samples: &[Sample],
    progress: Progress,
) -> Result<EstimateReport, LabError> {
    let config = params.config()?;
    let samples = since_tare(params, samples)?;
    let estimate = search(&samples, &config, params.seed, progress).map_err(|e| {
        e.context(format!(
            "identifying from {}",
            params.front_end.source(&params.log)
        ))
    })?;
    Ok(EstimateReport::new(&estimate, params.residual.form))
}

/// The samples as identification takes them: with a drift model, each time measured from the
/// tare (`--tare-time`, or the first record's time); without one, no times.
///
/// # Errors
/// Bad input for a record before the tare.
fn since_tare(params: &IdentifyLogParams, samples: &[Sample]) -> Result<Vec<Sample>, LabError> {
    let Some(drift) = &params.drift else {
        return Ok(samples
            .iter()
            .map(|s| Sample { time: None, ..*s })
            .collect());
    };
    let first = samples.first().and_then(|s| s.time).unwrap_or(0.0);
    let tare = drift.tare_time.unwrap_or(first);
    samples
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let time = s.time.unwrap_or(first);
            if time < tare {
                return Err(LabError::bad_input(format!(
                    "{} {tare}: record {i} of {} is at time {time}, before the tare; give the \
                     tare's time on the records' clock, at or before the first record",
                    params.front_end.spell("--tare-time"),
                    params.front_end.source(&params.log)
                )));
            }
            Ok(Sample {
                time: Some(time - tare),
                ..*s
            })
        })
        .collect()
}

/// The streaming search of [`estimate`], stepped until it is no longer unfinished.
fn search(
    samples: &[Sample],
    config: &IdentifierParams,
    seed: u64,
    progress: Progress,
) -> Result<Estimate, LabError> {
    let mut identifier = identifier(samples, config, seed)?;
    loop {
        let estimate = identifier.step(PROGRESS_TICK);
        let Ok(Estimate {
            unidentified:
                Some(Unidentified::Unfinished {
                    iterations,
                    required,
                }),
            ..
        }) = &estimate
        else {
            return estimate.map_err(|e| from_estimate(e, "identifying the wire"));
        };
        let round = required / config.swarm_iterations.max(1);
        progress(&if iterations < required {
            format!("search round {round}, swarm iteration {iterations}/{required}")
        } else {
            format!("search round {round}, refining the best fits")
        });
    }
}

/// The estimate as `ftwire identify --log` prints it: with `--json` one object of these
/// fields; the text is its [`fmt::Display`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EstimateReport {
    /// Samples used.
    pub samples: usize,
    /// The residual form.
    pub form: Form,
    /// Stiffnesses `(c1, c2, c3)` \[N·m²\].
    pub c: [f64; 3],
    /// Length \[m\].
    pub length: f64,
    /// Standard deviations of `c` \[N·m²\] (first order).
    pub c_std: [f64; 3],
    /// Standard deviation of `L` \[m\].
    pub length_std: f64,
    /// The linear density `λ` \[kg/m\] (with gravity; absent otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub linear_density: Option<f64>,
    /// Standard deviation of `λ` \[kg/m\] (with gravity).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub linear_density_std: Option<f64>,
    /// The first-order covariance of `(c1, c2, c3, L)`, then `λ` with gravity (4 × 4 or
    /// 5 × 5; `null` when the fit has none).
    pub covariance: Option<Vec<Vec<f64>>>,
    /// The 95 % interval `[low, high]` of each parameter in the covariance's order (`null`
    /// without a covariance).
    pub interval95: Option<Vec<[f64; 2]>>,
    /// `χ²` per degree of freedom under the assumed noise.
    pub chi2_per_dof: f64,
    /// `σ_min/σ_max` of the residual's Jacobian.
    pub condition: f64,
    /// Whether the data identify the wire.
    pub identified: bool,
    /// Why not ([`flag_name`]), or `null`.
    pub flag: Option<&'static str>,
    /// The reason in words, or `null`.
    pub reason: Option<String>,
}

impl EstimateReport {
    /// The report of `estimate`, identified with the residual `form`.
    pub fn new(estimate: &Estimate, form: Form) -> Self {
        Self {
            samples: estimate.samples,
            form,
            c: estimate.c,
            length: estimate.length,
            c_std: estimate.c_std,
            length_std: estimate.length_std,
            linear_density: estimate.linear_density,
            linear_density_std: estimate.linear_density_std,
            covariance: estimate.covariance.map(|c| c.rows()),
            interval95: estimate.interval95(),
            chi2_per_dof: estimate.chi2_per_dof,
            condition: estimate.condition,
            identified: estimate.is_identified(),
            flag: flag_name(estimate.unidentified.as_ref()),
            reason: estimate.unidentified.as_ref().map(ToString::to_string),
        }
    }

    /// `Ok` when the data identify the wire, else no answer naming `log` (the log read) and
    /// the reason: the estimate is a result either way, reported before the verdict.
    ///
    /// # Errors
    /// No answer (exit 1) with [`Self::reason`].
    pub fn verdict(&self, log: &Path) -> Result<(), LabError> {
        match &self.reason {
            None => Ok(()),
            Some(reason) => Err(LabError::no_answer(format!(
                "the data of {} do not identify the wire: {reason}",
                log.display()
            ))),
        }
    }
}

/// The human text: each parameter with its standard deviation, `χ²/dof`, the condition and
/// the verdict.
impl fmt::Display for EstimateReport {
    fn fmt(&self, out: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            out,
            "identified from {} samples ({:?} residual):",
            self.samples, self.form
        )?;
        let names = ["c1 [N·m²]", "c2 [N·m²]", "c3 [N·m²]", "L [m]", "λ [kg/m]"];
        let mut rows: Vec<(f64, f64)> = self.c.into_iter().zip(self.c_std).collect();
        rows.push((self.length, self.length_std));
        if let (Some(lambda), Some(std)) = (self.linear_density, self.linear_density_std) {
            rows.push((lambda, std));
        }
        for (i, (name, (value, std))) in names.iter().zip(rows).enumerate() {
            write!(out, "  {name:<10} {value:.6} ± {std:.2e}")?;
            match self.interval95.as_ref().and_then(|v| v.get(i)) {
                Some([low, high]) => writeln!(out, "  (95 %: {low:.6} to {high:.6})")?,
                None => writeln!(out)?,
            }
        }
        writeln!(
            out,
            "  χ²/dof {:.3}, condition {:.2e}",
            self.chi2_per_dof, self.condition
        )?;
        match &self.reason {
            None => writeln!(out, "  identified: yes"),
            Some(reason) => writeln!(out, "  identified: NO: {reason}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(line: usize, time: f64, a: Option<[f64; 6]>, raw: Option<[f64; 6]>) -> LogLine {
        LogLine {
            line,
            record: super::super::LogRecord {
                time,
                raw,
                a,
                b: Some(super::super::LogPose {
                    position: [0.5, 0.1, 0.0],
                    rotation: [0.0, 0.0, 0.3],
                }),
                markers: None,
                gravity: None,
            },
        }
    }

    #[test]
    fn the_verdict_is_no_answer_naming_the_log_and_the_reason() {
        let mut report = EstimateReport {
            samples: 3,
            form: Form::Absolute,
            c: [0.042, 0.055, 0.055],
            length: 0.63,
            c_std: [1e-4; 3],
            length_std: 1e-4,
            linear_density: None,
            linear_density_std: None,
            covariance: None,
            interval95: None,
            chi2_per_dof: 1.0,
            condition: 0.1,
            identified: true,
            flag: None,
            reason: None,
        };
        let log = Path::new("rig.jsonl");
        assert!(report.verdict(log).is_ok());
        report.identified = false;
        report.reason = Some("too little motion".to_owned());
        let error = report.verdict(log).expect_err("not identified");
        assert_eq!(error.kind(), "no_answer");
        assert_eq!(
            error.to_string(),
            "the data of rig.jsonl do not identify the wire: too little motion"
        );
    }

    #[test]
    fn a_raw_record_without_a_calibration_is_bad_input_naming_its_line() {
        let lines = [
            line(1, 0.0, Some([0.01, 0.02, -0.03, -0.1, 0.2, 0.05]), None),
            line(3, 0.5, None, Some([0.1; 6])),
        ];
        let path = std::path::Path::new("rig.jsonl");
        let error =
            samples_of(&lines, &RawMap::default(), path).expect_err("raw needs a calibration");
        assert_eq!(error.kind(), "bad_input");
        let message = error.to_string();
        assert!(
            message.starts_with("log rig.jsonl: line 3 (time 0.5) has a raw F/T reading"),
            "{message}"
        );
        assert!(message.contains("--calibration"), "{message}");
        let pairs = samples_of(&lines[..1], &RawMap::default(), path).expect("`a` as it is");
        assert_eq!(pairs.len(), 1);
        assert_eq!(pairs[0].0[5].to_bits(), 0.05_f64.to_bits());
        assert!((pairs[0].1.translation.vector.x - 0.5).abs() < 1e-15);
    }

    #[test]
    fn a_record_without_b_is_bad_input_naming_its_line() {
        let mut lines = [
            line(1, 0.0, Some([0.01, 0.02, -0.03, -0.1, 0.2, 0.05]), None),
            line(4, 0.5, Some([0.01, 0.02, -0.03, -0.1, 0.2, 0.05]), None),
        ];
        lines[1].record.b = None;
        let path = std::path::Path::new("rig.jsonl");
        let error = samples_of(&lines, &RawMap::default(), path).expect_err("b is needed");
        assert_eq!(error.kind(), "bad_input");
        assert!(
            error
                .to_string()
                .starts_with("log rig.jsonl: line 4 (time 0.5) has no `b`"),
            "{error}"
        );
    }

    #[test]
    fn bad_settings_and_more_samples_than_records_are_bad_input() {
        let dir = std::env::temp_dir().join(format!(
            "ftwire-lab-identify-log-{}.jsonl",
            std::process::id()
        ));
        let line = r#"{"time": 0.0, "a": [0.01, 0.02, -0.03, -0.1, 0.2, 0.05], "b": {"position": [0.5, 0.1, 0.0], "rotation": [0.0, 0.0, 0.3]}}"#;
        std::fs::write(&dir, format!("{line}\n")).expect("writes");
        let mut params = IdentifyLogParams {
            log: dir.clone(),
            calibration: None,
            mounting: None,
            samples: Some(2),
            residual: ResidualParams::default(),
            gravity: None,
            seed: 0,
            drift: None,
            front_end: Default::default(),
        };
        let error = samples(&params).expect_err("one record, two asked for");
        assert!(
            error.to_string().starts_with("--samples 2: the log "),
            "{error}"
        );
        params.samples = Some(1);
        let pairs = samples(&params);
        let _ = std::fs::remove_file(&dir);
        assert_eq!(pairs.expect("one record").len(), 1);
        params.residual.torsion_ratio = Some(-1.0);
        assert_eq!(params.check().expect_err("ν < 0").kind(), "bad_input");
    }
}
