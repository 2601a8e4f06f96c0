//! The wire's shape for every record of a rig log (paper §IV-C), as a real rig would run the
//! estimator offline.
//!
//! For each record, `ã` is the record's `a`, or its (tared) `raw` reading through the learnt
//! calibration ([`super::a_tilde`]); then `ShapeEstimator` gives the centreline (64 nodes,
//! base clamp frame) and a confidence flag (`confident`, `not_stable`, or `jump`: a possible
//! contact). With markers in the record, the mean distance of the seen markers to the estimate
//! is reported too. [`LogShapes`] reads and checks the log and gives the records' shapes in
//! order; [`shape_record`] is one record's. Guarded by this module's tests and
//! `crates/ftwire/tests/shape_log.rs` (a log the shape experiment saved gives the live run's
//! answer).

use std::fmt;
use std::path::PathBuf;

use ftwire_estimate::KirchhoffModel;
use ftwire_estimate::calibration::Calibration;
use ftwire_estimate::shape::{Confidence, ShapeEstimator, marker_distances};
use nalgebra::Point3;
use serde::Serialize;

use super::{LogRecord, a_tilde, load_calibration, read_log};
use crate::error::{LabError, from_estimate};
use crate::wire::WireSpec;

/// What to shape: the log, the wire, and the calibration of its `raw` records.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ShapeLogParams {
    /// The JSON Lines log ([`ftwire_estimate::log`]).
    pub log: PathBuf,
    /// The wire the shapes are solved for: a preset name or a wire file (TOML).
    pub wire: String,
    /// The learnt calibration's weights file, for records with `raw`; `None`: every record
    /// must hold `a`.
    pub calibration: Option<PathBuf>,
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

/// The shape of `record` (index `index` in its log, from 0) from `estimator`, which keeps the
/// previous estimate to flag jumps: give it the records in order. A model that cannot solve
/// `ã` is an answer too, with [`RecordShape::error`].
///
/// # Errors
/// Bad input for a record without `ã` ([`super::a_tilde`]: `raw` without `calibration`) or
/// markers the distance refuses.
pub fn shape_record(
    estimator: &mut ShapeEstimator<KirchhoffModel>,
    index: usize,
    record: &LogRecord,
    calibration: Option<&Calibration>,
) -> Result<RecordShape, LabError> {
    let a = a_tilde(record, calibration)
        .ok_or_else(|| LabError::bad_input(format!("record {index} has neither a nor raw")))?;
    let mut shape = RecordShape {
        record: index,
        time: record.time,
        a_tilde: Some(a.into()),
        confidence: None,
        points: None,
        marker_mean_mm: None,
        error: None,
    };
    match estimator.estimate(&a) {
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
        }
        Err(e) => shape.error = Some(e.to_string()),
    }
    Ok(shape)
}

/// The shapes of a log's records, in order ([`shape_record`] of each): an iterator over
/// [`RecordShape`]s, made by [`LogShapes::new`] once the log, the wire and the calibration
/// have been read and checked.
pub struct LogShapes {
    records: Vec<LogRecord>,
    calibration: Option<Calibration>,
    estimator: ShapeEstimator<KirchhoffModel>,
    next: usize,
}

impl LogShapes {
    /// The shapes of the log of `params`, for its wire.
    ///
    /// # Errors
    /// Bad input for an unknown or invalid wire, a log [`read_log`] refuses, a calibration
    /// [`load_calibration`] refuses, or a `raw` record without a calibration (named by its
    /// index and time).
    pub fn new(params: &ShapeLogParams) -> Result<Self, LabError> {
        let wire = WireSpec::load(&params.wire).map_err(|e| LabError::bad_input(e.to_string()))?;
        let wire_params = wire
            .wire_params()
            .map_err(|e| LabError::bad_input(format!("wire {}: {e}", wire.name)))?;
        let records = read_log(&params.log)?;
        let calibration = params
            .calibration
            .as_deref()
            .map(load_calibration)
            .transpose()?;
        if calibration.is_none()
            && let Some((i, r)) = records.iter().enumerate().find(|(_, r)| r.raw.is_some())
        {
            return Err(LabError::bad_input(format!(
                "--log {}: record {i} (time {}) has a raw F/T reading: give --calibration FILE \
                 (the weights from `ftwire experiment calibrate`) to turn it into ã",
                params.log.display(),
                r.time
            )));
        }
        Ok(Self {
            records,
            calibration,
            estimator: ShapeEstimator::new(KirchhoffModel::new(wire_params)),
            next: 0,
        })
    }

    /// The log's records.
    pub fn records(&self) -> &[LogRecord] {
        &self.records
    }
}

impl Iterator for LogShapes {
    type Item = Result<RecordShape, LabError>;

    fn next(&mut self) -> Option<Self::Item> {
        let index = self.next;
        let record = self.records.get(index)?;
        self.next += 1;
        Some(shape_record(
            &mut self.estimator,
            index,
            record,
            self.calibration.as_ref(),
        ))
    }
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
                writeln!(
                    out,
                    "record {} t = {:.3} s: {}, tip at ({:.4}, {:.4}, {:.4}) m{markers}",
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
        };
        let error = LogShapes::new(&params).err();
        let _ = std::fs::remove_file(&path);
        let error = error.expect("raw needs a calibration");
        assert_eq!(error.kind(), "bad_input");
        let message = error.to_string();
        assert!(message.contains("record 1 (time 0.25)"), "{message}");
        assert!(message.contains("--calibration"), "{message}");
    }
}
