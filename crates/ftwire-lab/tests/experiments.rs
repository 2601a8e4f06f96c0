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

#[test]
fn shape_from_a_calibration_file_reports_every_metric_and_writes_its_files() {
    let dir = TempDir::new("shape");
    // A small calibration, read back from its file as `--calibration` would.
    let calibrated = dir.results("calibrate");
    let settings = ftwire_lab::calibrate::CalibrateParams {
        common: common("nitinol-3mm-820", 40),
    };
    ftwire_lab::calibrate::run(&settings, &calibrated, &mut |_| {}).expect("calibrates");
    let weights = calibrated.dir().join("calibration.json");
    let folder = dir.results("shape");
    let settings = ftwire_lab::shape::ShapeParams {
        common: common("nitinol-2mm-630", 1),
        configs: Some(2),
        calibration: Some(weights),
        save_log: true,
        ..ftwire_lab::shape::ShapeParams::default()
    };
    let mut lines = Vec::new();
    let run = ftwire_lab::shape::run(&settings, &folder, &mut |l| lines.push(l.to_owned()))
        .expect("runs");
    assert!(
        lines.is_empty(),
        "a given calibration is not run: {lines:?}"
    );
    let summary = serde_json::to_value(&run.summary).expect("serialises");
    assert_eq!(summary["model"], "kirchhoff");
    let wire = &summary["wires"][0];
    for key in [
        "name",
        "configs",
        "mean_mm",
        "std_mm",
        "marker_mean_mm",
        "mounting_mean_mm",
        "kirchhoff_mean_mm",
        "loaded_mean_mm",
        "fused_mean_mm",
        "torque_rel",
        "force_rel",
        "not_confident",
        "skipped",
    ] {
        assert!(wire.get(key).is_some(), "{key} missing: {wire}");
    }
    assert_finite(&summary, "summary");
    let row = &run.summary.wires[0];
    assert_eq!(row.configs, 2);
    // The wire is known: the shape from F/T is within centimetres of the truth.
    assert!(row.mean_mm > 0.0 && row.mean_mm < 30.0, "{}", row.mean_mm);
    assert_eq!(run.timings.estimate_us_median.len(), 1);
    for file in [
        "configs.csv",
        "error_per_wire.png",
        "shape_nitinol-2mm-630.png",
        "logs/nitinol-2mm-630.jsonl",
    ] {
        assert!(exists(&folder, file), "{file}");
    }
    assert!(!exists(&folder, "calibration.json"));
}

#[test]
fn shape_refuses_no_configurations_before_any_work() {
    let settings = ftwire_lab::shape::ShapeParams {
        configs: Some(0),
        ..ftwire_lab::shape::ShapeParams::default()
    };
    let e = settings.check().expect_err("0 configurations");
    assert_eq!(e.exit_code(), 2);
}
