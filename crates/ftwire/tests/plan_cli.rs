//! `ftwire plan` and `ftwire scene check`, run as a user would: each exit code, and the scene's
//! obstacles in the simulator.

mod cli_support;

use cli_support::{assert_exit, assert_success, ftwire, json, numbers};
use rand::{RngExt, SeedableRng};

fn passage() -> String {
    concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/passage.toml").to_string()
}

/// A temporary scene file: the passage scene with `from` replaced by `to`.
fn edited(name: &str, from: &str, to: &str) -> std::path::PathBuf {
    let text = std::fs::read_to_string(passage()).expect("the passage scene");
    assert!(text.contains(from), "{from}");
    let path = std::env::temp_dir().join(format!(
        "ftwire-plan-cli-{}-{name}.toml",
        std::process::id()
    ));
    std::fs::write(&path, text.replace(from, to)).expect("writes");
    path
}

#[test]
fn plan_prints_a_path_with_poses_and_joints() {
    let out = ftwire(&[
        "plan",
        "--scene",
        &passage(),
        "--wire",
        "nitinol-3mm-820",
        "--seed",
        "2",
        "--first",
        // An iteration budget, not the default 2 s, so that a busy machine
        // does not end the search before seed 2 finds its path.
        "--iterations",
        "5000",
        "--time-budget",
        "600",
        "--resample",
        "10",
        "--json",
    ]);
    assert_success(&out, "plan the passage");
    let v = json(&out);
    let w = v["waypoints"].as_array().expect("waypoints");
    assert!(w.len() >= 2);
    let first = numbers(&w[0]["a_normalised"]);
    let start = [-0.35, -3.0, -0.3, -9.0, 0.47, 6.5];
    for (x, y) in first.iter().zip(start) {
        assert!((x - y).abs() < 1e-12, "{first:?}");
    }
    for key in ["a", "a_normalised"] {
        assert_eq!(numbers(&w[0][key]).len(), 6);
    }
    assert_eq!(numbers(&w[0]["joints"]["right"]).len(), 7);
    assert_eq!(numbers(&w[0]["tip"]["position"]).len(), 3);
    assert!(v["length"].as_f64().expect("a length") > 0.0);
    assert!(v["min_clearance"].as_f64().expect("clearance") >= 0.005);
    assert_eq!(v["resampled"].as_array().expect("resampled").len(), 11);
}

#[test]
fn a_bad_scene_exits_2_naming_the_item() {
    let bad = edited(
        "extent",
        "half_extents = [0.15, 0.015, 0.05]",
        "half_extents = [0.15, 0.0, 0.05]",
    );
    let bad = bad.to_string_lossy().to_string();
    let out = ftwire(&["plan", "--scene", &bad, "--json"]);
    assert_exit(&out, 2, "half_extents[1]", "plan, zero extent");
    assert_exit(&out, 2, "back block", "plan, zero extent");
    let out = ftwire(&["scene", "check", &bad]);
    assert_exit(&out, 2, "half_extents[1]", "scene check, zero extent");
    let unknown = edited("key", "[base]", "[base]\ncolor = 1");
    let out = ftwire(&["scene", "check", &unknown.to_string_lossy()]);
    assert_exit(&out, 2, "color", "scene check, unknown key");
    let out = ftwire(&["plan", "--scene", &passage(), "--start", "nowhere"]);
    assert_exit(&out, 2, "nowhere", "plan, unknown start");
    for (option, value, needle) in [
        ("--time-budget", "0", "--time-budget"),
        ("--time-budget", "-1", "--time-budget"),
        ("--time-budget", "1e300", "--time-budget"),
        ("--resample", "0", "--resample"),
        ("--margin", "-0.001", "margin"),
        ("--clearance-weight", "-1", "clearance_weight"),
        ("--max-span", "0", "max_span"),
        ("--max-span", "1.2", "max_span"),
        // The start holds the grippers 0.72 m apart, 88 % of the wire.
        ("--max-span", "0.85", "too far apart"),
    ] {
        let out = ftwire(&["plan", "--scene", &passage(), option, value]);
        assert_exit(&out, 2, needle, &format!("plan {option} {value}"));
    }
}

