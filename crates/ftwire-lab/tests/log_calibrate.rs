//! `calibrate --log` on recordings written the way a rig writes them: the simulator's session
//! (`experiment calibrate --save-log`: time, the raw reading not tared, the markers, no `b`)
//! with the clamp 0.11 m out along the sensor's z, learnt on the first blocks of time and
//! judged on the last, against the simulator's true centreline.

mod common;

use std::path::{Path, PathBuf};

use common::TempDir;
use ftwire_estimate::calibration::Calibration;
use ftwire_estimate::ft::MountingSpec;
use ftwire_estimate::shape::centreline_distance;
use ftwire_estimate::{KirchhoffModel, WireModel};
use ftwire_lab::experiment::{CommonParams, Gravity};
use ftwire_lab::log::calibrate::{self, LogCalibrateParams, LogCalibrateSummary};
use ftwire_lab::wire::WireSpec;
use nalgebra::{Vector3, Vector6};

const WIRE: &str = "nitinol-3mm-820";

/// A simulated recording of `count` rests with `sensor` (a preset or a file), gravity off:
/// the recording and its truth.
fn record(dir: &TempDir, sensor: &str, count: usize, seed: u64) -> (PathBuf, PathBuf) {
    let tag = format!("{}-{count}-{seed}", folder_name(sensor));
    let folder = dir.results(&format!("rec-{tag}"));
    let settings = ftwire_lab::calibrate::CalibrateParams {
        common: CommonParams {
            trials: Some(count),
            gravity: Gravity::Off,
            sensor: Some(sensor.to_owned()),
            seed,
            ..CommonParams::default()
        },
        save_log: true,
    };
    ftwire_lab::calibrate::run(&settings, &folder, &mut |_| {}).expect("records");
    // Keep the files past the folder's drop (an unfinished folder is removed).
    let keep = dir.0.join(tag);
    std::fs::create_dir_all(&keep).expect("a folder");
    let log = keep.join("recording.jsonl");
    let truth = keep.join("truth.jsonl");
    std::fs::copy(folder.dir().join("logs/recording.jsonl"), &log).expect("copied");
    std::fs::copy(folder.dir().join("logs/truth.jsonl"), &truth).expect("copied");
    (log, truth)
}

fn folder_name(sensor: &str) -> String {
    sensor.replace(['/', '.'], "_")
}

/// The `distorted` sensor with the clamp 0.11 m out along its z: a sensor file.
fn lever_arm_sensor(dir: &TempDir) -> String {
    let path = dir.0.join("sensor-0.11.toml");
    std::fs::write(&path, "clamp_position_in_sensor = [0.0, 0.0, 0.11]\n").expect("written");
    path.display().to_string()
}

fn mounting() -> MountingSpec {
    MountingSpec {
        clamp_position_in_sensor: [0.0, 0.0, 0.11],
        ..MountingSpec::default()
    }
}

fn params(log: &Path, seed: u64) -> LogCalibrateParams {
    LogCalibrateParams {
        log: log.to_owned(),
        wire: WireSpec::preset(WIRE).expect("a preset"),
        mounting: mounting(),
        gravity: None,
        marker_fractions: None,
        max_label_rms: calibrate::DEFAULT_MAX_LABEL_RMS,
        train: calibrate::default_train_params(),
        drift: true,
        seed,
        loss: calibrate::MapLoss::Shape,
        fit_gravity: None,
        rest_tolerance: calibrate::DEFAULT_REST_TOLERANCE,
        shape: Default::default(),
    }
}

/// The mean distance \[mm\] between `Φ(ã)` and the true centreline over the last `share` of
/// the recording's lines (after every training record in time).
fn held_out_shape_mm(
    calibration: &Calibration,
    log: &Path,
    truth: &Path,
    share: f64,
) -> (f64, usize) {
    let records = ftwire_estimate::log::read_log(std::io::BufReader::new(
        std::fs::File::open(log).expect("a log"),
    ))
    .expect("reads");
    let truths: Vec<Vec<Vector3<f64>>> = std::fs::read_to_string(truth)
        .expect("a truth file")
        .lines()
        .map(|line| {
            let v: serde_json::Value = serde_json::from_str(line).expect("JSON");
            v["points"]
                .as_array()
                .expect("points")
                .iter()
                .map(|p| {
                    let c: Vec<f64> = serde_json::from_value(p.clone()).expect("a point");
                    Vector3::new(c[0], c[1], c[2])
                })
                .collect()
        })
        .collect();
    let model = KirchhoffModel::new(
        WireSpec::preset(WIRE)
            .expect("a preset")
            .wire_params()
            .expect("valid"),
    );
    let first = ((1.0 - share) * records.len() as f64).ceil() as usize;
    let mut total = 0.0;
    let mut n = 0;
    for (record, truth) in records.iter().zip(&truths).skip(first) {
        let raw: Vector6<f64> = record.raw().expect("raw");
        let a = calibration.apply_at(&raw, record.time);
        let Ok(shape) = model.shape(&a, 101) else {
            continue;
        };
        total += centreline_distance(&shape.positions, truth, 100).expect("a distance");
        n += 1;
    }
    (1e3 * total / n.max(1) as f64, n)
}

