//! `ftwire robot`: forward and inverse kinematics of the SDA10F from the command line.

use std::io::{self, Write};

use ftwire::output::{self, Report};
use ftwire_core::Pose;
use ftwire_lab::error::{LabError, from_robot};
use ftwire_robot::{Arm, ArmJoints, EndFrame, IkParams, IkTarget, Robot};
use serde::Serialize;

use crate::cli::robot::{ArmArg, CommonArgs, FkArgs, FrameArg, IkArgs, RobotArgs, RobotCommand};

/// Runs `ftwire robot`.
pub fn run(args: RobotArgs) -> Result<(), LabError> {
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

/// Loads the robot; a URDF that cannot be read is bad input.
fn load(common: &CommonArgs) -> Result<Robot, LabError> {
    let robot = match &common.urdf {
        Some(path) => Robot::from_urdf_file(path, &Default::default()),
        None => Robot::sda10f(),
    };
    robot.map_err(|e| LabError::bad_input(e.to_string()))
}

/// The FK answer: position and row-major rotation matrix in the robot base frame.
#[derive(Serialize)]
struct FkReport {
    position: [f64; 3],
    rotation: [[f64; 3]; 3],
    #[serde(skip)]
    title: String,
    #[serde(skip)]
    pose: Pose,
}

impl Report for FkReport {
    fn write_text(&self, out: &mut dyn Write) -> io::Result<()> {
        writeln!(out, "{}", self.title)?;
        let p = self.position;
        writeln!(out, "  position [m]:           {}", format_list(&p))?;
        let r = self.pose.rotation.scaled_axis();
        writeln!(
            out,
            "  rotation vector [rad]:  {}",
            format_list(&[r.x, r.y, r.z])
        )?;
        writeln!(out, "  rotation matrix (rows):")?;
        for row in &self.rotation {
            writeln!(out, "    {}", format_list(row))?;
        }
        Ok(())
    }
}

fn fk(args: &FkArgs) -> Result<(), LabError> {
    let robot = load(&args.common)?;
    let (a, f) = (arm(args.common.arm), frame(args.common.frame));
    let q = ArmJoints::from_column_slice(&args.joints.0);
    let pose = robot
        .fk(a, args.common.torso, &q, f)
        .map_err(|e| LabError::bad_input(e.to_string()))?;
    let m = pose.rotation.to_rotation_matrix();
    let report = FkReport {
        position: pose.translation.vector.into(),
        rotation: std::array::from_fn(|i| std::array::from_fn(|k| m[(i, k)])),
        title: format!(
            "{a} arm {} pose in the robot base frame (torso {} rad):",
            frame_name(f),
            args.common.torso
        ),
        pose,
    };
    output::print(&report, args.common.output.json)
}

/// The IK answer.
#[derive(Serialize)]
struct IkReport {
    joints: Vec<f64>,
    #[serde(skip)]
    arm: Arm,
    #[serde(skip)]
    residual: String,
}

impl Report for IkReport {
    fn write_text(&self, out: &mut dyn Write) -> io::Result<()> {
        writeln!(
            out,
            "{} arm joints [rad]: {}",
            self.arm,
            format_list(&self.joints)
        )?;
        writeln!(out, "residual: {}", self.residual)
    }
}

/// The IK answer when there is none: `{"error": ...}` on stdout with `--json`.
#[derive(Serialize)]
struct NoSolution {
    error: String,
}

impl Report for NoSolution {
    fn write_text(&self, out: &mut dyn Write) -> io::Result<()> {
        writeln!(out, "no solution: {}", self.error)
    }
}

fn ik(args: &IkArgs) -> Result<(), LabError> {
    let robot = load(&args.common)?;
    let (a, f) = (arm(args.common.arm), frame(args.common.frame));
    let seed = args.seed_joints.map(|j| ArmJoints::from_column_slice(&j.0));
    let target = IkTarget {
        arm: a,
        pose: args.target.pose(),
        torso: args.common.torso,
        frame: f,
    };
    let json = args.common.output.json;
    match robot.ik(&target, seed.as_ref(), &IkParams::default()) {
        Ok(solution) => {
            let report = IkReport {
                joints: solution.joints.iter().copied().collect(),
                arm: a,
                residual: format!(
                    "{:.2e} m, {:.2e} rad ({} attempt(s), {} iterations)",
                    solution.position_error,
                    solution.rotation_error,
                    solution.attempts,
                    solution.iterations
                ),
            };
            output::print(&report, json)
        }
        Err(e) => {
            let error = from_robot(e, "inverse kinematics");
            if error.exit_code() == ftwire_lab::error::EXIT_NO_ANSWER {
                // The answer "there is none" is a result too: say so on stdout as well.
                output::print(
                    &NoSolution {
                        error: error.to_string(),
                    },
                    json,
                )?;
            }
            Err(error)
        }
    }
}

fn frame_name(f: EndFrame) -> &'static str {
    match f {
        EndFrame::Gripper => "gripper",
        EndFrame::Tool0 => "tool0",
    }
}

fn format_list(values: &[f64]) -> String {
    values
        .iter()
        .map(|v| format!("{v:.9}"))
        .collect::<Vec<_>>()
        .join(", ")
}
