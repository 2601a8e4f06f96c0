//! `ftwire solve` end to end: the built binary, its JSON, its batch mode and its exit codes.
#![allow(missing_docs)]

mod cli_support;

use std::io::{BufRead, BufReader, Write};
use std::process::{Command, Stdio};
use std::sync::mpsc;
use std::time::Duration;

use cli_support::{assert_exit, assert_success, ftwire_with_input as ftwire, json, numbers};

const SINGLE: [&str; 7] = [
    "solve",
    "--c",
    "0.214,0.278,0.278",
    "--length",
    "0.82",
    "--a",
    "0,0.2,0.1,-0.5,0.3,0",
];

#[test]
fn json_has_the_documented_keys_and_shapes() {
    let mut args = SINGLE.to_vec();
    args.extend(["--json", "--nodes", "10"]);
    let out = ftwire(&args, None);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
    let position = v["tip"]["position"].as_array().expect("position");
    assert_eq!(position.len(), 3);
    let rotation = v["tip"]["rotation"].as_array().expect("rotation");
    assert_eq!(rotation.len(), 3);
    assert!(
        rotation
            .iter()
            .all(|r| r.as_array().map(Vec::len) == Some(3))
    );
    let j = v["jacobian"].as_array().expect("jacobian");
    assert_eq!(j.len(), 6);
    assert!(j.iter().all(|r| r.as_array().map(Vec::len) == Some(6)));
    assert!(v["stable"].is_boolean() && v["self_intersecting"].is_boolean());
    let shape = v["shape"].as_array().expect("shape");
    assert_eq!(shape.len(), 10);
    assert_eq!(shape[0], serde_json::json!([0.0, 0.0, 0.0]));
    // The last node is the tip, and the rotation is orthonormal (row-major).
    assert_eq!(&shape[9], &v["tip"]["position"]);
    let r: Vec<Vec<f64>> = serde_json::from_value(v["tip"]["rotation"].clone()).expect("3x3");
    for i in 0..3 {
        for k in 0..3 {
            let dot: f64 = (0..3).map(|m| r[i][m] * r[k][m]).sum();
            assert!((dot - f64::from(u8::from(i == k))).abs() < 1e-12);
        }
    }
    // Matches the library.
    let rod = ftwire_rod::Rod::new(
        ftwire_rod::WireParams::new([0.214, 0.278, 0.278], 0.82, 0.001).expect("valid"),
    );
    let s = rod
        .solve(&nalgebra::Vector6::new(0.0, 0.2, 0.1, -0.5, 0.3, 0.0), 10)
        .expect("solves");
    let tip = s.jacobian.tip.translation.vector;
    for k in 0..3 {
        assert!((position[k].as_f64().expect("number") - tip[k]).abs() < 1e-15);
    }
    assert_eq!(v["stable"].as_bool(), Some(s.jacobian.stability.stable));
    let det_j_min = v["det_j_min"].as_f64().expect("det_j_min");
    assert!(
        det_j_min > 0.0,
        "a stable configuration keeps det J away from 0"
    );
    assert!((det_j_min - s.jacobian.stability.det_j_min).abs() <= 1e-12 * det_j_min);
    assert!((j[3][4].as_f64().expect("number") - s.jacobian.jacobian[(3, 4)]).abs() < 1e-12);
}

#[test]
fn human_summary_without_json() {
    let out = ftwire(&SINGLE, None);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("tip position") && text.contains("stable:"),
        "{text}"
    );
}

