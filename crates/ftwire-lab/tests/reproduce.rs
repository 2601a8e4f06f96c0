//! A reproduction as a library call, with a runner that stands in for the experiments: the
//! calibrations first, the others after them on the pool, each job's log moved into its folder,
//! a failure kept as a status, and nothing that needs a failed calibration.

use std::sync::Mutex;

use ftwire_lab::reproduce::{self, Job, OK, ReproduceParams};

mod common;

use common::TempDir;

/// Stands in for an experiment: writes its log, and its folder unless `fail` names it.
fn fake(job: &Job, fail: &str) -> Result<(), String> {
    std::fs::write(&job.log, format!("ran {}\n", job.id)).map_err(|e| e.to_string())?;
    if job.id == fail {
        return Err("exit 1: boom".to_owned());
    }
    std::fs::create_dir_all(&job.out).map_err(|e| e.to_string())
}

#[test]
fn a_failed_experiment_is_a_status_and_the_others_still_run() {
    let dir = TempDir::new("reproduce");
    let folder = dir.results("reproduce");
    let params = ReproduceParams {
        seed: 4,
        quick: true,
        jobs: Some(2),
        ..ReproduceParams::default()
    };
    params.check().expect("valid settings");
    let lines = Mutex::new(Vec::new());
    let progress = |line: &str| lines.lock().expect("not poisoned").push(line.to_owned());
    let run = reproduce::run(&params, &folder, &|job| fake(job, "goal"), &progress)
        .expect("runs every job");
    assert_eq!(
        run.ids(),
        [
            "calibrate",
            "calibrate_real_like",
            "identify",
            "shape",
            "goal",
            "track",
            "passage",
            "passage_offset",
            "shape_real_like"
        ]
    );
    for status in &run.summary.experiments {
        let expected = if status.id == "goal" {
            "exit 1: boom"
        } else {
            OK
        };
        assert_eq!(status.status, expected, "{}", status.id);
    }
    assert_eq!(run.timings.experiments.len(), 9);
    let shape_log = folder.dir().join("shape").join("log.txt");
    assert_eq!(
        std::fs::read_to_string(shape_log).ok().as_deref(),
        Some("ran shape\n")
    );
    assert!(
        folder.dir().join("goal.log").is_file(),
        "a job without a folder keeps its log"
    );
    assert!(
        run.report.contains("| `goal` | exit 1: boom |"),
        "{}",
        run.report
    );
    for file in ["report.md", "report.html"] {
        assert!(folder.dir().join(file).is_file(), "{file}");
    }
    let lines = lines.into_inner().expect("not poisoned");
    assert!(
        lines[0].contains("9 experiments (quick), 2 at a time"),
        "{lines:?}"
    );
    assert_eq!(lines.len(), 10);
    let e = run.require_all_ok(folder.dir()).expect_err("goal failed");
    assert_eq!(e.exit_code(), 1);
    assert!(
        e.to_string().starts_with("experiments that failed: goal "),
        "{e}"
    );
}

#[test]
fn nothing_that_needs_a_failed_calibration_runs() {
    let dir = TempDir::new("reproduce-no-calibration");
    let folder = dir.results("reproduce");
    let params = ReproduceParams {
        jobs: Some(1),
        quick: true,
        ..ReproduceParams::default()
    };
    let ran = Mutex::new(Vec::new());
    let runner = |job: &Job| {
        ran.lock().expect("not poisoned").push(job.id);
        fake(job, "calibrate")
    };
    let run = reproduce::run(&params, &folder, &runner, &|_| {}).expect("a report");
    // The real-like calibration and its experiment still run.
    assert_eq!(
        ran.into_inner().expect("not poisoned"),
        ["calibrate", "calibrate_real_like", "shape_real_like"]
    );
    for status in &run.summary.experiments[2..] {
        let expected = if status.id == "shape_real_like" {
            OK
        } else {
            "not run: the calibration calibrate failed"
        };
        assert_eq!(status.status, expected, "{}", status.id);
    }
}

#[test]
fn bad_settings_are_refused_before_anything_runs() {
    let dir = TempDir::new("reproduce-refused");
    let docs = dir.0.join("docs");
    std::fs::create_dir_all(&docs).expect("a docs folder");
    std::fs::write(docs.join("results.md"), "# Mine\n").expect("their page");
    let theirs = ReproduceParams {
        docs: Some(docs.clone()),
        ..ReproduceParams::default()
    };
    let e = theirs.check().expect_err("a page ftwire did not write");
    assert!(
        e.to_string().contains("not written by ftwire reproduce"),
        "{e}"
    );
    let forced = ReproduceParams {
        force: true,
        ..theirs
    };
    forced.check().expect("--force replaces it");
    let no_sensor = ReproduceParams {
        sensor: Some("/no/such/sensor.toml".to_owned()),
        ..ReproduceParams::default()
    };
    assert_eq!(
        no_sensor.check().expect_err("no sensor file").exit_code(),
        2
    );
}
