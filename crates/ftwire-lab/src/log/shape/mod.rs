//! The wire's shape for every record of a rig log (paper §IV-C), as a real rig would run the
//! estimator offline.
//!
//! For each record, `ã` is the record's `a`, or its `raw` reading through the learnt
//! calibration or the mounting ([`super::a_tilde`]); then the model gives the centreline (base
//! clamp frame) and a confidence flag (`confident`, `not_stable`, or `jump`: a possible
//! contact). [`ShapeLog::load`] reads and checks the log (every record's `ã` before any
//! shape), then:
//!
//! - [`LogShapes`] gives the records' shapes one by one, in order, as `ftwire shape --log`
//!   prints them ([`shape_record`] is one record's: 64 nodes, and with markers the mean
//!   distance of the seen markers to the estimate);
//! - [`ShapeLog::write`] writes `shapes.jsonl` into a results folder, as `ftwire shape --log
//!   --out DIR` does ([`folder`]: the records solved in parallel, flagged in order).
//!
//! **Error bars.** When the standard deviations of a record's `ã` are known, its shape
//! carries `σ(s)` at each point ([`ftwire_estimate::shape::shape_sigma`]: the RMS radius of
//! the point's first-order error, `sqrt(trace D Σ_ã Dᵀ)`), in mm. They are those given
//! (`--a-std`, [`ShapeLogParams::a_std`]: the whole error of `ã`, for every record); or the
//! covariance the sensor's data sheet gives at the record's time since the tare, with the
//! calibration's gain error ([`ShapeLogParams::sensor`]); or else, for a record whose `raw`
//! reading went through the learnt calibration, the calibration's per-channel RMS error on
//! its test split (`training.test_rmse` of `calibration.json`: its labels' error included). Otherwise a record has no `σ`, and none is computed: the
//! error bars cost 12 more shape solves per record.
//!
//! Guarded by this module's tests, `tests/logs.rs` and `crates/ftwire/tests/shape_log.rs` (a
//! log the shape experiment saved gives the live run's answer).

pub mod folder;

use std::fmt;
use std::path::PathBuf;

use ftwire_estimate::KirchhoffModel;
use ftwire_estimate::ft::MountingSpec;
use ftwire_estimate::identify::MeasurementNoise;
use ftwire_estimate::shape::{
    Confidence, ConfigurationStd, ModelError, ShapeEstimator, marker_distances, shape_sigma,
    with_model_error,
};
use nalgebra::{Matrix6, Point3, Vector6};
use serde::Serialize;

pub use folder::{
    BLOCK, DEFAULT_POINTS, MARKER_NODES, MAX_POINTS, MIN_POINTS, ShapeLogRun, ShapeLogSummary,
    ShapeLogTimings,
};

use super::{LogLine, LogRecord, RawMap, a_tilde, read_log};
use crate::error::{LabError, from_estimate};
use crate::wire::WireSpec;

/// What to shape: the log, the wire, and how its `raw` records become `ã`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ShapeLogParams {
    /// The JSON Lines log ([`ftwire_estimate::log`]).
    pub log: PathBuf,
    /// The wire the shapes are solved for: a preset name or a wire file (TOML).
    pub wire: String,
    /// The learnt calibration's weights file, for records with `raw`.
    pub calibration: Option<PathBuf>,
    /// The sensor's mounting (`--mounting`): the tool's weight is taken out of `raw`, and
    /// without a calibration the mounting alone maps it; `None`: not given (records with
    /// `raw` then need the calibration).
    pub mounting: Option<MountingSpec>,
    /// The standard deviations of every record's `ã` (`--a-std`), torque first \[N·m ×3,
    /// N ×3\], for the error bars (the module docs); `None`: the calibration's test error for
    /// the records read through it, no error bars for the others.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub a_std: Option<[f64; 6]>,
    /// The model's own error `e` per metre of arc length \[m/m\] (`--model-error`): each
    /// `σ(s)` adds `σ_model(s) = e · s` in quadrature ([`ftwire_estimate::shape::ModelError`]);
    /// `None`: not counted.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub model_error: Option<f64>,
    /// The sensor's data sheet (`--sensor`), for the error bars of every record: its rest's
    /// noise, the tare's and the drift since the tare at the record's time, mapped to `ã`
    /// ([`crate::experiment::rig::identification_noise_of`]), in place of the calibration's
    /// test error; `None`: not given.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sensor: Option<super::identify::LogDrift>,
    /// With [`Self::sensor`], the map's relative gain error per channel of `ã` as a fraction
    /// (`--gain-error`; `None`: 0).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gain_error: Option<f64>,
}