#[test]
fn bad_arguments_exit_2_with_a_clear_message() {
    let base = |extra: &[&'static str]| {
        let mut v = vec![
            "solve",
            "--c",
            "1,1,1",
            "--length",
            "1",
            "--a",
            "0,0,1,0,0,0",
        ];
        v.extend_from_slice(extra);
        v
    };
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            vec!["solve", "--c", "1,1", "--length", "1", "--a", "0,0,1,0,0,0"],
            "expected 3 comma-separated finite numbers",
        ),
        (
            vec![
                "solve",
                "--c",
                "1,1,1",
                "--length",
                "-1",
                "--a",
                "0,0,1,0,0,0",
            ],
            "length",
        ),
        (
            vec![
                "solve",
                "--c",
                "1,0,1",
                "--length",
                "1",
                "--a",
                "0,0,1,0,0,0",
            ],
            "c2",
        ),
        (
            vec!["solve", "--c", "1,1,1", "--length", "1", "--a", "0,0,1,0,0"],
            "expected 6 comma-separated finite numbers",
        ),
        (
            vec![
                "solve",
                "--c",
                "1,1,1",
                "--length",
                "1",
                "--a",
                "1,0,0,-1,0,0",
            ],
            "outside A",
        ),
        (
            vec![
                "solve",
                "--c",
                "1,1,1",
                "--length",
                "1",
                "--a",
                "0,0,NaN,0,0,0",
            ],
            "'--a <A1,..,A6>'",
        ),
        (
            base(&["--nodes", "1"]),
            "--nodes 1: at least 2 and at most 1000000",
        ),
        (
            base(&["--nodes", "-1"]),
            "--nodes \"-1\": not a whole number",
        ),
        (base(&["--radius", "0"]), "radius"),
        (base(&["--radius", "inf"]), "'--radius <R>'"),
        (base(&["--batch", "-"]), "cannot be used with"),
        (
            vec![
                "solve",
                "--c",
                "1,x,1",
                "--length",
                "1",
                "--a",
                "0,0,1,0,0,0",
            ],
            "invalid",
        ),
        (vec!["solve", "--length", "1", "--a", "0,0,1,0,0,0"], "--c"),
        (
            vec!["solve", "--batch", "/nonexistent/batch.jsonl"],
            "cannot open",
        ),
    ];
    for (args, needle) in cases {
        let out = ftwire(&args, None);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(
            stderr.contains(needle),
            "{args:?}: expected {needle:?} in {stderr}"
        );
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    }
}

#[test]
fn batch_goes_on_past_bad_lines() {
    let input = [
        r#"{"c":[0.042,0.055,0.055],"length":0.63,"a":[0,0,0.01,0,0,0]}"#,
        r#"{"c":[0.042,0.055,0.055],"length":0.63,"a":[1,0,0,0,0,0]}"#,
        "not json",
        "",
        r#"{"c":[0.042,0.055],"length":0.63,"a":[0,0,0.01,0,0,0]}"#,
        r#"{"c":[0.042,0.055,0.055],"length":0.63,"a":[0,0.01,0.01,-0.1,0,0],"nodes":5,"radius":0.002}"#,
        r#"{"c":[0.042,0.055,0.055],"length":0.63,"a":[0,0,0.01,0,0,0],"colour":"red"}"#,
    ]
    .join("\n");
    let out = ftwire(&["solve", "--batch", "-"], Some(&input));
    // Bad lines make the batch's exit code 2 at the end of the input.
    assert_exit(&out, 2, "4 line(s) of the batch were bad input", "batch");
    let lines: Vec<serde_json::Value> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).expect("each output line is JSON"))
        .collect();
    assert_eq!(lines.len(), 6, "one output per non-empty input line");
    assert_eq!(lines[0]["shape"].as_array().map(Vec::len), Some(64));
    assert!(
        lines[1]["error"]
            .as_str()
            .expect("error")
            .contains("outside A")
    );
    assert!(
        lines[2]["error"]
            .as_str()
            .expect("error")
            .contains("line 3")
    );
    assert_eq!(lines[2]["line"], 3);
    assert_eq!(lines[2]["kind"], "bad_input");
    assert_eq!(lines[5]["line"], 7, "empty lines count");
    assert!(
        lines[3]["error"]
            .as_str()
            .expect("error")
            .contains("c must have 3")
    );
    assert_eq!(lines[4]["shape"].as_array().map(Vec::len), Some(5));
    assert!(
        lines[5]["error"]
            .as_str()
            .expect("error")
            .contains("colour")
    );
}

