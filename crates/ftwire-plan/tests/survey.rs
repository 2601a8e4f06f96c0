//! The fixed-base planner (A_free) against the moving-base one (Z = A × Q) on the passage scene
//! and two variants: a narrower gap and a closed wall. Prints a table; slow, so ignored:
//!
//! `cargo test -p ftwire-plan --release --test survey -- --ignored --nocapture`

mod common;

use std::time::Duration;

use ftwire_plan::{FixedBase, MovingBase, PlannerParams, Scene, plan, scene_endpoint};

fn variant(from: &str, to: &str) -> Scene {
    let text = std::fs::read_to_string(common::passage_path()).expect("reads");
    assert!(text.contains(from));
    Scene::from_toml(&text.replace(from, to), "variant").expect("parses")
}

#[test]
#[ignore = "a survey: about a minute"]
fn fixed_against_moving_base() {
    let scenes = [
        ("passage, 50 mm gap", common::passage()),
        (
            "gap narrowed to 30 mm",
            variant(
                "centre = [0.825, 0.05, 0.35]",
                "centre = [0.805, 0.05, 0.35]",
            ),
        ),
        (
            "wall closed",
            variant(
                "centre = [0.825, 0.05, 0.35]",
                "centre = [0.775, 0.05, 0.35]",
            ),
        ),
    ];
    let budget = 3.0;
    let seeds = 0..4u64;
    println!(
        "| scene | planner | paths found (seeds 0–3, {budget} s each) | first path [s] | length |"
    );
    println!("| --- | --- | --- | --- | --- |");
    for (name, scene) in &scenes {
        let checker = common::checker(scene);
        let start = scene_endpoint(scene, &checker, "start", "start").expect("valid start");
        let goal = scene_endpoint(scene, &checker, "goal", "goal").expect("valid goal");
        let wire = *checker.rod().wire();
        let fixed = FixedBase::around(wire, scene.base, &[start.config, goal.config], 2.0);
        let moving = MovingBase::new(wire, scene.base, 0.0).with_a_box(fixed.lower, fixed.upper);
        for planner in ["fixed", "moving"] {
            let (mut found, mut first, mut length) = (0, Vec::new(), Vec::new());
            for seed in seeds.clone() {
                let params = PlannerParams {
                    seed,
                    time_budget: Some(Duration::from_secs_f64(budget)),
                    max_iterations: usize::MAX,
                    stop_at_first: true,
                    ..PlannerParams::default()
                };
                let result = match planner {
                    "fixed" => plan(&fixed, &checker, &start, &goal.config, &params),
                    _ => plan(&moving, &checker, &start, &goal.config, &params),
                };
                if let Ok(p) = result {
                    found += 1;
                    first.push(p.first_path_seconds);
                    length.push(p.path.length(&checker));
                }
            }
            let mean = |v: &[f64]| {
                if v.is_empty() {
                    "–".to_string()
                } else {
                    format!("{:.2}", v.iter().sum::<f64>() / v.len() as f64)
                }
            };
            println!(
                "| {name} | {planner} | {found}/{} | {} | {} |",
                seeds.end,
                mean(&first),
                mean(&length)
            );
        }
    }
}