/// A log read and checked for shaping: every record with its line in the file and its `ã`,
/// and the wire's model (the paper's weightless Kirchhoff rod).
#[derive(Debug, Clone)]
pub struct ShapeLog {
    log: PathBuf,
    lines: Vec<LogLine>,
    a_tilde: Vec<Vector6<f64>>,
    model: KirchhoffModel,
    /// `--a-std`.
    given_std: Option<ConfigurationStd>,
    /// The calibration's test error, if a calibration with one was given.
    calibration_std: Option<ConfigurationStd>,
    /// `--model-error`.
    model_error: Option<ModelError>,
    /// `--sensor`: the noise of `ã` from the data sheet, and the tare's time.
    sensor: Option<(MeasurementNoise, f64)>,
}

impl ShapeLog {
    /// Reads the wire, the calibration, the mounting and the log of `params`, and every
    /// record's `ã` ([`a_tilde`]), before any shape is solved.
    ///
    /// # Errors
    /// Bad input for an unknown or invalid wire, standard deviations that are not finite and
    /// `>= 0`, a calibration or mounting [`RawMap::load`] refuses, a calibration whose test
    /// error is not finite and `>= 0`, a log [`read_log`] refuses, or a record [`a_tilde`] refuses (named by its line
    /// and time: a `raw` reading with neither a calibration nor a mounting, or without
    /// `gravity` when the mounting has a tool).
    pub fn load(params: &ShapeLogParams) -> Result<Self, LabError> {
        let wire = WireSpec::load(&params.wire).map_err(|e| LabError::bad_input(e.to_string()))?;
        let wire_params = wire
            .wire_params()
            .map_err(|e| LabError::bad_input(format!("wire {}: {e}", wire.name)))?;
        let given_std = params
            .a_std
            .map(ConfigurationStd::new)
            .transpose()
            .map_err(|e| LabError::bad_input(format!("--a-std: {e}")))?;
        let map = RawMap::load(params.calibration.as_deref(), params.mounting.clone())?;
        let calibration_std = map
            .calibration()
            .and_then(|c| c.record().test_rmse)
            .map(ConfigurationStd::new)
            .transpose()
            .map_err(|e| LabError::bad_input(format!("the calibration's test_rmse: {e}")))?;
        let model_error = params
            .model_error
            .map(ModelError::new)
            .transpose()
            .map_err(|e| LabError::bad_input(format!("--model-error: {e}")))?;
        let lines = read_log(&params.log)?;
        let a_tilde = lines
            .iter()
            .map(|line| a_tilde(line, &map))
            .collect::<Result<_, _>>()
            .map_err(|e| e.context(format!("log {}", params.log.display())))?;
        let first_time = lines.first().map_or(0.0, |line| line.record.time);
        let sensor = params
            .sensor
            .as_ref()
            .map(|drift| sensor_noise(drift, params.mounting.as_ref(), params.gain_error))
            .transpose()?
            .map(|noise| {
                (
                    noise,
                    params
                        .sensor
                        .as_ref()
                        .and_then(|d| d.tare_time)
                        .unwrap_or(first_time),
                )
            });
        Ok(Self {
            log: params.log.clone(),
            lines,
            a_tilde,
            model: KirchhoffModel::new(wire_params),
            given_std,
            calibration_std,
            model_error,
            sensor,
        })
    }

