//! Shared fixtures: the 3 mm / 820 mm nitinol wire, the repository's passage scene, and the
//! planner tests' passage (`tests/data/passage-taut.toml`: the same boxes, the start taut).
#![allow(dead_code)]

use ftwire_plan::{Checker, Config, Plan, Scene, ValidityParams};
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
pub fn configs(plan: &Plan) -> Vec<Config> {
    plan.path.waypoints.iter().map(|w| w.config).collect()
}
