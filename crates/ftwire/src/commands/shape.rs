//! `ftwire shape --log`: the wire's shape for every record of a rig log (paper §IV-C), as a
//! real rig would run the estimator offline.
//!
//! For each record, `ã` is the record's `a`, or its (tared) `raw` reading through the learnt
//! calibration; then `ShapeEstimator` gives the centreline (64 nodes, base clamp frame) and a
//! confidence flag (`confident`, `not_stable`, or `jump`: a possible contact). With markers in
//! the record, the mean distance of the seen markers to the estimate is reported too.
//!
//! Output per record: with `--json`, one JSON object per line: `record` (from 0), `time`,
//! `a_tilde`, `confidence`, `points` (\[m\]), and `marker_mean_mm` when the record has
//! markers; without, one line of text. A record the model cannot solve gets an `error`
//! instead, and the command then exits 1 after the last record. A bad or empty log, or a
//! `raw` record without `--calibration`, is bad input (exit 2) naming the line or record.

use std::io::{self, BufReader, Write};

use ftwire::output::JsonLines;
use ftwire_estimate::KirchhoffModel;
use ftwire_estimate::calibration::Calibration;
use ftwire_estimate::log::read_log;
use ftwire_estimate::shape::{Confidence, ShapeEstimator, marker_distances};
use ftwire_lab::error::{LabError, from_estimate};
use ftwire_lab::wire::WireSpec;
use nalgebra::Point3;
use serde::Serialize;

use crate::cli::shape::ShapeArgs;

/// One record's answer.
#[derive(Debug, Serialize)]
struct RecordShape {
    record: usize,
    time: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    a_tilde: Option<[f64; 6]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    confidence: Option<&'static str>,
    #[serde(skip_serializing_if = "Option::is_none")]
    points: Option<Vec<[f64; 3]>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    marker_mean_mm: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    error: Option<String>,
}

fn confidence_name(confidence: &Confidence) -> &'static str {
    match confidence {
        Confidence::Confident => "confident",
        Confidence::NotStable => "not_stable",
        Confidence::Jump { .. } => "jump",
    }
}

/// Runs the command.
pub fn run(args: ShapeArgs) -> Result<(), LabError> {
    let wire = WireSpec::load(&args.wire).map_err(|e| LabError::bad_input(e.to_string()))?;
    let params = wire
        .wire_params()
        .map_err(|e| LabError::bad_input(format!("wire {}: {e}", wire.name)))?;
    let file = std::fs::File::open(&args.log).map_err(|e| {
        LabError::bad_input(format!("--log {}: cannot open it: {e}", args.log.display()))
    })?;
    let records = read_log(BufReader::new(file))
        .map_err(|e| LabError::bad_input(format!("--log {}: {e}", args.log.display())))?;
    let calibration =
        match &args.calibration.file {
            Some(path) => Some(Calibration::load(path).map_err(|e| {
                LabError::bad_input(format!("--calibration {}: {e}", path.display()))
            })?),
            None => None,
        };
    if calibration.is_none()
        && let Some((i, r)) = records.iter().enumerate().find(|(_, r)| r.raw.is_some())
    {
        return Err(LabError::bad_input(format!(
            "--log {}: record {i} (time {}) has a raw F/T reading: give --calibration FILE \
             (the weights from `ftwire experiment calibrate`) to turn it into ã",
            args.log.display(),
            r.time
        )));
    }
    let mut estimator = ShapeEstimator::new(KirchhoffModel::new(params));
    let stdout = io::stdout();
    let mut out = stdout.lock();
    let mut failed = 0_usize;
    for (i, record) in records.iter().enumerate() {
        let a = match (record.a(), record.raw(), &calibration) {
            (Some(a), _, _) => a,
            (None, Some(raw), Some(calibration)) => calibration.apply(&raw),
            _ => {
                return Err(LabError::bad_input(format!(
                    "record {i} has neither a nor raw"
                )));
            }
        };
        let mut answer = RecordShape {
            record: i,
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
                        .map_err(|e| from_estimate(e, &format!("markers of record {i}")))?;
                    if !d.is_empty() {
                        answer.marker_mean_mm = Some(1e3 * d.iter().sum::<f64>() / d.len() as f64);
                    }
                }
                answer.confidence = Some(confidence_name(&estimate.confidence));
                answer.points = Some(positions.iter().map(|p| [p.x, p.y, p.z]).collect());
            }
            Err(e) => {
                failed += 1;
                answer.error = Some(e.to_string());
            }
        }
        if args.output.json {
            JsonLines::new(&mut out).write(&answer)?;
        } else {
            write_text(&mut out, &answer)?;
        }
    }
    if failed > 0 {
        return Err(LabError::no_answer(format!(
            "no shape for {failed} of {} records (see their `error`)",
            records.len()
        )));
    }
    Ok(())
}

fn write_text(out: &mut impl Write, answer: &RecordShape) -> Result<(), LabError> {
    let text = match (&answer.points, &answer.error) {
        (Some(points), _) => {
            let tip = points.last().copied().unwrap_or_default();
            let markers = answer
                .marker_mean_mm
                .map_or_else(String::new, |m| format!(", markers {m:.2} mm"));
            format!(
                "record {} t = {:.3} s: {}, tip at ({:.4}, {:.4}, {:.4}) m{markers}\n",
                answer.record,
                answer.time,
                answer.confidence.unwrap_or("-"),
                tip[0],
                tip[1],
                tip[2]
            )
        }
        (None, error) => format!(
            "record {} t = {:.3} s: no shape: {}\n",
            answer.record,
            answer.time,
            error.as_deref().unwrap_or("unknown")
        ),
    };
    out.write_all(text.as_bytes())
        .and_then(|()| out.flush())
        .map_err(|e| LabError::io("writing the result", e))
}
