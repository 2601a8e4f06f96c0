//! A real rig's JSON Lines log (format and checks: [`ftwire_estimate::log`]), as `ftwire
//! identify --log` and `ftwire shape --log` read it: [`read_log`] reads a file and names the
//! file and the line of any bad record, [`load_calibration`] the learnt weights, and
//! [`a_tilde`] gives a record's `ã` (torque first, base clamp frame) by the rig layer's
//! [`RawMap`] of `--calibration` and `--mounting` ([`raw_map`]):
//!
//! - a record's `a` is used as it is;
//! - a record's `raw` reading (force first, sensor frame, not tared) first loses the weight
//!   of the tool below the sensor (`MountingSpec::compensate`, with the record's `gravity`),
//!   then goes through the learnt calibration at the record's time
//!   (`Calibration::apply_at`: its drift term, if it has one); without a calibration but with
//!   a mounting file, through the mounting alone (`Mounting::to_configuration`: the model as
//!   it is, uncalibrated); with neither, it is refused.
//!
//! - [`identify`]: identify the wire's `η = (c1, c2, c3, L)` from a log;
//! - [`shape`]: the wire's shape for every record of a log.
//!
//! Guarded by this module's tests, `tests/logs.rs` and
//! `crates/ftwire/tests/{identify_log,shape_log}.rs`.

pub mod calibrate;
mod calibrate_text;
pub mod identification;
pub mod identify;
pub mod shape;

use std::io::BufReader;
use std::path::Path;

use ftwire_estimate::calibration::Calibration;
use ftwire_estimate::ft::MountingSpec;
pub use ftwire_estimate::log::{LogLine, LogPose, LogRecord};
pub use ftwire_rig::RawMap;
use ftwire_rig::{Reading, RigError};
use nalgebra::Vector6;

use ftwire_app::error::LabError;

/// Reads the log at `path`: every record with its line number in the file, in order.
///
/// # Errors
/// Bad input naming the file: one that cannot be opened, an empty log (no record), or a bad
/// line, named by its number (from 1) and its value (what
/// [`ftwire_estimate::log::read_log_lines`] refuses: malformed JSON, an unknown or missing
/// key, a non-finite number, a time earlier than the line before, ...).
///
/// # Example
/// ```
/// # let dir = std::env::temp_dir().join(format!("ftwire-read-log-doc-{}", std::process::id()));
/// # std::fs::create_dir_all(&dir)?;
/// let path = dir.join("rig.jsonl");
/// let good = r#"{"time": 0.0, "a": [0, 0.01, 0, 0, 0.1, 0], "b": {"position": [0.5, 0.1, 0], "rotation": [0, 0, 0.4]}}"#;
/// std::fs::write(&path, format!("{good}\n{{\"time\": oops\n"))?;
/// let error = ftwire_logs::read_log(&path).err().ok_or("line 2 is bad")?;
/// assert!(error.to_string().contains("line 2"));
/// std::fs::write(&path, format!("# rig 7\n{good}\n"))?;
/// let log = ftwire_logs::read_log(&path)?;
/// assert_eq!((log.len(), log[0].line), (1, 2));
/// # std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn read_log(path: &Path) -> Result<Vec<LogLine>, LabError> {
    let file = ftwire_core::text::open_regular(path)
        .map_err(|e| LabError::bad_input(format!("cannot open log {}: {e}", path.display())))?;
    ftwire_estimate::log::read_log_lines(BufReader::new(file))
        .map_err(|e| LabError::bad_input(format!("log {}: {e}", path.display())))
}

/// Loads the learnt calibration (the weights file of `ftwire experiment calibrate` or
/// `ftwire calibrate --log`).
///
/// # Errors
/// Bad input naming the file (`--calibration FILE: ...`) when it cannot be read or is not a
/// calibration.
pub fn load_calibration(path: &Path) -> Result<Calibration, LabError> {
    Calibration::load(path)
        .map_err(|e| LabError::bad_input(format!("--calibration {}: {e}", path.display())))
}

/// The rig layer's [`RawMap`] of the calibration file `calibration` ([`load_calibration`])
/// and `mounting`, each if given.
///
/// # Errors
/// As [`load_calibration`]; bad input (`--mounting: ...`) for a mounting the map refuses.
pub fn raw_map(
    calibration: Option<&Path>,
    mounting: Option<MountingSpec>,
) -> Result<RawMap, LabError> {
    let calibration = calibration.map(load_calibration).transpose()?;
    RawMap::new(calibration, mounting).map_err(|e| LabError::bad_input(format!("--mounting: {e}")))
}

/// Gravity in the base clamp frame for the wire's model of `map`: the calibration's own label
/// model (`calibration.json`'s `model`) unless `--gravity-in-clamp` gives one, and the flag
/// only when it is the same model ([`ftwire_rig::WireModelChoice::of_calibration`]); without a
/// calibration, the flag.
///
/// # Errors
/// Bad input naming `--gravity-in-clamp` and `--calibration` when the two differ.
pub fn model_gravity(map: &RawMap, given: Option<[f64; 3]>) -> Result<Option<[f64; 3]>, LabError> {
    let Some(calibration) = map.calibration() else {
        return Ok(given);
    };
    ftwire_rig::WireModelChoice::of_calibration(calibration.model(), given)
        .map(|choice| choice.gravity_in_clamp())
        .map_err(|e| LabError::bad_input(format!("--gravity-in-clamp and --calibration: {e}")))
}

