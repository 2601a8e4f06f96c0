#![doc = include_str!("../README.md")]

mod choice;
mod endpoint;
mod error;
mod path;
mod policy;
mod polish;
mod rrt_star;
pub mod scene;
mod space;
pub mod validity;
mod waypoint;

pub use choice::{
    ChoiceOut, Chosen, PLAN_CANDIDATES, PLAN_ITERATIONS, PLAN_RESTARTS, ScenePlan, WAYPOINTS,
    candidate_seed, choose_plan, plan_in_scene,
};
pub use endpoint::{configuration_for_tip, scene_configuration, scene_endpoint};
pub use error::PlanError;
pub use path::Path;
pub use policy::{
    LANDING_SIGMAS, LANDING_TARGET, MARGIN_NOISY, MAX_SLACK_NOISY, MAX_SPAN_NOISY, PlanPolicy,
    STABILITY_MARGIN_NOISY, TOUCH_SAMPLES,
};
pub use polish::{
    Landing, PolishParams, Polished, Scatter, landing_clearance, polish_clearance, touch_rate,
};
pub use rrt_star::{Plan, PlannerParams, plan};
pub use scene::{ConfigurationSpec, Scene, SceneBox};
pub use space::{FixedBase, MovingBase, Space};
pub use validity::{Checker, Edge, Invalid, Sample, ValidityParams, ZPoint, joint_distance};
pub use waypoint::{
    NEAR_CLEARANCE, PolishOut, Waypoint, expected_touches, near_obstacles, polish_waypoints,
    relocation, waypoints_along, waypoints_at,
};
