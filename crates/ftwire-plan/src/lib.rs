//! Planning for the elastic wire (paper §III-D): scenes, validity in `Z_free`, and
//! RRT* in `A_free` (the base gripper fixed) and in `Z = A × Q` (the base gripper moving too).
//!
//! Workflow:
//! 1. read a [`Scene`] (TOML; [`scene`] documents the format): the base gripper's pose, box
//!    obstacles, a floor, named start and goal configurations;
//! 2. build a [`Checker`] from the wire model ([`ftwire_rod::Rod`]), the robot
//!    ([`ftwire_robot::Robot`]) and the scene; [`scene_endpoint`] checks a named configuration;
//! 3. [`plan`] with a [`Space`] — [`FixedBase`] (normalised `A`) or [`MovingBase`]
//!    (`Z = A × Q`) — and [`PlannerParams`] (seed, budget, clearance weight);
//! 4. the [`Path`]'s waypoints carry each `a`, both gripper poses and the joints;
//!    [`Path::resample`] gives `N + 1` waypoints `γ(i/N)` for tracking.
//! 5. For a plan that is to be tracked: a [`PlanPolicy`] (margins, polish and choice by how the
//!    execution lands the gripper), [`plan_in_scene`] (a fixed budget, seeded restarts,
//!    [`Waypoint`]s), [`choose_plan`] among candidates by their [`expected_touches`] after
//!    [`polish_waypoints`]; [`near_obstacles`] and [`relocation`] serve the tracker.
//!
//! Conventions: SI units; `a = (τ1, τ2, τ3, f1, f2, f3)` is the wrench the wire exerts on the
//! base gripper, torque first, in the base clamp frame; normalised `a` divides torques by
//! `c2/L` and forces by `c2/L²`. Poses are in the robot's world frame (`torso_base_link`);
//! the base gripper is the left arm's, the second gripper the right arm's.
//!
//! ```
//! use ftwire_plan::{Checker, FixedBase, PlannerParams, Scene, ValidityParams, plan, scene_endpoint};
//! use ftwire_robot::Robot;
//! use ftwire_rod::{Rod, WireParams};
//! // The passage scene's base pose (scenes/passage.toml) without its boxes.
//! let text = "[base]\nposition = [0.6, 0.35, 0.35]\nrotation = [0, 0, -1.5707963]\n\
//!     [configuration.start]\na_normalised = [-0.35, -1.97, -0.3, -4.02, 0.47, 3.49]\n\
//!     [configuration.goal]\na_normalised = [-0.35, -1.47, -0.3, -4.02, 0.47, 3.49]\n";
//! let scene = Scene::from_toml(text, "demo")?;
//! let rod = Rod::new(WireParams::new([0.214, 0.278, 0.278], 0.82, 0.0015)?);
//! let checker = Checker::new(rod, Robot::sda10f()?, &scene, ValidityParams::default())?;
//! let start = scene_endpoint(&scene, &checker, "start", "start")?;
//! let goal = scene_endpoint(&scene, &checker, "goal", "goal")?;
//! let space = FixedBase::around(*rod.wire(), scene.base, &[start.config, goal.config], 2.0);
//! let params = PlannerParams { max_iterations: 50, ..PlannerParams::default() };
//! let found = plan(&space, &checker, &start, &goal.config, &params)?;
//! assert_eq!(found.path.waypoints.first().map(|w| w.config.a), Some(start.config.a));
//! assert_eq!(found.path.waypoints.last().map(|w| w.config.a), Some(goal.config.a));
//! # Ok::<(), ftwire_plan::PlanError>(())
//! ```

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
