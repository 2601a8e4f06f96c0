//! Clear words for odd input:
//! - an over-large rotation vector (`--rotation`, `--tip-rotation`, sensor, scene and log files)
//!   is refused by its value and the bound, not reported as a NaN;
//! - a name that looks like a file (`--wire`, `--sensor`, and every other file option), a
//!   symbolic link in a loop included, is read as one and its read error reported;
//! - a TOML file that is not UTF-8 names the file, the line and the column of the bad byte;
//! - a UTF-8 byte-order mark before a log or a batch is dropped: the same answer as without;
//! - a rig or sensor time out of its range names the file, the key, the value and the range;
//! - `demo` reads and checks every input before its first phase.

mod cli_support;

use std::fs;
use std::path::Path;

use cli_support::{TempDir, assert_exit, assert_success, ftwire, ftwire_with_input};

/// The UTF-8 byte-order mark.
const BOM: &[u8] = b"\xEF\xBB\xBF";

fn text(path: &Path) -> &str {
    path.to_str().expect("a UTF-8 path")
}

/// Stderr of a run.
fn stderr(output: &std::process::Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// The demo with `args`, its results folder in `dir` (never written when the input is bad).
fn demo(dir: &Path, args: &[&str]) -> std::process::Output {
    let out = dir.join("demo");
    let mut all = vec!["demo", "--out", text(&out)];
    all.extend_from_slice(args);
    let output = ftwire(&all);
    assert!(!out.exists(), "nothing written for bad input");
    output
}

/// Asserts a refusal before the demo's first phase: exit 2 naming `needles`, no phase begun.
fn assert_refused_before_work(output: &std::process::Output, needles: &[&str], what: &str) {
    for needle in needles {
        assert_exit(output, 2, needle, what);
    }
    let stderr = stderr(output);
    assert!(!stderr.contains("[1/5]"), "{what}: a phase ran: {stderr}");
}

#[test]
fn an_over_large_rotation_vector_is_refused_by_its_value_and_the_bound() {
    let output = ftwire(&[
        "sim-equilibrium",
        "--c",
        "0.042,0.055,0.055",
        "--length",
        "0.63",
        "--tip-position",
        "0.4,0,0",
        "--tip-rotation",
        "1e300,0,0",
    ]);
    assert_exit(&output, 2, "--tip-rotation", "--tip-rotation 1e300");
    assert_exit(&output, 2, "[1e300, 0.0, 0.0]", "the value is named");
    assert_exit(&output, 2, "at most 1e6 rad", "the bound is named");
    assert!(!stderr(&output).contains("NaN"), "{}", stderr(&output));

    let output = ftwire(&[
        "robot",
        "ik",
        "--arm",
        "left",
        "--position",
        "0.5,0.3,1.0",
        "--rotation",
        "0,-2e6,0",
    ]);
    assert_exit(&output, 2, "--rotation", "--rotation 2e6");
    assert_exit(&output, 2, "at most 1e6 rad", "the bound is named");

    let tmp = TempDir::new("words-rotation");
    let sensor = tmp.0.join("sensor.toml");
    fs::write(
        &sensor,
        "rate = 1000.0\nclamp_rotation_in_sensor = [0.0, 1e300, 0.0]\n",
    )
    .expect("writes");
    let output = demo(&tmp.0, &["--sensor", text(&sensor)]);
    assert_refused_before_work(
        &output,
        &[
            "sensor.toml",
            "line 2, key clamp_rotation_in_sensor",
            "1e300",
        ],
        "a sensor mounting rotation of 1e300 rad",
    );

    let scene = fs::read_to_string("../../scenes/passage.toml").expect("the shipped scene");
    let turned = tmp.0.join("turned.toml");
    let base = "rotation = [0.0, 0.0, -1.5707963267948966]";
    assert!(scene.contains(base), "the passage's base rotation");
    fs::write(
        &turned,
        scene.replace(base, "rotation = [0.0, 0.0, -1e300]"),
    )
    .expect("writes");
    let output = ftwire(&["scene", "check", text(&turned)]);
    assert_exit(
        &output,
        2,
        "turned.toml",
        "a scene's base rotation of 1e300 rad",
    );
    assert_exit(&output, 2, "1e300", "the value is named");
    assert_exit(&output, 2, "at most 1e6 rad", "the bound is named");

    let log = tmp.0.join("turned.jsonl");
    fs::write(
        &log,
        r#"{"time": 0.0, "a": [0.01, 0.02, -0.03, -0.1, 0.2, 0.05], "b": {"position": [0.5, 0.1, 0.0], "rotation": [0.0, 1e300, 0.0]}}"#,
    )
    .expect("writes");
    let output = ftwire(&["identify", "--log", text(&log)]);
    assert_exit(&output, 2, "line 1", "a log's b.rotation of 1e300 rad");
    assert_exit(&output, 2, "b.rotation", "the key is named");
    assert_exit(&output, 2, "at most 1e6 rad", "the bound is named");
}

#[cfg(unix)]
#[test]
fn a_name_that_looks_like_a_file_is_read_as_one_and_its_error_reported() {
    let tmp = TempDir::new("words-loop");
    let looped = tmp.0.join("loop.toml");
    std::os::unix::fs::symlink(&looped, &looped).expect("a link to itself");
    let looped = text(&looped);
    let dangling = tmp.0.join("gone");
    std::os::unix::fs::symlink(tmp.0.join("nowhere"), &dangling).expect("a dangling link");
    let dangling = text(&dangling);
    let symlinks = "Too many levels of symbolic links";

    for option in ["--wire", "--sensor", "--rig", "--scene"] {
        let output = demo(&tmp.0, &[option, looped]);
        assert_refused_before_work(&output, &["loop.toml", symlinks], option);
        assert!(!stderr(&output).contains("unknown"), "{}", stderr(&output));
    }
    // A link that leads nowhere is a file that is not there, not an unknown preset.
    for option in ["--wire", "--sensor"] {
        let output = demo(&tmp.0, &[option, dangling]);
        assert_refused_before_work(&output, &["gone", "No such file"], option);
    }
    // A name with no path in it that is not there is still a misspelt preset.
    let output = demo(&tmp.0, &["--wire", "nitinol-2mm"]);
    assert_refused_before_work(&output, &["unknown wire", "nitinol-2mm-630"], "a typo");

    let output = ftwire(&["scene", "check", looped]);
    assert_exit(&output, 2, symlinks, "scene check");
    let output = ftwire(&[
        "scene",
        "check",
        "../../scenes/passage.toml",
        "--wire",
        looped,
    ]);
    assert_exit(&output, 2, symlinks, "scene check --wire");
    let output = ftwire(&["shape", "--log", looped, "--wire", "nitinol-2mm-630"]);
    assert_exit(&output, 2, symlinks, "shape --log");
    let output = ftwire(&["identify", "--log", looped]);
    assert_exit(&output, 2, symlinks, "identify --log");
    let log = tmp.0.join("one.jsonl");
    fs::write(
        &log,
        r#"{"time": 0.0, "a": [0.01, 0.02, -0.03, -0.1, 0.2, 0.05], "b": {"position": [0.5, 0.1, 0.0], "rotation": [0.0, 0.0, 0.3]}}"#,
    )
    .expect("writes");
    let output = ftwire(&["identify", "--log", text(&log), "--calibration", looped]);
    assert_exit(&output, 2, symlinks, "identify --calibration");
    let output = ftwire(&["solve", "--batch", looped]);
    assert_exit(&output, 2, symlinks, "solve --batch");
}

#[test]
fn a_toml_file_that_is_not_utf8_names_the_file_the_line_and_the_column() {
    let tmp = TempDir::new("words-utf8");
    // "é" in Latin-1 is the single byte 0xE9, which is not UTF-8.
    let latin1 = |name: &str, text: &str| {
        let path = tmp.0.join(name);
        let bytes: Vec<u8> = text
            .bytes()
            .map(|b| if b == b'@' { 0xE9 } else { b })
            .collect();
        fs::write(&path, bytes).expect("writes");
        path
    };
    let wire = latin1(
        "wire.toml",
        "c = [0.214, 0.278, 0.278]\nname = \"caf@\"\nlength = 0.82\n",
    );
    let sensor = latin1("sensor.toml", "rate = 1000.0\n# r@sum@\n");
    let rig = latin1("rig.toml", "\n\nsettle_time = 0.2 # apr@s\n");
    let scene = latin1(
        "scene.toml",
        "[base]\nposition = [0.6, 0.35, 0.35] # d@but\n",
    );
    for (option, path, at) in [
        ("--wire", &wire, "line 2, column 12"),
        ("--sensor", &sensor, "line 2, column 4"),
        ("--rig", &rig, "line 3, column 24"),
        ("--scene", &scene, "line 2, column 33"),
    ] {
        let output = demo(&tmp.0, &[option, text(path)]);
        let name = path.file_name().and_then(|n| n.to_str()).expect("a name");
        assert_refused_before_work(&output, &[name, at, "0xE9", "UTF-8"], option);
    }
    let output = ftwire(&["scene", "check", text(&scene)]);
    assert_exit(&output, 2, "line 2, column 33", "scene check");
}

/// A log of `a` records with the second gripper where the Kirchhoff model puts it for each
/// (from `ftwire solve --batch`), so that identification has something to identify.
fn consistent_log() -> String {
    let configurations: Vec<[f64; 6]> = (0..6)
        .map(|k| {
            let s = f64::from(k) / 5.0;
            [
                0.01 - 0.02 * s,
                0.02 + 0.03 * s,
                -0.03 + 0.02 * s,
                -0.1 + 0.05 * s,
                0.2 - 0.1 * s,
                0.05 + 0.1 * s,
            ]
        })
        .collect();
    let requests: String = configurations
        .iter()
        .map(|a| {
            serde_json::json!({"c": [0.042, 0.055, 0.055], "length": 0.63, "a": a}).to_string()
                + "\n"
        })
        .collect();
    let output = ftwire_with_input(&["solve", "--batch", "-"], Some(&requests));
    assert_success(&output, "solve --batch");
    let answers = String::from_utf8(output.stdout).expect("UTF-8");
    answers
        .lines()
        .zip(&configurations)
        .enumerate()
        .map(|(k, (line, a))| {
            let answer: serde_json::Value = serde_json::from_str(line).expect("JSON");
            let tip = &answer["tip"];
            let position = cli_support::numbers(&tip["position"]);
            let rows: Vec<Vec<f64>> = tip["rotation"]
                .as_array()
                .expect("a matrix")
                .iter()
                .map(cli_support::numbers)
                .collect();
            let matrix = nalgebra::Matrix3::from_fn(|i, j| rows[i][j]);
            let r = nalgebra::Rotation3::from_matrix_unchecked(matrix).scaled_axis();
            serde_json::json!({
                "time": 0.5 * f64::from(u8::try_from(k).expect("few")),
                "a": a,
                "b": {"position": position, "rotation": [r.x, r.y, r.z]},
            })
            .to_string()
                + "\n"
        })
        .collect()
}

#[test]
fn a_bom_before_a_log_or_a_batch_is_dropped_and_the_answer_is_the_same() {
    let tmp = TempDir::new("words-bom");
    let log = consistent_log();
    let plain = tmp.0.join("plain.jsonl");
    fs::write(&plain, &log).expect("writes");
    let with_bom = tmp.0.join("bom.jsonl");
    fs::write(&with_bom, [BOM, log.as_bytes()].concat()).expect("writes");

    let run = |args: &[&str], path: &Path| {
        let mut all = args.to_vec();
        all.extend_from_slice(&["--log", text(path), "--json"]);
        ftwire(&all)
    };
    for command in [
        &["identify", "--samples", "6"][..],
        &["shape", "--wire", "nitinol-2mm-630"][..],
    ] {
        let expected = run(command, &plain);
        assert_success(&expected, command[0]);
        let got = run(command, &with_bom);
        assert_success(&got, &format!("{} with a BOM", command[0]));
        assert_eq!(
            String::from_utf8_lossy(&got.stdout),
            String::from_utf8_lossy(&expected.stdout),
            "{}: the same answer with a BOM",
            command[0]
        );
    }

    let request =
        "{\"c\": [0.042, 0.055, 0.055], \"length\": 0.63, \"a\": [0, 0.1, 0, -0.2, 0, 0.3]}\n";
    let batch = tmp.0.join("bom-batch.jsonl");
    fs::write(&batch, [BOM, request.as_bytes()].concat()).expect("writes");
    let expected = ftwire_with_input(&["solve", "--batch", "-"], Some(request));
    assert_success(&expected, "solve --batch");
    let got = ftwire(&["solve", "--batch", text(&batch)]);
    assert_success(&got, "solve --batch with a BOM");
    assert_eq!(got.stdout, expected.stdout, "the same answer with a BOM");

    // A wire and a scene file with a BOM read as without (its first line's key found too).
    let wire = tmp.0.join("wire.toml");
    fs::write(
        &wire,
        [
            BOM,
            b"length = -0.82\nname = \"w\"\nc = [0.214, 0.278, 0.278]\nradius = 0.0015\ndensity = 6450.0\n",
        ]
        .concat(),
    )
    .expect("writes");
    let output = ftwire(&[
        "scene",
        "check",
        "../../scenes/passage.toml",
        "--wire",
        text(&wire),
    ]);
    assert_exit(
        &output,
        2,
        "line 1, key length",
        "a BOM before the first key",
    );

    // Invalid UTF-8 in a batch is a bad line named by its line and column; the batch goes on.
    let latin1 = tmp.0.join("latin1-batch.jsonl");
    fs::write(
        &latin1,
        [
            request.as_bytes(),
            b"{\"c\": \"\xE9\"}\n",
            request.as_bytes(),
        ]
        .concat(),
    )
    .expect("writes");
    let output = ftwire(&["solve", "--batch", text(&latin1)]);
    assert_exit(
        &output,
        2,
        "1 line(s) of the batch were bad input",
        "a Latin-1 line",
    );
    let lines: Vec<serde_json::Value> = String::from_utf8_lossy(&output.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).expect("JSON"))
        .collect();
    assert_eq!(lines.len(), 3, "every line answered");
    assert_eq!(lines[1]["line"], 2);
    let error = lines[1]["error"].as_str().expect("an error");
    assert!(
        error.contains("column 8") && error.contains("0xE9"),
        "{error}"
    );
}

