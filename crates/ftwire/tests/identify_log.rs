//! `ftwire experiment identify` and `ftwire identify --log`:
//! - the log command on a log that the experiment wrote (`--save-log`, mounting pipeline)
//!   gives the live run's estimate (same data, same seed); a bad log line and an empty log are
//!   bad input (exit 2) naming the line;
//! - with gravity off and the sensor's gain and cross-talk removed (what a perfect calibration
//!   gives), a short run recovers both nitinol wires, and the results folder holds what issue
//!   13 asks; bad options are bad input;
//! - through the learnt calibration with `--calibration FILE` (a tiny calibration, to keep the
//!   test fast) the summary names the pipeline and the weights, `ã` differs from the mounting
//!   pipeline's on the same readings, and a saved log replayed by `ftwire identify --log`
//!   gives the live estimate.

mod cli_support;

use std::collections::HashMap;
use std::fs;
use std::path::Path;

use cli_support::{TempDir, assert_exit, assert_success, ftwire, json, numbers, tiny_calibration};

/// The rows of `identify.csv` in the results folder `dir`, each a map from column to value.
fn csv_rows(dir: &Path) -> Vec<HashMap<String, String>> {
    let text = fs::read_to_string(dir.join("identify.csv")).expect("the CSV is written");
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().expect("a header").split(',').collect();
    lines
        .map(|line| {
            header
                .iter()
                .zip(line.split(','))
                .map(|(h, v)| ((*h).to_owned(), v.to_owned()))
                .collect()
        })
        .collect()
}

/// The numbers of `columns` in `row`.
fn row_numbers(row: &HashMap<String, String>, columns: &[&str]) -> Vec<f64> {
    columns
        .iter()
        .map(|c| {
            row.get(*c)
                .unwrap_or_else(|| panic!("no column {c} in {row:?}"))
                .parse()
                .expect("a number")
        })
        .collect()
}

/// The live run's row for `trial` and `samples` in `identify.csv` (the first model's):
/// `(c1, c2, c3, L)` and whether it was identified.
fn live_row(dir: &Path, trial: &str, samples: &str) -> ([f64; 4], bool) {
    let rows = csv_rows(dir);
    let row = rows
        .iter()
        .find(|r| r["trial"] == trial && r["samples"] == samples)
        .expect("the row of the trial and sample count");
    let eta = row_numbers(row, &["c1", "c2", "c3", "L"]);
    (
        [eta[0], eta[1], eta[2], eta[3]],
        row["identified"] == "true",
    )
}

#[test]
fn a_saved_log_gives_the_live_estimate() {
    let tmp = TempDir::new("identify-replay");
    let out = tmp.0.join("run");
    let body = identify(&out, &["--pipeline", "mounting"]);
    assert_eq!(body["wire"]["name"], "nitinol-2mm-630");
    assert_eq!(body["by_samples"][1]["samples"], 3);
    for key in ["mean", "std", "relative_error", "mean_abs_relative_error"] {
        assert_eq!(numbers(&body["by_samples"][1][key]).len(), 4, "{key}");
    }
    // The compute times are in timings.json, not in the summary.
    assert!(body["by_samples"][1].get("compute_ms_median").is_none());
    let timings: serde_json::Value =
        serde_json::from_slice(&fs::read(out.join("timings.json")).expect("timings"))
            .expect("JSON");
    let medians = timings["compute_ms_median"].as_array().expect("medians");
    assert!(
        medians
            .iter()
            .any(|m| m["samples"] == 3 && m["compute_ms_median"].as_f64().is_some()),
        "{timings}"
    );
    assert_replay_gives_the_live_estimate(&out);
    let log = out.join("logs").join("nitinol-2mm-630-trial0.jsonl");
    assert_many_independent_records_fit_in_little_memory(&tmp.0, &log);
    // Asking for more records than the log holds is bad input.
    let wrong = ftwire(&[
        "identify",
        "--log",
        &log.to_string_lossy(),
        "--samples",
        "9",
    ]);
    assert_exit(&wrong, 2, "holds only 3 records", "too many samples asked");
    // The sensor's data sheet: the drift modelled, counted from the first record; a tare
    // after a record, a tare time without a sensor, or a sensor file that is not one are bad
    // input.
    let log = log.to_string_lossy();
    let modelled = ftwire(&["identify", "--log", &log, "--sensor", "distorted", "--json"]);
    assert!(
        matches!(modelled.status.code(), Some(0 | 1)),
        "{modelled:?}"
    );
    let late = ftwire(&[
        "identify",
        "--log",
        &log,
        "--sensor",
        "distorted",
        "--tare-time",
        "1e6",
    ]);
    assert_exit(&late, 2, "before the tare", "a tare after the records");
    let alone = ftwire(&["identify", "--log", &log, "--tare-time", "0"]);
    assert_exit(&alone, 2, "--sensor", "--tare-time without --sensor");
    let missing = ftwire(&[
        "identify",
        "--log",
        &log,
        "--sensor",
        "/no/such/sensor.toml",
    ]);
    assert_exit(&missing, 2, "--sensor", "a sensor file that is not there");
}