fn run(dir: &TempDir, log: &Path, seed: u64) -> (LogCalibrateSummary, Calibration) {
    let folder = dir.results(&format!(
        "cal-{}",
        log.parent()
            .and_then(|p| p.file_name())
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned())
    ));
    let run = calibrate::run(&params(log, seed), &folder, &mut |_| {}).expect("calibrates");
    for file in [
        "calibration.json",
        "labels.csv",
        "test.csv",
        "label_fit.png",
        "test_errors.png",
    ] {
        assert!(folder.dir().join(file).is_file(), "{file} written");
    }
    (run.summary, run.calibration)
}

#[test]
fn a_recording_of_the_default_sensor_calibrates_to_within_a_millimetre() {
    let dir = TempDir::new("log-calibrate");
    let sensor = lever_arm_sensor(&dir);
    // 300 rests: the held-out shapes' error falls with the recording's size
    // (`survey_of_recording_sizes` below), and at this size the 1 mm holds with a margin.
    let (log, truth) = record(&dir, &sensor, 300, 3);
    let (summary, calibration) = run(&dir, &log, 3);
    let labels = summary.labels;
    assert!(labels.records >= 280, "{labels:?}");
    assert!(labels.fitted + labels.rejected == labels.records);
    assert!(labels.fitted * 10 >= labels.records * 9, "{labels:?}");
    assert!(labels.marker_rms_mm < 1.0, "{labels:?}");
    // The split is by blocks of time: 70 / 15 / 15 %.
    let s = summary.split;
    assert_eq!(s.train + s.validation + s.test, labels.fitted);
    assert!(s.test * 100 >= labels.fitted * 14, "{s:?}");
    let test = summary.test;
    // Against the markers, whose own noise puts a floor under any shape (the labels' own,
    // about 0.3 mm).
    assert!(
        test.calibrated_marker_mean_mm < 1.2
            && test.raw_marker_mean_mm > 5.0 * test.calibrated_marker_mean_mm,
        "{test:?}"
    );
    let (shape_mm, n) = held_out_shape_mm(&calibration, &log, &truth, 0.15);
    assert!(n >= 40, "{n} held-out shapes");
    assert!(
        shape_mm < 1.0,
        "held-out shapes {shape_mm:.3} mm from the truth"
    );
}

#[test]
fn a_real_like_sensor_with_offsets_calibrates() {
    let dir = TempDir::new("log-calibrate-real");
    let (log, truth) = record(&dir, "real-like", 120, 4);
    let (summary, calibration) = run(&dir, &log, 4);
    let test = summary.test;
    // Offsets of 1–2 N put the uncalibrated shapes far off; the calibration brings them
    // within a few millimetres. The sensor's hysteresis (loaded from the
    // tare's zero at every rest) is what no static map removes.
    assert!(test.raw_marker_mean_mm > 20.0, "{test:?}");
    assert!(test.calibrated_marker_mean_mm < 5.0, "{test:?}");
    assert!(
        test.calibrated_marker_mean_mm < 0.1 * test.raw_marker_mean_mm,
        "{test:?}"
    );
    let (shape_mm, _) = held_out_shape_mm(&calibration, &log, &truth, 0.15);
    assert!(
        shape_mm < 5.0,
        "held-out shapes {shape_mm:.3} mm from the truth"
    );
}

#[test]
fn bad_logs_are_refused_naming_why() {
    let dir = TempDir::new("log-calibrate-bad");
    let write = |name: &str, text: &str| {
        let path = dir.0.join(name);
        std::fs::write(&path, text).expect("written");
        path
    };
    let no_markers = write(
        "no-markers.jsonl",
        r#"{"time": 0, "raw": [1, 2, 3, 0.1, 0.2, 0.3]}
{"time": 1, "raw": [1, 2, 3, 0.1, 0.2, 0.3]}
"#,
    );
    let one = write(
        "one.jsonl",
        r#"{"time": 0, "raw": [1, 2, 3, 0.1, 0.2, 0.3], "markers": [[0, 0, 0], [0.1, 0, 0], [0.2, 0, 0], [0.3, 0, 0], [0.4, 0, 0]]}
"#,
    );
    // Markers no wire of 0.82 m passes through: every label is rejected.
    let far = write(
        "far.jsonl",
        &(0..5)
            .map(|k| {
                format!(
                    r#"{{"time": {k}, "raw": [1, 2, 3, 0.1, 0.2, 0.3], "markers": [[0, 0, 0], [0.5, 0.5, 0], [0, 1, 0], [-0.5, 0.5, 0], [3, 3, 3]]}}"#
                )
            })
            .collect::<Vec<_>>()
            .join("\n"),
    );
    for (log, needle) in [
        (&no_markers, "no record has markers"),
        (&one, "training on 1 labelled record"),
        (&far, "every record was rejected"),
    ] {
        let folder = dir.results(&format!(
            "bad-{}",
            log.file_stem()
                .map_or_else(String::new, |s| s.to_string_lossy().into_owned())
        ));
        let error = calibrate::run(&params(log, 0), &folder, &mut |_| {}).expect_err("refused");
        assert_eq!(error.exit_code(), 2, "{error}");
        assert!(
            error.to_string().contains(needle),
            "{error} should say {needle:?}"
        );
    }
}

