//! `ftwire shape --log` on a log that `ftwire experiment shape --save-log` wrote gives the same
//! answer as the live run; bad and empty logs, and raw readings without a calibration, are bad
//! input (exit 2) naming the line.

mod cli_support;

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
        let a = cli_support::numbers(&answer["a_tilde"]);
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
        assert_eq!(answer["points"].as_array().map(Vec::len), Some(64));
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
    assert!(String::from_utf8(output.stdout)?.contains("record 0"));
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