#[test]
fn a_bad_log_line_or_an_empty_log_is_bad_input() {
    let tmp = TempDir::new("identify-bad");
    let good = r#"{"time": 0.0, "a": [0.01, 0.02, -0.03, -0.1, 0.2, 0.05], "b": {"position": [0.5, 0.1, 0.0], "rotation": [0.0, 0.0, 0.3]}}"#;
    let bad = r#"{"time": 0.1, "a": [0.01, 0.02, -0.03, -0.1, 0.2, 1e999], "b": {"position": [0.5, 0.1, 0.0], "rotation": [0.0, 0.0, 0.3]}}"#;
    let path = tmp.0.join("bad.jsonl");
    fs::write(&path, format!("{good}\n{bad}\n")).expect("writes");
    let out = ftwire(&["identify", "--log", &path.to_string_lossy()]);
    assert_exit(&out, 2, "line 2", "a non-finite value");
    assert_exit(&out, 2, "1e999", "the value is named");

    let garbage = tmp.0.join("garbage.jsonl");
    fs::write(&garbage, format!("{good}\n{good}\n{{\"time\": oops\n")).expect("writes");
    let out = ftwire(&["identify", "--log", &garbage.to_string_lossy()]);
    assert_exit(&out, 2, "line 3", "malformed JSON");

    let empty = tmp.0.join("empty.jsonl");
    fs::write(&empty, "# only a comment\n\n").expect("writes");
    let out = ftwire(&["identify", "--log", &empty.to_string_lossy()]);
    assert_exit(&out, 2, "no record", "an empty log");

    let raw = tmp.0.join("raw.jsonl");
    fs::write(
        &raw,
        r#"{"time": 0.0, "raw": [0.1, 0.2, 0.3, 0.01, 0.02, 0.03], "b": {"position": [0.5, 0.1, 0.0], "rotation": [0.0, 0.0, 0.3]}}"#,
    )
    .expect("writes");
    let out = ftwire(&["identify", "--log", &raw.to_string_lossy()]);
    assert_exit(
        &out,
        2,
        "--calibration",
        "raw records without a calibration",
    );

    let one = tmp.0.join("one.jsonl");
    fs::write(&one, format!("{good}\n")).expect("writes");
    let out = ftwire(&["identify", "--log", &one.to_string_lossy()]);
    assert_exit(&out, 2, "at least", "too few samples");
}

