//! Issue 17, bad input: a `--out` whose parent is missing or cannot be written is exit 2 with a
//! message naming it, for the demo, `reproduce` and an experiment, before any work is done; an
//! existing results folder is left as it was.

mod cli_support;

use std::fs;

use cli_support::{TempDir, assert_exit, ftwire};

const COMMANDS: [&[&str]; 3] = [
    &["demo"],
    &["reproduce", "--quick"],
    &["experiment", "identify", "--pipeline", "mounting"],
];

#[test]
fn a_missing_out_parent_is_exit_2() {
    let tmp = TempDir::new("out");
    let missing = tmp.0.join("no").join("such").join("run");
    let missing = missing.to_string_lossy();
    for command in COMMANDS {
        let output = ftwire(&[command, &["--out", &missing]].concat());
        assert_exit(&output, 2, "does not exist", &format!("{command:?}"));
        assert_exit(&output, 2, &missing, &format!("{command:?}"));
    }
    assert!(!tmp.0.join("no").exists(), "nothing written");
}

/// `/proc` exists and nobody, not even root, can make a folder in it.
#[cfg(target_os = "linux")]
#[test]
fn an_unwritable_out_is_exit_2() {
    for command in COMMANDS {
        let output = ftwire(&[command, &["--out", "/proc/ftwire-results"]].concat());
        assert_exit(&output, 2, "cannot write in /proc", &format!("{command:?}"));
    }
}

#[test]
fn an_existing_results_folder_survives_a_bad_run() {
    let tmp = TempDir::new("out-keep");
    let out = tmp.0.join("run");
    fs::create_dir_all(&out).expect("creates a results folder");
    fs::write(out.join("summary.json"), "{}").expect("writes a summary");
    let output = ftwire(&[
        "experiment",
        "identify",
        "--pipeline",
        "mounting",
        "--sensor",
        "/no/such/sensor.toml",
        "--out",
        &out.to_string_lossy(),
    ]);
    assert_exit(&output, 2, "/no/such/sensor.toml", "a missing sensor file");
    let kept = fs::read_to_string(out.join("summary.json")).expect("the old summary");
    assert_eq!(kept, "{}");
    let leftovers = fs::read_dir(&tmp.0).map_or(0, Iterator::count);
    assert_eq!(leftovers, 1, "no partial folder left beside it");
}
