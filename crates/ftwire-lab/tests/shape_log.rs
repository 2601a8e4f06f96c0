//! `shape --log` into a results folder ([`ftwire_lab::log::shape::folder`]): `shapes.jsonl`'s
//! format and line numbers, `points`, the summary's keys and the inner markers' metric, the
//! jump flags across blocks and threads, and how records become `ã` (`b` not needed, a tool's
//! weight, the mounting alone).

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use approx::assert_relative_eq;
use ftwire_estimate::ft::MountingSpec;
use ftwire_estimate::log::{LogRecord, to_line};
use ftwire_estimate::{KirchhoffModel, WireModel};
use ftwire_lab::header::RunHeader;
use ftwire_lab::identify::ResidualParams;
use ftwire_lab::log::identify::{self, IdentifyLogParams};
use ftwire_lab::log::shape::{
    BLOCK, DEFAULT_POINTS, LogShapes, ShapeLog, ShapeLogParams, ShapeLogRun,
};
use ftwire_lab::wire::WireSpec;
use ftwire_rod::from_normalised;
use nalgebra::Vector6;
use serde_json::Value;

mod common;

use common::TempDir;

const WIRE: &str = "nitinol-2mm-630";

fn model() -> KirchhoffModel {
    let wire = WireSpec::load(WIRE).expect("the preset");
    KirchhoffModel::new(wire.wire_params().expect("a valid wire"))
}

/// `a` from normalised units for the 2 mm wire.
fn a_of(z: [f64; 6]) -> Vector6<f64> {
    from_normalised(model().wire(), &Vector6::from(z))
}

/// A record with `a` and nothing else.
fn a_record(time: f64, a: &Vector6<f64>) -> LogRecord {
    LogRecord {
        time,
        raw: None,
        a: Some((*a).into()),
        b: None,
        markers: None,
        gravity: None,
    }
}

fn line(record: &LogRecord) -> String {
    to_line(record).expect("serialises")
}

fn params(log: PathBuf) -> ShapeLogParams {
    ShapeLogParams::new(log, WIRE)
}

/// Shapes the log of `params` into the folder `dir/name` with `points` points; returns the
/// run, `shapes.jsonl`'s lines and `summary.json`.
fn write(
    dir: &TempDir,
    name: &str,
    params: &ShapeLogParams,
    points: usize,
) -> (ShapeLogRun, Vec<Value>, Value) {
    let params = ShapeLogParams {
        points,
        ..params.clone()
    };
    let log = ShapeLog::load(&params).expect("a good log");
    let folder = dir.results(name);
    let run = log.write(&folder, &mut |_| {}).expect("written");
    let header = RunHeader::new("shape", None, &serde_json::json!({"points": points})).expect("h");
    let target = folder
        .finish_run(&header, &run.summary, &run.timings)
        .expect("finished");
    let text = std::fs::read_to_string(target.join("shapes.jsonl")).expect("shapes.jsonl");
    let lines = text
        .lines()
        .map(|l| serde_json::from_str(l).expect("a JSON line"))
        .collect();
    let summary: Value = serde_json::from_str(
        &std::fs::read_to_string(target.join("summary.json")).expect("summary.json"),
    )
    .expect("JSON");
    assert!(target.join("report.md").is_file() && target.join("report.html").is_file());
    (run, lines, summary)
}

fn keys(value: &Value) -> BTreeSet<&str> {
    value
        .as_object()
        .map(|o| o.keys().map(String::as_str).collect())
        .unwrap_or_default()
}

fn numbers(value: &Value) -> Vec<f64> {
    value
        .as_array()
        .map(|a| a.iter().filter_map(Value::as_f64).collect())
        .unwrap_or_default()
}

fn write_log(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).expect("writes the log");
    path
}

