//! `ftwire sim-equilibrium` end to end: JSON, the physical shape, negative numbers in every
//! vector option, the `--edges` bounds and the exit codes.

mod cli_support;

use cli_support::{assert_exit, assert_success, both_forms, ftwire, json, numbers};
use nalgebra::{UnitQuaternion, Vector3};

#[test]
fn json_output_has_every_field_and_the_arc_moment() {
    // A quarter circle of radius 0.4 m towards +y, no gravity: base moment c3/R about z.
    let (r, l) = (0.4_f64, 0.4 * std::f64::consts::FRAC_PI_2);
    let length = l.to_string();
    let out = ftwire(&[
        "sim-equilibrium",
        "--c",
        "0.042,0.055,0.07",
        "--length",
        &length,
        "--tip-position",
        &format!("{r},{r},0"),
        "--tip-rotation",
        &format!("0,0,{}", std::f64::consts::FRAC_PI_2),
        "--gravity",
        "0,0,0",
        "--edges",
        "60",
        "--json",
    ]);
    assert_success(&out, "quarter circle");
    let v = json(&out);
    assert_eq!(v["converged"], true);
    assert_eq!(v["stable_minimum"], true);
    // Without --initial-a the wire is bent from straight by continuation: `iterations` is the
    // total over its steps, far more than one Newton solve takes.
    assert!(v["iterations"].as_u64().is_some_and(|n| n > 20), "{v}");
    assert!(v["energy"].as_f64().is_some_and(|e| e > 0.0));
    let base = numbers(&v["base_wrench"]);
    let tip = numbers(&v["tip_wrench"]);
    assert_eq!((base.len(), tip.len()), (6, 6));
    assert!((base[2] - 0.07 / r).abs() < 0.01 * 0.07 / r, "{base:?}");
    assert!((tip[2] + 0.07 / r).abs() < 0.01 * 0.07 / r, "{tip:?}");

    // The shape is the physical wire: N + 1 points from the base clamp point (the origin) to the
    // commanded tip position, no ghost node half an edge outside, all on the arc.
    let shape: Vec<Vec<f64>> = serde_json::from_value(v["shape"].clone()).expect("points");
    assert_eq!(shape.len(), 61);
    assert_eq!(shape[0], [0.0, 0.0, 0.0]);
    let last = &shape[60];
    assert!(
        (last[0] - r).abs() < 1e-12 && (last[1] - r).abs() < 1e-12 && last[2].abs() < 1e-12,
        "{last:?}"
    );
    for p in &shape {
        // The arc is centred at (0, r); the discrete wire lies on it to O(h²).
        let radius = (p[0] * p[0] + (p[1] - r) * (p[1] - r)).sqrt();
        assert!((radius - r).abs() < 1e-3 * r, "{p:?} is off the arc");
        assert!(
            p[0] >= 0.0 && p[1] <= r + 1e-12,
            "{p:?} lies outside the wire's span"
        );
    }
}

#[test]
fn human_output_names_the_frames() {
    let out = ftwire(&[
        "sim-equilibrium",
        "--c",
        "0.042,0.055,0.055",
        "--length",
        "0.63",
        "--tip-position",
        "0.5,0.1,0",
        "--tip-rotation",
        "0,0,0.5",
        "--edges",
        "30",
    ]);
    assert_success(&out, "human output");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("base clamp frame"), "{text}");
}

fn run(args: &[&str], extra: &[Vec<String>]) -> std::process::Output {
    let mut all: Vec<&str> = args.to_vec();
    all.extend(extra.iter().flatten().map(String::as_str));
    ftwire(&all)
}

