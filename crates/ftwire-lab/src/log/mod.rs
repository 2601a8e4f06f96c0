//! A real rig's JSON Lines log (format and checks: [`ftwire_estimate::log`]), as `ftwire
//! identify --log` and `ftwire shape --log` read it: [`read_log`] reads a file and names the
//! file and the line of any bad record, [`load_calibration`] the learnt weights that turn a
//! record's tared `raw` reading into `ã`, and [`a_tilde`] gives a record's `ã` (torque first,
//! base clamp frame).
//!
//! - [`identify`]: identify the wire's `η = (c1, c2, c3, L)` from a log;
//! - [`shape`]: the wire's shape for every record of a log.
//!
//! Guarded by this module's tests and `crates/ftwire/tests/{identify_log,shape_log}.rs`.

pub mod calibrate;
pub mod identify;
pub mod shape;

use std::fs::File;
use std::io::BufReader;
use std::path::Path;

use ftwire_estimate::calibration::Calibration;
pub use ftwire_estimate::log::{LogPose, LogRecord};
use nalgebra::Vector6;

use crate::error::LabError;

/// Reads the log at `path`: every record, in order.
///
/// # Errors
/// Bad input naming the file: one that cannot be opened, an empty log (no record), or a bad
/// line, named by its number (from 1) and its value (what [`ftwire_estimate::log::read_log`]
/// refuses: malformed JSON, an unknown or missing key, a non-finite number, a time earlier
/// than the line before, ...).
///
/// # Example
/// ```
/// # let dir = std::env::temp_dir().join(format!("ftwire-read-log-doc-{}", std::process::id()));
/// # std::fs::create_dir_all(&dir)?;
/// let path = dir.join("rig.jsonl");
/// let good = r#"{"time": 0.0, "a": [0, 0.01, 0, 0, 0.1, 0], "b": {"position": [0.5, 0.1, 0], "rotation": [0, 0, 0.4]}}"#;
/// std::fs::write(&path, format!("{good}\n{{\"time\": oops\n"))?;
/// let error = ftwire_lab::log::read_log(&path).err().ok_or("line 2 is bad")?;
/// assert!(error.to_string().contains("line 2"));
/// std::fs::write(&path, format!("{good}\n"))?;
/// assert_eq!(ftwire_lab::log::read_log(&path)?.len(), 1);
/// # std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn read_log(path: &Path) -> Result<Vec<LogRecord>, LabError> {
    let file = File::open(path)
        .map_err(|e| LabError::bad_input(format!("cannot open log {}: {e}", path.display())))?;
    ftwire_estimate::log::read_log(BufReader::new(file))
        .map_err(|e| LabError::bad_input(format!("log {}: {e}", path.display())))
}

/// Loads the learnt calibration (the weights file of `ftwire experiment calibrate`).
///
/// # Errors
/// Bad input naming the file (`--calibration FILE: ...`) when it cannot be read or is not a
/// calibration.
pub fn load_calibration(path: &Path) -> Result<Calibration, LabError> {
    Calibration::load(path)
        .map_err(|e| LabError::bad_input(format!("--calibration {}: {e}", path.display())))
}

/// The record's `ã` (torque first, base clamp frame): its `a` as it is, or its tared `raw`
/// reading through `calibration`; `None` for a `raw` record without a calibration.
///
/// A calibration may map an extreme reading to a value that is not finite; a caller that
/// needs finite values checks them.
pub fn a_tilde(record: &LogRecord, calibration: Option<&Calibration>) -> Option<Vector6<f64>> {
    match (record.a(), record.raw(), calibration) {
        (Some(a), _, _) => Some(a),
        (None, Some(raw), Some(calibration)) => Some(calibration.apply(&raw)),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unique file path under the system's temporary folder (the caller removes it).
    fn temp_file(tag: &str) -> std::path::PathBuf {
        std::env::temp_dir().join(format!("ftwire-lab-log-{tag}-{}.jsonl", std::process::id()))
    }

    const GOOD: &str = r#"{"time": 0.0, "a": [0, 0.01, 0.01, -0.05, 0.03, 0], "b": {"position": [0.5, 0.1, 0], "rotation": [0, 0, 0.4]}}"#;

    #[test]
    fn a_bad_line_is_bad_input_naming_the_file_the_line_and_the_value() {
        let path = temp_file("bad");
        let bad = GOOD.replace("-0.05", "1e999");
        std::fs::write(&path, format!("{GOOD}\n\n{bad}\n")).expect("writes");
        let error = read_log(&path).expect_err("a non-finite value");
        let _ = std::fs::remove_file(&path);
        assert_eq!(error.kind(), "bad_input");
        let message = error.to_string();
        assert!(
            message.starts_with(&format!("log {}: ", path.display())),
            "{message}"
        );
        assert!(message.contains("line 3"), "{message}");
        assert!(
            message.contains("inf") || message.contains("1e999"),
            "{message}"
        );
    }

    #[test]
    fn an_empty_or_missing_log_is_bad_input() {
        let path = temp_file("empty");
        std::fs::write(&path, "# a comment only\n\n").expect("writes");
        let error = read_log(&path).expect_err("no record");
        let _ = std::fs::remove_file(&path);
        assert_eq!(error.kind(), "bad_input");
        assert!(error.to_string().contains("no record"), "{error}");
        let error = read_log(&temp_file("missing")).expect_err("no file");
        assert_eq!(error.kind(), "bad_input");
        assert!(error.to_string().starts_with("cannot open log "), "{error}");
    }

    #[test]
    fn a_good_log_reads_in_order_and_gives_its_a() {
        let path = temp_file("good");
        let later = GOOD.replace("\"time\": 0.0", "\"time\": 0.5");
        std::fs::write(&path, format!("# rig\n{GOOD}\n{later}\n")).expect("writes");
        let records = read_log(&path);
        let _ = std::fs::remove_file(&path);
        let records = records.expect("a good log");
        assert_eq!(records.len(), 2);
        assert!(records[1].time > records[0].time);
        let a = a_tilde(&records[0], None).expect("`a` needs no calibration");
        assert_eq!(a[4].to_bits(), 0.03_f64.to_bits());
        let raw = LogRecord {
            a: None,
            raw: Some([0.1; 6]),
            ..records[0].clone()
        };
        assert!(a_tilde(&raw, None).is_none(), "`raw` needs a calibration");
    }

    #[test]
    fn a_missing_calibration_is_bad_input_naming_the_flag() {
        let error =
            load_calibration(Path::new("/nonexistent/calibration.json")).expect_err("no such file");
        assert_eq!(error.kind(), "bad_input");
        assert!(
            error
                .to_string()
                .starts_with("--calibration /nonexistent/calibration.json: ")
        );
    }
}
