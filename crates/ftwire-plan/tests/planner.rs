//! RRT* in the passage scene: seeded determinism, validity of the found paths at a finer
//! resolution, cost that does not rise with iterations, the anytime budget, resampling, and
//! the `Z = A × Q` planner.

mod common;

use std::time::{Duration, Instant};

use ftwire_plan::{
    Checker, FixedBase, MovingBase, Plan, PlanError, PlannerParams, Sample, ValidityParams, plan,
    scene_endpoint,
};
use ftwire_robot::Robot;

fn endpoints(checker: &Checker) -> (ftwire_plan::Scene, Sample, Sample) {
    let scene = common::passage();
    let start = scene_endpoint(&scene, checker, "start", "start").expect("valid start");
    let goal = scene_endpoint(&scene, checker, "goal", "goal").expect("valid goal");
    (scene, start, goal)
}

fn fixed_plan(params: &PlannerParams) -> (Checker, FixedBase, Result<Plan, PlanError>) {
    let checker = common::checker(&common::passage());
    let (scene, start, goal) = endpoints(&checker);
    let space = FixedBase::around(
        *checker.rod().wire(),
        scene.base,
        &[start.config, goal.config],
        2.0,
    );
    let result = plan(&space, &checker, &start, &goal.config, params);
    (checker, space, result)
}

fn quick(seed: u64) -> PlannerParams {
    PlannerParams {
        seed,
        max_iterations: 400,
        stop_at_first: true,
        ..PlannerParams::default()
    }
}

#[test]
fn same_seed_same_path() {
    let (_, _, a) = fixed_plan(&quick(4));
    let (_, _, b) = fixed_plan(&quick(4));
    let (a, b) = (a.expect("a path"), b.expect("a path"));
    assert_eq!(a.iterations, b.iterations);
    assert_eq!(common::configs(&a), common::configs(&b));
    let (_, _, c) = fixed_plan(&quick(5));
    assert_ne!(
        common::configs(&a),
        common::configs(&c.expect("a path")),
        "another seed, another path"
    );
}

#[test]
fn found_paths_are_valid_at_a_finer_resolution() {
    let fine_params = ValidityParams {
        max_step: 0.25 / 4.0,
        ..ValidityParams::default()
    };
    let scene = common::passage();
    let fine = Checker::new(
        common::rod(),
        Robot::sda10f().expect("robot"),
        &scene,
        fine_params,
    )
    .expect("valid settings");
    for seed in [0, 4] {
        let (checker, _, found) = fixed_plan(&quick(seed));
        let found = found.expect("a path");
        let w = &found.path.waypoints;
        assert!(w.len() >= 2);
        let (_, start, goal) = endpoints(&checker);
        assert_eq!(w[0].config, start.config);
        assert_eq!(w[w.len() - 1].config, goal.config);
        assert_eq!(found.path.edge_clearance.len(), w.len() - 1);
        assert!(found.path.min_clearance() >= checker.params().margin);
        for pair in w.windows(2) {
            let edge = fine.edge(&pair[0], &pair[1].config);
            let edge = edge.unwrap_or_else(|e| panic!("seed {seed}: an edge fails finer: {e}"));
            assert!(edge.min_clearance >= fine.params().margin);
        }
    }
}

#[test]
fn the_cost_does_not_rise_with_iterations() {
    let run = |iterations| {
        let params = PlannerParams {
            seed: 0,
            max_iterations: iterations,
            shortcut_attempts: 0,
            ..PlannerParams::default()
        };
        fixed_plan(&params)
            .2
            .expect("a path")
            .best_cost_before_shortcut
    };
    // From the iteration that found the first path, and 150 iterations on.
    let first = fixed_plan(&quick(0))
        .2
        .expect("a path")
        .first_path_iteration;
    let (short, long) = (run(first), run(first + 150));
    assert!(long <= short, "{long} > {short}");
}

#[test]
fn the_time_budget_is_respected() {
    let budget = Duration::from_millis(400);
    let params = PlannerParams {
        seed: 1,
        time_budget: Some(budget),
        max_iterations: usize::MAX,
        shortcut_attempts: 0,
        ..PlannerParams::default()
    };
    let clock = Instant::now();
    let (_, _, result) = fixed_plan(&params);
    let elapsed = clock.elapsed();
    // One iteration and the endpoints' IK may overrun the budget a little; not by seconds.
    assert!(elapsed < budget + Duration::from_secs(2), "{elapsed:?}");
    match result {
        Ok(p) => assert!(p.seconds >= budget.as_secs_f64()),
        Err(PlanError::NoPath { seconds, .. }) => assert!(seconds >= budget.as_secs_f64()),
        Err(e) => panic!("{e}"),
    }
}

#[test]
fn a_path_resamples_into_n_continuous_waypoints() {
    let (checker, space, found) = fixed_plan(&quick(0));
    let path = found.expect("a path").path;
    let n = 20;
    let waypoints = path
        .resample(&space, &checker, n)
        .expect("valid along the path");
    assert_eq!(waypoints.len(), n + 1);
    assert_eq!(waypoints[0].config, path.waypoints[0].config);
    let last = &path.waypoints[path.waypoints.len() - 1];
    assert!((waypoints[n].config.a - last.config.a).norm() <= 1e-9 * last.config.a.norm());
    // Equal steps in normalised a, but where a step cuts a corner of the path.
    let wire = checker.rod().wire();
    let steps: Vec<f64> = waypoints
        .windows(2)
        .map(|w| {
            (ftwire_rod::to_normalised(wire, &w[1].config.a)
                - ftwire_rod::to_normalised(wire, &w[0].config.a))
            .norm()
        })
        .collect();
    let mean = path.length(&checker) / n as f64;
    assert!(steps.iter().all(|&s| s <= mean * (1.0 + 1e-9)));
    let equal = steps
        .iter()
        .filter(|&&s| approx::relative_eq!(s, mean, max_relative = 1e-6));
    assert!(equal.count() >= n - (path.waypoints.len() - 2));
}

#[test]
fn the_moving_base_planner_finds_a_path_in_the_passage() {
    let checker = common::checker(&common::passage());
    let (scene, start, goal) = endpoints(&checker);
    let fixed = FixedBase::around(
        *checker.rod().wire(),
        scene.base,
        &[start.config, goal.config],
        2.0,
    );
    let space = MovingBase {
        translation_range: 0.05,
        rotation_range: 0.2,
        ..MovingBase::new(*checker.rod().wire(), scene.base, 0.0)
    }
    .with_a_box(fixed.lower, fixed.upper);
    let params = PlannerParams {
        max_iterations: 600,
        stop_at_first: true,
        ..PlannerParams::default()
    };
    let found = plan(&space, &checker, &start, &goal.config, &params).expect("a path");
    let w = &found.path.waypoints;
    assert_eq!(w[w.len() - 1].config, goal.config);
}