#[test]
fn each_record_is_a_line_with_its_file_line_and_shape() {
    let dir = TempDir::new("shape-log-format");
    let a = a_of([0.5, 2.0, -1.0, -3.0, 1.5, 0.5]);
    let outside = Vector6::new(0.1, 0.0, 0.0, -0.2, 0.0, 0.0); // ∉ A: no shape
    let text = format!(
        "# a rig log\n\n{}\n# moved\n{}\n{}\n",
        line(&a_record(0.0, &a)),
        line(&a_record(0.1, &outside)),
        line(&a_record(0.2, &a)),
    );
    let log = write_log(&dir.0, "rig.jsonl", &text);
    let (run, lines, summary) = write(&dir, "out", &params(log), DEFAULT_POINTS);
    assert_eq!(lines.len(), 3);
    let shape_keys = BTreeSet::from([
        "line",
        "time",
        "a",
        "points",
        "stable",
        "confident",
        "confidence",
    ]);
    for (row, (number, time)) in lines.iter().zip([(3, 0.0), (5, 0.1), (6, 0.2)]) {
        assert_eq!(row["line"], number, "{row}");
        assert_relative_eq!(row["time"].as_f64().unwrap_or(f64::NAN), time);
    }
    let shaped = model().shape(&a, DEFAULT_POINTS).expect("a shape");
    for row in [&lines[0], &lines[2]] {
        assert_eq!(keys(row), shape_keys, "{row}");
        assert_eq!(row["stable"], true);
        for (got, want) in numbers(&row["a"]).iter().zip(a.iter()) {
            assert_eq!(got.to_bits(), want.to_bits());
        }
        let points = row["points"].as_array().expect("points");
        assert_eq!(points.len(), DEFAULT_POINTS);
        for (p, q) in points.iter().zip(&shaped.positions) {
            let p = numbers(p);
            assert_eq!(p.len(), 3);
            assert!((nalgebra::Vector3::new(p[0], p[1], p[2]) - q).norm() < 1e-15);
        }
    }
    // The base clamp first, the tip last.
    let first = numbers(&lines[0]["points"][0]);
    assert!(first.iter().all(|v| v.abs() < 1e-15), "{first:?}");
    let tip = model().tip(&a).expect("Γ(a)").translation.vector;
    let last = numbers(&lines[0]["points"][DEFAULT_POINTS - 1]);
    assert!((nalgebra::Vector3::new(last[0], last[1], last[2]) - tip).norm() < 1e-9);
    // No shape: points empty, flags false, and why.
    let failed = &lines[1];
    let mut failed_keys = shape_keys.clone();
    failed_keys.insert("error");
    assert_eq!(keys(failed), failed_keys, "{failed}");
    assert_eq!(failed["points"].as_array().map(Vec::len), Some(0));
    assert_eq!(
        (&failed["stable"], &failed["confident"]),
        (&Value::Bool(false), &Value::Bool(false))
    );
    assert!(failed["error"].as_str().is_some_and(|e| !e.is_empty()));
    // The failed record does not break the jump test: the third is confident.
    assert_eq!(lines[0]["confident"], true);
    assert_eq!(lines[2]["confident"], true);
    assert_eq!(run.no_shape, 1);
    let body = &summary["summary"];
    assert_eq!(
        keys(body),
        BTreeSet::from(["records", "not_stable", "not_confident", "marker_mean_mm"])
    );
    assert_eq!(body["records"], 3);
    assert_eq!(body["not_stable"], 1);
    assert_eq!(body["not_confident"], 1);
    assert!(body["marker_mean_mm"].is_null(), "no markers: null");
}

#[test]
fn points_sets_the_nodes_and_is_bounded() {
    let dir = TempDir::new("shape-log-points");
    let a = a_of([0.5, 2.0, -1.0, -3.0, 1.5, 0.5]);
    let log = write_log(
        &dir.0,
        "rig.jsonl",
        &format!("{}\n", line(&a_record(0.0, &a))),
    );
    for points in [2, 7] {
        let (_, lines, _) = write(&dir, &format!("out{points}"), &params(log.clone()), points);
        let want = model().shape(&a, points).expect("a shape");
        let got = lines[0]["points"].as_array().expect("points");
        assert_eq!(got.len(), points);
        for (p, q) in got.iter().zip(&want.positions) {
            let p = numbers(p);
            assert!((nalgebra::Vector3::new(p[0], p[1], p[2]) - q).norm() < 1e-15);
        }
    }
    for points in [0, 1, 10_001] {
        let error = ShapeLog::load(&ShapeLogParams {
            points,
            ..params(log.clone())
        })
        .expect_err("out of range");
        assert_eq!(error.kind(), "bad_input");
        assert!(
            error
                .to_string()
                .starts_with(&format!("--points {points}: ")),
            "{error}"
        );
    }
}

