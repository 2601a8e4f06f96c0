//! A plan for tracking on the shipped passage: one plan without a choice where the loop
//! converges, the margins of a noisy plan kept along its path, the waypoints near the boxes,
//! and a relocation of both grippers.

mod common;

use common::{rod, shipped_passage};
use ftwire_core::{GripperPoses, Pose};
use ftwire_plan::{
    Checker, MARGIN_NOISY, MAX_SPAN_NOISY, PlanError, PlanPolicy, ScenePlan, WAYPOINTS, Waypoint,
    ZPoint, candidate_seed, choose_plan, near_obstacles, plan_in_scene, relocation,
    scene_configuration, waypoints_along,
};
use ftwire_robot::Robot;
use ftwire_rod::{Load, Rod, WireParams};
use nalgebra::{Point3, Vector3, Vector6};

/// The paper's noise (10 mm, 3° per axis, 1 σ).
fn noisy() -> PlanPolicy {
    PlanPolicy::scattered(0.010, 3f64.to_radians())
}

/// The nitinol wire of `length` loaded by its weight in the passage's base clamp frame.
fn loaded(length: f64) -> Rod {
    let scene = shipped_passage();
    let wire = WireParams::new([0.214, 0.278, 0.278], length, 0.0015).expect("valid wire");
    let g_clamp = scene.base.rotation.inverse() * Vector3::new(0.0, 0.0, -9.81);
    Rod::new(wire).with_load(Load::from_gravity(6450.0, 0.0015, g_clamp).expect("a load"))
}

#[test]
fn one_plan_is_made_without_a_choice_where_the_loop_converges() {
    let scene = shipped_passage();
    let tracker = loaded(0.82);
    let planner = Rod::new(*tracker.wire());
    let policy = PlanPolicy::converging();
    let validity = policy.validity_tracked(&tracker);
    let prepare = |planned: &ScenePlan| {
        waypoints_along(
            &tracker,
            &scene.base,
            &planned.plan.path.waypoints,
            WAYPOINTS,
        )
    };
    let choose = |candidates| {
        choose_plan::<PlanError>(
            &scene, &planner, &tracker, validity, &policy, 3, candidates, false, prepare,
        )
    };
    let err = choose(0).expect_err("no plan to make");
    assert!(matches!(err, PlanError::InvalidParameter { .. }), "{err}");
    // Four candidates asked for: the one plan `plan_in_scene` makes.
    let chosen = choose(4).expect("a path");
    assert!(chosen.choice.is_none());
    assert!(chosen.polish.is_none());
    let (alone, _) = plan_in_scene(&scene, &planner, validity, 3).expect("a path");
    let a = |path: &ftwire_plan::Path| -> Vec<Vector6<f64>> {
        path.waypoints.iter().map(|w| w.config.a).collect()
    };
    assert_eq!(a(&chosen.planned.plan.path), a(&alone.plan.path));
    assert_eq!(chosen.waypoints, prepare(&alone).expect("waypoints"));
    assert_eq!(chosen.waypoints.len(), WAYPOINTS + 1);
    // The first candidate plans from the run's seed; the others from seeds of their own.
    assert_eq!(candidate_seed(3, 0), 3);
    let seeds: std::collections::BTreeSet<u64> = (0..8).map(|k| candidate_seed(3, k)).collect();
    assert_eq!(seeds.len(), 8);
}

#[test]
fn the_910_mm_wire_plans_through_the_shipped_passage_under_the_paper_noise() {
    // At 93 % of its length it had no path there: the slack rule keeps 57.4 mm.
    let scene = shipped_passage();
    let tracker = loaded(0.91);
    let params = noisy().validity_tracked(&tracker);
    assert!(params.max_span > MAX_SPAN_NOISY);
    let planner = Rod::new(*tracker.wire());
    let (planned, checker) = plan_in_scene(&scene, &planner, params, 0).expect("a path");
    let waypoints = &planned.plan.path.waypoints;
    assert!(waypoints.len() >= 2);
    // Every waypoint keeps the noisy margins: clear of the boxes by 15 mm.
    for w in waypoints {
        assert!(checker.clearance(&w.config).expect("solves") >= MARGIN_NOISY - 1e-9);
    }
}

#[test]
fn a_wire_through_the_passage_gap_is_near_its_boxes_and_one_above_the_wall_is_not() {
    let scene = shipped_passage();
    // A straight wire across the wall's plane (y = 0.05) at `x`, `z`.
    let across = |x: f64, z: f64| Waypoint {
        a: Vector6::zeros(),
        tip: Pose::identity(),
        centreline: (0..=40)
            .map(|k| Point3::new(x, 0.25 - 0.01 * f64::from(k), z))
            .collect(),
    };
    let near = near_obstacles(
        &scene,
        &rod(),
        &[
            // The gap's middle: 25 mm to each box, 23.5 mm from the wire's surface.
            across(0.6, 0.35),
            // 30 mm above the wall: 28.5 mm.
            across(0.6, 0.43),
            // Through the back block.
            across(0.45, 0.35),
            // Far above.
            across(0.6, 0.7),
        ],
    )
    .expect("runs");
    assert_eq!(near, [true, false, true, false]);
}

#[test]
fn a_relocation_is_one_clear_axis_translation_from_which_the_arms_reach() {
    let scene = shipped_passage();
    let rod = rod();
    let steps = [0.01, 0.02, 0.03, 0.04];
    let goal = scene_configuration(&scene, &rod, "goal").expect("goal");
    let tip = scene.base * rod.tip(&goal.a).expect("solves");
    let poses = GripperPoses {
        base: scene.base,
        tip,
    };
    let policy = PlanPolicy::converging();
    let base = relocation(&scene, &policy, &rod, &poses, &goal.a, &goal.a, &steps)
        .expect("runs")
        .expect("the passage's goal has room around it");
    assert_eq!(base.rotation, scene.base.rotation, "a pure translation");
    let t = base.translation.vector - scene.base.translation.vector;
    let along = t.iter().filter(|c| c.abs() > 1e-12).count();
    assert_eq!(along, 1, "along one axis: {t:?}");
    assert!(steps.iter().any(|s| (t.norm() - s).abs() < 1e-12));
    let robot = Robot::sda10f().expect("robot");
    let checker = Checker::new(rod, robot, &scene, policy.validity(0.82)).expect("ok");
    assert!(checker.endpoint(&ZPoint { a: goal.a, base }).is_ok());
    // A relative pose no base near here reaches (the grippers 3 m apart): none.
    let far = GripperPoses {
        base: scene.base,
        tip: scene.base * Pose::translation(3.0, 0.0, 0.0),
    };
    assert_eq!(
        relocation(&scene, &policy, &rod, &far, &goal.a, &goal.a, &steps).expect("runs"),
        None
    );
}
