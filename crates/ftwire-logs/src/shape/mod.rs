//! The wire's shape for every record of a rig log (paper §IV-C), as a real rig would run the
//! estimator offline.
//!
//! Every record takes the rig layer's one path ([`ftwire_rig`]): `ã` is the record's `a`, or
//! its `raw` reading through the learnt calibration or the mounting ([`super::a_tilde`]);
//! then the measurement's model (weight-free, or loaded with `--gravity-in-clamp`) gives the
//! centreline (base clamp frame) and the stream flags it (`confident`, `not_stable`, `jump`:
//! a possible contact, or `no_shape`). [`ShapeLog::load`] reads and checks the log (every
//! record's `ã` before any shape), then:
//!
//! - [`LogShapes`] gives the records' [`ShapeRecord`]s one by one, in order, and
//!   [`LogShapes::write_all`] prints them as `ftwire shape --log` does (text or JSON Lines);
//! - [`ShapeLog::write`] writes the same records as `shapes.jsonl` into a results folder, as
//!   `ftwire shape --log --out DIR` does ([`folder`]: the records solved in parallel, flagged
//!   in order).
//!
//! Both have the same points ([`ShapeLogParams::points`]) and the same marker metric (the
//! inner markers' mean distance, [`Measurement::inner_marker_mean`]).
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

use std::io::Write;
use std::path::PathBuf;

use ftwire_estimate::KirchhoffModel;
use ftwire_estimate::ft::MountingSpec;
use ftwire_estimate::identify::MeasurementNoise;
use ftwire_estimate::shape::{ConfigurationStd, ModelError};
use ftwire_rig::{
    Measurement, MeasurementParams, RawMap, ShapeRecord, Stream, StreamParams, WireBody,
    WireModelChoice,
};
use nalgebra::{Matrix6, Vector3, Vector6};
use serde::Serialize;

pub use folder::{BLOCK, ShapeLogRun, ShapeLogSummary, ShapeLogTimings};
pub use ftwire_rig::shape::{DEFAULT_POINTS, MARKER_NODES, MAX_POINTS, MIN_POINTS};

use super::{LogLine, a_tilde, raw_map, read_log};
use ftwire_app::config::wire::WireSpec;
use ftwire_app::error::LabError;
use ftwire_app::output::JsonLines;

/// What to shape: the log, the wire, the model, and how its `raw` records become `ã`.
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
    /// Gravity in the base clamp frame \[m/s²\] (`--gravity-in-clamp`): the shapes are the
    /// loaded model's, with the wire's weight; `None`: the weight-free model.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gravity_in_clamp: Option<[f64; 3]>,
    /// Points of each shape (`--points`, [`MIN_POINTS`] to [`MAX_POINTS`]).
    pub points: usize,
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
    /// ([`super::identify::LogDrift::noise`]), in place of the calibration's
    /// test error; `None`: not given.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sensor: Option<super::identify::LogDrift>,
    /// With [`Self::sensor`], the map's relative gain error per channel of `ã` as a fraction
    /// (`--gain-error`; `None`: 0).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gain_error: Option<f64>,
}

impl ShapeLogParams {
    /// The shapes of `log` for `wire`: `ã` as recorded, the weight-free model,
    /// [`DEFAULT_POINTS`] points, no error bars.
    pub fn new(log: PathBuf, wire: impl Into<String>) -> Self {
        Self {
            log,
            wire: wire.into(),
            calibration: None,
            mounting: None,
            gravity_in_clamp: None,
            points: DEFAULT_POINTS,
            a_std: None,
            model_error: None,
            sensor: None,
            gain_error: None,
        }
    }
}

/// `wire`'s model: the loaded rod under `gravity_in_clamp` (base clamp frame, m/s²: the
/// wire's weight and rest curvature), or the paper's weight-free one without.
///
/// # Errors
/// Bad input for an invalid wire, or a gravity naming `--gravity-in-clamp`.
pub fn wire_model(
    wire: &WireSpec,
    gravity_in_clamp: Option<[f64; 3]>,
) -> Result<KirchhoffModel, LabError> {
    let body = WireBody {
        params: wire
            .wire_params()
            .map_err(|e| LabError::bad_input(format!("wire {}: {e}", wire.name)))?,
        density: wire.density,
        natural_curvature: Vector3::from(wire.natural_curvature),
    };
    let choice = gravity_in_clamp
        .map(WireModelChoice::loaded)
        .transpose()
        .map_err(|e| LabError::bad_input(format!("--gravity-in-clamp: {e}")))?
        .unwrap_or_default();
    choice
        .model(&body)
        .map_err(|e| LabError::bad_input(format!("--gravity-in-clamp: {e}")))
}