#[test]
fn every_vector_option_takes_a_leading_minus_in_both_forms() {
    let wire = [
        "sim-equilibrium",
        "--c",
        "0.042,0.055,0.055",
        "--length",
        "0.63",
    ];
    // The tip behind and beside the base, turned about −x and z, gravity along −x: the last
    // shape point is the commanded (negative) tip position, and the forces balance the weight,
    // f_base + R_tip f_tip = m g (wrenches are those the wire exerts on the grippers).
    let (position, rotation, gravity) = ("-0.2,0.3,0", "-0.3,0,2.5", "-9.81,0,0");
    let rotation_matrix = UnitQuaternion::from_scaled_axis(Vector3::new(-0.3, 0.0, 2.5));
    let weight = 6450.0 * std::f64::consts::PI * 0.001_f64.powi(2) * 0.63 * 9.81;
    for form in 0..2 {
        let extra: Vec<Vec<String>> = [
            ("--tip-position", position),
            ("--tip-rotation", rotation),
            ("--gravity", gravity),
        ]
        .iter()
        .map(|(o, v)| both_forms(o, v)[form].clone())
        .chain([vec!["--edges".into(), "30".into(), "--json".into()]])
        .collect();
        let out = run(&wire, &extra);
        assert_success(&out, &format!("form {form}"));
        let v = json(&out);
        let shape: Vec<Vec<f64>> = serde_json::from_value(v["shape"].clone()).expect("points");
        let last = shape.last().expect("points");
        assert!(
            (last[0] + 0.2).abs() < 1e-12 && (last[1] - 0.3).abs() < 1e-12,
            "{last:?}"
        );
        let (base, tip) = (numbers(&v["base_wrench"]), numbers(&v["tip_wrench"]));
        let total = Vector3::new(base[3], base[4], base[5])
            + rotation_matrix * Vector3::new(tip[3], tip[4], tip[5]);
        let expected = Vector3::new(-weight, 0.0, 0.0);
        assert!(
            (total - expected).norm() < 1e-3 * weight,
            "form {form}: forces {total} do not balance the weight {expected}"
        );

        // --initial-a with a leading minus: the pure-bending arc a = (0, 0, −τ, 0, 0, 0) towards
        // −y, started from its own Kirchhoff shape with a small twist −0.001 in the guess.
        let (c3, tau, l) = (0.055_f64, 0.12_f64, 0.63_f64);
        let (r, turn) = (c3 / tau, l * tau / c3);
        let tip_position = format!("{},{},0", r * turn.sin(), -r * (1.0 - turn.cos()));
        let tip_rotation = format!("0,0,{}", -turn);
        let initial_a = format!("-0.001,0,{},0,0,0", -tau);
        let extra: Vec<Vec<String>> = vec![
            vec!["--tip-position".into(), tip_position],
            vec!["--tip-rotation".into(), tip_rotation],
            vec!["--gravity".into(), "0,0,0".into(), "--json".into()],
            both_forms("--initial-a", &initial_a)[form].clone(),
        ];
        let out = run(&wire, &extra);
        assert_success(&out, &format!("--initial-a, form {form}"));
        let base = numbers(&json(&out)["base_wrench"]);
        assert!((base[2] + tau).abs() < 1e-3 * tau, "{base:?}");

        // --c with a leading minus is parsed, then refused by the wire's own check.
        let out = run(
            &["sim-equilibrium", "--length", "0.63"],
            &[
                both_forms("--c", "-0.042,0.055,0.055")[form].clone(),
                vec!["--tip-position".into(), "0.5,0,0".into()],
                vec!["--tip-rotation".into(), "0,0,0".into()],
            ],
        );
        assert_exit(&out, 2, "c1", &format!("--c, form {form}"));
    }
}

#[test]
fn edges_are_bounded_with_a_clear_message() {
    let run = |edges: &str, name: &str| {
        ftwire(&[
            "sim-equilibrium",
            "--c",
            "0.042,0.055,0.055",
            "--length",
            "0.63",
            "--tip-position",
            "0.5,0.1,0",
            "--tip-rotation",
            "0,0,0.5",
            name,
            edges,
        ])
    };
    // The old name `--nodes` is the same option, named by its own name in the message.
    for (edges, name) in [("11", "--edges"), ("2001", "--edges"), ("0", "--nodes")] {
        let out = run(edges, name);
        let message = format!("--edges {edges}: at least 12 and at most 2000");
        assert_exit(&out, 2, &message, name);
    }
    assert_exit(
        &run("-5", "--edges"),
        2,
        "--edges \"-5\": not a whole number",
        "-5",
    );
    // The old name still works and means edges: N + 1 shape points.
    let out = run("12", "--nodes");
    assert_success(&out, "--nodes 12");
    assert!(String::from_utf8_lossy(&out.stdout).contains("shape: 13 points"));
}

