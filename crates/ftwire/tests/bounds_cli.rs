//! Bounds on what one command may ask for, end to end: every count option has a range, stated in
//! `--help` and checked before any work; the batch service answers every line, whatever it
//! holds; inputs that cannot have an equilibrium are refused, and the simulator's work is
//! bounded; a scene of many obstacles is read in one pass.
#![allow(missing_docs)]

mod cli_support;

use std::io::{Read, Write};
use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use cli_support::{TempDir, assert_exit, assert_success, ftwire, ftwire_with_input};

/// The shipped passage scene.
const PASSAGE: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/passage.toml");

/// Runs `ftwire args` with `stdin` (any bytes) written to its input, killed and failed if it
/// has not finished within `limit`: a guard against a run that takes minutes, far above what
/// any of these inputs needs.
fn ftwire_within(args: &[&str], stdin: &[u8], limit: Duration) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_ftwire"))
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary runs");
    let mut input = child.stdin.take().expect("stdin");
    let bytes = stdin.to_vec();
    let writer = std::thread::spawn(move || {
        // The child may exit before reading everything (a refused option).
        let _ = input.write_all(&bytes);
    });
    // Read both outputs while the child runs, so that a full pipe never stalls it.
    let drain = |pipe: Option<Box<dyn Read + Send>>| {
        std::thread::spawn(move || {
            let mut bytes = Vec::new();
            if let Some(mut pipe) = pipe {
                let _ = pipe.read_to_end(&mut bytes);
            }
            bytes
        })
    };
    let stdout = drain(
        child
            .stdout
            .take()
            .map(|p| Box::new(p) as Box<dyn Read + Send>),
    );
    let stderr = drain(
        child
            .stderr
            .take()
            .map(|p| Box::new(p) as Box<dyn Read + Send>),
    );
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("waits") {
            break status;
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            panic!("ftwire {args:?} still ran after {limit:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let _ = writer.join();
    Output {
        status,
        stdout: stdout.join().expect("reads stdout"),
        stderr: stderr.join().expect("reads stderr"),
    }
}

/// Generous for every refused input here (they take milliseconds) and for the bounded solves.
const LIMIT: Duration = Duration::from_secs(60);

/// Stdout's lines as JSON values.
fn json_lines(output: &Output) -> Vec<serde_json::Value> {
    String::from_utf8_lossy(&output.stdout)
        .lines()
        .map(|line| serde_json::from_str(line).expect("each line is JSON"))
        .collect()
}

/// `--help` of a command with its whitespace runs made single spaces (clap wraps lines).
fn help(command: &[&str]) -> String {
    let mut args = command.to_vec();
    args.push("--help");
    let output = ftwire(&args);
    assert_success(&output, &format!("{command:?} --help"));
    String::from_utf8_lossy(&output.stdout)
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
}

/// Every count option: its command, its range, and the arguments its command needs besides.
const COUNTS: [(&[&str], &str, usize, usize); 16] = [
    (&["experiment", "identify"], "--trials", 1, 10_000),
    (&["experiment", "calibrate"], "--trials", 1, 10_000),
    (&["experiment", "identify"], "--rest-samples", 100, 100_000),
    (&["experiment", "shape"], "--rest-samples", 100, 100_000),
    (&["experiment", "shape"], "--configs", 1, 10_000),
    (&["experiment", "goal"], "--pairs", 1, 1000),
    (&["experiment", "track"], "--pairs", 1, 1000),
    (&["experiment", "passage"], "--attempts", 1, 1000),
    (&["experiment", "passage"], "--plan-candidates", 1, 100),
    (&["experiment", "passage"], "--waypoint-moves", 1, 1000),
    (&["reproduce"], "--jobs", 1, 64),
    (&["plan", "--scene", PASSAGE], "--iterations", 1, 1_000_000),
    (&["plan", "--scene", PASSAGE], "--resample", 1, 100_000),
    (&["identify", "--log", "x.jsonl"], "--samples", 1, 1_000_000),
    (
        &["solve", "--c", "0.1,0.1,0.1", "--length", "0.5"],
        "--nodes",
        2,
        1_000_000,
    ),
    (&["sim-equilibrium"], "--edges", 12, 2000),
];

#[test]
fn every_count_has_a_range_in_its_help_and_is_checked_before_any_work() {
    for (command, option, min, max) in COUNTS {
        let what = format!("{command:?} {option}");
        // The help of the command proper (without its other arguments) states the range.
        let name: Vec<&str> = command
            .iter()
            .copied()
            .take_while(|a| !a.starts_with("--"))
            .collect();
        let text = help(&name);
        let shown = format!("{option} <N>");
        let from = text
            .find(&shown)
            .unwrap_or_else(|| panic!("{what}: not in the help"));
        let range = format!("{min} to {max}");
        let next = text[from + shown.len()..]
            .find(" --")
            .map_or(text.len(), |i| from + shown.len() + i);
        assert!(
            text[from..next].contains(&range),
            "{what}: {range:?} not in {:?}",
            &text[from..next]
        );
        // Just above and just below the range: refused at once, naming the option and range.
        let message = |value: usize| format!("{option} {value}: at least {min} and at most {max}");
        for value in [max + 1, min - 1] {
            let text = value.to_string();
            let mut args = command.to_vec();
            args.extend([option, text.as_str()]);
            let output = ftwire_within(&args, b"", LIMIT);
            assert_exit(&output, 2, &message(value), &what);
        }
    }
}

/// The inputs of the report: a panic (capacity overflow), allocations of tens of gigabytes.
#[test]
fn the_counts_that_panicked_or_aborted_are_refused() {
    let cases: [(&[&str], &str); 5] = [
        (
            &[
                "experiment",
                "identify",
                "--rest-samples",
                "18446744073709551615",
            ],
            "--rest-samples 18446744073709551615: at least 100 and at most 100000",
        ),
        (
            &[
                "experiment",
                "shape",
                "--rest-samples",
                "18446744073709551615",
            ],
            "--rest-samples 18446744073709551615: at least 100 and at most 100000",
        ),
        (
            &["experiment", "identify", "--rest-samples", "1000000000"],
            "--rest-samples 1000000000: at least 100 and at most 100000",
        ),
        (
            &["plan", "--scene", PASSAGE, "--resample", "100000000"],
            "--resample 100000000: at least 1 and at most 100000",
        ),
        (
            // Beyond any machine's usize: out of range all the same.
            &["experiment", "goal", "--pairs", "99999999999999999999999"],
            "--pairs 99999999999999999999999: at least 1 and at most 1000",
        ),
    ];
    for (args, message) in cases {
        let output = ftwire_within(args, b"", LIMIT);
        assert_exit(&output, 2, message, &format!("{args:?}"));
    }
    let output = ftwire(&["plan", "--scene", PASSAGE, "--time-budget", "601"]);
    assert_exit(
        &output,
        2,
        "--time-budget 601 s: give more than 0 and at most 600 seconds",
        "--time-budget 601",
    );
}

/// The documented largest node count: solved, the self-contact test included, in a second or
/// two and a couple of hundred megabytes (the table of all pairs of chunks it replaces needed
/// 16 GB and aborted), on the command line and as a batch line.
#[test]
fn a_million_nodes_are_solved() {
    let args = [
        "solve",
        "--c",
        "0.042,0.055,0.055",
        "--length",
        "0.63",
        "--a",
        "0,0.547,0,0,0,0",
        "--nodes",
        "1000000",
        "--json",
    ];
    let output = ftwire_within(&args, b"", LIMIT);
    assert_success(&output, "--nodes 1000000");
    let answer: serde_json::Value = serde_json::from_slice(&output.stdout).expect("JSON");
    assert_eq!(answer["shape"].as_array().map(Vec::len), Some(1_000_000));
    // A pure bend through a little more than a full turn: the ends overlap.
    assert_eq!(answer["self_intersecting"], true);
    let batch = concat!(
        r#"{"c":[0.042,0.055,0.055],"length":0.63,"a":[0,0.02,0,0,0.1,0],"nodes":1000000}"#,
        "\n",
        r#"{"c":[0.042,0.055,0.055],"length":0.63,"a":[0,0.02,0,0,0.1,0],"nodes":5}"#,
        "\n"
    );
    let output = ftwire_within(&["solve", "--batch", "-"], batch.as_bytes(), LIMIT);
    assert_success(&output, "a batch line of a million nodes");
    let lines = json_lines(&output);
    assert_eq!(lines.len(), 2);
    assert_eq!(lines[0]["self_intersecting"], false);
    assert_eq!(lines[1]["shape"].as_array().map(Vec::len), Some(5));
}

const LINE: &str = r#"{"c":[0.042,0.055,0.055],"length":0.63,"a":[0,0.02,0,0,0.1,0],"nodes":5}"#;

#[test]
fn batch_lines_obey_the_bounds_of_the_flags() {
    let input = [
        r#"{"c":[0.042,0.055,0.055],"length":0.63,"a":[0,0.02,0,0,0.1,0],"nodes":1000001}"#,
        r#"{"c":[0.042,0.055,0.055],"length":0.63,"a":[0,0.02,0,0,0.1,0],"nodes":1}"#,
        r#"{"c":[0.042,0.055,0.055],"length":0.63,"a":[0,0.02,0,0,0.1,0],"radius":1}"#,
        LINE,
    ]
    .join("\n");
    let output = ftwire_with_input(&["solve", "--batch", "-"], Some(&input));
    assert_exit(&output, 2, "bad input", "bad lines");
    let lines = json_lines(&output);
    assert_eq!(lines.len(), 4);
    let error = |i: usize| lines[i]["error"].as_str().unwrap_or_default().to_owned();
    assert!(error(0).contains("nodes 1000001: at least 2 and at most 1000000"));
    assert!(error(1).contains("nodes 1: at least 2 and at most 1000000"));
    assert!(error(2).contains("radius 1: give less than half the wire's length (length 0.63 m)"));
    assert_eq!(lines[2]["kind"], "bad_input");
    assert_eq!(lines[3]["shape"].as_array().map(Vec::len), Some(5));
}

#[test]
fn a_line_that_is_not_utf8_gets_its_error_and_the_batch_goes_on() {
    let mut input = Vec::new();
    input.extend_from_slice(LINE.as_bytes());
    input.extend_from_slice(b"\n{\"c\": \"\xff\xfe\"}\n");
    input.extend_from_slice(LINE.as_bytes());
    input.push(b'\n');
    let output = ftwire_within(&["solve", "--batch", "-"], &input, LIMIT);
    assert_exit(
        &output,
        2,
        "1 line(s) of the batch were bad input",
        "not UTF-8",
    );
    let lines = json_lines(&output);
    assert_eq!(lines.len(), 3, "an answer to every line");
    assert!(lines[0]["shape"].is_array());
    assert_eq!(lines[1]["line"], 2);
    assert_eq!(lines[1]["kind"], "bad_input");
    let error = lines[1]["error"].as_str().unwrap_or_default();
    assert!(error.contains("is not valid UTF-8"), "{error}");
    assert!(lines[2]["shape"].is_array());
}

#[test]
fn a_folder_given_as_the_batch_is_bad_input() {
    let dir = TempDir::new("bounds-batch-dir");
    let path = dir.0.to_str().expect("a UTF-8 path");
    let output = ftwire(&["solve", "--batch", path]);
    assert_exit(&output, 2, "a folder, not a file", "--batch DIR");
}

#[test]
fn an_error_object_cuts_a_huge_echoed_value() {
    let huge = "x".repeat(10_000_000);
    let input = format!(
        "{{\"c\":\"{huge}\",\"length\":0.63,\"a\":[0,0,0,0,0,0]}}\n{{\"{huge}\":1}}\n{LINE}\n"
    );
    let output = ftwire_within(&["solve", "--batch", "-"], input.as_bytes(), LIMIT);
    assert_exit(&output, 2, "bad input", "a huge value");
    let lines = json_lines(&output);
    assert_eq!(lines.len(), 3);
    for line in &lines[..2] {
        let error = line["error"].as_str().unwrap_or_default();
        assert!(error.len() < 1000, "{} characters", error.len());
        assert!(error.contains("… (10000000 characters)"), "{error}");
    }
    assert!(lines[2]["shape"].is_array());
}

/// `sim-equilibrium` with a wire and a tip pose, and more arguments.
fn sim_equilibrium(position: &str, rotation: &str, extra: &[&str]) -> Output {
    let mut args = vec![
        "sim-equilibrium",
        "--c",
        "0.042,0.055,0.055",
        "--length",
        "0.63",
        "--tip-position",
        position,
        "--tip-rotation",
        rotation,
    ];
    args.extend_from_slice(extra);
    ftwire_within(&args, b"", LIMIT)
}

#[test]
fn coincident_clamps_are_refused_naming_the_values() {
    let output = sim_equilibrium("0,0,0", "0,0,0", &[]);
    assert_exit(
        &output,
        2,
        "--tip-position 0,0,0: the clamp points are 0 m apart; give at least the wire's \
         diameter 2 · --radius = 0.002 m",
        "coincident clamps",
    );
    let output = sim_equilibrium("0,0.001,0", "0,0,0", &["--radius", "0.001"]);
    assert_exit(&output, 2, "at least the wire's diameter", "1 mm apart");
}

/// Clamps 1 cm apart, facing the same way: the continuation creeps and fails, the fallback
/// finds the loop. The work of each motion is bounded, so the answer comes in seconds (it took
/// a minute and a half before).
#[test]
fn nearly_coincident_clamps_are_answered_in_bounded_work() {
    let output = sim_equilibrium("0.01,0,0", "0,0,0", &["--json"]);
    assert_success(&output, "clamps 1 cm apart");
    let answer: serde_json::Value = serde_json::from_slice(&output.stdout).expect("JSON");
    assert_eq!(answer["converged"], true);
}

#[test]
fn a_huge_initial_a_is_bad_input_naming_the_range() {
    let output = sim_equilibrium("0.5,0.1,0", "0,0,0.5", &["--initial-a", "1e300,0,0,0,0,0"]);
    assert_exit(
        &output,
        2,
        "--initial-a: τ1 = 1e300 N·m is too large for this wire: give each torque within \
         ±8.7302 N·m and each force within ±13.8574 N",
        "--initial-a 1e300",
    );
}

#[test]
fn too_few_edges_are_bad_input() {
    for edges in ["3", "11"] {
        let output = sim_equilibrium("0.5,0.1,0", "0,0,0.5", &["--edges", edges]);
        let message = format!("--edges {edges}: at least 12 and at most 2000");
        assert_exit(&output, 2, &message, &message);
    }
    let output = sim_equilibrium("0.5,0.1,0", "0,0,0.5", &["--edges", "12"]);
    assert_success(&output, "--edges 12");
}

#[test]
fn a_radius_of_half_the_length_is_bad_input() {
    let base = ["--c", "0.042,0.055,0.055", "--length", "0.63"];
    let mut solve = vec!["solve", "--a", "0,0.02,0,0,0.1,0", "--radius", "1"];
    solve.extend(base);
    let output = ftwire(&solve);
    let message = "--radius 1: give less than half the wire's length (--length 0.63 m)";
    assert_exit(&output, 2, message, "solve --radius 1");
    let mut sim = vec![
        "sim-equilibrium",
        "--tip-position",
        "0.5,0,0",
        "--tip-rotation",
        "0,0,0",
        "--radius",
        "0.315",
    ];
    sim.extend(base);
    let output = ftwire(&sim);
    assert_exit(
        &output,
        2,
        "--radius 0.315: give less than half",
        "--radius L/2",
    );
}

/// A scene of `count` small boxes; the last one flat (a zero half extent) if `flat_last`.
fn many_boxes(path: &Path, count: usize, flat_last: bool) {
    let passage = std::fs::read_to_string(PASSAGE).expect("the shipped scene");
    let first = passage.find("[[obstacle]]").expect("an obstacle");
    let endpoints = passage.find("[configuration.start]").expect("a start");
    let mut text = passage[..first].to_owned();
    for k in 0..count {
        let half = if flat_last && k + 1 == count {
            "0.0"
        } else {
            "0.001"
        };
        let (x, y) = (5.0 + 0.01 * (k % 100) as f64, 5.0 + 0.01 * (k / 100) as f64);
        text.push_str(&format!(
            "[[obstacle]]\ncentre = [{x:.2}, {y:.2}, 3.0]\nhalf_extents = [0.001, {half}, 0.001]\n"
        ));
    }
    text.push_str(&passage[endpoints..]);
    std::fs::write(path, text).expect("writes the scene");
}

/// Twenty thousand obstacles: read in one pass over the file (it was counted from the start for
/// every obstacle), and an error in the last names its line.
#[test]
fn a_scene_of_many_obstacles_loads_and_names_the_line_of_its_last() {
    let dir = TempDir::new("bounds-scene");
    let count = 20_000;
    let good = dir.0.join("many.toml");
    many_boxes(&good, count, false);
    let output = ftwire_within(
        &["scene", "check", good.to_str().expect("UTF-8")],
        b"",
        LIMIT,
    );
    assert_success(&output, "20000 obstacles");
    let bad = dir.0.join("flat.toml");
    many_boxes(&bad, count, true);
    let text = std::fs::read_to_string(&bad).expect("reads");
    let line = text
        .lines()
        .position(|l| l.contains("half_extents = [0.001, 0.0, 0.001]"))
        .expect("the flat box")
        - 1;
    let output = ftwire_within(
        &["scene", "check", bad.to_str().expect("UTF-8")],
        b"",
        LIMIT,
    );
    let message = format!(
        "line {line}: obstacle \"obstacle {count}\": half_extents[1] = 0 m must be positive"
    );
    assert_exit(&output, 2, &message, "the last of 20000 obstacles");
}

/// `identify --help` says how to take a window of a long log, and that progress is shown.
#[test]
fn identify_says_how_to_use_a_window_of_a_long_log() {
    let text = help(&["identify"]);
    assert!(
        text.contains("a window of the first few hundred of a long log"),
        "{text}"
    );
    assert!(text.contains("progress is shown on stderr"), "{text}");
}