/// The paper's metric: inner markers only, against a curve of a fixed number of nodes, so
/// that `points` does not change it; unstable and jumping records are counted.
#[test]
fn the_summary_measures_inner_markers_and_counts_the_flags() {
    let dir = TempDir::new("shape-log-summary");
    let z = [0.5, 2.0, -1.0, -3.0, 1.5, 0.5];
    let a = a_of(z);
    let on_wire = model().shape(&a, 11).expect("a shape");
    // Each marker 2 mm off its node, normal to the wire (along the node's frame's y axis).
    let mut markers: Vec<Option<[f64; 3]>> = on_wire
        .positions
        .iter()
        .zip(&on_wire.rotations)
        .map(|(p, r)| {
            let m = p + r * nalgebra::Vector3::y() * 0.002;
            Some([m.x, m.y, m.z])
        })
        .collect();
    // The clamp's and the gripper's markers are far off, and one inner marker is missing:
    // only the seen inner markers count.
    markers[0] = Some([0.0, 1.0, 0.0]);
    markers[10] = Some([0.0, -1.0, 0.0]);
    markers[4] = None;
    let with_markers = LogRecord {
        markers: Some(markers),
        ..a_record(0.0, &a)
    };
    let buckled = a_of([0.0, 0.0, 1e-3, -50.0, 0.0, 0.0]);
    let mut jumped = z;
    jumped[2] += 3.0;
    let text = [
        line(&with_markers),
        line(&a_record(0.1, &buckled)),
        line(&a_record(0.2, &a)),
        line(&a_record(0.3, &a_of(jumped))),
    ]
    .join("\n");
    let log = write_log(&dir.0, "rig.jsonl", &text);
    let (_, lines, summary) = write(&dir, "fine", &params(log.clone()), DEFAULT_POINTS);
    let (_, _, coarse) = write(&dir, "coarse", &params(log), 5);
    let flags: Vec<(bool, bool)> = lines
        .iter()
        .map(|l| (l["stable"] == true, l["confident"] == true))
        .collect();
    // The buckled record is not stable; the jump back from it is a jump; the last is a jump.
    assert_eq!(
        flags,
        [(true, true), (false, false), (true, false), (true, false)]
    );
    let body = &summary["summary"];
    assert_eq!(body["records"], 4);
    assert_eq!(body["not_stable"], 1);
    assert_eq!(body["not_confident"], 3);
    let mm = body["marker_mean_mm"].as_f64().expect("a marker metric");
    // 2 mm, but for the polyline's chords.
    assert!((mm - 2.0).abs() < 0.02, "{mm}");
    let coarse = coarse["summary"]["marker_mean_mm"]
        .as_f64()
        .expect("metric");
    assert_relative_eq!(mm, coarse, max_relative = 1e-12);
}

/// Records solved in parallel by blocks and flagged in order: the same flags as the
/// estimator record by record (`LogShapes`), across a block boundary, and the same bytes on
/// one thread as on several.
#[test]
fn flags_match_the_estimator_across_blocks_and_threads() {
    let dir = TempDir::new("shape-log-blocks");
    let records = BLOCK + 40;
    let base = [0.5, 2.0, -1.0, -3.0, 1.5, 0.5];
    let text: Vec<String> = (0..records)
        .map(|i| {
            let mut z = base;
            // A slow drift, with jumps here and there, one on the first record of a block.
            #[allow(clippy::cast_precision_loss)]
            let t = i as f64;
            z[1] += 0.3 * (0.01 * t).sin();
            if i % 97 == 0 || i == BLOCK {
                z[2] += 3.0;
            }
            line(&a_record(0.01 * t, &a_of(z)))
        })
        .collect();
    let log = write_log(&dir.0, "rig.jsonl", &text.join("\n"));
    let params = ShapeLogParams {
        points: 3,
        ..params(log)
    };
    let shapes = ShapeLog::load(&params).expect("a good log");
    let mut bytes = Vec::new();
    shapes
        .write_shapes(&mut bytes, &mut |_| {})
        .expect("written");
    let one_thread = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a pool");
    let mut alone = Vec::new();
    one_thread
        .install(|| shapes.write_shapes(&mut alone, &mut |_| {}))
        .expect("written");
    assert!(bytes == alone, "the threads change nothing");
    let written: Vec<bool> = String::from_utf8(bytes)
        .expect("UTF-8")
        .lines()
        .map(|l| serde_json::from_str::<Value>(l).expect("JSON")["confident"] == true)
        .collect();
    let estimated: Vec<bool> = LogShapes::new(&params)
        .expect("a good log")
        .map(|s| s.expect("a record").confident)
        .collect();
    assert_eq!(written.len(), records);
    assert_eq!(written, estimated);
    assert!(!written[BLOCK], "the jump at the block's start");
    assert!(written.iter().filter(|c| !**c).count() > records / 100);
}