#[test]
fn bad_inputs_exit_with_code_2_and_a_message() {
    let run = |c: &str, position: &str, extra: &[&str]| {
        let mut all = vec![
            "sim-equilibrium",
            "--c",
            c,
            "--length",
            "0.6",
            "--tip-position",
            position,
            "--tip-rotation",
            "0,0,0",
        ];
        all.extend_from_slice(extra);
        ftwire(&all)
    };
    let ok_c = "0.04,0.05,0.05";
    let expected_3 = "expected 3 comma-separated finite numbers";
    let cases = [
        (run("0.04,-0.05,0.05", "0.5,0,0", &[]), "c2"),
        (run("0.04,0.05", "0.5,0,0", &[]), expected_3),
        (run(ok_c, "0.7,0,0", &[]), "apart"),
        (run(ok_c, "-0.7,0,0", &[]), "apart"),
        (run(ok_c, "0.5,nan,0", &[]), "'--tip-position <X,Y,Z>'"),
        (
            run(ok_c, "0.5,0,0", &["--gravity", "0,0,-inf"]),
            "'--gravity <GX,GY,GZ>'",
        ),
        (run(ok_c, "0.5,0,0", &["--density", "-1"]), "density"),
        (run(ok_c, "0.5,0,0", &["--radius", "nan"]), "'--radius <R>'"),
        (
            run(ok_c, "0.5,0,0", &["--initial-a", "0,0,0.1,0,0"]),
            "expected 6 comma-separated finite numbers",
        ),
        (
            run(ok_c, "0.5,0,0", &["--initial-a", "1,0,0,1,0,0"]),
            "not a valid wire configuration",
        ),
    ];
    for (out, expected) in cases {
        assert_exit(&out, 2, expected, expected);
    }
}

#[test]
fn no_equilibrium_exits_1() {
    // Newton started from the Kirchhoff shape of a strongly bent arc, with the tip clamp on a
    // straight line: no equilibrium near the guess (deterministic, 200 iterations).
    let out = ftwire(&[
        "sim-equilibrium",
        "--c",
        "0.042,0.055,0.055",
        "--length",
        "0.63",
        "--tip-position",
        "0.5,0,0",
        "--tip-rotation",
        "0,0,0",
        "--gravity",
        "0,0,0",
        "--edges",
        "30",
        "--initial-a",
        "0,0,5,0,0,0",
    ]);
    assert_exit(&out, 1, "Newton failed", "far guess");
}

#[test]
fn initial_a_starts_newton_on_the_kirchhoff_branch() {
    // Pure bending a = (0, 0, τ, 0, 0, 0) is an arc of radius c3/τ; with the tip on that arc
    // and Newton started from the Kirchhoff shape, the base wrench is a again.
    let (c3, tau, l) = (0.055_f64, 0.12_f64, 0.6_f64);
    let r = c3 / tau;
    let turn = l / r;
    let out = ftwire(&[
        "sim-equilibrium",
        "--c",
        "0.042,0.055,0.055",
        "--length",
        &l.to_string(),
        "--tip-position",
        &format!("{},{},0", r * turn.sin(), r * (1.0 - turn.cos())),
        "--tip-rotation",
        &format!("0,0,{turn}"),
        "--gravity",
        "0,0,0",
        "--initial-a",
        &format!("0,0,{tau},0,0,0"),
        "--json",
    ]);
    assert_success(&out, "arc from its Kirchhoff shape");
    let v = json(&out);
    let wrench = numbers(&v["base_wrench"]);
    assert!((wrench[2] - tau).abs() < 1e-3 * tau, "{wrench:?}");
    // Other components vanish up to the simulator's discretisation error (N = 100): 0.1 % of τ
    // for torques, 1 % of the force scale c3/L² for forces.
    let force_scale = c3 / (l * l);
    for i in [0, 1] {
        assert!(wrench[i].abs() < 1e-3 * tau, "torque {i}: {wrench:?}");
    }
    for i in [3, 4, 5] {
        assert!(
            wrench[i].abs() < 1e-2 * force_scale,
            "force {i}: {wrench:?}"
        );
    }
    assert_eq!(v["stable_minimum"], true);
}