#[test]
fn an_undistorted_sensor_without_gravity_identifies_both_wires() {
    let tmp = TempDir::new("identify-experiment");
    let out = tmp.0.join("run");
    let run = ftwire(&[
        "experiment",
        "identify",
        "--trials",
        "3",
        "--samples",
        "3",
        "--gravity",
        "off",
        "--sensor",
        "undistorted",
        "--pipeline",
        "mounting",
        "--seed",
        "11",
        "--out",
        &out.to_string_lossy(),
    ]);
    assert_success(&run, "experiment identify");
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(stdout.contains("Table I"), "{stdout}");
    let summary: serde_json::Value =
        serde_json::from_slice(&fs::read(out.join("summary.json")).expect("a summary"))
            .expect("JSON");
    assert_eq!(summary["header"]["seed"], 11);
    let body = &summary["summary"];
    assert_eq!(body["pipeline"], "mounting");
    assert!(
        body["calibration"].is_null(),
        "no weights: {}",
        body["calibration"]
    );
    let wires = body["wires"].as_array().expect("a list of wires");
    let names: Vec<&str> = wires
        .iter()
        .map(|w| w["wire"]["name"].as_str().expect("a name"))
        .collect();
    assert_eq!(names, ["nitinol-2mm-630", "nitinol-3mm-820"]);
    assert_eq!(
        body["wire"], wires[0]["wire"],
        "the first wire at the top level"
    );
    for wire in wires {
        let row = &wire["by_samples"][0];
        assert_eq!(row["samples"], 3);
        assert_eq!(row["estimated"], 3);
        // The measured floor is 0.1–0.5 % (the simulator's discretisation, the tare and the
        // noise); twice the worst parameter's is allowed here, for any seed.
        for (name, error) in ["c1", "c2", "c3", "L"]
            .iter()
            .zip(numbers(&row["mean_abs_relative_error"]))
        {
            assert!(error < 0.01, "{}: {name} {error}", wire["wire"]["name"]);
        }
        let identified = row["identified"].as_u64().expect("a count");
        assert!(
            identified >= 1,
            "{}: {identified} of 3",
            wire["wire"]["name"]
        );
    }
    let csv = fs::read_to_string(out.join("identify.csv")).expect("the CSV");
    assert_eq!(csv.lines().count(), 1 + 2 * 3, "a row per wire and trial");
    for file in [
        "timings.json",
        "error_vs_samples_nitinol-3mm-820.png",
        "error_vs_samples_nitinol-3mm-820.svg",
        "time_vs_samples.png",
    ] {
        assert!(out.join(file).is_file(), "{file}");
    }
    assert!(!out.join("logs").exists(), "logs only with --save-log");
}

#[test]
fn bad_options_are_bad_input() {
    let tmp = TempDir::new("identify-bad-options");
    let out = tmp.0.join("run").to_string_lossy().into_owned();
    let cases: [(&[&str], &str); 11] = [
        (&["--wire", "copper"], "unknown wire"),
        (&["--gain-error", "100"], "--gain-error 100"),
        (&["--pose-noise-deg", "0"], "--pose-noise-deg 0"),
        (&["--pose-noise-mm", "-0.1"], "--pose-noise-mm -0.1"),
        (&["--rest-samples", "99"], "--rest-samples 99: at least 100"),
        (&["--samples", "1"], "at least two samples"),
        (&["--trials", "0"], "--trials"),
        (&["--torsion-ratio", "-1"], "--torsion-ratio"),
        // The undistorted sensor is what a perfect calibration gives: not learnt on top.
        (&["--sensor", "undistorted"], "--pipeline mounting"),
        (
            &["--pipeline", "mounting", "--calibration", "weights.json"],
            "--pipeline calibrated",
        ),
        (
            &["--calibration", "/no/such/weights.json", "--trials", "1"],
            "--calibration /no/such/weights.json",
        ),
    ];
    for (extra, needle) in cases {
        let mut args = vec!["experiment", "identify", "--out", &out];
        args.extend_from_slice(extra);
        assert_exit(&ftwire(&args), 2, needle, needle);
    }
    let missing = tmp.0.join("no").join("such").join("run");
    let args = [
        "experiment",
        "identify",
        "--samples",
        "2",
        "--trials",
        "1",
        "--out",
        &missing.to_string_lossy(),
    ];
    assert_exit(
        &ftwire(&args),
        2,
        "does not exist",
        "a missing --out parent",
    );
}

