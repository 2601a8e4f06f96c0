//! `ftwire robot fk|ik`, run as a user would.

use std::process::{Command, Output};

use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};
use serde_json::Value;

fn ftwire(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_ftwire"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn json(output: &Output) -> Value {
    serde_json::from_slice(&output.stdout).expect("stdout is JSON")
}

fn numbers(v: &Value) -> Vec<f64> {
    v.as_array()
        .expect("an array")
        .iter()
        .map(|x| x.as_f64().expect("a number"))
        .collect()
}

fn fk(arm: &str, joints: &str, torso: &str, frame: &str) -> (Vector3<f64>, Matrix3<f64>) {
    let out = ftwire(&[
        "robot", "fk", "--arm", arm, "--joints", joints, "--torso", torso, "--frame", frame,
        "--json",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v = json(&out);
    let p = numbers(&v["position"]);
    let rows: Vec<Vec<f64>> = v["rotation"]
        .as_array()
        .expect("rows")
        .iter()
        .map(numbers)
        .collect();
    let m = Matrix3::from_fn(|i, j| rows[i][j]);
    (Vector3::new(p[0], p[1], p[2]), m)
}

#[test]
fn fk_of_the_zero_posture_matches_the_robot_data() {
    let (p, m) = fk("left", "0,0,0,0,0,0,0", "0", "tool0");
    assert!(
        (p - Vector3::new(0.09996, 1.119645, 0.333993)).norm() < 1e-5,
        "{p}"
    );
    assert!((m * m.transpose() - Matrix3::identity()).norm() < 1e-12);
    // Row-major: row 1 is the base-frame y components of tool0's axes; tool0's z axis is −y.
    assert!((m[(1, 2)] + 1.0).abs() < 1e-5);
    let (p, _) = fk("right", "0,0,0,0,0,0,0", "0", "tool0");
    assert!((p.y + 1.12).abs() < 0.005);
}

#[test]
fn ik_inverts_fk_through_the_command_line() {
    let joints = "0.3,-0.8,0.5,-1.1,0.7,0.9,-0.4";
    let (p, m) = fk("right", joints, "-0.3", "gripper");
    let r =
        UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(m)).scaled_axis();
    let position = format!("{},{},{}", p.x, p.y, p.z);
    let rotation = format!("{},{},{}", r.x, r.y, r.z);
    let out = ftwire(&[
        "robot",
        "ik",
        "--arm",
        "right",
        "--position",
        &position,
        "--rotation",
        &rotation,
        "--torso",
        "-0.3",
        "--json",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
    let q = numbers(&json(&out)["joints"]);
    assert_eq!(q.len(), 7);
    let q: Vec<String> = q.iter().map(f64::to_string).collect();
    let (p2, m2) = fk("right", &q.join(","), "-0.3", "gripper");
    assert!((p2 - p).norm() < 1e-6, "{p2} vs {p}");
    assert!((m2 - m).norm() < 1e-5);
}

#[test]
fn ik_of_tool0_with_a_seed_and_human_output() {
    let (p, m) = fk("left", "0.1,0.7,-0.2,-1.3,0.2,-0.5,0.3", "0", "tool0");
    let r =
        UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(m)).scaled_axis();
    let position = format!("{},{},{}", p.x, p.y, p.z);
    let rotation = format!("{},{},{}", r.x, r.y, r.z);
    let out = ftwire(&[
        "robot",
        "ik",
        "--arm",
        "left",
        "--position",
        &position,
        "--rotation",
        &rotation,
        "--seed-joints",
        "0,0.6,0,-1.2,0,-0.6,0",
        "--frame",
        "tool0",
    ]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{text}");
    assert!(
        text.contains("left arm joints [rad]:") && text.contains("residual"),
        "{text}"
    );
}

#[test]
fn unreachable_target_prints_an_error_and_exits_1() {
    let out = ftwire(&[
        "robot",
        "ik",
        "--arm",
        "left",
        "--position",
        "3,0,0",
        "--rotation",
        "0,0,0",
        "--json",
    ]);
    assert_eq!(out.status.code(), Some(1));
    let v = json(&out);
    assert!(
        v["error"].as_str().is_some_and(|e| e.contains("reach")),
        "{v}"
    );
}

#[test]
fn bad_arguments_exit_2_with_a_clear_message() {
    let cases: [(&[&str], &str); 6] = [
        (
            &["robot", "fk", "--arm", "left", "--joints", "0,0,0"],
            "expected 7",
        ),
        (
            &["robot", "fk", "--arm", "up", "--joints", "0,0,0,0,0,0,0"],
            "possible values",
        ),
        (
            &[
                "robot",
                "fk",
                "--arm",
                "left",
                "--joints",
                "0,2.5,0,0,0,0,0",
            ],
            "outside its limits",
        ),
        (
            &[
                "robot",
                "fk",
                "--arm",
                "left",
                "--joints",
                "0,0,0,0,0,0,0",
                "--torso",
                "nan",
            ],
            "finite",
        ),
        (
            &[
                "robot",
                "ik",
                "--arm",
                "left",
                "--position",
                "1,x,0",
                "--rotation",
                "0,0,0",
            ],
            "not a number",
        ),
        (
            &[
                "robot",
                "fk",
                "--arm",
                "left",
                "--joints",
                "0,0,0,0,0,0,0",
                "--urdf",
                "/no/such.urdf",
            ],
            "cannot read",
        ),
    ];
    for (args, message) in cases {
        let out = ftwire(args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(message), "{args:?}: {stderr}");
    }
}
