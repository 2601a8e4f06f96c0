//! `ftwire sim-equilibrium` end to end.

use std::process::Command;

fn ftwire(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_ftwire"))
        .args(args)
        .output()
        .expect("runs the binary")
}

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
        "--nodes",
        "60",
        "--json",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    assert_eq!(v["converged"], true);
    assert_eq!(v["stable_minimum"], true);
    // Without --initial-a the wire is bent from straight by continuation: `iterations` is the
    // total over its steps, far more than one Newton solve takes.
    assert!(v["iterations"].as_u64().is_some_and(|n| n > 20), "{v}");
    assert!(v["energy"].as_f64().is_some_and(|e| e > 0.0));
    let base: Vec<f64> = serde_json::from_value(v["base_wrench"].clone()).expect("6 numbers");
    let tip: Vec<f64> = serde_json::from_value(v["tip_wrench"].clone()).expect("6 numbers");
    assert_eq!((base.len(), tip.len()), (6, 6));
    assert!((base[2] - 0.07 / r).abs() < 0.01 * 0.07 / r, "{base:?}");
    assert!((tip[2] + 0.07 / r).abs() < 0.01 * 0.07 / r, "{tip:?}");
    let shape = v["shape"].as_array().expect("shape");
    assert_eq!(shape.len(), 61);
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
        "--nodes",
        "30",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("base clamp frame"), "{text}");
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
    let cases = [
        (run("0.04,-0.05,0.05", "0.5,0,0", &[]), "c2"),
        (run("0.04,0.05", "0.5,0,0", &[]), "exactly 3"),
        (run(ok_c, "0.7,0,0", &[]), "apart"),
        (run(ok_c, "0.5,0,0", &["--nodes", "2"]), "edges"),
        (
            run(ok_c, "0.5,0,0", &["--initial-a", "0,0,0.1,0,0"]),
            "exactly 6",
        ),
        (
            run(ok_c, "0.5,0,0", &["--initial-a", "1,0,0,1,0,0"]),
            "not a valid wire configuration",
        ),
    ];
    for (out, expected) in cases {
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{expected}: {err}");
        assert!(err.contains(expected), "{expected}: {err}");
    }
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
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    let wrench: Vec<f64> = v["base_wrench"]
        .as_array()
        .expect("base_wrench")
        .iter()
        .map(|x| x.as_f64().expect("number"))
        .collect();
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