/// The rig layer's measurement of `wire` with `map`: [`wire_model`] under
/// `gravity_in_clamp`, `points` per shape.
///
/// # Errors
/// Bad input naming `--gravity-in-clamp`, `--points` or `--model-error`.
pub fn measurement(
    wire: &WireSpec,
    map: RawMap,
    gravity_in_clamp: Option<[f64; 3]>,
    points: usize,
    model_error: Option<f64>,
) -> Result<Measurement, LabError> {
    let model = wire_model(wire, gravity_in_clamp)?;
    let model_error = model_error
        .map(ModelError::new)
        .transpose()
        .map_err(|e| LabError::bad_input(format!("--model-error: {e}")))?;
    let params = MeasurementParams {
        points,
        model_error,
        ..MeasurementParams::default()
    };
    Measurement::new(map, model, params)
        .map_err(|e| LabError::bad_input(format!("--points {points}: {e}")))
}

/// A log read and checked for shaping: every record with its line in the file and its `ã`,
/// and the measurement that shapes them.
#[derive(Debug, Clone)]
pub struct ShapeLog {
    log: PathBuf,
    lines: Vec<LogLine>,
    a_tilde: Vec<Vector6<f64>>,
    measurement: Measurement,
    /// `--a-std`.
    given_std: Option<ConfigurationStd>,
    /// The calibration's test error, if a calibration with one was given.
    calibration_std: Option<ConfigurationStd>,
    /// `--sensor`: the noise of `ã` from the data sheet, and the tare's time.
    sensor: Option<(MeasurementNoise, f64)>,
}

