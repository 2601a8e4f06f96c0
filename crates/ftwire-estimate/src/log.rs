//! The JSON Lines log that the estimators read: what a real rig records.
//!
//! One JSON object per line, in time order:
//!
//! ```json
//! {"time": 0.0, "raw": [0.41, -0.20, 0.63, 0.015, -0.006, 0.004], "b": {"position": [0.6, 0.05, 0.0], "rotation": [0.0, 0.0, 0.3]}}
//! {"time": 0.1, "a": [0.002, 0.011, -0.004, -0.12, 0.05, 0.0], "b": {"position": [0.6, 0.06, 0.0], "rotation": [0.0, 0.0, 0.31]}, "markers": [[0.0, 0.0, 0.0], null]}
//! ```
//!
//! | key | unit, frame | required |
//! | --- | --- | --- |
//! | `time` | s, the rig's clock, non-decreasing | yes |
//! | `raw` | the F/T reading averaged over the rest period, **force first** `(f1, f2, f3, τ1, τ2, τ3)`, N and N·m, sensor frame | one of `raw` and `a` |
//! | `a` | the configuration, already tared and calibrated, **torque first** `(τ1, τ2, τ3, f1, f2, f3)`, base clamp frame | one of `raw` and `a` |
//! | `b` | the second gripper's clamp pose relative to the base clamp frame: `position` in m, `rotation` a rotation vector (axis × angle) in rad | for identification |
//! | `markers` | motion-capture markers in the base clamp frame, m, in the order of the marker arc lengths; `null` for a missing marker | no |
//! | `gravity` | the gravity vector in the sensor frame at this record, m/s² (it turns with the wrist); needed with `raw` when the mounting has a tool whose weight is taken out | no |
//!
//! Values must be plausible: `time` at most 1e10 s in size, forces at most 1e4 N, torques 1e3
//! N·m, gravity 100 m/s², positions (of `b` and the markers) 1e3 m, at most 1000 markers, and a
//! line at most 16 MiB ([`MAX_FORCE`] and the constants beside it). Unknown keys are errors (a typo never passes
//! silently). Blank lines and lines starting with
//! `#` are skipped. A rotation vector's angle is at most `ftwire_core::MAX_ROTATION_ANGLE`. The
//! log is UTF-8 text; a leading byte-order mark is dropped. Every error names the line and the
//! offending value (or, for a byte that is not UTF-8, its column). [`read_log`] gives the
//! records; [`read_log_lines`] gives each with its line number in the file ([`LogLine`]), for
//! later messages about a record.

use std::io::{BufRead, Read};

use ftwire_core::text::Number;
use ftwire_core::{CoreError, Pose, ensure_rotation_vector, text};
use nalgebra::{Point3, Translation3, UnitQuaternion, Vector3, Vector6};
use serde::{Deserialize, Serialize};

use crate::EstimateError;

/// Largest force a log may hold \[N\]: far above any wrist sensor's range (a small 6-axis
/// sensor reads tens to hundreds of newtons).
pub const MAX_FORCE: f64 = 1e4;

/// Largest torque a log may hold \[N·m\].
pub const MAX_TORQUE: f64 = 1e3;

/// Largest gravity a log may hold \[m/s²\]: ten times the Earth's.
pub const MAX_GRAVITY: f64 = 100.0;

/// Largest position (a pose's, a marker's) a log may hold \[m\].
pub const MAX_POSITION: f64 = 1e3;

/// Largest time a log may hold \[s\]: Unix time is 1.7e9 s.
pub const MAX_TIME: f64 = 1e10;

/// Most markers a record may hold: a motion-capture session tracks tens (the paper's 11), and
/// each marker costs a closest-point search in every shape fit of `calibrate --log`.
pub const MAX_MARKERS: usize = 1000;

/// Longest line a log may hold \[bytes\]: a record with a few hundred markers is tens of kB.
pub const MAX_LINE_BYTES: usize = 16 << 20;

/// The units of the plausible ranges, for messages.
const PLAUSIBLE: &str = "forces in N up to 1e4, torques in N·m up to 1e3, gravity in m/s² up to \
                         100, positions in m up to 1e3";