#[test]
fn batch_from_a_file_matches_single_solves() {
    let dir = std::env::temp_dir().join(format!("ftwire-solve-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("batch.jsonl");
    std::fs::write(
        &path,
        r#"{"c":[0.214,0.278,0.278],"length":0.82,"a":[0,0.2,0.1,-0.5,0.3,0]}"#,
    )
    .expect("writes");
    let batch = ftwire(&["solve", "--batch", path.to_str().expect("utf-8")], None);
    let mut args = SINGLE.to_vec();
    args.push("--json");
    let single = ftwire(&args, None);
    assert!(batch.status.success() && single.status.success());
    assert_eq!(batch.stdout, single.stdout);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn euler_buckling_through_the_cli() {
    // a = (0, 0, 1e-4, −P, 0, 0) on c = (1, 1, 1), L = 1: stable below the clamped–clamped
    // Euler load 4π² ≈ 39.5 N, unstable above (ftwire-rod's stability test).
    for (p, stable) in [("30", true), ("50", false)] {
        let a = format!("0,0,1e-4,-{p},0,0");
        let out = ftwire(
            &[
                "solve", "--c", "1,1,1", "--length", "1", "--a", &a, "--json",
            ],
            None,
        );
        assert_success(&out, p);
        let v = json(&out);
        assert_eq!(v["stable"], stable, "P = {p}");
        let det_j_min = v["det_j_min"].as_f64().expect("det_j_min");
        if stable {
            assert!(det_j_min > 0.0, "P = {p}: {det_j_min}");
        }
    }
}

#[test]
fn vector_options_take_a_leading_minus_in_both_forms() {
    // a with a leading minus (τ1 < 0): both spellings give the library's tip.
    let a = [-0.01, 0.2, 0.1, -0.5, 0.3, 0.0];
    let text = "-0.01,0.2,0.1,-0.5,0.3,0";
    let rod = ftwire_rod::Rod::new(
        ftwire_rod::WireParams::new([0.214, 0.278, 0.278], 0.82, 0.001).expect("valid"),
    );
    let tip = rod
        .tip(&nalgebra::Vector6::from(a))
        .expect("solves")
        .translation
        .vector;
    let spaced = ["--a", text];
    let joined = format!("--a={text}");
    for extra in [&spaced[..], &[joined.as_str()][..]] {
        let mut args = vec![
            "solve",
            "--c",
            "0.214,0.278,0.278",
            "--length",
            "0.82",
            "--json",
        ];
        args.extend_from_slice(extra);
        let out = ftwire(&args, None);
        assert_success(&out, &format!("{extra:?}"));
        let position = cli_support::numbers(&json(&out)["tip"]["position"]);
        for k in 0..3 {
            assert!(
                (position[k] - tip[k]).abs() < 1e-12,
                "{extra:?}: {position:?}"
            );
        }
    }
    // --c with a leading minus is parsed, then refused by the wire's own check (not by clap).
    for c in [&["--c", "-1,1,1"][..], &["--c=-1,1,1"][..]] {
        let mut args = vec!["solve", "--length", "1", "--a", "0,0,1,0,0,0"];
        args.extend_from_slice(c);
        assert_exit(&ftwire(&args, None), 2, "c1", &format!("{c:?}"));
    }
}

#[test]
fn no_answer_exits_1() {
    // A load far too large for the integrator: valid input, no answer.
    let out = ftwire(
        &[
            "solve",
            "--c",
            "1,1,1",
            "--length",
            "1",
            "--a",
            "0,0,1e6,0,1e6,0",
        ],
        None,
    );
    assert_exit(&out, 1, "non-finite values", "diverged");
    // In a batch, such a line gets its error object and the batch exits 1 at the end.
    let input = [
        r#"{"c":[1,1,1],"length":1,"a":[0,0,1e6,0,1e6,0]}"#,
        r#"{"c":[1,1,1],"length":1,"a":[0,0,0.1,0,0,0]}"#,
    ]
    .join("\n");
    let out = ftwire(&["solve", "--batch", "-"], Some(&input));
    assert_exit(&out, 1, "1 had no answer", "batch");
    let lines: Vec<serde_json::Value> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).expect("JSON"))
        .collect();
    assert_eq!(lines.len(), 2);
    assert_eq!(lines[0]["kind"], "no_answer");
    assert!(lines[1]["tip"].is_object());
}

#[test]
fn batch_answers_each_line_before_the_next_arrives() {
    let mut child = Command::new(env!("CARGO_BIN_EXE_ftwire"))
        .args(["solve", "--batch", "-"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("the binary runs");
    let mut input = child.stdin.take().expect("stdin");
    let stdout = child.stdout.take().expect("stdout");
    // Read the answers on another thread, so that a binary that waits for the end of its input
    // makes the test fail on the timeout instead of hanging.
    let (sender, answers) = mpsc::channel();
    let reader = std::thread::spawn(move || {
        for line in BufReader::new(stdout).lines() {
            let Ok(line) = line else { break };
            if sender.send(line).is_err() {
                break;
            }
        }
    });
    let timeout = Duration::from_secs(30);
    let requests = [
        r#"{"c":[0.042,0.055,0.055],"length":0.63,"a":[0,0,0.01,0,0,0],"nodes":3}"#,
        "not json",
        r#"{"c":[0.042,0.055,0.055],"length":0.63,"a":[0,0.1,0,-0.2,0,0],"nodes":4}"#,
    ];
    let mut replies = Vec::new();
    for request in requests {
        writeln!(input, "{request}").expect("writes a request");
        input.flush().expect("flushes");
        let reply = answers
            .recv_timeout(timeout)
            .unwrap_or_else(|e| panic!("no answer to {request:?} while stdin is open: {e}"));
        replies.push(serde_json::from_str::<serde_json::Value>(&reply).expect("JSON"));
    }
    drop(input);
    let status = child.wait().expect("exits at the end of its input");
    let _ = reader.join();
    assert_eq!(replies[0]["shape"].as_array().map(Vec::len), Some(3));
    assert_eq!(replies[1]["line"], 2);
    assert_eq!(replies[2]["shape"].as_array().map(Vec::len), Some(4));
    assert_eq!(status.code(), Some(2), "a bad line makes the exit code 2");
}

/// `--gravity`, `--density`, `--radius` and `--natural-curvature` solve the loaded model
/// (`ftwire_rod::Rod::with_load`): the same numbers as the library, the same JSON keys as
/// without a load, and a tip that the weight and rest curvature have moved.
#[test]
fn gravity_and_rest_curvature_solve_the_loaded_model() {
    let mut args = SINGLE.to_vec();
    args.extend([
        "--json",
        "--nodes",
        "10",
        "--radius",
        "0.0015",
        "--gravity",
        "0,-9.81,0",
        "--density",
        "6450",
        "--natural-curvature",
        "0,0.5,-1",
    ]);
    let out = ftwire(&args, None);
    assert_success(&out, "loaded solve");
    let v = json(&out);
    let wire = ftwire_rod::WireParams::new([0.214, 0.278, 0.278], 0.82, 0.0015).expect("valid");
    let load =
        ftwire_rod::Load::from_gravity(6450.0, 0.0015, nalgebra::Vector3::new(0.0, -9.81, 0.0))
            .and_then(|l| l.with_natural_curvature(nalgebra::Vector3::new(0.0, 0.5, -1.0)))
            .expect("valid load");
    let a = nalgebra::Vector6::new(0.0, 0.2, 0.1, -0.5, 0.3, 0.0);
    let rod = ftwire_rod::Rod::new(wire);
    let loaded = rod.with_load(load).solve(&a, 10).expect("solves");
    let unloaded = rod.solve(&a, 10).expect("solves");
    let position = numbers(&v["tip"]["position"]);
    let tip = loaded.jacobian.tip.translation.vector;
    for k in 0..3 {
        assert!(
            (position[k] - tip[k]).abs() < 1e-15,
            "{position:?} vs {tip}"
        );
    }
    let moved = (tip - unloaded.jacobian.tip.translation.vector).norm();
    assert!(moved > 1e-3, "the load moved the tip only {moved} m");
    assert_eq!(
        v["stable"].as_bool(),
        Some(loaded.jacobian.stability.stable)
    );
    let j = v["jacobian"].as_array().expect("jacobian");
    assert!((j[3][4].as_f64().expect("number") - loaded.jacobian.jacobian[(3, 4)]).abs() < 1e-12);
    // The JSON keys are those of the unloaded answer.
    let mut plain = SINGLE.to_vec();
    plain.extend(["--json", "--nodes", "10"]);
    let plain = json(&ftwire(&plain, None));
    let keys = |v: &serde_json::Value| {
        let mut k: Vec<String> = v.as_object().expect("object").keys().cloned().collect();
        k.sort();
        k
    };
    assert_eq!(keys(&v), keys(&plain));
    // Without the flags, the answer is the unloaded model's.
    let plain_tip = numbers(&plain["tip"]["position"]);
    let unloaded_tip = unloaded.jacobian.tip.translation.vector;
    assert!((0..3).all(|k| (plain_tip[k] - unloaded_tip[k]).abs() < 1e-15));
    // The human summary states the load.
    let mut text = args.clone();
    text.retain(|a| *a != "--json");
    let out = ftwire(&text, None);
    assert_success(&out, "loaded summary");
    assert!(String::from_utf8_lossy(&out.stdout).contains("load: w = "));
}

/// A bad load is bad input (exit 2) naming the value.
#[test]
fn bad_load_arguments_exit_2_naming_the_value() {
    let with = |extra: &[&'static str]| {
        let mut v = SINGLE.to_vec();
        v.extend_from_slice(extra);
        ftwire(&v, None)
    };
    assert_exit(
        &with(&["--gravity", "0,0,-9.81", "--density", "-1"]),
        2,
        "density",
        "negative density",
    );
    assert_exit(
        &with(&["--gravity", "0,0,-9.81", "--density", "0"]),
        2,
        "density = 0 must be finite and > 0",
        "zero density",
    );
    assert_exit(
        &with(&["--gravity", "0,nan,-9.81"]),
        2,
        "expected 3 comma-separated finite numbers",
        "non-finite gravity",
    );
    assert_exit(
        &with(&["--natural-curvature", "1,2"]),
        2,
        "expected 3 comma-separated finite numbers",
        "two curvatures",
    );
    assert_exit(
        &with(&["--natural-curvature", "1,inf,0"]),
        2,
        "--natural-curvature",
        "infinite curvature",
    );
}