impl ShapeLog {
    /// Reads the wire, the calibration, the mounting and the log of `params`, and every
    /// record's `ã` ([`a_tilde`]), before any shape is solved.
    ///
    /// # Errors
    /// Bad input for an unknown or invalid wire, a gravity, point count or model error
    /// [`measurement`] refuses, standard deviations that are not finite and `>= 0`, a
    /// calibration or mounting [`raw_map`] refuses, a calibration whose test error is not
    /// finite and `>= 0`, a log [`read_log`] refuses, or a record [`a_tilde`] refuses (named by
    /// its line and time).
    pub fn load(params: &ShapeLogParams) -> Result<Self, LabError> {
        let wire = WireSpec::load(&params.wire).map_err(|e| LabError::bad_input(e.to_string()))?;
        let given_std = params
            .a_std
            .map(ConfigurationStd::new)
            .transpose()
            .map_err(|e| LabError::bad_input(format!("--a-std: {e}")))?;
        let map = raw_map(params.calibration.as_deref(), params.mounting.clone())?;
        let calibration_std = map
            .calibration()
            .and_then(|c| c.record().test_rmse)
            .map(ConfigurationStd::new)
            .transpose()
            .map_err(|e| LabError::bad_input(format!("the calibration's test_rmse: {e}")))?;
        let gravity = super::model_gravity(&map, params.gravity_in_clamp)?;
        let measurement = measurement(&wire, map, gravity, params.points, params.model_error)?;
        let lines = read_log(&params.log)?;
        let a_tilde = lines
            .iter()
            .map(|line| a_tilde(line, measurement.map()))
            .collect::<Result<_, _>>()
            .map_err(|e| e.context(format!("log {}", params.log.display())))?;
        let first_time = lines.first().map_or(0.0, |line| line.record.time);
        let sensor = params
            .sensor
            .as_ref()
            .map(|drift| {
                let noise = drift.noise(params.mounting.as_ref(), params.gain_error)?;
                Ok::<_, LabError>((noise, drift.tare_time.unwrap_or(first_time)))
            })
            .transpose()?;
        Ok(Self {
            log: params.log.clone(),
            lines,
            a_tilde,
            measurement,
            given_std,
            calibration_std,
            sensor,
        })
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

    /// The measurement the shapes are solved with (its map, model and points).
    pub fn measurement(&self) -> &Measurement {
        &self.measurement
    }

    /// The log's file.
    pub fn path(&self) -> &std::path::Path {
        &self.log
    }

    /// A new stream of the log's measurement: no tare, each record alone (a record is one
    /// reading or a rest averaged by the rig), the jump flag from the first record.
    ///
    /// # Errors
    /// None for these settings; typed for the rig layer's.
    pub fn stream(&self) -> Result<Stream, LabError> {
        Stream::new(&self.measurement, StreamParams::default())
            .map_err(|e| LabError::bad_input(e.to_string()))
    }
}

/// The record of `line` with its `ã` `a` through `measurement`, flagged by `stream` (give it
/// the records in order), with the covariance `a_covariance` of `ã` its error bars, and with
/// inner markers their mean distance. A model that cannot solve `ã` is an answer too, with
/// [`ShapeRecord::error`].
///
/// # Errors
/// Bad input for markers the distance refuses (named by the record's line).
pub fn shape_record(
    measurement: &Measurement,
    stream: &mut Stream,
    line: &LogLine,
    a: &Vector6<f64>,
    a_covariance: Option<&Matrix6<f64>>,
) -> Result<ShapeRecord, LabError> {
    let solved = measurement.solve(a, a_covariance);
    let confidence = stream.flag(a, &solved);
    let markers = match (&solved, line.record.markers.as_deref()) {
        (Ok(s), Some(markers)) => measurement
            .inner_marker_mean(a, markers, s)
            .map_err(|e| LabError::bad_input(format!("the markers of line {}: {e}", line.line)))?,
        _ => None,
    };
    Ok(ShapeRecord::new(
        (line.line, line.record.time),
        a,
        &solved,
        confidence,
        markers,
    ))
}

/// The shapes of a log's records, in order ([`shape_record`] of each): an iterator over
/// [`ShapeRecord`]s, made by [`LogShapes::new`] once the log, the wire and the calibration
/// have been read and checked.
pub struct LogShapes {
    log: ShapeLog,
    stream: Stream,
    next: usize,
}

impl LogShapes {
    /// The shapes of the log of `params`, for its wire.
    ///
    /// # Errors
    /// As [`ShapeLog::load`].
    pub fn new(params: &ShapeLogParams) -> Result<Self, LabError> {
        let log = ShapeLog::load(params)?;
        let stream = log.stream()?;
        Ok(Self {
            log,
            stream,
            next: 0,
        })
    }

    /// The log's records, each with its line in the file.
    pub fn lines(&self) -> &[LogLine] {
        self.log.lines()
    }
}

impl LogShapes {
    /// Writes every record's shape to `out` as soon as it has it, each flushed so that a
    /// reader at the other end of a pipe gets it at once: one JSON object per line with `json`
    /// ([`ftwire_app::output::JsonLines`]), its line of text ([`ShapeRecord`]'s `Display`)
    /// otherwise. A record the model cannot solve is written with its `error`.
    ///
    /// # Errors
    /// Bad input for a record the iterator refuses; [`LabError::Io`] when `out` cannot be
    /// written; after the last record, no answer when the model had no shape for some
    /// records ([`no_shape`]).
    pub fn write_all(self, out: &mut impl Write, json: bool) -> Result<(), LabError> {
        let records = self.lines().len();
        let mut failed = 0_usize;
        for shape in self {
            let shape = shape?;
            if shape.error.is_some() {
                failed += 1;
            }
            if json {
                JsonLines::new(&mut *out).write(&shape)?;
            } else {
                write!(out, "{shape}")
                    .and_then(|()| out.flush())
                    .map_err(|e| LabError::io("writing the result", e))?;
            }
        }
        no_shape(failed, records, "see their `error`")
    }
}

/// No answer when the model had no shape for `failed` of the `records` (`where_` says where
/// their `error` is); `Ok` when it had one for every record.
///
/// # Errors
/// No answer (exit 1) naming the count.
pub fn no_shape(failed: usize, records: usize, where_: &str) -> Result<(), LabError> {
    if failed > 0 {
        return Err(LabError::no_answer(format!(
            "no shape for {failed} of {records} records ({where_})"
        )));
    }
    Ok(())
}

impl Iterator for LogShapes {
    type Item = Result<ShapeRecord, LabError>;