#[test]
fn shape_needs_no_b_but_identify_does() {
    let dir = TempDir::new("shape-log-no-b");
    let a = a_of([0.5, 2.0, -1.0, -3.0, 1.5, 0.5]);
    let with_b = LogRecord {
        b: Some(ftwire_estimate::log::LogPose {
            position: [0.5, 0.1, 0.0],
            rotation: [0.0, 0.0, 0.3],
        }),
        ..a_record(0.0, &a)
    };
    let text = format!("{}\n\n{}\n", line(&with_b), line(&a_record(0.5, &a)));
    let log = write_log(&dir.0, "rig.jsonl", &text);
    let shapes = ShapeLog::load(&params(log.clone())).expect("b is not needed");
    assert_eq!(shapes.lines().len(), 2);
    let error = identify::samples(&IdentifyLogParams {
        log,
        calibration: None,
        mounting: None,
        samples: None,
        residual: ResidualParams::default(),
        gravity: None,
        seed: 0,
        drift: None,
        front_end: Default::default(),
    })
    .expect_err("identification needs b");
    assert_eq!(error.kind(), "bad_input");
    let message = error.to_string();
    assert!(
        message.contains("line 3 (time 0.5) has no `b`"),
        "{message}"
    );
}

/// Without a calibration, `--mounting` maps `raw` by the mounting alone, after the tool's
/// weight is taken out with the record's gravity; a record without gravity is refused when
/// there is a tool.
#[test]
fn raw_goes_through_the_mounting_after_the_tools_weight() {
    let dir = TempDir::new("shape-log-mounting");
    let spec = MountingSpec {
        clamp_position_in_sensor: [0.0, 0.0, 0.11],
        tool_mass: 0.35,
        tool_centre_of_mass: [0.0, 0.0, 0.05],
        ..MountingSpec::default()
    };
    let mounting = spec.mounting().expect("a valid mounting");
    let a = a_of([0.5, 2.0, -1.0, -3.0, 1.5, 0.5]);
    let gravity = nalgebra::Vector3::new(0.0, -9.81, 0.0);
    let raw = mounting.to_sensor(&a) + spec.tool_reading(&gravity);
    let record = LogRecord {
        raw: Some(raw.into()),
        a: None,
        gravity: Some(gravity.into()),
        ..a_record(0.25, &a)
    };
    let log = write_log(&dir.0, "rig.jsonl", &format!("# rig\n{}\n", line(&record)));
    let mut params = params(log);
    let error = ShapeLog::load(&params).expect_err("raw needs a map");
    assert_eq!(error.kind(), "bad_input");
    let message = error.to_string();
    assert!(message.contains("line 2 (time 0.25)"), "{message}");
    assert!(
        message.contains("--calibration") && message.contains("--mounting"),
        "{message}"
    );
    params.mounting = Some(spec.clone());
    let shapes = ShapeLog::load(&params).expect("the mounting alone");
    let expected = spec
        .mounting()
        .expect("valid")
        .to_configuration(&(raw - spec.tool_reading(&gravity)));
    assert_eq!(shapes.a_tilde().len(), 1);
    for (got, want) in shapes.a_tilde()[0].iter().zip(expected.iter()) {
        assert_eq!(got.to_bits(), want.to_bits());
    }
    assert!((shapes.a_tilde()[0] - a).norm() < 1e-12);
    let (_, lines, _) = write(&dir, "out", &params, DEFAULT_POINTS);
    for (got, want) in numbers(&lines[0]["a"]).iter().zip(expected.iter()) {
        assert_eq!(got.to_bits(), want.to_bits());
    }

    let no_gravity = LogRecord {
        gravity: None,
        ..record
    };
    let log = write_log(
        &dir.0,
        "no-gravity.jsonl",
        &format!("{}\n", line(&no_gravity)),
    );
    params.log = log;
    let error = ShapeLog::load(&params).expect_err("the tool needs gravity");
    assert_eq!(error.kind(), "bad_input");
    let message = error.to_string();
    assert!(
        message.contains("line 1 (time 0.25)") && message.contains("`gravity`"),
        "{message}"
    );
}

