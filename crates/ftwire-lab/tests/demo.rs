//! The demo as a library call: with a small calibration and few shape configurations it runs
//! its five phases into a temporary results folder, reports each phase's start, steps and
//! result in order, writes its files there and returns a summary with every part and finite
//! values; bad settings are refused before any work. (The full demo's summary is compared with
//! its recording by the `ftwire` binary's `demo_cli` test.)

use ftwire_lab::demo::{self, DemoParams, DemoProgress, PHASES};

mod common;

use common::TempDir;

/// What the demo reported.
#[derive(Default)]
struct Recorder {
    /// `(number, name, steps)` of each phase started.
    started: Vec<(usize, String, usize)>,
    /// Steps reported, in order.
    steps: Vec<usize>,
    /// `(number, result, seconds)` of each phase finished.
    finished: Vec<(usize, String, f64)>,
}

impl DemoProgress for Recorder {
    fn phase_started(&mut self, number: usize, name: &str, steps: usize) {
        self.started.push((number, name.to_owned(), steps));
    }

    fn step(&mut self, done: usize) {
        self.steps.push(done);
    }

    fn phase_finished(&mut self, number: usize, _name: &str, result: &str, seconds: f64) {
        self.finished.push((number, result.to_owned(), seconds));
    }
}

/// Every number in `value` is finite.
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

#[test]
fn a_small_demo_runs_its_five_phases_and_writes_its_files() {
    let dir = TempDir::new("demo");
    let folder = dir.results("demo");
    let params = DemoParams {
        calibration_configs: 40,
        shape_configs: 2,
        ..DemoParams::default()
    };
    let mut progress = Recorder::default();
    let run = demo::run(&params, &folder, &mut progress).expect("the demo runs");

    let numbers: Vec<usize> = (1..=PHASES).collect();
    let started: Vec<usize> = progress.started.iter().map(|p| p.0).collect();
    let finished: Vec<usize> = progress.finished.iter().map(|p| p.0).collect();
    assert_eq!(started, numbers);
    assert_eq!(finished, numbers);
    assert_eq!(
        progress.started[0].2, 40,
        "phase 1 steps over the configurations"
    );
    assert_eq!(
        progress.started[2].2, 2,
        "phase 3 steps over the configurations"
    );
    assert!(progress.steps.contains(&40), "{:?}", progress.steps);
    assert!(
        progress.finished[0].1.contains("nitinol-3mm-820"),
        "{:?}",
        progress.finished[0]
    );

    let summary = serde_json::to_value(&run.summary).expect("serialises");
    for key in [
        "wire",
        "calibration",
        "identification",
        "shape",
        "plan",
        "tracking",
    ] {
        assert!(summary.get(key).is_some(), "{key} missing: {summary}");
    }
    assert_finite(&summary, "summary");
    assert_eq!(summary["wire"]["name"], demo::DEFAULT_WIRE);
    assert_eq!(summary["tracking"]["noise_model"], "offset");
    assert_eq!(run.summary.identification.samples, demo::IDENTIFY_SAMPLES);
    assert!(run.summary.shape.configurations <= 2);
    assert!(run.summary.calibration.configurations <= 40);
    assert!(run.timings.total_s >= run.timings.calibrate_s);
    for file in [
        "calibration.json",
        "shape.png",
        "tracking.png",
        "report.html",
    ] {
        assert!(folder.dir().join(file).is_file(), "{file}");
    }
}

#[test]
fn bad_demo_settings_are_refused_before_any_work() {
    let refused = |params: DemoParams, what: &str| {
        let error = params.check().expect_err(what);
        assert_eq!(error.exit_code(), 2, "{what}: {error}");
    };
    refused(
        DemoParams {
            wire: "copper".to_owned(),
            ..DemoParams::default()
        },
        "an unknown wire",
    );
    refused(
        DemoParams {
            scene: Some("no/such/scene.toml".into()),
            ..DemoParams::default()
        },
        "a missing scene",
    );
    refused(
        DemoParams {
            calibration_configs: 0,
            ..DemoParams::default()
        },
        "no calibration configuration",
    );
    refused(
        DemoParams {
            shape_configs: 0,
            ..DemoParams::default()
        },
        "no shape configuration",
    );
    DemoParams::default()
        .check()
        .expect("the defaults are good");
}
