//! `ftwire solve` end to end: the built binary, its JSON, its batch mode and its exit codes.
#![allow(missing_docs)]

use std::io::Write;
use std::process::{Command, Output, Stdio};

fn ftwire(args: &[&str], stdin: Option<&str>) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_ftwire"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    if let Some(input) = stdin {
        child
            .stdin
            .take()
            .expect("stdin")
            .write_all(input.as_bytes())
            .expect("writes stdin");
    } else {
        drop(child.stdin.take());
    }
    child.wait_with_output().expect("finishes")
}

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
    assert!(v["det_j_min"].as_f64().expect("det_j_min") >= 0.0);
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
            "c must have 3",
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
            "a must have 6",
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
            "not finite",
        ),
        (base(&["--nodes", "1"]), "nodes"),
        (base(&["--radius", "0"]), "radius"),
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
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
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
