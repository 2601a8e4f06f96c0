//! `ftwire shape --log` on a log that `ftwire experiment shape --save-log` wrote gives the same
//! answer as the live run; bad and empty logs, and raw readings without a calibration, are bad
//! input (exit 2) naming the line. With `--out DIR` it writes `shapes.jsonl` and a summary of
//! exactly its keys; bad input writes nothing; a record without a shape is exit 1 with the
//! folder written.

mod cli_support;

use std::collections::BTreeSet;
use std::path::Path;

use cli_support::{TempDir, assert_exit, assert_success, ftwire, tiny_calibration};

fn text(path: &Path) -> &str {
    path.to_str().expect("a UTF-8 path")
}

#[test]
fn a_saved_log_gives_the_live_runs_answer() -> Result<(), Box<dyn std::error::Error>> {
    let tmp = TempDir::new("shape-log");
    let weights = tiny_calibration(&tmp.0);
    let live = tmp.0.join("live");
    let output = ftwire(&[
        "experiment",
        "shape",
        "--wire",
        "nitinol-2mm-630",
        "--configs",
        "2",
        "--gravity",
        "off",
        "--save-log",
        "--calibration",
        text(&weights),
        "--out",
        text(&live),
    ]);
    assert_success(&output, "experiment shape");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(live.join("summary.json"))?)?;
    let wires = summary["summary"]["wires"].as_array().ok_or("wires")?;
    assert_eq!(wires.len(), 1);
    for key in ["mean_mm", "std_mm", "marker_mean_mm", "fused_mean_mm"] {
        assert!(wires[0][key].as_f64().is_some_and(f64::is_finite), "{key}");
    }
    assert_eq!(wires[0]["name"], "nitinol-2mm-630");
    let csv = std::fs::read_to_string(live.join("configs.csv"))?;
    let rows: Vec<Vec<&str>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    assert_eq!(
        rows.len(),
        wires[0]["configs"].as_u64().ok_or("configs")? as usize
    );

    let log = live.join("logs").join("nitinol-2mm-630.jsonl");
    let output = ftwire(&[
        "shape",
        "--log",
        text(&log),
        "--wire",
        "nitinol-2mm-630",
        "--calibration",
        text(&weights),
        "--json",
    ]);
    assert_success(&output, "shape --log");
    let answers: Vec<serde_json::Value> = String::from_utf8(output.stdout)?
        .lines()
        .map(serde_json::from_str)
        .collect::<Result<_, _>>()?;
    assert_eq!(answers.len(), rows.len());
    for (answer, row) in answers.iter().zip(&rows) {
        let a = cli_support::numbers(&answer["a"]);
        for (i, value) in a.iter().enumerate() {
            let live: f64 = row[7 + i].parse()?;
            assert!(
                (value - live).abs() <= 1e-12 * live.abs().max(1e-9),
                "a[{i}]"
            );
        }
        let live_marker: f64 = row[4].parse()?;
        let marker = answer["marker_mean_mm"].as_f64().ok_or("marker_mean_mm")?;
        assert!(
            (marker - live_marker).abs() < 1e-9,
            "{marker} vs {live_marker}"
        );
        assert_eq!(answer["points"].as_array().map(Vec::len), Some(100));
    }

    // Raw readings need the calibration.
    let output = ftwire(&["shape", "--log", text(&log), "--wire", "nitinol-2mm-630"]);
    assert_exit(&output, 2, "--calibration", "raw without calibration");
    Ok(())
}

#[test]
fn bad_and_empty_logs_are_bad_input() -> Result<(), Box<dyn std::error::Error>> {
    let tmp = TempDir::new("shape-bad");
    let good = r#"{"time": 0.0, "a": [0, 0.01, 0.01, -0.05, 0.03, 0], "b": {"position": [0.5, 0.1, 0], "rotation": [0, 0, 0.4]}}"#;
    let bad = good.replace("-0.05", "1e999");
    let cases = [
        ("nonfinite.jsonl", format!("{good}\n{bad}\n"), "line 2"),
        ("garbage.jsonl", format!("{good}\n{{not json\n"), "line 2"),
        ("empty.jsonl", "# nothing\n\n".to_owned(), "no record"),
    ];
    for (name, contents, needle) in cases {
        let path = tmp.0.join(name);
        std::fs::write(&path, contents)?;
        let output = ftwire(&["shape", "--log", text(&path), "--wire", "nitinol-2mm-630"]);
        assert_exit(&output, 2, needle, name);
    }
    let path = tmp.0.join("good.jsonl");
    std::fs::write(&path, format!("{good}\n"))?;
    let output = ftwire(&["shape", "--log", text(&path), "--wire", "nitinol-2mm-630"]);
    assert_success(&output, "a good log with a");
    assert!(String::from_utf8(output.stdout)?.starts_with("line 1 t = 0.000 s: "));
    Ok(())
}

