//! The experiments as library calls: each runs with tiny settings into a temporary results
//! folder, writes its files there and returns a summary with every key and finite values.
//! (The full summaries are compared with their recordings by the `ftwire` binary's tests.)

use std::path::Path;

use ftwire_lab::experiment::{CommonParams, Gravity};
use ftwire_lab::results::ResultsFolder;

mod common;

use common::TempDir;

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
        save_log: false,
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
    let text = run.text(Path::new("out"));
    let printed: Vec<&str> = text.lines().collect();
    assert!(
        printed[0].starts_with(&format!(
            "calibration on nitinol-3mm-820 ({} train, {} validation, {} test; skipped",
            s.train, s.validation, s.test
        )),
        "{text}"
    );
    assert_eq!(
        printed[1],
        "                 torque_rel  force_rel  shape_mm"
    );
    assert!(printed[2].starts_with("raw (mounting)  "), "{text}");
    assert!(printed[3].starts_with("calibrated      "), "{text}");
    assert!(printed[4].starts_with("labels: marker RMS "), "{text}");
    assert!(printed[5].ends_with("; results in out"), "{text}");
}

#[test]
fn shape_from_a_calibration_file_reports_every_metric_and_writes_its_files() {
    let dir = TempDir::new("shape");
    // A small calibration, read back from its file as `--calibration` would.
    let calibrated = dir.results("calibrate");
    let settings = ftwire_lab::calibrate::CalibrateParams {
        common: common("nitinol-3mm-820", 40),
        save_log: false,
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
    let text = run.text(Path::new("out"));
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(
        lines[0],
        "shape: kirchhoff model (mean_mm), the loaded model from the same ã beside it"
    );
    assert!(
        lines[1].starts_with("wire               configs  mean_mm"),
        "{text}"
    );
    // The wire's row: its name, 2 configurations, and Table II's 5.72 mm beside it.
    assert!(
        lines[2].starts_with("nitinol-2mm-630          2 "),
        "{text}"
    );
    assert!(lines[2].contains(" 5.72 "), "{text}");
    assert!(lines[3].ends_with("; results in out"), "{text}");
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

/// One trial of the 2 mm wire through the mounting pipeline (no calibration to run first).
fn identify_settings(gravity: Gravity) -> ftwire_lab::identify::IdentifyParams {
    ftwire_lab::identify::IdentifyParams {
        common: CommonParams {
            gravity,
            ..common("nitinol-2mm-630", 1)
        },
        samples: Some(vec![5, 3]),
        pipeline: ftwire_lab::identify::Pipeline::Mounting,
        save_log: true,
        ..ftwire_lab::identify::IdentifyParams::default()
    }
}

#[test]
fn identify_recovers_the_wire_and_writes_its_files() {
    let dir = TempDir::new("identify");
    let folder = dir.results("identify");
    let settings = identify_settings(Gravity::Off);
    let mut lines = Vec::new();
    let run = ftwire_lab::identify::run(&settings, &folder, &mut |l| lines.push(l.to_owned()))
        .expect("runs");
    let summary = serde_json::to_value(&run.summary).expect("serialises");
    for key in [
        "model",
        "form",
        "gravity",
        "sensor",
        "pipeline",
        "calibration",
        "trials",
        "noise",
        "sample_counts",
        "wire",
        "by_samples",
        "wires",
        "by_model",
    ] {
        assert!(summary.get(key).is_some(), "{key} missing: {summary}");
    }
    // The default sensor through its mounting alone: its own gain and cross-talk (about
    // 1.5 %) are the shared gain error; the simulated robot's pose noise.
    let noise = &run.summary.noise;
    assert!(noise.bias_model, "{noise:?}");
    assert!((1.0..2.0).contains(&noise.gain_error_percent), "{noise:?}");
    assert!((noise.pose_noise_deg - 0.005).abs() < 1e-12, "{noise:?}");
    assert!((noise.pose_noise_mm - 0.01).abs() < 1e-12, "{noise:?}");
    assert_eq!(summary["pipeline"], "mounting");
    assert_eq!(summary["form"], "absolute");
    assert!(summary["calibration"].is_null());
    assert_eq!(summary["sample_counts"], serde_json::json!([3, 5]));
    // Without gravity the loaded model is the paper's: one model runs.
    assert_eq!(run.summary.by_model.len(), 1);
    let row = &run.summary.by_samples[1];
    assert_eq!((row.samples, row.estimated), (5, 1));
    for j in 0..4 {
        assert!(row.mean[j].is_finite(), "{row:?}");
    }
    // The length within 1 % of the truth, the stiffnesses within 5 % (one trial, the
    // mounting's gain error of about 1 % left in ã).
    assert!(row.mean_abs_relative_error[3] < 0.01, "{row:?}");
    for j in 0..3 {
        assert!(row.mean_abs_relative_error[j] < 0.05, "{row:?}");
    }
    assert_eq!(run.timings.identifications.len(), 2);
    assert!(
        run.timings
            .median_ms(run.summary.model, "nitinol-2mm-630", 5)
            .is_finite()
    );
    for file in [
        "identify.csv",
        "error_vs_samples_nitinol-2mm-630.png",
        "logs/nitinol-2mm-630-trial0.jsonl",
    ] {
        assert!(exists(&folder, file), "{file}");
    }
    assert_eq!(lines.len(), 1, "one line per trial and model: {lines:?}");
}

#[test]
fn identify_until_stops_each_trial_at_the_first_precise_estimate() {
    let dir = TempDir::new("identify-until");
    let folder = dir.results("identify");
    // A loose target (the mounting pipeline leaves about 1 % of gain error) and a strict one.
    for (target, expect_reached) in [(50.0, true), (0.01, false)] {
        let settings = ftwire_lab::identify::IdentifyParams {
            until: Some(target),
            save_log: false,
            ..identify_settings(Gravity::Off)
        };
        let run = ftwire_lab::identify::run(&settings, &folder, &mut |_| {}).expect("runs");
        let until = run.summary.until.as_ref().expect("until");
        assert_eq!(run.summary.wires[0].until.as_ref(), Some(until));
        assert_eq!((until.trials, until.limit), (1, 5), "{until:?}");
        assert_eq!(until.reached == 1, expect_reached, "{until:?}");
        if expect_reached {
            assert!(until.samples_max < 5, "{until:?}");
        } else {
            assert_eq!(until.samples, [5]);
        }
        let json = serde_json::to_value(until).expect("serialises");
        for key in [
            "target_percent",
            "trials",
            "reached",
            "samples_median",
            "samples_max",
            "mean_abs_relative_error",
            "max_abs_relative_error",
            "coverage95",
        ] {
            assert!(json.get(key).is_some(), "{key} missing: {json}");
        }
    }
    for bad in [0.0, -1.0, 101.0, f64::NAN] {
        let settings = ftwire_lab::identify::IdentifyParams {
            until: Some(bad),
            ..identify_settings(Gravity::Off)
        };
        let err = settings.check().expect_err("refused");
        assert_eq!(err.exit_code(), 2);
        assert!(err.to_string().contains("--until"), "{err}");
    }
}

#[test]
fn identify_with_gravity_runs_both_models_on_the_same_data() {
    let dir = TempDir::new("identify-gravity");
    let folder = dir.results("identify");
    let settings = ftwire_lab::identify::IdentifyParams {
        samples: Some(vec![3]),
        save_log: false,
        ..identify_settings(Gravity::On)
    };
    let run = ftwire_lab::identify::run(&settings, &folder, &mut |_| {}).expect("runs");
    let models: Vec<&str> = run
        .summary
        .by_model
        .iter()
        .map(|m| m.model.name())
        .collect();
    assert_eq!(models, ["loaded", "kirchhoff"]);
    let loaded = &run.summary.by_samples[0];
    let density = loaded
        .linear_density
        .as_ref()
        .expect("the loaded model's λ");
    assert!(
        density.mean.is_finite() && density.mean > 0.0,
        "{density:?}"
    );
    assert!(
        run.summary.by_model[1].wires[0].by_samples[0]
            .linear_density
            .is_none()
    );
}

#[test]
fn identify_refuses_bad_settings_before_any_work() {
    let bad = [
        ftwire_lab::identify::IdentifyParams {
            samples: Some(vec![1]),
            ..ftwire_lab::identify::IdentifyParams::default()
        },
        ftwire_lab::identify::IdentifyParams {
            calibration: Some("weights.json".into()),
            ..identify_settings(Gravity::Off)
        },
    ];
    for settings in bad {
        let e = settings.check().expect_err("bad input");
        assert_eq!(e.exit_code(), 2, "{e}");
    }
}

#[test]
fn goal_steers_one_pair_closed_and_open_loop_and_writes_its_files() {
    let dir = TempDir::new("goal");
    let calibrated = dir.results("calibrate");
    let settings = ftwire_lab::calibrate::CalibrateParams {
        common: common("nitinol-3mm-820", 40),
        save_log: false,
    };
    ftwire_lab::calibrate::run(&settings, &calibrated, &mut |_| {}).expect("calibrates");
    let folder = dir.results("goal");
    let settings = ftwire_lab::goal::GoalParams {
        common: common("nitinol-3mm-820", 1),
        pairs: 1,
        noise_model: ftwire_control::NoiseModel::Offset,
        calibration: Some(calibrated.dir().join("calibration.json")),
        ..ftwire_lab::goal::GoalParams::default()
    };
    let mut lines = Vec::new();
    let run =
        ftwire_lab::goal::run(&settings, &folder, &mut |l| lines.push(l.to_owned())).expect("runs");
    assert!(
        lines.iter().any(|l| l.starts_with("1 pairs drawn")),
        "{lines:?}"
    );
    let summary = serde_json::to_value(&run.summary).expect("serialises");
    assert_eq!(summary["noise_model"], "offset");
    assert_eq!(summary["pairs"], 1);
    for loop_kind in ["open_loop", "closed_loop"] {
        for variant in ["no_noise", "noise"] {
            let m = &summary["results"][loop_kind][variant];
            let counted = m["trials"].as_u64().zip(m["failed"].as_u64());
            assert_eq!(
                counted.map(|(t, f)| t + f),
                Some(1),
                "{loop_kind}.{variant}: {m}"
            );
        }
    }
    // Without noise the closed loop reaches the goal: the true shape within millimetres.
    let free = &run.summary.results.closed_loop.no_noise;
    assert_eq!(free.trials, 1, "{:?}", run.summary.failures);
    assert!(free.mean_mm < 10.0, "{}", free.mean_mm);
    assert_eq!(run.summary.epsilon_tradeoff.no_noise.len(), 3);
    assert_eq!(run.summary.collision.free_motions, 1);
    assert!(run.timings.controller_step_us_median > 0.0);
    let text = run.text(Path::new("out"));
    assert!(
        text.starts_with(
            "goal: nitinol-3mm-820 (kirchhoff model), 1 pairs, K = 0.2, noise model offset\n"
        ),
        "{text}"
    );
    for row in [
        "open loop, no noise",
        "closed loop, no noise",
        "open loop, noise",
        "closed loop, noise",
        "paper Table III: open 4.80 / 17.35, closed 9.67 / 9.11 (no noise / noise)",
        "collision: ",
    ] {
        assert!(text.contains(&format!("\n{row}")), "{row}: {text}");
    }
    assert!(text.ends_with("; results in out\n"), "{text}");
    for file in [
        "trials.csv",
        "motion_in_a.png",
        "shape_error_along_motion.svg",
    ] {
        assert!(exists(&folder, file), "{file}");
    }
    assert!(!exists(&folder, "calibration.json"));
}

#[test]
fn goal_refuses_bad_settings_before_any_work() {
    let bad = [
        ftwire_lab::goal::GoalParams {
            pairs: 0,
            ..ftwire_lab::goal::GoalParams::default()
        },
        ftwire_lab::goal::GoalParams {
            shape_stop_mm: Some(-2.0),
            ..ftwire_lab::goal::GoalParams::default()
        },
        ftwire_lab::goal::GoalParams {
            common: CommonParams {
                wire: Some("no-such-wire".to_owned()),
                ..CommonParams::default()
            },
            ..ftwire_lab::goal::GoalParams::default()
        },
    ];
    for settings in bad {
        let e = settings.check().expect_err("bad input");
        assert_eq!(e.exit_code(), 2, "{e}");
    }
}
