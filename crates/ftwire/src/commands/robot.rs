//! `ftwire robot`: forward and inverse kinematics of the SDA10F from the command line.

use std::process::ExitCode;

use anyhow::Context;
use ftwire_core::Pose;
use ftwire_robot::{Arm, ArmJoints, EndFrame, IkParams, IkTarget, Robot, RobotError};
use nalgebra::Vector3;
use serde_json::json;

use crate::cli::robot::{ArmArg, CommonArgs, FkArgs, FrameArg, IkArgs, RobotArgs, RobotCommand};

/// Exit code for a bad argument (as clap's own).
const BAD_ARGUMENT: u8 = 2;
/// Exit code when IK finds no solution.
const NO_SOLUTION: u8 = 1;

/// Runs `ftwire robot`.
pub fn run(args: RobotArgs) -> anyhow::Result<ExitCode> {
    match args.command {
        RobotCommand::Fk(args) => fk(&args),
        RobotCommand::Ik(args) => ik(&args),
    }
}

fn arm(a: ArmArg) -> Arm {
    match a {
        ArmArg::Left => Arm::Left,
        ArmArg::Right => Arm::Right,
    }
}

fn frame(f: FrameArg) -> EndFrame {
    match f {
        FrameArg::Gripper => EndFrame::Gripper,
        FrameArg::Tool0 => EndFrame::Tool0,
    }
}

fn bad_argument(error: &dyn std::fmt::Display) -> ExitCode {
    eprintln!("error: {error}");
    ExitCode::from(BAD_ARGUMENT)
}

/// Loads the robot; a URDF that cannot be read is a bad argument.
fn load(common: &CommonArgs) -> Result<Robot, ExitCode> {
    let robot = match &common.urdf {
        Some(path) => Robot::from_urdf_file(path, &Default::default()),
        None => Robot::sda10f(),
    };
    robot.map_err(|e| bad_argument(&e))
}

fn fk(args: &FkArgs) -> anyhow::Result<ExitCode> {
    let robot = match load(&args.common) {
        Ok(r) => r,
        Err(code) => return Ok(code),
    };
    let (a, f) = (arm(args.common.arm), frame(args.common.frame));
    let q = ArmJoints::from_column_slice(&args.joints.0);
    let pose = match robot.fk(a, args.common.torso, &q, f) {
        Ok(p) => p,
        Err(e) => return Ok(bad_argument(&e)),
    };
    if args.common.json {
        println!("{}", pose_json(&pose));
    } else {
        println!(
            "{a} arm {} pose in the robot base frame (torso {} rad):",
            frame_name(f),
            args.common.torso
        );
        print_pose(&pose);
    }
    Ok(ExitCode::SUCCESS)
}

fn ik(args: &IkArgs) -> anyhow::Result<ExitCode> {
    let robot = match load(&args.common) {
        Ok(r) => r,
        Err(code) => return Ok(code),
    };
    let (a, f) = (arm(args.common.arm), frame(args.common.frame));
    let pose = ftwire_robot::pose_from_vectors(
        Vector3::from(args.position.0),
        Vector3::from(args.rotation.0),
    );
    let seed = args.seed_joints.map(|j| ArmJoints::from_column_slice(&j.0));
    let target = IkTarget {
        arm: a,
        pose,
        torso: args.common.torso,
        frame: f,
    };
    match robot.ik(&target, seed.as_ref(), &IkParams::default()) {
        Ok(solution) => {
            let joints: Vec<f64> = solution.joints.iter().copied().collect();
            if args.common.json {
                println!("{}", json!({ "joints": joints }));
            } else {
                println!("{a} arm joints [rad]: {}", format_list(&joints));
                println!(
                    "residual: {:.2e} m, {:.2e} rad ({} attempt(s), {} iterations)",
                    solution.position_error,
                    solution.rotation_error,
                    solution.attempts,
                    solution.iterations
                );
            }
            Ok(ExitCode::SUCCESS)
        }
        Err(e @ (RobotError::Unreachable { .. } | RobotError::OutOfReach { .. })) => {
            if args.common.json {
                println!("{}", json!({ "error": e.to_string() }));
            } else {
                println!("no solution: {e}");
            }
            Ok(ExitCode::from(NO_SOLUTION))
        }
        Err(
            e @ (RobotError::Core(_)
            | RobotError::OutOfLimit { .. }
            | RobotError::JointCount { .. }
            | RobotError::InvalidParameter { .. }),
        ) => Ok(bad_argument(&e)),
        Err(e) => Err(e).context("solving the inverse kinematics"),
    }
}

fn frame_name(f: EndFrame) -> &'static str {
    match f {
        EndFrame::Gripper => "gripper",
        EndFrame::Tool0 => "tool0",
    }
}

fn pose_json(pose: &Pose) -> serde_json::Value {
    let m = pose.rotation.to_rotation_matrix();
    let rows: Vec<[f64; 3]> = (0..3).map(|i| [m[(i, 0)], m[(i, 1)], m[(i, 2)]]).collect();
    let p = pose.translation.vector;
    json!({ "position": [p.x, p.y, p.z], "rotation": rows })
}

fn format_list(values: &[f64]) -> String {
    values
        .iter()
        .map(|v| format!("{v:.9}"))
        .collect::<Vec<_>>()
        .join(", ")
}

fn print_pose(pose: &Pose) {
    let p = pose.translation.vector;
    println!(
        "  position [m]:           {}",
        format_list(&[p.x, p.y, p.z])
    );
    let r = pose.rotation.scaled_axis();
    println!(
        "  rotation vector [rad]:  {}",
        format_list(&[r.x, r.y, r.z])
    );
    let m = pose.rotation.to_rotation_matrix();
    println!("  rotation matrix (rows):");
    for i in 0..3 {
        println!("    {}", format_list(&[m[(i, 0)], m[(i, 1)], m[(i, 2)]]));
    }
}