/// The second gripper's pose as it is written in a log.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LogPose {
    /// Position \[m\] in the base clamp frame.
    pub position: [f64; 3],
    /// Orientation as a rotation vector \[rad\] (axis × angle), base clamp frame from tip clamp
    /// frame.
    pub rotation: [f64; 3],
}

impl LogPose {
    /// The pose as an isometry.
    pub fn to_pose(&self) -> Pose {
        Pose::from_parts(
            Translation3::from(Vector3::from(self.position)),
            UnitQuaternion::from_scaled_axis(Vector3::from(self.rotation)),
        )
    }

    /// The log form of a pose.
    pub fn from_pose(pose: &Pose) -> Self {
        let p = pose.translation.vector;
        let r = pose.rotation.scaled_axis();
        Self {
            position: [p.x, p.y, p.z],
            rotation: [r.x, r.y, r.z],
        }
    }
}

/// One line of a log.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LogRecord {
    /// Time \[s\] on the rig's clock.
    pub time: f64,
    /// Averaged raw F/T reading, force first, sensor frame.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub raw: Option<[f64; 6]>,
    /// Calibrated configuration, torque first, base clamp frame.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub a: Option<[f64; 6]>,
    /// The second gripper's pose relative to the base clamp frame (identification needs it;
    /// shape estimation and calibration do not).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub b: Option<LogPose>,
    /// Marker positions in the base clamp frame; `None` for a missing marker.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub markers: Option<Vec<Option<[f64; 3]>>>,
    /// The gravity vector in the sensor frame \[m/s²\] at this record (it turns with the
    /// wrist), for taking a tool's weight out of `raw` (`crate::ft::MountingSpec`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gravity: Option<[f64; 3]>,
}

impl LogRecord {
    /// The raw reading as a vector, if the line has one.
    pub fn raw(&self) -> Option<Vector6<f64>> {
        self.raw.map(|r| Vector6::from_column_slice(&r))
    }

    /// The configuration as a vector, if the line has one.
    pub fn a(&self) -> Option<Vector6<f64>> {
        self.a.map(|a| Vector6::from_column_slice(&a))
    }

    /// The markers as points (`None` where missing).
    pub fn markers(&self) -> Option<Vec<Option<Point3<f64>>>> {
        self.markers
            .as_ref()
            .map(|m| m.iter().map(|p| p.map(Point3::from)).collect())
    }

