//! A plan and a scene's check as library calls: the path runs from the scene's start to its
//! goal, the check gives each configuration's verdict, and bad settings are refused first.

use ftwire_lab::plan::{self, PlanParams, PlanWireParams, Planner, SceneCheckParams};

mod common;

use common::TempDir;

/// The shipped passage scene without its two blocks: an open scene, where a path is found
/// in a few iterations.
const OPEN: &str = "[base]\nposition = [0.60, 0.35, 0.35]\nrotation = [0.0, 0.0, -1.5707963267948966]\n\
    [configuration.start]\na_normalised = [-0.35, -3.0, -0.3, -9.0, 0.47, 6.5]\n\
    [configuration.goal]\na_normalised = [-0.92, 1.22, 0.17, -5.47, 2.52, 3.79]\n";

#[test]
fn a_plan_in_an_open_scene_runs_from_start_to_goal() {
    let dir = TempDir::new("plan");
    let scene = dir.0.join("open.toml");
    std::fs::write(&scene, OPEN).expect("writes the scene");
    let params = PlanParams {
        scene: Some(scene),
        iterations: 2_000,
        time_budget: 60.0,
        first: true,
        resample: Some(4),
        seed: 1,
        ..PlanParams::default()
    };
    params.check().expect("valid settings");
    let report = plan::run(&params).expect("a path");
    assert_eq!(report.planner, Planner::Fixed);
    let (first, last) = (
        report.waypoints.first().expect("a start"),
        report.waypoints.last().expect("a goal"),
    );
    let start = [-0.35, -3.0, -0.3, -9.0, 0.47, 6.5];
    let goal = [-0.92, 1.22, 0.17, -5.47, 2.52, 3.79];
    for (w, expected) in [(first, start), (last, goal)] {
        for (x, y) in w.a_normalised.iter().zip(expected) {
            approx::assert_abs_diff_eq!(*x, y, epsilon = 1e-9);
        }
        assert_eq!(w.joints.left.len(), 7);
    }
    assert_eq!(report.resampled.as_ref().map(Vec::len), Some(5));
    assert!(report.min_clearance >= params.wire.margin);
    assert!(report.length > 0.0 && report.cost >= report.length - 1e-12);
    let text = report.to_string();
    assert!(
        text.starts_with("path from \"start\" to \"goal\""),
        "{text}"
    );
    assert_eq!(text.lines().count(), 3 + report.waypoints.len());
}

#[test]
fn bad_plan_settings_are_refused_before_any_work() {
    let no_scene = PlanParams::default();
    let e = no_scene.check().expect_err("no scene");
    assert!(e.to_string().contains("--scene"), "{e}");
    for budget in [0.0, -1.0, f64::NAN, 601.0] {
        let params = PlanParams {
            time_budget: budget,
            ..PlanParams::default()
        };
        let e = params.check().expect_err("a bad budget");
        assert_eq!(e.exit_code(), 2);
        assert!(e.to_string().starts_with("--time-budget"), "{e}");
    }
}

#[test]
fn the_passage_check_finds_start_and_goal_free_and_names_a_missing_one() {
    let dir = TempDir::new("scene-check");
    let file = dir.0.join("passage.toml");
    std::fs::write(&file, ftwire_lab::scene::PASSAGE).expect("writes the scene");
    let mut params = SceneCheckParams {
        file,
        wire: PlanWireParams::default(),
        start: "start".to_owned(),
        goal: "goal".to_owned(),
    };
    let report = plan::check_scene(&params).expect("a readable scene");
    assert_eq!(report.obstacles, ["front block", "back block"]);
    assert!(report.configurations.iter().all(|c| c.valid));
    report
        .require_endpoints()
        .expect("start and goal in Z_free");
    assert!(report.to_string().contains("start (start): in Z_free"));
    params.goal = "elsewhere".to_owned();
    let report = plan::check_scene(&params).expect("a readable scene");
    let e = report.require_endpoints().expect_err("no such goal");
    assert_eq!(e.exit_code(), 2);
    assert!(e.to_string().starts_with("--goal: "), "{e}");
    assert!(e.to_string().contains("goal, start"), "{e}");
}