#[test]
fn too_short_a_rest_is_bad_input() {
    let out = std::env::temp_dir().join(format!("ftwire-shape-rest-{}", std::process::id()));
    let output = ftwire(&[
        "experiment",
        "shape",
        "--rest-samples",
        "10",
        "--out",
        out.to_str().expect("UTF-8"),
    ]);
    assert_exit(
        &output,
        2,
        "--rest-samples 10: at least 100",
        "a 10-sample rest",
    );
    assert!(!out.exists(), "nothing written on bad input");
}

/// Two records with `a` (one with markers, no `b`) after a comment, and one the model cannot
/// solve when `failing`.
fn small_log(dir: &Path, failing: bool) -> std::path::PathBuf {
    let a = r#""a": [0.0005, 0.002, -0.001, -0.03, 0.015, 0.005]"#;
    let markers = r#""markers": [[0, 0, 0], [0.1, 0.01, 0], null, [0.3, 0.02, 0], [0.6, 0, 0]]"#;
    let mut text =
        format!("# a rig\n{{\"time\": 0.0, {a}, {markers}}}\n\n{{\"time\": 0.1, {a}}}\n");
    if failing {
        text.push_str(r#"{"time": 0.2, "a": [0.1, 0, 0, -0.2, 0, 0]}"#);
        text.push('\n');
    }
    let path = dir.join(if failing {
        "failing.jsonl"
    } else {
        "rig.jsonl"
    });
    std::fs::write(&path, text).expect("writes the log");
    path
}

fn keys(value: &serde_json::Value) -> BTreeSet<String> {
    value
        .as_object()
        .map(|o| o.keys().cloned().collect())
        .unwrap_or_default()
}

#[test]
fn out_writes_the_shapes_and_a_summary_of_exactly_its_keys()
-> Result<(), Box<dyn std::error::Error>> {
    let tmp = TempDir::new("shape-log-out");
    let log = small_log(&tmp.0, false);
    let out = tmp.0.join("shapes");
    let output = ftwire(&[
        "shape",
        "--log",
        text(&log),
        "--wire",
        "nitinol-2mm-630",
        "--out",
        text(&out),
        "--points",
        "3",
        "--json",
    ]);
    assert_success(&output, "shape --log --out");
    let printed = cli_support::json(&output);
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json"))?)?;
    let body = &summary["summary"];
    let expected: BTreeSet<String> = ["records", "not_stable", "not_confident", "marker_mean_mm"]
        .map(String::from)
        .into();
    assert_eq!(keys(body), expected);
    assert_eq!(&printed, body, "--json prints the summary");
    assert_eq!(body["records"], 2);
    assert!(body["marker_mean_mm"].as_f64().is_some_and(f64::is_finite));
    assert_eq!(summary["header"]["command"], "shape");
    for file in ["report.md", "report.html", "timings.json"] {
        assert!(out.join(file).is_file(), "{file}");
    }
    let lines: Vec<serde_json::Value> = std::fs::read_to_string(out.join("shapes.jsonl"))?
        .lines()
        .map(serde_json::from_str)
        .collect::<Result<_, _>>()?;
    assert_eq!(lines.len(), 2);
    let line_keys: BTreeSet<String> = [
        "line",
        "time",
        "a",
        "points",
        "stable",
        "confident",
        "confidence",
    ]
    .map(String::from)
    .into();
    for (line, number) in lines.iter().zip([2, 4]) {
        // The first record has inner markers: their mean distance too.
        let mut expected = line_keys.clone();
        if number == 2 {
            expected.insert("marker_mean_mm".to_owned());
        }
        assert_eq!(keys(line), expected);
        assert_eq!(line["line"], number);
        assert_eq!(line["points"].as_array().map(Vec::len), Some(3));
    }

    // Text: the summary and where the results are.
    let output = ftwire(&[
        "shape",
        "--log",
        text(&log),
        "--wire",
        "nitinol-2mm-630",
        "--out",
        text(&out),
    ]);
    assert_success(&output, "shape --log --out, again");
    let stdout = String::from_utf8(output.stdout)?;
    assert!(
        stdout.starts_with("2 records: 0 not stable, 0 not confident"),
        "{stdout}"
    );
    assert!(stdout.contains(text(&out)), "{stdout}");
    Ok(())
}

#[test]
fn bad_input_with_out_is_exit_2_and_writes_nothing() {
    let tmp = TempDir::new("shape-log-out-bad");
    let log = small_log(&tmp.0, false);
    let out = tmp.0.join("shapes");
    let raw = tmp.0.join("raw.jsonl");
    std::fs::write(
        &raw,
        "# raw\n{\"time\": 0.5, \"raw\": [0.1, 0.2, -0.3, 0.01, 0.0, 0.02]}\n",
    )
    .expect("writes");
    let tool = tmp.0.join("tool.toml");
    std::fs::write(
        &tool,
        "tool_mass = 0.3\ntool_centre_of_mass = [0, 0, 0.05]\n",
    )
    .expect("w");
    let base = ["shape", "--wire", "nitinol-2mm-630"];
    let cases: [(&[&str], &str); 7] = [
        (&["--log", text(&raw), "--out", text(&out)], "--mounting"),
        (
            &["--log", text(&log), "--sensor", "nope", "--out", text(&out)],
            "--sensor",
        ),
        (
            &[
                "--log",
                text(&log),
                "--gain-error",
                "0.1",
                "--out",
                text(&out),
            ],
            "--sensor",
        ),
        (
            &[
                "--log",
                text(&log),
                "--sensor",
                "undistorted",
                "--gain-error",
                "100",
                "--out",
                text(&out),
            ],
            "--gain-error 100",
        ),
        (
            &[
                "--log",
                text(&raw),
                "--mounting",
                text(&tool),
                "--out",
                text(&out),
            ],
            "line 2 (time 0.5) has a raw F/T reading but no `gravity`",
        ),
        (
            &["--log", text(&log), "--out", text(&out), "--points", "1"],
            "--points",
        ),
        (&["--log", text(&log), "--force"], "--out"),
    ];
    for (extra, needle) in cases {
        let output = ftwire(&[&base[..], extra].concat());
        assert_exit(&output, 2, needle, &format!("{extra:?}"));
        assert!(!out.exists(), "{extra:?}: nothing written");
    }
}

#[test]
fn a_record_without_a_shape_is_exit_1_with_the_folder_written() {
    let tmp = TempDir::new("shape-log-out-fail");
    let log = small_log(&tmp.0, true);
    let out = tmp.0.join("shapes");
    let output = ftwire(&[
        "shape",
        "--log",
        text(&log),
        "--wire",
        "nitinol-2mm-630",
        "--out",
        text(&out),
    ]);
    assert_exit(
        &output,
        1,
        "no shape for 1 of 3 records",
        "a record outside A",
    );
    let shapes = std::fs::read_to_string(out.join("shapes.jsonl")).expect("written");
    let last: serde_json::Value =
        serde_json::from_str(shapes.lines().last().expect("3 lines")).expect("JSON");
    assert_eq!(last["line"], 5);
    assert!(last["error"].is_string());
    assert_eq!(last["points"].as_array().map(Vec::len), Some(0));
    assert!(out.join("summary.json").is_file());
}

/// A run never deletes its own input: a `--wire` file inside `--out` is refused (exit 2) and
/// stays, for `shape --log` and `calibrate --log` alike.
#[test]
fn inputs_inside_out_are_refused_and_kept() {
    let tmp = TempDir::new("shape-log-inputs-in-out");
    let log = small_log(&tmp.0, false);
    let out = tmp.0.join("outA");
    let first = ftwire(&[
        "shape",
        "--log",
        text(&log),
        "--wire",
        "nitinol-2mm-630",
        "--out",
        text(&out),
    ]);
    assert_success(&first, "a first run");
    let wire = out.join("wire.toml");
    std::fs::write(
        &wire,
        "name = \"w\"\nc = [0.042, 0.055, 0.055]\nlength = 0.63\nradius = 0.001\ndensity = 6450.0\n",
    )
    .expect("a wire file");
    let output = ftwire(&[
        "shape",
        "--log",
        text(&log),
        "--wire",
        text(&wire),
        "--out",
        text(&out),
    ]);
    assert_exit(&output, 2, "holds the run's input", "shape --wire");
    assert!(wire.is_file(), "shape: the input is kept");
    let calibrate = ftwire(&[
        "calibrate",
        "--log",
        text(&log),
        "--wire",
        text(&wire),
        "--out",
        text(&out),
    ]);
    assert_exit(&calibrate, 2, "holds the run's input", "calibrate --wire");
    assert!(wire.is_file(), "calibrate: the input is kept");
    // Every other file input, each alone inside --out, in either spelling of its option.
    let inner_log = out.join("rig.jsonl");
    std::fs::copy(&log, &inner_log).expect("a copy of the log");
    let sensor = out.join("sensor.toml");
    std::fs::write(
        &sensor,
        "noise_std = [0.05, 0.05, 0.05, 0.002, 0.002, 0.002]\n",
    )
    .expect("a sensor file");
    let mounting = out.join("mounting.toml");
    std::fs::write(&mounting, "clamp_position_in_sensor = [0.0, 0.0, 0.11]\n")
        .expect("a mounting file");
    let wire_preset = ["--wire", "nitinol-2mm-630"];
    let cases: [(&str, Vec<String>); 4] = [
        ("shape", vec!["--log".into(), text(&inner_log).into()]),
        ("shape", vec![format!("--sensor={}", text(&sensor))]),
        ("shape", vec!["--mounting".into(), text(&mounting).into()]),
        (
            "calibrate",
            vec!["--mounting".into(), text(&mounting).into()],
        ),
    ];
    for (command, input) in &cases {
        let mut args = vec![*command];
        if !input.iter().any(|a| a == "--log") {
            args.extend(["--log", text(&log)]);
        }
        args.extend(input.iter().map(String::as_str));
        args.extend(wire_preset);
        args.extend(["--out", text(&out)]);
        let output = ftwire(&args);
        assert_exit(
            &output,
            2,
            "holds the run's input",
            &format!("{command} {input:?}"),
        );
    }
    for kept in [&inner_log, &sensor, &mounting] {
        assert!(kept.is_file(), "{} is kept", kept.display());
    }
}