#[test]
fn a_start_in_collision_exits_2_naming_it() {
    // The back block moved up onto the start's crossing of the wall.
    let blocked = edited(
        "blocked",
        "centre = [0.425, 0.05, 0.35]",
        "centre = [0.575, 0.05, 0.45]",
    );
    let blocked = blocked.to_string_lossy().to_string();
    let out = ftwire(&["plan", "--scene", &blocked]);
    assert_exit(
        &out,
        2,
        "start configuration \"start\"",
        "plan, start blocked",
    );
    assert_exit(&out, 2, "back block", "plan, start blocked");
    let out = ftwire(&["scene", "check", &blocked, "--json"]);
    assert_exit(&out, 2, "\"start\"", "scene check, start blocked");
    let v = json(&out);
    let start = v["configurations"]
        .as_array()
        .expect("configurations")
        .iter()
        .find(|c| c["name"] == "start")
        .expect("start is reported");
    assert_eq!(start["valid"], false);
}

#[test]
fn scene_check_reports_a_valid_scene() {
    let out = ftwire(&["scene", "check", &passage(), "--json"]);
    assert_success(&out, "scene check the passage");
    let v = json(&out);
    for c in v["configurations"].as_array().expect("configurations") {
        assert_eq!(c["valid"], true, "{c}");
        assert!(c["clearance"].as_f64().expect("clearance") >= 0.005);
    }
}

#[test]
fn no_path_exits_1_with_the_reason() {
    // The front block moved back onto the back block: the gap is closed, and the only ways
    // left, around the ends of the wall, are not found in 30 iterations.
    let closed = edited(
        "closed",
        "centre = [0.825, 0.05, 0.35]",
        "centre = [0.775, 0.05, 0.35]",
    );
    let out = ftwire(&[
        "plan",
        "--scene",
        &closed.to_string_lossy(),
        "--iterations",
        "30",
        "--seed",
        "1",
    ]);
    assert_exit(
        &out,
        1,
        "no path found in 30 iterations",
        "plan, closed wall",
    );
}

#[test]
fn the_simulator_gets_the_scenes_boxes() {
    let scene = ftwire_plan::Scene::load(passage()).expect("parses");
    let obstacles = ftwire_lab::scene::sim_obstacles(&scene).expect("valid boxes");
    assert_eq!(obstacles.len(), scene.boxes.len());
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
    for (o, b) in obstacles.iter().zip(&scene.boxes) {
        let ftwire_sim::Obstacle::Box(sim) = o else {
            panic!("a box");
        };
        for _ in 0..200 {
            let p = nalgebra::Point3::new(
                rng.random_range(0.1..1.2),
                rng.random_range(-0.2..0.3),
                rng.random_range(0.1..0.6),
            );
            let planner = ftwire_robot::point_box_distance(&p, &b.geometry);
            let simulator = sim.signed_distance(&p);
            if simulator > 0.0 {
                assert!(
                    (planner - simulator).abs() < 1e-12,
                    "{planner} vs {simulator}"
                );
            } else {
                assert!(planner.abs() < 1e-12, "inside: {planner}");
            }
        }
    }
    // A floor comes along too.
    let text = std::fs::read_to_string(passage()).expect("reads") + "\n[floor]\nheight = -0.4\n";
    let scene = ftwire_plan::Scene::from_toml(&text, "floor").expect("parses");
    let obstacles = ftwire_lab::scene::sim_obstacles(&scene).expect("valid");
    assert!(matches!(obstacles.last(), Some(ftwire_sim::Obstacle::Floor(f)) if f.height == -0.4));
}