/// With `a_std`, each shaped line has `sigma` as long as `points` (zero at the clamp, the
/// estimator's σ in m), the summary `sigma_mean_mm`, and a printed record its `sigma`;
/// without, none of them; a negative standard deviation is bad input naming `--a-std`.
#[test]
fn error_bars_only_with_standard_deviations() {
    use ftwire_estimate::shape::{ConfigurationStd, shape_sigma};
    let dir = TempDir::new("shape-log-sigma");
    let a = a_of([0.5, 2.0, -1.0, -3.0, 1.5, 0.5]);
    let outside = Vector6::new(0.1, 0.0, 0.0, -0.2, 0.0, 0.0); // ∉ A: no shape
    let text = format!(
        "{}\n{}\n{}\n",
        line(&a_record(0.0, &a)),
        line(&a_record(0.1, &outside)),
        line(&a_record(0.2, &a)),
    );
    let log = write_log(&dir.0, "rig.jsonl", &text);
    let std = [1e-4, 2e-4, 1e-4, 5e-3, 5e-3, 1e-2];
    let with = ShapeLogParams {
        a_std: Some(std),
        model_error: None,
        ..params(log.clone())
    };
    let (_, lines, summary) = write(&dir, "with", &with, 30);
    let expected = shape_sigma(
        &model(),
        &a,
        30,
        &ConfigurationStd::new(std).expect("std").covariance(),
    )
    .expect("sigma");
    for row in [&lines[0], &lines[2]] {
        let sigma = numbers(&row["sigma"]);
        assert_eq!(sigma.len(), 30, "{row}");
        assert!(sigma[0].abs() < 1e-12);
        for (got, want) in sigma.iter().zip(&expected.sigma) {
            assert_relative_eq!(*got, *want, max_relative = 1e-12);
        }
    }
    assert!(lines[1].get("sigma").is_none(), "{}", lines[1]);
    let mean: f64 = expected.sigma.iter().sum::<f64>() * 1e3 / 30.0;
    let got = summary["summary"]["sigma_mean_mm"]
        .as_f64()
        .expect("sigma_mean_mm");
    assert_relative_eq!(got, mean, max_relative = 1e-12);

    // The model's own error e·s adds in quadrature: the same σ at the base clamp, more along
    // the wire, exactly sqrt(σ_a² + (e s)²) with s the arc length of each of the 30 points.
    let e = 2e-3;
    let modelled = ShapeLogParams {
        model_error: Some(e),
        ..with.clone()
    };
    let (_, lines, _) = write(&dir, "model", &modelled, 30);
    let length = ftwire_estimate::WireModel::wire(&model()).length();
    let sigma = numbers(&lines[0]["sigma"]);
    for (k, (got, want)) in sigma.iter().zip(&expected.sigma).enumerate() {
        let s = length * k as f64 / 29.0;
        assert_relative_eq!(*got, want.hypot(e * s), max_relative = 1e-9);
    }
    let bad = ShapeLogParams {
        model_error: Some(-1.0),
        ..with.clone()
    };
    let Err(error) = LogShapes::new(&bad) else {
        panic!("a negative model error is refused");
    };
    assert!(error.to_string().contains("--model-error"), "{error}");

    let (_, lines, summary) = write(&dir, "without", &params(log.clone()), 30);
    assert!(lines.iter().all(|row| row.get("sigma").is_none()));
    assert!(
        summary["summary"].get("sigma_mean_mm").is_none(),
        "{summary}"
    );

    let printed: Vec<_> = LogShapes::new(&ShapeLogParams { points: 30, ..with })
        .expect("a good log")
        .map(|r| r.expect("a record"))
        .collect();
    let sigma = printed[0].sigma.as_ref().expect("sigma");
    assert_eq!(sigma.len(), printed[0].points.len());
    assert!(printed[0].to_string().contains(" ± "), "{}", printed[0]);
    assert!(printed[1].sigma.is_none());
    let plain: Vec<_> = LogShapes::new(&params(log.clone()))
        .expect("a good log")
        .map(|r| r.expect("a record"))
        .collect();
    assert!(plain[0].sigma.is_none());

    let bad = ShapeLogParams {
        a_std: Some([0.0, 0.0, 0.0, -1.0, 0.0, 0.0]),
        model_error: None,
        ..params(log)
    };
    let error = ShapeLog::load(&bad).expect_err("a negative std");
    assert_eq!(error.kind(), "bad_input");
    assert!(error.to_string().contains("--a-std"), "{error}");
}

