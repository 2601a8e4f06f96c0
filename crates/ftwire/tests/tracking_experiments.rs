//! `ftwire experiment track` and `ftwire experiment passage`: small runs write the
//! summary keys the issue names, the same results for the same seed, and bad input is refused
//! with exit 2 before any work.

mod cli_support;

use std::path::Path;

use cli_support::{assert_exit, assert_success, ftwire, tiny_calibration};

fn run(args: &[&str], out: &Path, calibration: &Path) -> serde_json::Value {
    let mut all: Vec<&str> = args.to_vec();
    let (calibration, out) = (
        calibration.to_str().expect("a UTF-8 path"),
        out.to_str().expect("a UTF-8 path"),
    );
    all.extend(["--calibration", calibration, "--out", out]);
    let output = ftwire(&all);
    assert_success(&output, &all.join(" "));
    let text = std::fs::read_to_string(Path::new(out).join("summary.json")).expect("summary");
    let summary: serde_json::Value = serde_json::from_str(&text).expect("JSON");
    summary["summary"].clone()
}

/// `timings.json` of the results folder `out`.
fn timings(out: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(out.join("timings.json")).expect("timings.json");
    serde_json::from_str(&text).expect("JSON")
}

fn temp(name: &str) -> std::path::PathBuf {
    let tmp = std::env::temp_dir().join(format!("ftwire-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&tmp).expect("a temporary folder");
    tmp
}

#[test]
fn a_small_passage_experiment_writes_the_issue_keys_deterministically() {
    let tmp = temp("passage");
    let calibration = tiny_calibration(&tmp);
    let args = [
        "experiment",
        "passage",
        "--attempts",
        "2",
        "--noise-model",
        "offset",
        "--seed",
        "5",
    ];
    let first = run(&args, &tmp.join("a"), &calibration);
    cli_support::assert_golden_summary("passage-offset-seed5", &tmp.join("a"));
    for mode in ["open_loop", "closed_loop"] {
        let r = &first["results"][mode];
        assert_eq!(r["attempts"], 2, "results.{mode}.attempts");
        for key in ["successes", "collisions", "detected"] {
            let n = r[key].as_u64().unwrap_or(u64::MAX);
            assert!(n <= 2, "results.{mode}.{key} = {n}");
        }
        assert!(r["detected"].as_u64() <= r["collisions"].as_u64());
    }
    let closed = &first["results"]["closed_loop"];
    for key in ["retreats", "recovered", "false_alarms"] {
        assert!(closed[key].as_u64().is_some(), "results.closed_loop.{key}");
    }
    // Under `offset` the defaults are gain 0.5 and the ε stops (no shape stop).
    assert_eq!(first["gain"], 0.5);
    assert_eq!(first["shape_stop_mm"], 0.0);
    assert_eq!(first["shape_stop_near_mm"], 0.0);
    // The plan passes the 50 mm gap: some waypoints are near its boxes.
    assert!(
        first["plan"]["near_waypoints"]
            .as_u64()
            .is_some_and(|n| n >= 1)
    );
    // The plan's time is in timings.json, not in the summary.
    assert!(first.get("plan_ms").is_none());
    assert!(
        timings(&tmp.join("a"))["plan_ms"]
            .as_f64()
            .is_some_and(|t| t > 0.0)
    );
    assert!(first["plan"]["waypoints"].as_u64().is_some_and(|n| n >= 2));
    // Under `offset` the loop converges onto the plan: no clearance polish.
    assert!(first["plan"]["polish"].is_null());
    // waypoints.csv: an attempt with a leg that touched a box is counted as a collision.
    let legs = std::fs::read_to_string(tmp.join("a").join("waypoints.csv")).expect("waypoints.csv");
    assert!(legs.starts_with("attempt,waypoint,moves,outcome,shape_mm,scored,touched\n"));
    let mut touching: Vec<&str> = legs
        .lines()
        .skip(1)
        .filter(|l| l.ends_with(",true"))
        .filter_map(|l| l.split(',').next())
        .collect();
    touching.dedup();
    assert!(legs.lines().count() > 2, "{legs}");
    assert!(
        Some(touching.len() as u64) <= closed["collisions"].as_u64(),
        "{legs}"
    );
    for file in [
        "attempts.csv",
        "report.md",
        "report.html",
        "timings.json",
        "passage_path_in_a.png",
        "passage_shape_error.svg",
        "passage_scene.png",
    ] {
        assert!(tmp.join("a").join(file).is_file(), "{file}");
    }
    let second = run(&args, &tmp.join("b"), &calibration);
    assert_eq!(first, second, "same seed, same results");
    // Under the paper's noise the waypoints whose landings come close to a box are polished:
    // the closest landing moves away, and every waypoint keeps the plan's 15 mm margin;
    // `--no-polish` tracks them as resampled.
    let noisy = ["experiment", "passage", "--attempts", "1", "--seed", "5"];
    let polished = run(
        &[&noisy[..], &["--plan-candidates", "2"]].concat(),
        &tmp.join("c"),
        &calibration,
    );
    // Of two plans, the one expecting fewer touching landings is tracked.
    let choice = &polished["plan"]["choice"];
    assert_eq!(choice["candidates"], 2, "{choice}");
    let touches: Vec<f64> = choice["expected_touches"]
        .as_array()
        .expect("plan.choice.expected_touches")
        .iter()
        .map(|t| t.as_f64().unwrap_or(f64::INFINITY))
        .collect();
    assert_eq!(touches.len(), 2, "{choice}");
    let chosen = choice["chosen"].as_u64().expect("plan.choice.chosen") as usize;
    assert!(touches.iter().all(|&t| touches[chosen] <= t), "{choice}");
    assert!(
        touches[..chosen].iter().all(|&t| t > touches[chosen]),
        "{choice}"
    );
    assert!(choice.get("plan_ms").is_none(), "{choice}");
    assert_eq!(
        timings(&tmp.join("c"))["candidate_plan_ms"]
            .as_array()
            .map(Vec::len),
        Some(2),
        "each candidate's planning time"
    );
    // Under `offset` one plan is made, without a choice.
    assert!(first["plan"]["choice"].is_null());
    let polish = &polished["plan"]["polish"];
    assert_eq!(polish["valid"], true, "{polish}");
    assert!(polish["moved"].as_u64().is_some_and(|n| n >= 1), "{polish}");
    let mm = |key: &str| polish[key].as_f64().unwrap_or(f64::NAN);
    assert!(
        mm("min_landing_clearance_after_mm") > mm("min_landing_clearance_before_mm"),
        "{polish}"
    );
    assert!(mm("min_clearance_after_mm") >= 15.0, "{polish}");
    let unpolished = run(
        &[&noisy[..], &["--no-polish"]].concat(),
        &tmp.join("d"),
        &calibration,
    );
    assert!(unpolished["plan"]["polish"].is_null());
    let _ = std::fs::remove_dir_all(&tmp);
}

#[test]
fn a_small_track_experiment_writes_table_iv() {
    let tmp = temp("track");
    let calibration = tiny_calibration(&tmp);
    let args = [
        "experiment",
        "track",
        "--pairs",
        "1",
        "--gravity",
        "off",
        "--noise-model",
        "offset",
        "--seed",
        "2",
    ];
    let summary = run(&args, &tmp.join("a"), &calibration);
    cli_support::assert_golden_summary("track-offset-seed2", &tmp.join("a"));
    for mode in ["open_loop", "closed_loop"] {
        let r = &summary["results"][mode];
        let (mean, std, max) = (
            r["mean_mm"].as_f64().expect("mean_mm"),
            r["std_mm"].as_f64().expect("std_mm"),
            r["max_mm"].as_f64().expect("max_mm"),
        );
        assert!(mean > 0.0 && std >= 0.0 && max >= mean, "{mode}: {r}");
    }
    assert!(summary.get("plan_ms_median").is_none());
    assert!(
        timings(&tmp.join("a"))["plan_ms_median"]
            .as_f64()
            .is_some_and(|t| t > 0.0)
    );
    assert_eq!(summary["pairs"], 1);
    for file in ["pairs.csv", "track_path_in_a.png", "track_shape_error.png"] {
        assert!(tmp.join("a").join(file).is_file(), "{file}");
    }
    // waypoints.csv: its scored legs are exactly Table IV's closed-loop waypoints.
    let legs = std::fs::read_to_string(tmp.join("a").join("waypoints.csv")).expect("waypoints.csv");
    let mut lines = legs.lines();
    assert_eq!(
        lines.next(),
        Some("pair,waypoint,moves,outcome,shape_mm,scored,touched")
    );
    let scored: Vec<f64> = lines
        .map(|l| l.split(',').collect::<Vec<_>>())
        .filter(|fields| fields[fields.len() - 2] == "true")
        .map(|fields| fields[fields.len() - 3].parse().expect("shape_mm"))
        .collect();
    let closed = &summary["results"]["closed_loop"];
    assert_eq!(
        Some(scored.len() as u64),
        closed["waypoints"].as_u64(),
        "{legs}"
    );
    let mean = scored.iter().sum::<f64>() / scored.len() as f64;
    let reported = closed["mean_mm"].as_f64().expect("mean_mm");
    assert!((mean - reported).abs() < 1e-3, "{mean} against {reported}");
    let _ = std::fs::remove_dir_all(&tmp);
}

#[test]
fn bad_options_are_refused_before_any_work() {
    let output = ftwire(&["experiment", "passage", "--attempts", "0"]);
    assert_exit(&output, 2, "--attempts 0", "passage --attempts 0");
    let output = ftwire(&["experiment", "track", "--pairs", "0"]);
    assert_exit(&output, 2, "--pairs 0", "track --pairs 0");
    let output = ftwire(&["experiment", "passage", "--plan-candidates", "0"]);
    assert_exit(
        &output,
        2,
        "--plan-candidates 0",
        "passage --plan-candidates 0",
    );
    let output = ftwire(&["experiment", "passage", "--gain", "1.5"]);
    assert_exit(&output, 2, "--gain 1.5", "passage --gain 1.5");
    let output = ftwire(&["experiment", "track", "--shape-stop", "-1"]);
    assert_exit(&output, 2, "--shape-stop -1", "track --shape-stop -1");
    let output = ftwire(&["experiment", "passage", "--near-shape-stop", "-2"]);
    assert_exit(
        &output,
        2,
        "--near-shape-stop -2",
        "passage --near-shape-stop -2",
    );
    for command in ["track", "passage"] {
        let output = ftwire(&["experiment", command, "--waypoint-moves", "0"]);
        assert_exit(&output, 2, "--waypoint-moves 0", "--waypoint-moves 0");
    }
    let output = ftwire(&["experiment", "passage", "--scene", "/no/such/scene.toml"]);
    assert_exit(&output, 2, "scene.toml", "passage --scene missing");
}

#[test]
fn a_scene_with_an_unknown_key_names_it() {
    let tmp = temp("passage-bad-scene");
    let scene = tmp.join("bad.toml");
    std::fs::write(
        &scene,
        "[base]\nposition = [0.6, 0.35, 0.35]\ncolour = \"red\"\n",
    )
    .expect("write");
    let output = ftwire(&[
        "experiment",
        "passage",
        "--scene",
        scene.to_str().expect("UTF-8"),
    ]);
    assert_exit(&output, 2, "colour", "passage with an unknown scene key");
    let _ = std::fs::remove_dir_all(&tmp);
}

#[test]
fn the_shipped_passage_variants_have_their_start_and_goal_in_z_free() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/variants");
    let mut checked = 0;
    for entry in std::fs::read_dir(&dir).expect("scenes/variants") {
        let path = entry.expect("an entry").path();
        if path.extension().is_some_and(|e| e == "toml") {
            let output = ftwire(&["scene", "check", path.to_str().expect("UTF-8")]);
            assert_success(&output, &format!("scene check {}", path.display()));
            checked += 1;
        }
    }
    assert!(checked >= 7, "{checked} variants");
}