    fn next(&mut self) -> Option<Self::Item> {
        let index = self.next;
        let line = self.log.lines.get(index)?;
        let a = self.log.a_tilde.get(index)?;
        self.next += 1;
        let covariance = self.log.a_covariance(index);
        Some(shape_record(
            &self.log.measurement,
            &mut self.stream,
            line,
            a,
            covariance.as_ref(),
        ))
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

    const GOOD: &str = r#"{"time": 0.25, "a": [0, 0.01, 0.01, -0.05, 0.03, 0], "b": {"position": [0.5, 0.1, 0], "rotation": [0, 0, 0.4]}, "markers": [[0.0, 0.0, 0.0], [0.1, 0.0, 0.0], null]}"#;

    #[test]
    fn every_record_gets_a_shape_in_order() {
        let path = log_file(
            "good",
            &format!("{GOOD}\n{}\n", GOOD.replace("0.25", "0.5")),
        );
        let params = ShapeLogParams::new(path.clone(), "nitinol-2mm-630");
        let shapes: Result<Vec<ShapeRecord>, LabError> =
            LogShapes::new(&params).and_then(Iterator::collect);
        let _ = std::fs::remove_file(&path);
        let shapes = shapes.expect("a good log");
        assert_eq!(shapes.len(), 2);
        for (shape, line) in shapes.iter().zip([1, 2]) {
            assert_eq!(shape.line, line);
            assert!(shape.error.is_none(), "{:?}", shape.error);
            let points = &shape.points;
            assert_eq!(points.len(), DEFAULT_POINTS);
            // The centreline starts at the base clamp point.
            assert!(points[0].iter().all(|v| v.abs() < 1e-12));
            assert!(shape.marker_mean_mm.is_some_and(f64::is_finite));
        }
        let text = shapes[0].to_string();
        assert!(
            text.starts_with("line 1 t = 0.250 s: confident, "),
            "{text}"
        );
        assert!(text.ends_with(" mm\n"), "{text}");
    }

    #[test]
    fn every_record_is_written_as_text_or_json_lines_and_a_missing_shape_is_no_answer() {
        // Outside A (a2 = a3 = a5 = a6 = 0): the model has no shape for it.
        let outside = GOOD.replace(
            "[0, 0.01, 0.01, -0.05, 0.03, 0]",
            "[0.01, 0, 0, -0.05, 0, 0]",
        );
        let path = log_file("write", &format!("{GOOD}\n{outside}\n"));
        let params = ShapeLogParams::new(path.clone(), "nitinol-2mm-630");
        let write = |json| -> (String, Result<(), LabError>) {
            let mut out = Vec::new();
            let result = LogShapes::new(&params).and_then(|s| s.write_all(&mut out, json));
            (String::from_utf8_lossy(&out).into_owned(), result)
        };
        let (text, result) = write(false);
        let (json, json_result) = write(true);
        let _ = std::fs::remove_file(&path);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 2, "{text}");
        assert!(
            lines[0].starts_with("line 1 t = 0.250 s: confident, "),
            "{text}"
        );
        assert!(
            lines[1].starts_with("line 2 t = 0.250 s: no shape: "),
            "{text}"
        );
        let objects: Vec<serde_json::Value> = json
            .lines()
            .map(|l| serde_json::from_str(l).expect("a JSON line"))
            .collect();
        assert_eq!(objects.len(), 2, "{json}");
        assert_eq!(objects[1]["line"], 2);
        assert!(objects[1]["error"].is_string(), "{json}");
        for result in [result, json_result] {
            let error = result.expect_err("one record has no shape");
            assert_eq!(error.kind(), "no_answer");
            assert_eq!(
                error.to_string(),
                "no shape for 1 of 2 records (see their `error`)"
            );
        }
        assert!(no_shape(0, 2, "anywhere").is_ok());
    }

    #[test]
    fn a_raw_record_without_a_calibration_is_bad_input() {
        let raw = GOOD.replace("\"a\"", "\"raw\"");
        let path = log_file("raw", &format!("{GOOD}\n{raw}\n"));
        let params = ShapeLogParams::new(path.clone(), "nitinol-2mm-630");
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
