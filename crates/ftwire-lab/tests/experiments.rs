//! The experiments as library calls: each runs with tiny settings into a temporary results
//! folder, writes its files there and returns a summary with every key and finite values.
//! (The full summaries are compared with their recordings by the `ftwire` binary's tests.)

use std::path::{Path, PathBuf};

use ftwire_lab::experiment::{CommonParams, Gravity};
use ftwire_lab::results::{OutGuard, ResultsFolder};

/// A unique empty folder under the system's temporary folder, removed on drop.
struct TempDir(PathBuf);

impl TempDir {
    fn new(tag: &str) -> Self {
        let nanos = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_nanos());
        let path =
            std::env::temp_dir().join(format!("ftwire-lab-{tag}-{}-{nanos}", std::process::id()));
        std::fs::create_dir_all(&path).expect("a temporary folder");
        Self(path)
    }

    /// A results folder `name` inside.
    fn results(&self, name: &str) -> ResultsFolder {
        ResultsFolder::create(&self.0.join(name), &OutGuard::default()).expect("a results folder")
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// The settings every test starts from: one wire, gravity off, a fixed seed.
fn common(wire: &str, trials: usize) -> CommonParams {
    CommonParams {
        wire: Some(wire.to_owned()),
        seed: 3,
        trials: Some(trials),
        gravity: Gravity::Off,
        ..CommonParams::default()
    }
}

/// Every number in `value` is finite (JSON has no NaN: serde writes it as `null`, which is
/// allowed where the key is optional, so only numbers are checked).
fn assert_finite(value: &serde_json::Value, path: &str) {
    match value {
        serde_json::Value::Number(n) => {
            assert!(n.as_f64().is_some_and(f64::is_finite), "{path}: {n}");
        }
        serde_json::Value::Array(items) => {
            for (i, item) in items.iter().enumerate() {
                assert_finite(item, &format!("{path}[{i}]"));
            }
        }
        serde_json::Value::Object(map) => {
            for (key, item) in map {
                assert_finite(item, &format!("{path}.{key}"));
            }
        }
        _ => {}
    }
}

fn exists(folder: &ResultsFolder, file: &str) -> bool {
    Path::new(folder.dir()).join(file).is_file()
}

#[test]
fn calibrate_writes_the_weights_and_reports_both_maps() {
    let dir = TempDir::new("calibrate");
    let folder = dir.results("calibrate");
    let settings = ftwire_lab::calibrate::CalibrateParams {
        common: common("nitinol-3mm-820", 40),
    };
    let mut lines = Vec::new();
    let run = ftwire_lab::calibrate::run(&settings, &folder, &mut |l| lines.push(l.to_owned()))
        .expect("calibrates");
    let summary = serde_json::to_value(&run.summary).expect("serialises");
    for key in [
        "wire",
        "model",
        "samples",
        "raw",
        "calibrated",
        "label_fit_mm",
        "label_shape_mm",
        "skipped",
    ] {
        assert!(summary.get(key).is_some(), "{key} missing: {summary}");
    }
    assert_finite(&summary, "summary");
    assert_eq!(summary["model"], "kirchhoff");
    let s = &run.summary.samples;
    assert!(s.train > 0 && s.test > 0, "{s:?}");
    assert!(run.summary.calibrated.torque_rel < run.summary.raw.torque_rel);
    assert!(exists(&folder, "calibration.json") && exists(&folder, "samples.csv"));
    assert!(lines.first().is_some_and(|l| l.contains("nitinol-3mm-820")));
}