    fn check(&self, line: usize, previous_time: Option<f64>) -> Result<(), EstimateError> {
        let bad = |key: String, value: f64, allowed: &'static str| EstimateError::BadLogLine {
            line,
            message: format!("{key} = {} is not allowed: {allowed}", Number(value)),
        };
        if !(self.time.is_finite() && self.time.abs() <= MAX_TIME) {
            return Err(bad(
                "time".into(),
                self.time,
                "a finite number of seconds, at most 1e10 in size (Unix time is 1.7e9)",
            ));
        }
        if let Some(previous) = previous_time
            && self.time < previous
        {
            return Err(bad(
                "time".into(),
                self.time,
                "non-decreasing along the log (the previous line is later)",
            ));
        }
        match (&self.raw, &self.a) {
            (None, None) => {
                return Err(EstimateError::BadLogLine {
                    line,
                    message: "the line has neither `raw` nor `a`: one of them is needed".into(),
                });
            }
            (Some(_), Some(_)) => {
                return Err(EstimateError::BadLogLine {
                    line,
                    message: "the line has both `raw` and `a`: give one of them".into(),
                });
            }
            _ => {}
        }
        let vectors = [
            ("raw", self.raw.as_ref().map(|v| v.as_slice())),
            ("a", self.a.as_ref().map(|v| v.as_slice())),
            ("b.position", self.b.as_ref().map(|b| b.position.as_slice())),
            ("b.rotation", self.b.as_ref().map(|b| b.rotation.as_slice())),
            ("gravity", self.gravity.as_ref().map(|v| v.as_slice())),
        ];
        for (key, values) in vectors {
            if let Some(values) = values
                && let Some(i) = values.iter().position(|v| !v.is_finite())
            {
                return Err(bad(format!("{key}[{i}]"), values[i], "a finite number"));
            }
        }
        // Plausible sizes, so that one absurd value cannot stall or spoil the work after.
        let force_first = [
            MAX_FORCE, MAX_FORCE, MAX_FORCE, MAX_TORQUE, MAX_TORQUE, MAX_TORQUE,
        ];
        let torque_first = [
            MAX_TORQUE, MAX_TORQUE, MAX_TORQUE, MAX_FORCE, MAX_FORCE, MAX_FORCE,
        ];
        // (key, its values if present, each value's largest size)
        type Range<'a> = (&'a str, Option<&'a [f64]>, &'a [f64]);
        let ranges: [Range<'_>; 4] = [
            ("raw", self.raw.as_ref().map(|v| v.as_slice()), &force_first),
            ("a", self.a.as_ref().map(|v| v.as_slice()), &torque_first),
            (
                "gravity",
                self.gravity.as_ref().map(|v| v.as_slice()),
                &[MAX_GRAVITY; 3],
            ),
            (
                "b.position",
                self.b.as_ref().map(|b| b.position.as_slice()),
                &[MAX_POSITION; 3],
            ),
        ];
        for (key, values, limits) in ranges {
            if let Some(values) = values
                && let Some(i) = (0..values.len()).find(|&i| values[i].abs() > limits[i])
            {
                return Err(EstimateError::BadLogLine {
                    line,
                    message: format!(
                        "{key}[{i}] = {} is not allowed: at most {} in size ({})",
                        Number(values[i]),
                        limits[i],
                        PLAUSIBLE
                    ),
                });
            }
        }
        if let Some(markers) = &self.markers
            && markers.len() > MAX_MARKERS
        {
            return Err(EstimateError::BadLogLine {
                line,
                message: format!(
                    "markers holds {} markers, more than the {MAX_MARKERS} a record may hold",
                    markers.len()
                ),
            });
        }
        for (k, marker) in self.markers.iter().flatten().enumerate() {
            if let Some(p) = marker
                && let Some(i) = p.iter().position(|v| v.abs() > MAX_POSITION)
            {
                return Err(EstimateError::BadLogLine {
                    line,
                    message: format!(
                        "markers[{k}][{i}] = {} is not allowed: at most {MAX_POSITION} m in size",
                        Number(p[i])
                    ),
                });
            }
        }
        if let Some(b) = &self.b {
            ensure_rotation_vector("b.rotation", &b.rotation).map_err(|e| {
                EstimateError::BadLogLine {
                    line,
                    message: e.to_string(),
                }
            })?;
        }
        for (k, marker) in self.markers.iter().flatten().enumerate() {
            if let Some(p) = marker
                && let Some(i) = p.iter().position(|v| !v.is_finite())
            {
                return Err(bad(format!("markers[{k}][{i}]"), p[i], "a finite number"));
            }
        }
        Ok(())
    }
}

/// One record of a log with the number of the line it was read from (from 1, counting the
/// blank and comment lines that [`read_log_lines`] skips), so that a later check can name it.
#[derive(Debug, Clone, PartialEq)]
pub struct LogLine {
    /// The line's number in the file, from 1.
    pub line: usize,
    /// The record on that line.
    pub record: LogRecord,
}

/// Reads a whole log. Empty logs are an error: there is nothing to estimate from.
///
/// # Errors
/// [`EstimateError::BadLogLine`] naming the line (1-based) and the value for a line that is not
/// UTF-8 or not valid JSON, has an unknown or missing key, a non-finite number, a rotation
/// vector of angle beyond `ftwire_core::MAX_ROTATION_ANGLE`, or a time earlier than the line
/// before; [`EstimateError::EmptyLog`] when no record is found; [`EstimateError::Io`] when
/// reading fails.
///
/// # Example
/// ```
/// let text = r#"{"time": 0.0, "a": [0, 0, 0.01, 0, 0, 0], "b": {"position": [0.5, 0.1, 0], "rotation": [0, 0, 0.4]}}"#;
/// let log = ftwire_estimate::log::read_log(text.as_bytes())?;
/// assert_eq!(log.len(), 1);
/// assert!(ftwire_estimate::log::read_log("{\"time\": 0}".as_bytes()).is_err());
/// # Ok::<(), ftwire_estimate::EstimateError>(())
/// ```
pub fn read_log(reader: impl BufRead) -> Result<Vec<LogRecord>, EstimateError> {
    read_log_lines(reader).map(|lines| lines.into_iter().map(|l| l.record).collect())
}

