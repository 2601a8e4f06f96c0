//! The crate's one error type.

use ftwire_core::CoreError;
use ftwire_estimate::EstimateError;
use ftwire_robot::RobotError;
use ftwire_rod::RodError;
use thiserror::Error;

/// What can go wrong before or outside a controlled motion. How a motion itself ends (reached,
/// iteration limit, collision, …) is not an error but an [`crate::Outcome`].
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum ControlError {
    /// Non-finite or non-positive input caught by the shared checks.
    #[error(transparent)]
    Core(#[from] CoreError),
    /// The wire model failed (e.g. a configuration outside `A`).
    #[error("wire model: {0}")]
    Model(#[from] EstimateError),
    /// The Kirchhoff rod failed.
    #[error("rod: {0}")]
    Rod(#[from] RodError),
    /// The robot's kinematics failed on bad input.
    #[error("robot: {0}")]
    Robot(#[from] RobotError),
    /// A setting outside its allowed range.
    #[error("setting {name} = {value} is not allowed: {allowed}")]
    BadSetting {
        /// The setting's name.
        name: &'static str,
        /// The value given.
        value: f64,
        /// What is allowed.
        allowed: &'static str,
    },
    /// The goal configuration has a non-finite component.
    #[error("goal a_g[{index}] = {value}: every component of the goal must be finite")]
    NonFiniteGoal {
        /// Index of the first non-finite component (torque first).
        index: usize,
        /// Its value.
        value: f64,
    },
    /// The goal configuration is not a stable equilibrium of the model.
    #[error(
        "goal a_g = {goal:?} is outside A_stable of the model: the controller only steers to stable equilibria"
    )]
    GoalUnstable {
        /// The goal, torque first.
        goal: [f64; 6],
    },
    /// The second gripper's start pose is not reachable by the robot.
    #[error("the start pose of the second gripper is unreachable: {reason}")]
    UnreachableStart {
        /// Why (from the reach check).
        reason: String,
    },
    /// The rig failed before any motion (reading poses or the first measurement).
    #[error("rig: {message}")]
    Rig {
        /// The rig's own message.
        message: String,
    },
    /// Too few residuals to calibrate the collision threshold.
    #[error(
        "collision calibration needs at least {needed} finite residuals from free motion, got {got}"
    )]
    TooFewResiduals {
        /// Finite residuals given.
        got: usize,
        /// Needed.
        needed: usize,
    },
    /// A path to track with no waypoint.
    #[error("an empty path: tracking needs at least its start")]
    EmptyPath,
    /// Relocating both grippers failed before any move (the search could not run).
    #[error("relocating the base: {message}")]
    Relocation {
        /// What went wrong.
        message: String,
    },
    /// Too few steps for an open-loop path.
    #[error("an open-loop path needs at least 1 step, got {steps}")]
    NoSteps {
        /// Steps asked for.
        steps: usize,
    },
}
