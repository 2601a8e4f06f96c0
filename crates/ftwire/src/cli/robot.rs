//! Arguments of `ftwire robot`.

use std::path::PathBuf;

use clap::{Args, Subcommand, ValueEnum};
use ftwire::args::{JsonArgs, PoseArgs, Vec7, parse_finite, parse_numbers};

/// Arguments of `ftwire robot`.
#[derive(Debug, Args)]
#[command(after_help = "Exit codes: 0 success, 1 no IK solution, 2 bad input.")]
pub struct RobotArgs {
    /// What to compute.
    #[command(subcommand)]
    pub command: RobotCommand,
}

/// The `ftwire robot` subcommands.
#[derive(Debug, Subcommand)]
pub enum RobotCommand {
    /// Forward kinematics: the pose of an arm's gripper (or tool0) in the robot base frame.
    Fk(FkArgs),
    /// Inverse kinematics: joint angles that put an arm's gripper (or tool0) at a pose.
    Ik(IkArgs),
}

/// Which arm.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ArmArg {
    /// The left arm (F/T sensor, base gripper).
    Left,
    /// The right arm (second gripper).
    Right,
}

/// Which end frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, ValueEnum)]
pub enum FrameArg {
    /// The gripper's clamp frame (x along the wire).
    #[default]
    Gripper,
    /// The URDF flange frame `arm_*_link_tool0`.
    Tool0,
}

/// Options shared by `fk` and `ik`.
#[derive(Debug, Args)]
pub struct CommonArgs {
    /// Which arm.
    #[arg(long, value_enum)]
    pub arm: ArmArg,
    /// Torso angle [rad].
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true, value_parser = parse_finite)]
    pub torso: f64,
    /// End frame the pose refers to.
    #[arg(long, value_enum, default_value_t = FrameArg::Gripper)]
    pub frame: FrameArg,
    /// Output format.
    #[command(flatten)]
    pub output: JsonArgs,
    /// Load the robot from this URDF file instead of the built-in SDA10F model.
    #[arg(long, value_name = "PATH")]
    pub urdf: Option<PathBuf>,
}

/// Arguments of `ftwire robot fk`.
#[derive(Debug, Args)]
pub struct FkArgs {
    /// Shared options.
    #[command(flatten)]
    pub common: CommonArgs,
    /// The arm's seven joint angles [rad], shoulder first: Q1,..,Q7.
    #[arg(
        long,
        value_name = "Q1,..,Q7",
        allow_hyphen_values = true,
        value_parser = parse_numbers::<7>
    )]
    pub joints: Vec7,
}

/// Arguments of `ftwire robot ik`.
#[derive(Debug, Args)]
pub struct IkArgs {
    /// Shared options.
    #[command(flatten)]
    pub common: CommonArgs,
    /// The target pose of the end frame, in the robot base frame.
    #[command(flatten)]
    pub target: PoseArgs,
    /// Start from these joint angles [rad] (e.g. the previous solution); the solution stays
    /// near them. Default: the robot's preferred posture.
    #[arg(
        long,
        value_name = "Q1,..,Q7",
        allow_hyphen_values = true,
        value_parser = parse_numbers::<7>
    )]
    pub seed_joints: Option<Vec7>,
}
