use ftwire_core::CoreError;
use thiserror::Error;

use crate::arm::Arm;

/// Errors of the robot model, its kinematics and its queries.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum RobotError {
    /// A value that must be finite is not (wrapped from `ftwire-core`).
    #[error(transparent)]
    Core(#[from] CoreError),
    /// A joint vector has the wrong number of values.
    #[error("expected {expected} joint values, got {got}")]
    JointCount {
        /// How many values are needed.
        expected: usize,
        /// How many were given.
        got: usize,
    },
    /// A joint value lies outside the joint's limits.
    #[error("joint {name} = {position} rad is outside its limits [{min}, {max}] rad")]
    OutOfLimit {
        /// Index of the joint in its arm (0..7), or 7 for the torso joint.
        joint: usize,
        /// The URDF name of the joint.
        name: String,
        /// The offending value \[rad\].
        position: f64,
        /// Lower limit \[rad\].
        min: f64,
        /// Upper limit \[rad\].
        max: f64,
    },
    /// The target lies beyond a guaranteed upper bound of the arm's reach: definitely unreachable.
    #[error(
        "the {arm} arm cannot reach the target: it is {distance:.4} m from the shoulder, beyond the arm's reach bound of {reach:.4} m"
    )]
    OutOfReach {
        /// The arm asked to reach.
        arm: Arm,
        /// Distance from the first joint's origin to the target point \[m\].
        distance: f64,
        /// Upper bound of the distance the frame can reach from there \[m\].
        reach: f64,
    },
    /// No inverse-kinematics solution within tolerance was found from any seed.
    #[error(
        "no IK solution for the {arm} arm within tolerance after {attempts} attempts; best residual {position_error:.3e} m, {rotation_error:.3e} rad{}",
        limited_joint.map(|j| format!(" with arm joint {} of 7 at a limit", j + 1)).unwrap_or_default()
    )]
    Unreachable {
        /// The arm asked to reach.
        arm: Arm,
        /// Position residual of the best attempt \[m\].
        position_error: f64,
        /// Rotation residual (angle) of the best attempt \[rad\].
        rotation_error: f64,
        /// Number of seeds tried.
        attempts: usize,
        /// A joint (0-based) that sat at one of its limits in the best attempt, if any: the limit
        /// is then a likely reason.
        limited_joint: Option<usize>,
    },
    /// The dual-arm problem has no solution at any torso angle tried.
    #[error(
        "no dual-arm solution at {torsos_tried} torso angle(s): left arm failed {left_failures} time(s), right arm {right_failures} time(s), arms collided {collisions} time(s)"
    )]
    DualArmUnreachable {
        /// Number of torso angles tried.
        torsos_tried: usize,
        /// Torso angles at which the left (base gripper) arm had no solution.
        left_failures: usize,
        /// Torso angles at which the right (second gripper) arm had no solution.
        right_failures: usize,
        /// Torso angles at which both arms had solutions that collided with each other.
        collisions: usize,
    },
    /// The URDF text could not be parsed.
    #[error("cannot parse the URDF: {message}")]
    Urdf {
        /// The parser's message.
        message: String,
    },
    /// The URDF parsed but does not describe the expected kinematic structure.
    #[error("the URDF does not describe the expected robot: {message}")]
    Model {
        /// What is missing or unexpected.
        message: String,
    },
    /// A file could not be read.
    #[error("cannot read {path}: {message}")]
    Io {
        /// The path.
        path: String,
        /// The operating system's message.
        message: String,
    },
    /// A parameter is out of its allowed range.
    #[error("{name} = {value} is invalid: {allowed}")]
    InvalidParameter {
        /// The parameter's name.
        name: &'static str,
        /// The offending value.
        value: f64,
        /// What is allowed.
        allowed: &'static str,
    },
}
