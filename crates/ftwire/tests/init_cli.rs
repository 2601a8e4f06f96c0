//! Issue 17, configuration: `ftwire init DIR` writes a commented example of each file, every
//! command that takes one accepts the example as written, the sensor and rig examples are the
//! defaults (a run with them gives the same results as one without), and a bad file is exit 2
//! naming the file, the line and the key.

mod cli_support;

use std::fs;
use std::path::{Path, PathBuf};

use cli_support::{TempDir, assert_exit, assert_success, ftwire};

fn text(path: &Path) -> &str {
    path.to_str().expect("a UTF-8 path")
}

/// `ftwire init dir/cfg`, asserted to succeed; returns the folder.
fn init(dir: &Path) -> PathBuf {
    let cfg = dir.join("cfg");
    assert_success(&ftwire(&["init", text(&cfg)]), "ftwire init");
    cfg
}

/// The summary of a results folder without its run header (which records the options).
fn body(folder: &Path) -> serde_json::Value {
    let bytes = fs::read(folder.join("summary.json")).expect("summary.json");
    let summary: serde_json::Value = serde_json::from_slice(&bytes).expect("JSON");
    summary["summary"].clone()
}

#[test]
fn init_writes_the_examples_once_and_refuses_to_overwrite_them() {
    let tmp = TempDir::new("init-write");
    let cfg = init(&tmp.0);
    for name in [
        "wire.toml",
        "sensor.toml",
        "rig.toml",
        "scene.toml",
        "mounting.toml",
    ] {
        let example = fs::read_to_string(cfg.join(name)).expect("an example");
        assert!(example.starts_with('#'), "{name} opens with a comment");
    }
    let mounting = ftwire_lab::setup::mounting::load(Some(&cfg.join("mounting.toml")))
        .expect("the mounting example reads");
    assert_eq!(mounting, ftwire_estimate::ft::MountingSpec::default());
    fs::write(cfg.join("rig.toml"), "settle_time = 0.5\n").expect("edits the rig");
    let again = ftwire(&["init", text(&cfg)]);
    assert_exit(&again, 2, "wire.toml exists already", "init over examples");
    assert_exit(&again, 2, "--force", "init over examples");
    let kept = fs::read_to_string(cfg.join("rig.toml")).expect("rig.toml");
    assert_eq!(kept, "settle_time = 0.5\n", "nothing overwritten");
    assert_success(&ftwire(&["init", "--force", text(&cfg)]), "init --force");
    assert!(fs::read_to_string(cfg.join("rig.toml")).is_ok_and(|t| t.starts_with('#')));
    let missing = tmp.0.join("no").join("cfg");
    assert_exit(
        &ftwire(&["init", text(&missing)]),
        2,
        "does not exist",
        "init with a missing parent",
    );
    let file = cfg.join("wire.toml");
    assert_exit(
        &ftwire(&["init", text(&file)]),
        2,
        "is a file",
        "init into a file",
    );
}

#[test]
fn every_command_accepts_the_examples_as_written() {
    let tmp = TempDir::new("init-accept");
    let cfg = init(&tmp.0);
    let [wire, sensor, rig, scene] =
        ["wire.toml", "sensor.toml", "rig.toml", "scene.toml"].map(|name| cfg.join(name));
    let (wire, sensor, rig, scene) = (text(&wire), text(&sensor), text(&rig), text(&scene));
    let out = |name: &str| tmp.0.join(name).to_string_lossy().into_owned();
    let setup = ["--wire", wire, "--sensor", sensor, "--rig", rig];
    let cal = out("cal");
    let weights = tmp.0.join("cal").join("calibration.json");
    let weights = text(&weights);
    let (id, shape, goal) = (out("identify"), out("shape"), out("goal"));
    let mounting = cfg.join("mounting.toml");
    let mounting = text(&mounting);
    let log = tmp.0.join("rig.jsonl");
    fs::write(
        &log,
        "{\"time\": 0.0, \"raw\": [0.01, 0.02, -0.03, 0.0004, 0.0002, -0.0001]}\n",
    )
    .expect("writes a log");
    let log = text(&log);
    let runs: Vec<(&str, Vec<&str>)> = vec![
        ("scene check", vec!["scene", "check", scene, "--wire", wire]),
        (
            "shape --log",
            vec![
                "shape",
                "--log",
                log,
                "--wire",
                wire,
                "--mounting",
                mounting,
            ],
        ),
        (
            "plan",
            vec![
                "plan",
                "--scene",
                scene,
                "--wire",
                wire,
                "--seed",
                "2",
                "--first",
                "--json",
                // An iteration budget, not the default 2 s: the same path on a loaded machine.
                "--iterations",
                "5000",
                "--time-budget",
                "600",
            ],
        ),
        (
            "experiment identify",
            [
                &["experiment", "identify"][..],
                &setup,
                &["--pipeline", "mounting", "--samples", "2", "--trials", "1"],
                &["--out", &id],
            ]
            .concat(),
        ),
        (
            "experiment calibrate",
            [
                &["experiment", "calibrate"][..],
                &setup,
                &["--trials", "20", "--out", &cal],
            ]
            .concat(),
        ),
        (
            "experiment shape",
            [
                &["experiment", "shape"][..],
                &setup,
                &["--configs", "1", "--calibration", weights, "--out", &shape],
            ]
            .concat(),
        ),
        (
            "experiment goal",
            [
                &["experiment", "goal"][..],
                &setup,
                &["--pairs", "1", "--calibration", weights, "--out", &goal],
            ]
            .concat(),
        ),
    ];
    for (what, args) in runs {
        assert_success(&ftwire(&args), what);
    }
}