/// [`read_log`] keeping each record's line number in the file, for messages about a record
/// that name its line (`ftwire shape --log`'s `shapes.jsonl`, a record without `b` or
/// `gravity`).
///
/// # Errors
/// As [`read_log`].
///
/// # Example
/// ```
/// let a = r#"{"time": 0.0, "a": [0, 0, 0.01, 0, 0, 0]}"#;
/// let log = ftwire_estimate::log::read_log_lines(format!("# rig\n\n{a}\n{a}\n").as_bytes())?;
/// assert_eq!(log.iter().map(|l| l.line).collect::<Vec<_>>(), [3, 4]);
/// # Ok::<(), ftwire_estimate::EstimateError>(())
/// ```
pub fn read_log_lines(mut reader: impl BufRead) -> Result<Vec<LogLine>, EstimateError> {
    let mut records: Vec<LogLine> = Vec::new();
    let mut bytes = Vec::new();
    for line_number in 1.. {
        bytes.clear();
        let read = (&mut reader)
            .take(MAX_LINE_BYTES as u64 + 1)
            .read_until(b'\n', &mut bytes)
            .map_err(|e| EstimateError::Io {
                what: format!("line {line_number} of the log"),
                message: e.to_string(),
            })?;
        if read == 0 {
            break;
        }
        if bytes.len() > MAX_LINE_BYTES {
            return Err(EstimateError::BadLogLine {
                line: line_number,
                message: format!(
                    "the line is longer than {} MiB: a log is text, one record per line",
                    MAX_LINE_BYTES >> 20
                ),
            });
        }
        let line = if line_number == 1 {
            text::strip_bom(&bytes)
        } else {
            &bytes
        };
        let text = text::utf8(line).map_err(|e| EstimateError::BadLogLine {
            line: line_number,
            message: match e {
                CoreError::NotUtf8 { column, byte, .. } => format!(
                    "column {column}: byte 0x{byte:02X} is not valid UTF-8; a log is UTF-8 text"
                ),
                e => e.to_string(),
            },
        })?;
        let trimmed = text.trim();
        if trimmed.is_empty() || trimmed.starts_with('#') {
            continue;
        }
        let record: LogRecord =
            serde_json::from_str(trimmed).map_err(|e| EstimateError::BadLogLine {
                line: line_number,
                message: format!("{e}, near `{}`", snippet(trimmed, e.column())),
            })?;
        record.check(line_number, records.last().map(|r| r.record.time))?;
        records.push(LogLine {
            line: line_number,
            record,
        });
    }
    if records.is_empty() {
        return Err(EstimateError::EmptyLog);
    }
    Ok(records)
}

/// Up to 24 characters of `text` ending at the 1-based `column` serde_json reports, so that an
/// error shows the offending value.
fn snippet(text: &str, column: usize) -> String {
    let chars: Vec<char> = text.chars().collect();
    let end = column.clamp(1, chars.len().max(1)).min(chars.len());
    let start = end.saturating_sub(24);
    chars
        .get(start..end)
        .map_or_else(String::new, |c| c.iter().collect())
}

