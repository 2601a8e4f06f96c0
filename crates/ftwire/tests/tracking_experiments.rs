//! `ftwire experiment track` and `ftwire experiment passage`: the binary passes its options to
//! the lab and writes the results folder (the summary with its run header, `timings.json`,
//! the report and the lab's files), the same for the same seed; bad input is refused with
//! exit 2 before any work. The runs are tiny: the experiments themselves, their recorded
//! summaries and their CSV files are checked as library calls by ftwire-lab's
//! `tests/tracking.rs`, and how the options map to the lab's settings by the unit tests of
//! `commands::experiment`.

mod cli_support;

use std::path::Path;

use cli_support::{assert_exit, assert_success, ftwire, tiny_calibration};

/// Runs `ftwire ARGS --calibration CALIBRATION --out OUT` and returns its `summary.json`.
fn run(args: &[&str], out: &Path, calibration: &Path) -> serde_json::Value {
    let mut all: Vec<&str> = args.to_vec();
    let (calibration, out) = (
        calibration.to_str().expect("a UTF-8 path"),
        out.to_str().expect("a UTF-8 path"),
    );
    all.extend(["--calibration", calibration, "--out", out]);
    let output = ftwire(&all);
    assert_success(&output, &all.join(" "));
    let text = std::fs::read_to_string(Path::new(out).join("summary.json")).expect("summary");
    serde_json::from_str(&text).expect("JSON")
}

/// `timings.json` of the results folder `out`.
fn timings(out: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(out.join("timings.json")).expect("timings.json");
    serde_json::from_str(&text).expect("JSON")
}

fn temp(name: &str) -> std::path::PathBuf {
    let tmp = std::env::temp_dir().join(format!("ftwire-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&tmp).expect("a temporary folder");
    tmp
}

#[test]
fn a_passage_run_writes_its_folder_with_the_options_given() {
    let tmp = temp("passage");
    let calibration = tiny_calibration(&tmp);
    let args = [
        "experiment",
        "passage",
        "--attempts",
        "1",
        "--noise-model",
        "offset",
        "--seed",
        "5",
    ];
    let out = tmp.join("a");
    let written = run(&args, &out, &calibration);
    assert_eq!(written["header"]["command"], "experiment passage");
    assert_eq!(written["header"]["seed"], 5);
    let summary = &written["summary"];
    for mode in ["open_loop", "closed_loop"] {
        assert_eq!(summary["results"][mode]["attempts"], 1, "{mode}");
    }
    assert_eq!(summary["noise_model"], "offset");
    // Under `offset` the defaults are gain 0.5 and one plan, without a choice.
    assert_eq!(summary["gain"], 0.5);
    assert!(summary["plan"]["choice"].is_null());
    // The plan's time is in timings.json, not in the summary.
    assert!(summary.get("plan_ms").is_none());
    assert!(timings(&out)["plan_ms"].as_f64().is_some_and(|t| t > 0.0));
    for file in [
        "attempts.csv",
        "waypoints.csv",
        "report.md",
        "report.html",
        "passage_path_in_a.png",
        "passage_shape_error.svg",
        "passage_scene.png",
    ] {
        assert!(out.join(file).is_file(), "{file}");
    }
    let _ = std::fs::remove_dir_all(&tmp);
}

/// Seed 8 draws a plannable pair within a few tries.
#[test]
fn a_track_run_writes_its_folder_with_the_options_given_the_same_for_the_same_seed() {
    let tmp = temp("track");
    let calibration = tiny_calibration(&tmp);
    let args = [
        "experiment",
        "track",
        "--pairs",
        "1",
        "--gravity",
        "off",
        "--noise-model",
        "offset",
        "--seed",
        "8",
    ];
    let out = tmp.join("a");
    let written = run(&args, &out, &calibration);
    assert_eq!(written["header"]["command"], "experiment track");
    assert_eq!(written["header"]["seed"], 8);
    assert_eq!(
        written["header"]["configuration"]["common"]["gravity"],
        "off"
    );
    let summary = &written["summary"];
    assert_eq!(summary["pairs"], 1);
    assert_eq!(summary["noise_model"], "offset");
    assert_eq!(summary["gain"], 0.5);
    assert!(summary.get("plan_ms_median").is_none());
    assert!(
        timings(&out)["plan_ms_median"]
            .as_f64()
            .is_some_and(|t| t > 0.0)
    );
    for file in [
        "pairs.csv",
        "waypoints.csv",
        "report.md",
        "report.html",
        "track_path_in_a.png",
        "track_shape_error.png",
    ] {
        assert!(out.join(file).is_file(), "{file}");
    }
    let again = run(&args, &tmp.join("b"), &calibration);
    assert_eq!(*summary, again["summary"], "same seed, same results");
    let _ = std::fs::remove_dir_all(&tmp);
}

#[test]
fn bad_options_are_refused_before_any_work() {
    let output = ftwire(&["experiment", "passage", "--attempts", "0"]);
    assert_exit(&output, 2, "--attempts 0", "passage --attempts 0");
    let output = ftwire(&["experiment", "track", "--pairs", "0"]);
    assert_exit(&output, 2, "--pairs 0", "track --pairs 0");
    let output = ftwire(&["experiment", "passage", "--plan-candidates", "0"]);
    assert_exit(
        &output,
        2,
        "--plan-candidates 0",
        "passage --plan-candidates 0",
    );
    let output = ftwire(&["experiment", "passage", "--gain", "1.5"]);
    assert_exit(&output, 2, "--gain 1.5", "passage --gain 1.5");
    let output = ftwire(&["experiment", "track", "--shape-stop", "-1"]);
    assert_exit(&output, 2, "--shape-stop -1", "track --shape-stop -1");
    let output = ftwire(&["experiment", "passage", "--near-shape-stop", "-2"]);
    assert_exit(
        &output,
        2,
        "--near-shape-stop -2",
        "passage --near-shape-stop -2",
    );
    for command in ["track", "passage"] {
        let output = ftwire(&["experiment", command, "--waypoint-moves", "0"]);
        assert_exit(&output, 2, "--waypoint-moves 0", "--waypoint-moves 0");
    }
    let output = ftwire(&["experiment", "passage", "--scene", "/no/such/scene.toml"]);
    assert_exit(&output, 2, "scene.toml", "passage --scene missing");
}

#[test]
fn a_scene_with_an_unknown_key_names_it() {
    let tmp = temp("passage-bad-scene");
    let scene = tmp.join("bad.toml");
    std::fs::write(
        &scene,
        "[base]\nposition = [0.6, 0.35, 0.35]\ncolour = \"red\"\n",
    )
    .expect("write");
    let output = ftwire(&[
        "experiment",
        "passage",
        "--scene",
        scene.to_str().expect("UTF-8"),
    ]);
    assert_exit(&output, 2, "colour", "passage with an unknown scene key");
    let _ = std::fs::remove_dir_all(&tmp);
}

#[test]
fn the_shipped_passage_variants_have_their_start_and_goal_in_z_free() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/variants");
    let mut checked = 0;
    for entry in std::fs::read_dir(&dir).expect("scenes/variants") {
        let path = entry.expect("an entry").path();
        if path.extension().is_some_and(|e| e == "toml") {
            let output = ftwire(&["scene", "check", path.to_str().expect("UTF-8")]);
            assert_success(&output, &format!("scene check {}", path.display()));
            checked += 1;
        }
    }
    assert!(checked >= 7, "{checked} variants");
}
