//! Arguments of `ftwire robot`.

use std::path::PathBuf;

use clap::{Args, Subcommand, ValueEnum};

/// Arguments of `ftwire robot`.
#[derive(Debug, Args)]
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
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
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
    #[arg(long, value_name = "Q1,..,Q7", allow_hyphen_values = true, value_parser = parse_joints)]
    pub joints: Joints,
}

/// Arguments of `ftwire robot ik`.
#[derive(Debug, Args)]
pub struct IkArgs {
    /// Shared options.
    #[command(flatten)]
    pub common: CommonArgs,
    /// Target position [m] in the robot base frame: X,Y,Z.
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true, value_parser = parse_vector3)]
    pub position: Vector3Arg,
    /// Target rotation as a rotation vector (axis times angle) [rad]: RX,RY,RZ.
    #[arg(long, value_name = "RX,RY,RZ", allow_hyphen_values = true, value_parser = parse_vector3)]
    pub rotation: Vector3Arg,
    /// Start from these joint angles [rad] (e.g. the previous solution); the solution stays
    /// near them. Default: the robot's preferred posture.
    #[arg(long, value_name = "Q1,..,Q7", allow_hyphen_values = true, value_parser = parse_joints)]
    pub seed_joints: Option<Joints>,
}

/// Seven joint angles [rad].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Joints(pub [f64; 7]);

/// Three numbers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Vector3Arg(pub [f64; 3]);

fn parse_list<const N: usize>(text: &str) -> Result<[f64; N], String> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    if parts.len() != N {
        return Err(format!(
            "expected {N} comma-separated numbers, got {} in `{text}`",
            parts.len()
        ));
    }
    let mut out = [0.0; N];
    for (slot, part) in out.iter_mut().zip(&parts) {
        *slot = parse_finite(part)?;
    }
    Ok(out)
}

fn parse_finite(text: &str) -> Result<f64, String> {
    let value: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("`{text}` is not a number"))?;
    if value.is_finite() {
        Ok(value)
    } else {
        Err(format!("`{text}` is not a finite number"))
    }
}

fn parse_joints(text: &str) -> Result<Joints, String> {
    parse_list::<7>(text).map(Joints)
}

fn parse_vector3(text: &str) -> Result<Vector3Arg, String> {
    parse_list::<3>(text).map(Vector3Arg)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lists_parse_and_say_what_is_wrong() {
        assert_eq!(
            parse_vector3("1, -2,3e-1").map(|v| v.0),
            Ok([1.0, -2.0, 0.3])
        );
        assert!(parse_joints("1,2,3").is_err_and(|e| e.contains("expected 7")));
        assert!(parse_vector3("1,x,3").is_err_and(|e| e.contains("`x` is not a number")));
        assert!(parse_vector3("1,NaN,3").is_err_and(|e| e.contains("not a finite")));
    }
}