    /// The model's own error (`--model-error`), if given.
    pub fn model_error(&self) -> Option<ModelError> {
        self.model_error
    }

    /// The covariance of the `ã` of record `index` (the module docs), if known: from
    /// `--a-std`, from the sensor's data sheet at the record's time since the tare, or from
    /// the calibration's test error for a record read through it.
    pub fn a_covariance(&self, index: usize) -> Option<Matrix6<f64>> {
        let line = self.lines.get(index)?;
        if let Some(std) = &self.given_std {
            return Some(std.covariance());
        }
        if let Some((noise, tare_time)) = &self.sensor {
            let since = (line.record.time - tare_time).max(0.0);
            return Some(noise.sample_covariance(self.a_tilde.get(index)?, since));
        }
        self.calibration_std
            .as_ref()
            .filter(|_| line.record.raw().is_some())
            .map(ConfigurationStd::covariance)
    }

    /// The log's records, each with its line in the file.
    pub fn lines(&self) -> &[LogLine] {
        &self.lines
    }

    /// Each record's `ã` (torque first, base clamp frame), in the order of [`Self::lines`].
    pub fn a_tilde(&self) -> &[Vector6<f64>] {
        &self.a_tilde
    }

    /// The wire's model the shapes are solved with.
    pub fn model(&self) -> &KirchhoffModel {
        &self.model
    }

    /// The log's file.
    pub fn path(&self) -> &std::path::Path {
        &self.log
    }
}

/// One record's shape, as `ftwire shape --log` prints it: with `--json` one JSON line of
/// these fields (those that are `None` left out); the text is its [`fmt::Display`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RecordShape {
    /// The record's index in the log, from 0.
    pub record: usize,
    /// The record's time \[s\].
    pub time: f64,
    /// `ã` (torque first, base clamp frame).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub a_tilde: Option<[f64; 6]>,
    /// `confident`, `not_stable` or `jump` ([`confidence_name`]); `None` without a shape.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub confidence: Option<&'static str>,
    /// The centreline's nodes \[m\], base clamp frame; `None` without a shape.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub points: Option<Vec<[f64; 3]>>,
    /// `σ(s)` at each of `points` \[mm\] (the module docs); `None` without a shape, without
    /// the standard deviations of `ã`, or when a shifted `ã` of the differences has no shape.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sigma_mm: Option<Vec<f64>>,
    /// The mean distance of the record's seen markers to the centreline \[mm\]; `None`
    /// without markers.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub marker_mean_mm: Option<f64>,
    /// Why the model has no shape for this `ã`; `None` with a shape.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub error: Option<String>,
}

/// The name of a confidence flag in [`RecordShape::confidence`].
pub fn confidence_name(confidence: &Confidence) -> &'static str {
    match confidence {
        Confidence::Confident => "confident",
        Confidence::NotStable => "not_stable",
        Confidence::Jump { .. } => "jump",
    }
}

/// The shape of `record` (index `index` in its log, from 0) at its `ã` `a` from `estimator`,
/// which keeps the previous estimate to flag jumps: give it the records in order. A model
/// that cannot solve `ã` is an answer too, with [`RecordShape::error`]. Without error bars:
/// [`shape_record_with_std`] with `None`.
///
/// # Errors
/// Bad input for markers the distance refuses.
pub fn shape_record(
    estimator: &mut ShapeEstimator<KirchhoffModel>,
    index: usize,
    record: &LogRecord,
    a: &Vector6<f64>,
) -> Result<RecordShape, LabError> {
    shape_record_with_std(estimator, index, record, a, None)
}