fn text(path: &Path) -> &str {
    path.to_str().expect("a UTF-8 path")
}

/// Runs `experiment identify` on the 2 mm wire, one trial, 2 and 3 samples, seed 5, gravity
/// off, with the log saved and the samples' errors independent (`--no-bias-model`, as the log
/// command treats them), plus `extra`; returns the summary's body.
fn identify(out: &Path, extra: &[&str]) -> serde_json::Value {
    let mut args = vec![
        "experiment",
        "identify",
        "--wire",
        "nitinol-2mm-630",
        "--trials",
        "1",
        "--samples",
        "2,3",
        "--gravity",
        "off",
        "--seed",
        "5",
        "--save-log",
        "--no-bias-model",
        "--out",
        text(out),
    ];
    args.extend_from_slice(extra);
    assert_success(&ftwire(&args), "experiment identify");
    let summary: serde_json::Value =
        serde_json::from_slice(&fs::read(out.join("summary.json")).expect("a summary"))
            .expect("JSON");
    summary["summary"].clone()
}

/// 1500 independent records (the log's three, again and again) identify under a 700 MB limit
/// of address space: the fit's memory is linear in the records. A dense `6N × 6N` covariance
/// of them would take 650 MB alone.
fn assert_many_independent_records_fit_in_little_memory(dir: &Path, log: &Path) {
    let records: Vec<serde_json::Value> = fs::read_to_string(log)
        .expect("the log")
        .lines()
        .map(|l| serde_json::from_str(l).expect("a record"))
        .collect();
    let many = dir.join("many.jsonl");
    let text_of: String = (0..1500_u16)
        .map(|k| {
            let mut r = records[usize::from(k) % records.len()].clone();
            r["time"] = serde_json::json!(f64::from(k));
            format!("{r}\n")
        })
        .collect();
    fs::write(&many, text_of).expect("written");
    let command =
        "ulimit -v 700000 && exec \"$0\" identify --log \"$1\" --json --seed 1 > /dev/null";
    let done = std::process::Command::new("sh")
        .args(["-c", command, env!("CARGO_BIN_EXE_ftwire"), text(&many)])
        .output()
        .expect("sh runs");
    // 0 identified or 1 not identified; never an abort (134) or a kill for memory.
    assert!(
        matches!(done.status.code(), Some(0 | 1)),
        "{:?}: {}",
        done.status,
        String::from_utf8_lossy(&done.stderr)
    );
}

/// The `a` of every record of a trial's log.
fn logged_a(out: &Path) -> Vec<Vec<f64>> {
    let log = out.join("logs").join("nitinol-2mm-630-trial0.jsonl");
    fs::read_to_string(log)
        .expect("the log")
        .lines()
        .map(|line| numbers(&serde_json::from_str::<serde_json::Value>(line).expect("JSON")["a"]))
        .collect()
}

