//! `ftwire robot fk|ik`, run as a user would.

mod cli_support;

use cli_support::{assert_exit, assert_success, both_forms, ftwire, json, numbers};
use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};

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
    assert_exit(&out, 1, "reach", "unreachable");
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
        assert_exit(&ftwire(args), 2, message, &format!("{args:?}"));
    }
}

#[test]
fn vector_options_take_a_leading_minus_in_both_forms() {
    // These joints put the right gripper at x < 0 with a rotation vector whose first component
    // is negative, so --position and --rotation start with a minus sign too.
    let joints = "-0.3,-0.8,0.5,-1.1,0.7,0.9,-0.4";
    let robot = ftwire_robot::Robot::sda10f().expect("built-in model");
    let q = ftwire_robot::ArmJoints::from_column_slice(&[-0.3, -0.8, 0.5, -1.1, 0.7, 0.9, -0.4]);
    let expected = robot
        .fk(
            ftwire_robot::Arm::Right,
            0.0,
            &q,
            ftwire_robot::EndFrame::Gripper,
        )
        .expect("within limits");
    let p = expected.translation.vector;
    let r = expected.rotation.scaled_axis();
    assert!(
        p.x < 0.0 && r.x < 0.0,
        "the test needs leading minus signs: {p}, {r}"
    );
    let position = format!("{},{},{}", p.x, p.y, p.z);
    let rotation = format!("{},{},{}", r.x, r.y, r.z);
    for form in 0..2 {
        let run = |head: &[&str], options: &[(&str, &str)]| {
            let mut args: Vec<String> = head.iter().map(|s| (*s).to_owned()).collect();
            for (option, value) in options {
                args.extend(both_forms(option, value)[form].clone());
            }
            let args: Vec<&str> = args.iter().map(String::as_str).collect();
            ftwire(&args)
        };
        let out = run(
            &["robot", "fk", "--arm", "right", "--json"],
            &[("--joints", joints)],
        );
        assert_success(&out, "fk");
        let got = numbers(&json(&out)["position"]);
        assert!(
            (Vector3::new(got[0], got[1], got[2]) - p).norm() < 1e-12,
            "form {form}: {got:?}"
        );

        let out = run(
            &["robot", "ik", "--arm", "right", "--json"],
            &[
                ("--position", &position),
                ("--rotation", &rotation),
                ("--seed-joints", "-0.25,-0.75,0.45,-1.05,0.65,0.85,-0.35"),
            ],
        );
        assert_success(&out, "ik");
        let q = numbers(&json(&out)["joints"]);
        let q = ftwire_robot::ArmJoints::from_column_slice(&q);
        let reached = robot
            .fk(
                ftwire_robot::Arm::Right,
                0.0,
                &q,
                ftwire_robot::EndFrame::Gripper,
            )
            .expect("within limits");
        assert!(
            (reached.translation.vector - p).norm() < 1e-6,
            "form {form}: {}",
            reached.translation.vector
        );
        assert!(reached.rotation.angle_to(&expected.rotation) < 1e-5);
    }
}