/// [`shape_record`], and with the covariance `a_covariance` of `ã` also `σ(s)` at each
/// point ([`RecordShape::sigma_mm`]).
///
/// # Errors
/// As [`shape_record`].
pub fn shape_record_with_std(
    estimator: &mut ShapeEstimator<KirchhoffModel>,
    index: usize,
    record: &LogRecord,
    a: &Vector6<f64>,
    a_covariance: Option<&Matrix6<f64>>,
) -> Result<RecordShape, LabError> {
    let mut shape = RecordShape {
        record: index,
        time: record.time,
        a_tilde: Some((*a).into()),
        confidence: None,
        points: None,
        sigma_mm: None,
        marker_mean_mm: None,
        error: None,
    };
    match estimator.estimate(a) {
        Ok(estimate) => {
            let positions = &estimate.shape.positions;
            if let Some(markers) = record.markers() {
                let seen: Vec<Point3<f64>> = markers.into_iter().flatten().collect();
                let d = marker_distances(&seen, positions)
                    .map_err(|e| from_estimate(e, &format!("markers of record {index}")))?;
                if !d.is_empty() {
                    shape.marker_mean_mm = Some(1e3 * d.iter().sum::<f64>() / d.len() as f64);
                }
            }
            shape.confidence = Some(confidence_name(&estimate.confidence));
            shape.points = Some(positions.iter().map(|p| [p.x, p.y, p.z]).collect());
            if let Some(covariance) = a_covariance {
                let nodes = positions.len();
                let length = ftwire_estimate::WireModel::wire(estimator.model()).length();
                shape.sigma_mm = shape_sigma(estimator.model(), a, nodes, covariance)
                    .ok()
                    .map(|sigma| match estimator.model_error() {
                        Some(model) => with_model_error(&sigma.sigma, model, length),
                        None => sigma.sigma,
                    })
                    .map(|sigma| sigma.iter().map(|s| 1e3 * s).collect());
            }
        }
        Err(e) => shape.error = Some(e.to_string()),
    }
    Ok(shape)
}

/// The shapes of a log's records, in order ([`shape_record`] of each): an iterator over
/// [`RecordShape`]s, made by [`LogShapes::new`] once the log, the wire and the calibration
/// have been read and checked.
pub struct LogShapes {
    log: ShapeLog,
    estimator: ShapeEstimator<KirchhoffModel>,
    next: usize,
}

impl LogShapes {
    /// The shapes of the log of `params`, for its wire.
    ///
    /// # Errors
    /// As [`ShapeLog::load`].
    pub fn new(params: &ShapeLogParams) -> Result<Self, LabError> {
        let log = ShapeLog::load(params)?;
        let estimator = ShapeEstimator::new(*log.model()).with_model_error(log.model_error);
        Ok(Self {
            log,
            estimator,
            next: 0,
        })
    }

    /// The log's records, each with its line in the file.
    pub fn lines(&self) -> &[LogLine] {
        self.log.lines()
    }
}

impl Iterator for LogShapes {
    type Item = Result<RecordShape, LabError>;

    fn next(&mut self) -> Option<Self::Item> {
        let index = self.next;
        let line = self.log.lines.get(index)?;
        let a = self.log.a_tilde.get(index)?;
        self.next += 1;
        let covariance = self.log.a_covariance(index);
        Some(shape_record_with_std(
            &mut self.estimator,
            index,
            &line.record,
            a,
            covariance.as_ref(),
        ))
    }
}

/// The noise of `ã` from the sensor's data sheet `drift`, mapped by `mounting` (or the
/// sensor's own clamp), with the gain error `gain` (a fraction).
///
/// # Errors
/// Bad input naming `--sensor`, `--mounting` or `--gain-error`.
fn sensor_noise(
    drift: &super::identify::LogDrift,
    mounting: Option<&MountingSpec>,
    gain: Option<f64>,
) -> Result<MeasurementNoise, LabError> {
    let mount = match mounting {
        Some(spec) => spec
            .mounting()
            .map_err(|e| LabError::bad_input(format!("--mounting: {e}")))?,
        None => ftwire_estimate::ft::Mounting::new(drift.params.sensor_from_clamp())
            .map_err(|e| LabError::bad_input(format!("--sensor's mounting: {e}")))?,
    };
    crate::identify::data_sheet_noise(
        &drift.params,
        &mount,
        (drift.rest_samples, drift.tare_samples),
        gain,
    )
}