/// `ftwire identify --log` on the 3-sample log of trial 0 in the results folder `out` (seed
/// 5) gives the live run's estimate and flag.
fn assert_replay_gives_the_live_estimate(out: &Path) {
    let log = out.join("logs").join("nitinol-2mm-630-trial0.jsonl");
    assert_eq!(
        fs::read_to_string(&log).expect("the log").lines().count(),
        3,
        "one record per sample"
    );
    let (live, identified) = live_row(out, "0", "3");
    let replay = ftwire(&[
        "identify",
        "--log",
        text(&log),
        "--samples",
        "3",
        "--seed",
        "5",
        // The simulated rig's pose noise, which `experiment identify` models.
        "--pose-noise-deg",
        "0.005",
        "--pose-noise-mm",
        "0.01",
        "--json",
    ]);
    // Exit 0 when identified, 1 when the estimate is flagged; either way it is printed.
    let expected_code = if identified { 0 } else { 1 };
    assert_eq!(
        replay.status.code(),
        Some(expected_code),
        "{}",
        String::from_utf8_lossy(&replay.stderr)
    );
    let answer = json(&replay);
    assert_eq!(answer["identified"], identified);
    let mut logged = numbers(&answer["c"]);
    logged.push(answer["length"].as_f64().expect("a length"));
    for (name, (l, r)) in ["c1", "c2", "c3", "L"].iter().zip(live.iter().zip(&logged)) {
        // The log holds the samples at full precision but the pose as a rotation vector: a
        // rounding-level change, which the fit does not amplify.
        assert!((l - r).abs() <= 1e-6 * l.abs(), "{name}: live {l}, log {r}");
    }
    // The uncertainty: a 4 × 4 covariance whose diagonal is the standard deviations, and a
    // 95 % interval around each value.
    let covariance = answer["covariance"].as_array().expect("a covariance");
    let intervals = answer["interval95"].as_array().expect("intervals");
    assert_eq!((covariance.len(), intervals.len()), (4, 4));
    let mut std = numbers(&answer["c_std"]);
    std.push(answer["length_std"].as_f64().expect("a length std"));
    for (i, (row, interval)) in covariance.iter().zip(intervals).enumerate() {
        let variance = numbers(row)[i];
        assert!(
            (variance.sqrt() - std[i]).abs() <= 1e-9 * std[i],
            "{i}: {variance}"
        );
        let [low, high] = numbers(interval)[..] else {
            panic!("{interval}")
        };
        assert!(
            low < logged[i] && logged[i] < high,
            "{low} {} {high}",
            logged[i]
        );
    }
}

#[test]
fn given_weights_are_used_recorded_and_replayed() {
    let tmp = TempDir::new("identify-given");
    let weights = tiny_calibration(&tmp.0);

    let calibrated = tmp.0.join("calibrated");
    let body = identify(&calibrated, &["--calibration", text(&weights)]);
    assert_eq!(body["pipeline"], "calibrated");
    assert_eq!(body["calibration"], text(&weights));
    assert_eq!(body["by_samples"][1]["samples"], 3);
    for key in ["mean", "std", "relative_error", "mean_abs_relative_error"] {
        assert_eq!(numbers(&body["by_samples"][1][key]).len(), 4, "{key}");
    }
    assert!(body["by_samples"][1]["mean_abs_relative_error_identified"].is_array());
    assert!(
        !calibrated.join("calibration.json").exists(),
        "given weights are not cached again"
    );
    let timings: serde_json::Value =
        serde_json::from_slice(&fs::read(calibrated.join("timings.json")).expect("timings"))
            .expect("JSON");
    assert_eq!(timings["calibration_s"].as_f64(), Some(0.0));
    assert_eq!(timings["identifications"].as_array().map(Vec::len), Some(2));

    // The same seed reads the same raw samples: the two pipelines map them differently.
    let mounting = tmp.0.join("mounting");
    let body = identify(&mounting, &["--pipeline", "mounting"]);
    assert_eq!(body["pipeline"], "mounting");
    assert!(body["calibration"].is_null());
    let (learnt, mounted) = (logged_a(&calibrated), logged_a(&mounting));
    assert_eq!(learnt.len(), 3);
    assert_eq!(mounted.len(), 3);
    for (l, m) in learnt.iter().zip(&mounted) {
        let difference = l
            .iter()
            .zip(m)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        let size = m.iter().map(|y| y.abs()).fold(0.0, f64::max);
        assert!(
            difference > 1e-6 * size,
            "the calibration is applied: {l:?} against {m:?}"
        );
        // A calibration learnt on 40 samples is rough but not wild: within 20 % of the
        // mounting pipeline's `ã` (whose own error is about 1 %).
        assert!(difference < 0.2 * size, "{l:?} against {m:?}");
    }

    // The log holds the calibrated `ã`: replaying it gives the live estimate.
    assert_replay_gives_the_live_estimate(&calibrated);
}