/// Writes one record as a line of JSON (no trailing newline).
///
/// # Errors
/// [`EstimateError::Io`] if serialisation fails (it cannot for finite values).
pub fn to_line(record: &LogRecord) -> Result<String, EstimateError> {
    serde_json::to_string(record).map_err(|e| EstimateError::Io {
        what: "a log record".into(),
        message: e.to_string(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(extra: &str) -> String {
        format!(
            r#"{{"time": 0.5, "b": {{"position": [0.5, 0.1, 0], "rotation": [0, 0, 0.4]}}{extra}}}"#
        )
    }

    #[test]
    fn a_record_round_trips_through_its_line() -> Result<(), EstimateError> {
        let record = LogRecord {
            time: 1.25,
            raw: Some([0.41, -0.2, 0.63, 0.015, -0.006, 0.004]),
            a: None,
            b: Some(LogPose::from_pose(&Pose::from_parts(
                Translation3::new(0.6, 0.05, -0.01),
                UnitQuaternion::from_euler_angles(0.1, -0.2, 0.3),
            ))),
            markers: Some(vec![Some([0.0, 0.0, 0.0]), None, Some([0.3, 0.01, 0.0])]),
            gravity: Some([0.0, -9.81, 0.0]),
        };
        let text = to_line(&record)?;
        let back = read_log(text.as_bytes())?;
        assert_eq!(back, vec![record.clone()]);
        let Some(b) = record.b else {
            panic!("the record has a pose");
        };
        let again = LogPose::from_pose(&b.to_pose());
        for i in 0..3 {
            assert!((again.rotation[i] - b.rotation[i]).abs() < 1e-15);
        }
        Ok(())
    }

    #[test]
    fn a_record_without_the_grippers_pose_is_read() -> Result<(), EstimateError> {
        let text = r#"{"time": 0, "raw": [1, 2, 3, 0.1, 0.2, 0.3], "markers": [[0, 0, 0], null]}"#;
        let log = read_log(text.as_bytes())?;
        assert_eq!(log.first().map(|r| r.b), Some(None));
        Ok(())
    }

    #[test]
    fn every_bad_line_names_its_line_and_value() {
        let cases = [
            (line(r#", "a": [0, 0, 0.01, 0, 0, 0], "extra": 1"#), "extra"),
            (line(""), "neither"),
            (
                line(r#", "a": [0, 0, 0.01], "raw": [1, 2, 3, 4, 5, 6]"#),
                "invalid length",
            ),
            (line(r#", "a": [0, 0, 0.01, 0, 0, 1e999]"#), "1e999"),
            (
                // serde_json refuses the overflow itself; the snippet names the key.
                line(r#", "raw": [0, 0, 0.01, 0, 0, 0], "gravity": [0, 1e999, 0]"#),
                r#""gravity": [0, 1e999"#,
            ),
            ("{not json".to_string(), "key must be a string"),
        ];
        for (text, needle) in cases {
            let input = format!("# a comment\n\n{text}\n");
            match read_log(input.as_bytes()) {
                Err(EstimateError::BadLogLine { line, message }) => {
                    assert_eq!(line, 3, "{message}");
                    assert!(
                        message.contains(needle),
                        "{message} should mention {needle}"
                    );
                }
                other => panic!("{text}: expected BadLogLine, got {other:?}"),
            }
        }
    }

    #[test]
    fn a_leading_bom_is_dropped_and_invalid_utf8_is_located() -> Result<(), EstimateError> {
        let a = line(r#", "a": [0, 0, 0.01, 0, 0, 0]"#);
        let plain = read_log(format!("{a}\n").as_bytes())?;
        let with_bom = [b"\xEF\xBB\xBF".as_slice(), a.as_bytes(), b"\n"].concat();
        assert_eq!(read_log(with_bom.as_slice())?, plain);
        // Only at the start: a BOM on a later line is not JSON.
        let late = [a.as_bytes(), b"\n\xEF\xBB\xBF", a.as_bytes()].concat();
        assert!(matches!(
            read_log(late.as_slice()),
            Err(EstimateError::BadLogLine { line: 2, .. })
        ));
        let latin1 = [a.as_bytes(), b"\n# caf\xE9\n"].concat();
        match read_log(latin1.as_slice()) {
            Err(EstimateError::BadLogLine { line, message }) => {
                assert_eq!(line, 2);
                assert!(
                    message.contains("column 6") && message.contains("0xE9"),
                    "{message}"
                );
            }
            other => panic!("expected BadLogLine, got {other:?}"),
        }
        Ok(())
    }

    #[test]
    fn an_over_large_rotation_vector_is_named_with_its_value() {
        let input = line(r#", "a": [0, 0, 0.01, 0, 0, 0]"#).replace("0.4]", "1e300]");
        match read_log(input.as_bytes()) {
            Err(EstimateError::BadLogLine { line, message }) => {
                assert_eq!(line, 1);
                assert!(
                    message.contains("b.rotation")
                        && message.contains("1e300")
                        && message.contains("at most 1e6 rad"),
                    "{message}"
                );
            }
            other => panic!("expected BadLogLine, got {other:?}"),
        }
    }

    #[test]
    fn time_going_backwards_is_refused() {
        let a = r#", "a": [0, 0, 0.01, 0, 0, 0]"#;
        let input = format!("{}\n{}\n", line(a), line(a).replace("0.5", "0.25"));
        match read_log(input.as_bytes()) {
            Err(EstimateError::BadLogLine { line, message }) => {
                assert_eq!(line, 2);
                assert!(message.contains("time = 0.25"), "{message}");
            }
            other => panic!("expected BadLogLine, got {other:?}"),
        }
    }

    #[test]
    fn each_record_keeps_its_line_in_the_file() -> Result<(), EstimateError> {
        let a = line(r#", "a": [0, 0, 0.01, 0, 0, 0]"#);
        let input = [
            b"\xEF\xBB\xBF# rig 7\n\n".as_slice(),
            a.as_bytes(),
            b"\n   \n# moved\n",
            a.as_bytes(),
        ]
        .concat();
        let lines = read_log_lines(input.as_slice())?;
        assert_eq!(lines.iter().map(|l| l.line).collect::<Vec<_>>(), [3, 6]);
        let records: Vec<LogRecord> = lines.into_iter().map(|l| l.record).collect();
        assert_eq!(records, read_log(input.as_slice())?);
        Ok(())
    }

    #[test]
    fn an_empty_log_is_an_error() {
        assert!(matches!(
            read_log("# only a comment\n\n".as_bytes()),
            Err(EstimateError::EmptyLog)
        ));
    }

    /// Every value has a plausible size, checked per line before any work: a huge reading, a
    /// time beyond 1e10 s or a line beyond 16 MiB is refused naming the line and the key;
    /// Unix time is fine.
    #[test]
    fn implausible_values_and_endless_lines_are_refused_naming_the_line() {
        let record = |raw: &str, time: &str| format!(r#"{{"time": {time}, "raw": [{raw}]}}"#);
        let unix = record("1, 2, 3, 0.1, 0.2, 0.3", "1.7e9");
        assert!(read_log(format!("{unix}\n").as_bytes()).is_ok());
        let ok = record("1, 2, 3, 0.1, 0.2, 0.3", "0");
        for (text, key) in [
            (record("1e308, 2, 3, 0.1, 0.2, 0.3", "0"), "raw[0] = 1e308 "),
            (record("1, 2, 3, 0.1, 2e3, 0.3", "0"), "raw[4]"),
            (
                record("1, 2, 3, 0.1, 0.2, 0.3", "1e11"),
                "time = 100000000000 ",
            ),
            (
                r#"{"time": 0, "a": [0, 0, 0, 1e5, 0, 0]}"#.to_owned(),
                "a[3]",
            ),
            (
                r#"{"time": 0, "raw": [1, 2, 3, 0, 0, 0], "gravity": [0, 0, 1e200]}"#.to_owned(),
                "gravity[2] = 1e200 ",
            ),
            (
                r#"{"time": 0, "a": [0, 0, 0.01, 0, 0, 0], "markers": [[0, 0, 1e9]]}"#.to_owned(),
                "markers[0][2]",
            ),
        ] {
            let error = read_log(format!("{ok}\n{text}\n").as_bytes()).expect_err(key);
            let message = error.to_string();
            assert!(
                message.contains("line 2") && message.contains(key) && message.len() < 300,
                "{message}"
            );
        }
        let many = vec!["[0, 0, 0]"; MAX_MARKERS + 1].join(", ");
        let text = format!(r#"{{"time": 1, "a": [0, 0, 0.01, 0, 0, 0], "markers": [{many}]}}"#);
        let error = read_log(format!("{ok}\n{text}\n").as_bytes()).expect_err("too many markers");
        assert!(
            error
                .to_string()
                .contains("line 2: markers holds 1001 markers"),
            "{error}"
        );
        let endless = vec![b'x'; MAX_LINE_BYTES + 10];
        let error = read_log(&endless[..]).expect_err("an endless line");
        assert!(error.to_string().contains("16 MiB"), "{error}");
    }
}