#[test]
fn rig_and_sensor_times_out_of_range_name_the_file_the_key_the_value_and_the_range() {
    let tmp = TempDir::new("words-times");
    let file = |name: &str, text: &str| {
        let path = tmp.0.join(name);
        fs::write(&path, text).expect("writes");
        path
    };
    let cases = [
        (
            "--rig",
            file("settle.toml", "linear_speed = 0.05\nsettle_time = 1e300\n"),
            ["line 2, key settle_time", "1e300", "[0, 3600] s"],
        ),
        (
            "--rig",
            file("slow.toml", "linear_speed = 1e-300\n"),
            ["line 1, key linear_speed", "1e-300", "[0.001, 10] m/s"],
        ),
        (
            "--rig",
            file("spin.toml", "angular_speed = 1e300\n"),
            ["line 1, key angular_speed", "1e300", "[0.001, 10] rad/s"],
        ),
        (
            "--sensor",
            file("rate.toml", "rate = 1e300\n"),
            ["line 1, key rate", "1e300", "1 ..= 1000000"],
        ),
        (
            "--sensor",
            file("offset.toml", "\nclock_offset = -1e300\n"),
            ["line 2, key clock_offset", "-1e300", "-1000000 ..= 1000000"],
        ),
        (
            "--sensor",
            file("drift.toml", "bias_time_constant = 1e300\n"),
            ["line 1, key bias_time_constant", "1e300", "≤ 1e9 s, or inf"],
        ),
    ];
    for (option, path, needles) in &cases {
        let name = path.file_name().and_then(|n| n.to_str()).expect("a name");
        let output = demo(&tmp.0, &[option, text(path)]);
        assert_refused_before_work(&output, &[name], name);
        assert_refused_before_work(&output, needles, name);
    }
}

#[test]
fn the_demo_checks_its_scene_before_any_work() {
    let tmp = TempDir::new("words-demo");
    let output = demo(&tmp.0, &["--scene", "/nonexistent.toml"]);
    assert_refused_before_work(
        &output,
        &["--scene", "/nonexistent.toml", "No such file"],
        "a missing scene",
    );
    let scene = fs::read_to_string("../../scenes/passage.toml").expect("the shipped scene");
    let goal = scene.find("[configuration.goal]").expect("a goal");
    let no_goal = tmp.0.join("no-goal.toml");
    fs::write(
        &no_goal,
        scene.get(..goal).expect("the scene before its goal"),
    )
    .expect("writes");
    let output = demo(&tmp.0, &["--scene", text(&no_goal)]);
    assert_refused_before_work(&output, &["--scene", "\"goal\""], "a scene without a goal");
}
