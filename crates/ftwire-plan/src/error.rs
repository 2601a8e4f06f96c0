//! The one error type of ftwire-plan.

use ftwire_core::CoreError;
use ftwire_robot::RobotError;
use ftwire_rod::RodError;
use thiserror::Error;

/// What went wrong while reading a scene or planning.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum PlanError {
    /// A shared input check failed (a non-finite or non-positive value).
    #[error(transparent)]
    Core(#[from] CoreError),
    /// The wire model refused an input.
    #[error(transparent)]
    Rod(#[from] RodError),
    /// The robot model refused an input.
    #[error(transparent)]
    Robot(#[from] RobotError),
    /// The scene file could not be read.
    #[error("cannot read scene {file}: {message}")]
    Read {
        /// The file.
        file: String,
        /// The operating system's message.
        message: String,
    },
    /// The scene file is malformed or holds a bad value: the message names the line and the
    /// key or item.
    #[error("bad scene {file}: {message}")]
    Scene {
        /// The file (or `<string>` for text).
        file: String,
        /// What is wrong, where, and what is allowed.
        message: String,
    },
    /// A named configuration is not in the scene.
    #[error("no configuration named {name:?} in the scene (it has: {available})")]
    UnknownConfiguration {
        /// The name asked for.
        name: String,
        /// The names the scene has, comma separated.
        available: String,
    },
    /// A start or goal configuration is not in `Z_free`.
    #[error("{role} configuration {name:?} is not valid: {reason}")]
    InvalidEndpoint {
        /// `"start"` or `"goal"`.
        role: &'static str,
        /// Its name in the scene.
        name: String,
        /// Why it is not in `Z_free`.
        reason: String,
    },
    /// No configuration of the wire puts the second gripper at the requested pose.
    #[error(
        "no stable configuration found for the second-gripper pose of {name:?} (closest: {residual:.3e} of the SE(3) log)"
    )]
    NoConfigurationForTip {
        /// The configuration's name.
        name: String,
        /// The smallest residual reached.
        residual: f64,
    },
    /// A planner setting is out of range.
    #[error("{name} = {value} is out of range: {allowed}")]
    InvalidParameter {
        /// The setting.
        name: &'static str,
        /// Its value.
        value: f64,
        /// What is allowed.
        allowed: &'static str,
    },
    /// A path with no waypoint where one was needed.
    #[error("an empty path")]
    EmptyPath,
    /// The planner found no path within its budget.
    #[error("no path found in {iterations} iterations ({seconds:.2} s, {nodes} tree nodes)")]
    NoPath {
        /// Iterations run.
        iterations: usize,
        /// Tree size at the end.
        nodes: usize,
        /// Wall time spent \[s\].
        seconds: f64,
    },
}

impl PlanError {
    /// The first of the named settings that is not finite and positive, as
    /// [`PlanError::InvalidParameter`].
    ///
    /// # Errors
    /// As above.
    pub(crate) fn check_positive(settings: &[(&'static str, f64)]) -> Result<(), PlanError> {
        match settings
            .iter()
            .find(|(_, value)| !(value.is_finite() && *value > 0.0))
        {
            Some(&(name, value)) => Err(PlanError::InvalidParameter {
                name,
                value,
                allowed: "a finite value > 0",
            }),
            None => Ok(()),
        }
    }
}