/// The record's `ã` (torque first, base clamp frame) by the rig layer's one map
/// ([`RawMap::a_tilde`]): its `a` as it is; its `raw` reading with the tool's weight taken
/// out, then through the calibration at the record's time, or else through the mounting alone.
///
/// # Errors
/// Bad input naming the record's line and time: a record with neither `raw` nor `a`, a `raw`
/// record without `gravity` when the mounting has a tool, a `raw` record with neither a
/// calibration nor a mounting given, or a calibration output that is not finite.
///
/// # Example
/// ```
/// use ftwire_estimate::ft::MountingSpec;
/// use ftwire_logs::{LogLine, LogRecord, a_tilde};
/// use ftwire_rig::RawMap;
/// let record = LogRecord { time: 0.5, raw: Some([0.1, 0.0, -0.2, 0.0, 0.01, 0.0]), a: None, b: None, markers: None, gravity: None };
/// let line = LogLine { line: 7, record };
/// let error = a_tilde(&line, &RawMap::default()).err().ok_or("raw needs a map")?;
/// assert!(error.to_string().starts_with("line 7 (time 0.5) has a raw F/T reading"));
/// let mounting = RawMap::new(None, Some(MountingSpec::default()))?;
/// let a = a_tilde(&line, &mounting)?;
/// let expected = MountingSpec::default().mounting()?.to_configuration(&line.record.raw().ok_or("raw")?);
/// assert_eq!(a, expected);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn a_tilde(line: &LogLine, map: &RawMap) -> Result<Vector6<f64>, LabError> {
    let record = &line.record;
    map.a_tilde(&Reading::from(record)).map_err(|e| {
        let at = format!("line {} (time {})", line.line, record.time);
        LabError::bad_input(match e {
            RigError::Empty => format!("{at} has neither `raw` nor `a`"),
            RigError::NoGravity { tool_mass } => format!(
                "{at} has a raw F/T reading but no `gravity`: the mounting's tool (tool_mass = \
                 {tool_mass} kg) weighs on the sensor, and its weight is taken out with the \
                 gravity vector in the sensor frame at each record; give every raw record its \
                 `gravity`"
            ),
            RigError::NoMap => format!(
                "{at} has a raw F/T reading: give --calibration FILE (the weights from \
                 `ftwire calibrate --log` or `ftwire experiment calibrate`) to turn it into ã, \
                 or --mounting FILE.toml to take it through the mounting alone, uncalibrated"
            ),
            other => format!("{at}: {other}"),
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

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
        assert_eq!((records[0].line, records[1].line), (2, 3));
        assert!(records[1].record.time > records[0].record.time);
        let a = a_tilde(&records[0], &RawMap::default()).expect("`a` needs no calibration");
        assert_eq!(a[4].to_bits(), 0.03_f64.to_bits());
        let raw = LogLine {
            line: 9,
            record: LogRecord {
                a: None,
                raw: Some([0.1; 6]),
                ..records[0].record.clone()
            },
        };
        let error = a_tilde(&raw, &RawMap::default()).expect_err("`raw` needs a map");
        assert_eq!(error.kind(), "bad_input");
        let message = error.to_string();
        assert!(
            message.starts_with("line 9 (time 0) has a raw F/T reading"),
            "{message}"
        );
        assert!(
            message.contains("--calibration") && message.contains("--mounting"),
            "{message}"
        );
    }

    /// The tool's weight comes out before the mounting or the calibration, with the record's
    /// gravity; a record without gravity is refused when there is a tool.
    #[test]
    fn a_tools_weight_is_taken_out_first() {
        let spec = MountingSpec {
            tool_mass: 0.4,
            tool_centre_of_mass: [0.0, 0.01, 0.05],
            ..MountingSpec::default()
        };
        let map = raw_map(None, Some(spec.clone())).expect("a valid mounting");
        let gravity = Vector3::new(0.0, -9.81, 0.0);
        let wire = Vector6::new(0.3, -0.1, 0.2, 0.01, 0.0, -0.02);
        let line = LogLine {
            line: 4,
            record: LogRecord {
                time: 1.5,
                raw: Some((wire + spec.tool_reading(&gravity)).into()),
                a: None,
                b: None,
                markers: None,
                gravity: Some(gravity.into()),
            },
        };
        let a = a_tilde(&line, &map).expect("raw with gravity");
        let expected = spec.mounting().expect("valid").to_configuration(&wire);
        assert!((a - expected).norm() < 1e-12, "{a} vs {expected}");
        let no_gravity = LogLine {
            record: LogRecord {
                gravity: None,
                ..line.record.clone()
            },
            ..line
        };
        let error = a_tilde(&no_gravity, &map).expect_err("the tool needs gravity");
        assert_eq!(error.kind(), "bad_input");
        let message = error.to_string();
        assert!(
            message.starts_with("line 4 (time 1.5) ") && message.contains("`gravity`"),
            "{message}"
        );
        let bad = MountingSpec {
            tool_mass: -1.0,
            ..MountingSpec::default()
        };
        let error = raw_map(None, Some(bad)).expect_err("a negative mass");
        assert!(error.to_string().starts_with("--mounting: "), "{error}");
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