/// The survey of the real-rigs page (`docs/real-rig.md`): recordings of 120, 300 and 600 rests
/// of both sensors, three seeds each; prints the test block's marker errors and the held-out
/// shapes' distance to the truth. Run it with
/// `cargo test --release -p ftwire-lab --test log_calibrate -- --ignored --nocapture`.
#[test]
#[ignore = "a survey of several minutes; run by hand"]
fn survey_of_recording_sizes() {
    let dir = TempDir::new("log-calibrate-survey");
    let lever = lever_arm_sensor(&dir);
    println!(
        "| sensor | rests | seed | labels kept | raw marker mm | calibrated marker mm | label floor mm | held-out shape mm | drift term |"
    );
    println!("| --- | --- | --- | --- | --- | --- | --- | --- | --- |");
    for (name, sensor) in [
        ("distorted, 0.11 m", lever.as_str()),
        ("real-like", "real-like"),
    ] {
        for count in [120, 300, 600] {
            for seed in 0..3 {
                let (log, truth) = record(&dir, sensor, count, 100 + seed);
                let (summary, calibration) = run(&dir, &log, seed);
                let (shape_mm, _) = held_out_shape_mm(&calibration, &log, &truth, 0.15);
                let t = summary.test;
                println!(
                    "| {name} | {count} | {seed} | {} / {} | {:.1} | {:.2} | {:.2} | {shape_mm:.2} | {} |",
                    summary.labels.fitted,
                    summary.labels.records,
                    t.raw_marker_mean_mm,
                    t.calibrated_marker_mean_mm,
                    t.label_marker_mean_mm,
                    if summary.drift.is_some() {
                        "kept"
                    } else {
                        "none"
                    },
                );
            }
        }
    }
}

/// `--protocol single-readings` records a session as a real rig logs it: one reading per
/// record, 4 Hz within a rest, 2–3 records at some rests, the gripper about 17 mm from one
/// rest to the next, and readings at one rest that scatter by the sensor's noise.
#[test]
fn a_single_readings_session_records_as_a_rig_logs() {
    use ftwire_lab::experiment::ModelKind;
    use ftwire_lab::experiment::calibration::{REST_INTERVAL, SINGLE_READING_RATE, collect};
    use ftwire_lab::setup::{Protocol, SimSetup};
    let setup = SimSetup::load(Some("real-like"), None)
        .expect("a preset")
        .with_protocol(Protocol::SingleReadings);
    let wire = WireSpec::preset("nitinol-2mm-630").expect("a preset");
    let (_, _, recording) = collect(
        &wire,
        (Gravity::On, ModelKind::Loaded),
        &setup,
        40,
        7,
        |_| {},
    )
    .expect("collected");
    assert!(recording.len() > 40, "{} records", recording.len());
    // Rests by their session slot.
    let slot = |t: f64| (t / REST_INTERVAL).floor() as i64;
    let mut rests: Vec<Vec<usize>> = Vec::new();
    for (k, r) in recording.iter().enumerate() {
        match rests.last_mut() {
            Some(g) if slot(recording[g[0]].time) == slot(r.time) => g.push(k),
            _ => rests.push(vec![k]),
        }
    }
    let shared = rests.iter().filter(|g| g.len() > 1).count();
    assert!(
        shared >= 3 && rests.iter().all(|g| g.len() <= 3),
        "{rests:?}"
    );
    let mut scatter = Vec::new();
    for g in rests.iter().filter(|g| g.len() > 1) {
        let (a, b) = (&recording[g[0]], &recording[g[1]]);
        assert!((b.time - a.time - 1.0 / SINGLE_READING_RATE).abs() < 1e-9);
        // The same wire: the same truth, and readings apart by the noise alone.
        assert_eq!(a.truth, b.truth);
        scatter.push((b.raw - a.raw).norm());
    }
    assert!(scatter.iter().all(|&d| d > 0.0 && d < 0.5), "{scatter:?}");
    let tip = |k: usize| *recording[k].truth.last().expect("a centreline");
    let mut steps: Vec<f64> = rests
        .windows(2)
        .map(|w| (tip(w[1][0]) - tip(w[0][0])).norm())
        .collect();
    steps.sort_by(f64::total_cmp);
    let median = steps[steps.len() / 2];
    assert!(
        (0.010..0.030).contains(&median),
        "median step {median} m of {steps:?}"
    );
}
