//! Shared fixtures: the 3 mm / 820 mm nitinol wire and the repository's passage scene.
#![allow(dead_code)]

use ftwire_plan::{Checker, Scene, ValidityParams};
use ftwire_robot::Robot;
use ftwire_rod::{Rod, WireParams};

/// The passage scene's path in the repository.
pub fn passage_path() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/passage.toml")
}

/// The 3 mm / 820 mm nitinol wire (the passage scene's wire).
pub fn rod() -> Rod {
    Rod::new(WireParams::new([0.214, 0.278, 0.278], 0.82, 0.0015).expect("valid wire"))
}

/// The passage scene.
pub fn passage() -> Scene {
    Scene::load(passage_path()).expect("the shipped passage scene parses")
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
