//! Shared fixtures: the 3 mm / 820 mm nitinol wire, the repository's passage scene, and the
//! planner tests' passage (`tests/data/passage-taut.toml`: the same boxes, the start taut).
#![allow(dead_code)]

use ftwire_plan::{
    Checker, FixedBase, Plan, Sample, Scene, ValidityParams, ZPoint, scene_endpoint,
};
use ftwire_robot::Robot;
use ftwire_rod::{Rod, WireParams};

/// The planner tests' passage scene: the shipped passage with its first, taut start, from
/// which RRT* finds a path in tens of iterations (see the file's comment).
pub fn passage_path() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/passage-taut.toml")
}

/// The shipped passage scene, `scenes/passage.toml`.
pub fn shipped_passage() -> Scene {
    Scene::load(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/passage.toml"))
        .expect("the shipped passage scene parses")
}

/// The 3 mm / 820 mm nitinol wire (the passage scene's wire).
pub fn rod() -> Rod {
    Rod::new(WireParams::new([0.214, 0.278, 0.278], 0.82, 0.0015).expect("valid wire"))
}

/// The planner tests' passage scene ([`passage_path`]).
pub fn passage() -> Scene {
    Scene::load(passage_path()).expect("the planner tests' passage scene parses")
}

/// A checker of `scene` with the default settings.
pub fn checker(scene: &Scene) -> Checker {
    Checker::new(
        rod(),
        Robot::sda10f().expect("robot"),
        scene,
        ValidityParams::default(),
    )
    .expect("default settings are valid")
}

/// A plan's waypoints' configurations (to compare two plans' paths).
pub fn configs(plan: &Plan) -> Vec<ZPoint> {
    plan.path.waypoints.iter().map(|w| w.config).collect()
}

/// The shipped passage's planning problem: its checker, the fixed-base space padded 2
/// normalised units around start and goal, and the start and goal.
pub struct ShippedProblem {
    pub checker: Checker,
    pub space: FixedBase,
    pub start: Sample,
    pub goal: Sample,
}

/// [`ShippedProblem`] of [`shipped_passage`].
pub fn shipped_problem() -> ShippedProblem {
    let scene = shipped_passage();
    let checker = checker(&scene);
    let start = scene_endpoint(&scene, &checker, "start", "start").expect("valid start");
    let goal = scene_endpoint(&scene, &checker, "goal", "goal").expect("valid goal");
    let space = FixedBase::around(
        *checker.rod().wire(),
        scene.base,
        &[start.config, goal.config],
        2.0,
    );
    ShippedProblem {
        checker,
        space,
        start,
        goal,
    }
}