/// With gravity on, the loaded model identifies the wire's weight too; both models are
/// reported from the same data, and `ftwire identify --log --gravity` replays the live loaded
/// estimate, linear density included.
#[test]
fn the_loaded_model_identifies_the_weight_and_its_log_replays() {
    let tmp = TempDir::new("identify-loaded");
    let out = tmp.0.join("run");
    let args = [
        "experiment",
        "identify",
        "--wire",
        "nitinol-3mm-820",
        "--trials",
        "1",
        "--samples",
        "3",
        "--gravity",
        "on",
        "--pipeline",
        "mounting",
        "--seed",
        "5",
        "--save-log",
        "--no-bias-model",
        "--out",
        text(&out),
    ];
    assert_success(&ftwire(&args), "experiment identify, gravity on");
    let summary: serde_json::Value =
        serde_json::from_slice(&fs::read(out.join("summary.json")).expect("a summary"))
            .expect("JSON");
    let body = &summary["summary"];
    assert_eq!(body["model"], "loaded", "the default with gravity on");
    let models: Vec<&str> = body["by_model"]
        .as_array()
        .expect("by_model")
        .iter()
        .map(|m| m["model"].as_str().expect("a name"))
        .collect();
    assert_eq!(models, ["loaded", "kirchhoff"]);
    let truth = body["wire"]["linear_density"].as_f64().expect("true λ");
    assert!((truth - 6450.0 * std::f64::consts::PI * 0.0015 * 0.0015).abs() < 1e-12);
    let density = &body["by_samples"][0]["linear_density"];
    assert!(density["mean"].as_f64().is_some(), "{density}");
    assert!(body["by_model"][1]["wires"][0]["by_samples"][0]["linear_density"].is_null());

    // The replay: c, L and λ as live.
    let rows = csv_rows(&out);
    let row = rows
        .iter()
        .find(|r| r["model"] == "loaded")
        .expect("the loaded row");
    let live = row_numbers(row, &["c1", "c2", "c3", "L", "linear_density"]);
    let log = out.join("logs").join("nitinol-3mm-820-trial0.jsonl");
    let replay = ftwire(&[
        "identify",
        "--log",
        text(&log),
        "--samples",
        "3",
        "--seed",
        "5",
        "--gravity",
        "0,0,-9.81",
        // The simulated rig's pose noise, which `experiment identify` models.
        "--pose-noise-deg",
        "0.005",
        "--pose-noise-mm",
        "0.01",
        "--json",
    ]);
    let answer = json(&replay);
    let mut logged = numbers(&answer["c"]);
    logged.push(answer["length"].as_f64().expect("a length"));
    logged.push(answer["linear_density"].as_f64().expect("λ"));
    for (name, (l, r)) in ["c1", "c2", "c3", "L", "λ"]
        .iter()
        .zip(live.iter().zip(&logged))
    {
        assert!((l - r).abs() <= 1e-6 * l.abs(), "{name}: live {l}, log {r}");
    }
    // A zero gravity names the option.
    let zero = ftwire(&["identify", "--log", text(&log), "--gravity", "0,0,0"]);
    assert_exit(&zero, 2, "--gravity", "a zero gravity");
}

/// `ftwire identify --help`'s example runs as printed, in a fresh folder, and identifies.
#[test]
fn the_help_example_runs_as_printed() {
    let help = ftwire(&["identify", "--help"]);
    assert_success(&help, "identify --help");
    let text = String::from_utf8(help.stdout).expect("UTF-8");
    let lines: Vec<&str> = text
        .lines()
        .map(str::trim)
        .filter(|l| l.starts_with("ftwire "))
        .collect();
    assert_eq!(lines.len(), 2, "{text}");
    let tmp = cli_support::TempDir::new("identify-help-example");
    for line in lines {
        let args: Vec<&str> = line.split_whitespace().skip(1).collect();
        let output = std::process::Command::new(env!("CARGO_BIN_EXE_ftwire"))
            .args(&args)
            .current_dir(&tmp.0)
            .output()
            .expect("the binary runs");
        assert_success(&output, line);
    }
}