/// With the sensor's data sheet, every record carries error bars from its time since the
/// tare: the same `ã` read later has drifted further, so its `σ` is larger; a gain error adds
/// to them; and `--a-std`, when given, is used instead.
#[test]
fn error_bars_from_the_sensor_grow_with_the_drift() {
    let dir = TempDir::new("shape-log-sensor");
    let a = a_of([0.5, 2.0, -1.0, -3.0, 1.5, 0.5]);
    let text = format!(
        "{}\n{}\n",
        line(&a_record(10.0, &a)),
        line(&a_record(70.0, &a))
    );
    let log = write_log(&dir.0, "rig.jsonl", &text);
    let spec = ftwire_lab::setup::SensorSpec::load("undistorted").expect("the preset");
    let sensor = |tare_time| ftwire_lab::log::identify::LogDrift {
        sensor: "undistorted".to_owned(),
        params: ftwire_lab::setup::sensor::data_sheet(&spec.config),
        rest_samples: 400,
        tare_samples: 500,
        tare_time,
    };
    let mean = |sigma: &[f64]| sigma.iter().sum::<f64>() / sigma.len() as f64;
    let shaped = |params: &ShapeLogParams| -> Vec<f64> {
        LogShapes::new(params)
            .expect("a good log")
            .map(|r| mean(r.expect("a record").sigma.as_deref().expect("sigma")))
            .collect()
    };
    let with = ShapeLogParams {
        sensor: Some(sensor(None)),
        ..params(log.clone())
    };
    let drifted = shaped(&with);
    assert!(drifted[1] > 1.5 * drifted[0], "{drifted:?}");
    // Tared just before the first record: its error is the tare's and the rest's noise.
    let early = shaped(&ShapeLogParams {
        sensor: Some(sensor(Some(10.0))),
        ..params(log.clone())
    });
    assert!(
        (early[0] - drifted[0]).abs() < 1e-12,
        "{early:?} {drifted:?}"
    );
    let late = shaped(&ShapeLogParams {
        sensor: Some(sensor(Some(-100.0))),
        ..params(log.clone())
    });
    assert!(late[0] > drifted[0], "{late:?} {drifted:?}");
    let gain = shaped(&ShapeLogParams {
        gain_error: Some(0.01),
        ..with.clone()
    });
    assert!(gain[0] > drifted[0], "{gain:?} {drifted:?}");
    let given = shaped(&ShapeLogParams {
        a_std: Some([1e-4, 2e-4, 1e-4, 5e-3, 5e-3, 1e-2]),
        ..with.clone()
    });
    let only_given = shaped(&ShapeLogParams {
        a_std: Some([1e-4, 2e-4, 1e-4, 5e-3, 5e-3, 1e-2]),
        ..params(log.clone())
    });
    assert_eq!(given, only_given, "--a-std is used instead");
    let bad = ShapeLogParams {
        gain_error: Some(2.0),
        ..with
    };
    let error = ShapeLog::load(&bad).expect_err("a gain error of 200 %");
    assert!(error.to_string().contains("--gain-error"), "{error}");
}