/// One line of text: the confidence and the tip, or why there is no shape.
impl fmt::Display for RecordShape {
    fn fmt(&self, out: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (&self.points, &self.error) {
            (Some(points), _) => {
                let tip = points.last().copied().unwrap_or_default();
                let markers = self
                    .marker_mean_mm
                    .map_or_else(String::new, |m| format!(", markers {m:.2} mm"));
                let sigma = self
                    .sigma_mm
                    .as_ref()
                    .and_then(|s| s.last())
                    .map_or_else(String::new, |s| format!(" ± {s:.2} mm"));
                writeln!(
                    out,
                    "record {} t = {:.3} s: {}, tip at ({:.4}, {:.4}, {:.4}) m{sigma}{markers}",
                    self.record,
                    self.time,
                    self.confidence.unwrap_or("-"),
                    tip[0],
                    tip[1],
                    tip[2]
                )
            }
            (None, error) => writeln!(
                out,
                "record {} t = {:.3} s: no shape: {}",
                self.record,
                self.time,
                error.as_deref().unwrap_or("unknown")
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn log_file(tag: &str, contents: &str) -> PathBuf {
        let path = std::env::temp_dir().join(format!(
            "ftwire-lab-shape-log-{tag}-{}.jsonl",
            std::process::id()
        ));
        std::fs::write(&path, contents).expect("writes");
        path
    }

    const GOOD: &str = r#"{"time": 0.25, "a": [0, 0.01, 0.01, -0.05, 0.03, 0], "b": {"position": [0.5, 0.1, 0], "rotation": [0, 0, 0.4]}, "markers": [[0.1, 0.0, 0.0], null]}"#;

    #[test]
    fn every_record_gets_a_shape_in_order() {
        let path = log_file(
            "good",
            &format!("{GOOD}\n{}\n", GOOD.replace("0.25", "0.5")),
        );
        let params = ShapeLogParams {
            log: path.clone(),
            wire: "nitinol-2mm-630".into(),
            calibration: None,
            mounting: None,
            a_std: None,
            model_error: None,
            sensor: None,
            gain_error: None,
        };
        let shapes: Result<Vec<RecordShape>, LabError> =
            LogShapes::new(&params).and_then(Iterator::collect);
        let _ = std::fs::remove_file(&path);
        let shapes = shapes.expect("a good log");
        assert_eq!(shapes.len(), 2);
        for (i, shape) in shapes.iter().enumerate() {
            assert_eq!(shape.record, i);
            assert!(shape.error.is_none(), "{:?}", shape.error);
            let points = shape.points.as_ref().expect("a shape");
            // The centreline starts at the base clamp point.
            assert!(points[0].iter().all(|v| v.abs() < 1e-12));
            assert!(shape.marker_mean_mm.is_some_and(f64::is_finite));
        }
        let text = shapes[0].to_string();
        assert!(text.starts_with("record 0 t = 0.250 s: "), "{text}");
        assert!(text.ends_with(" mm\n"), "{text}");
    }

    #[test]
    fn a_raw_record_without_a_calibration_is_bad_input() {
        let raw = GOOD.replace("\"a\"", "\"raw\"");
        let path = log_file("raw", &format!("{GOOD}\n{raw}\n"));
        let params = ShapeLogParams {
            log: path.clone(),
            wire: "nitinol-2mm-630".into(),
            calibration: None,
            mounting: None,
            a_std: None,
            model_error: None,
            sensor: None,
            gain_error: None,
        };
        let error = LogShapes::new(&params).err();
        let _ = std::fs::remove_file(&path);
        let error = error.expect("raw needs a calibration");
        assert_eq!(error.kind(), "bad_input");
        let message = error.to_string();
        assert!(message.contains(": line 2 (time 0.25) "), "{message}");
        assert!(
            message.contains("--calibration") && message.contains("--mounting"),
            "{message}"
        );
    }
}