#[test]
fn the_sensor_and_rig_examples_are_the_defaults_and_a_sensor_file_takes_effect() {
    let tmp = TempDir::new("init-defaults");
    let cfg = init(&tmp.0);
    let sensor = cfg.join("sensor.toml");
    let rig = cfg.join("rig.toml");
    let identify = |out: &Path, extra: &[&str]| {
        let args = [
            &[
                "experiment",
                "identify",
                "--wire",
                "nitinol-2mm-630",
                "--pipeline",
                "mounting",
                "--samples",
                "2,3",
                "--trials",
                "1",
                "--gravity",
                "off",
                "--out",
                text(out),
            ][..],
            extra,
        ]
        .concat();
        assert_success(&ftwire(&args), "experiment identify");
        let mut summary = body(out);
        summary["sensor"] = serde_json::Value::Null;
        summary
    };
    let plain = identify(&tmp.0.join("plain"), &[]);
    let with_files = identify(
        &tmp.0.join("files"),
        &["--sensor", text(&sensor), "--rig", text(&rig)],
    );
    assert_eq!(plain, with_files, "the examples are the library's defaults");
    // A sensor ten times noisier: the same run identifies differently.
    let example = fs::read_to_string(&sensor).expect("sensor.toml");
    let noisy = cfg.join("noisy.toml");
    let noisier = example.replace(
        "noise_std = [0.05, 0.05, 0.05, 0.002, 0.002, 0.002]",
        "noise_std = [0.5, 0.5, 0.5, 0.02, 0.02, 0.02]",
    );
    assert_ne!(noisier, example, "the example sets noise_std");
    fs::write(&noisy, noisier).expect("writes the noisy sensor");
    let noisy = identify(&tmp.0.join("noisy"), &["--sensor", text(&noisy)]);
    assert_ne!(plain, noisy, "the sensor file reaches the simulated sensor");
}

#[test]
fn a_bad_sensor_or_rig_file_is_exit_2_naming_the_file_the_line_and_the_key() {
    let tmp = TempDir::new("init-bad");
    let write = |name: &str, contents: &str| {
        let path = tmp.0.join(name);
        fs::write(&path, contents).expect("writes a file");
        path.to_string_lossy().into_owned()
    };
    let misspelt = write("misspelt.toml", "rate = 500.0\n\nnoise_sdt = 0.1\n");
    let negative = write("negative.toml", "[markers]\nnoise_std = -0.001\n");
    let not_toml = write("broken.toml", "rate = = 1\n");
    let out = tmp.0.join("out").to_string_lossy().into_owned();
    let cases: [(&[&str], &[&str]); 5] = [
        (
            &["--sensor", &misspelt],
            &["misspelt.toml", "line 3", "noise_sdt"],
        ),
        (
            &["--rig", &negative],
            &["negative.toml", "line 2", "noise_std", "≥ 0"],
        ),
        (&["--sensor", &not_toml], &["broken.toml", "line 1"]),
        (
            &["--sensor", "perfect"],
            &["unknown sensor \"perfect\"", "undistorted"],
        ),
        (&["--rig", "/no/such/rig.toml"], &["/no/such/rig.toml"]),
    ];
    for (extra, needles) in cases {
        for command in [
            &[
                "experiment",
                "identify",
                "--pipeline",
                "mounting",
                "--out",
                &out,
            ][..],
            &["experiment", "shape", "--out", &out],
            &["demo", "--out", &out],
        ] {
            let output = ftwire(&[command, extra].concat());
            for needle in needles {
                assert_exit(&output, 2, needle, &format!("{command:?} {extra:?}"));
            }
        }
    }
    assert!(!tmp.0.join("out").exists(), "nothing written");
}

/// A folder name with an ESC sequence is printed escaped: no name the user gives can retitle
/// the terminal or drive it.
#[test]
fn a_control_character_in_a_folder_name_is_printed_escaped() {
    let tmp = TempDir::new("init-escape");
    let cfg = tmp.0.join("z\u{1b}]0;PWNED\u{7}");
    let output = ftwire(&["init", text(&cfg)]);
    assert_success(&output, "ftwire init");
    assert!(
        !output.stdout.iter().any(|&b| b == 0x1b || b == 0x07),
        "{:?}",
        String::from_utf8_lossy(&output.stdout)
    );
    assert!(
        String::from_utf8_lossy(&output.stdout).contains("\\u{1b}]0;PWNED\\u{7}"),
        "{}",
        String::from_utf8_lossy(&output.stdout)
    );
}
