//! `ftwire robot`: forward and inverse kinematics of the SDA10F from the command line. The
//! work and the answers are [`ftwire_lab::robot`]'s; this command maps the options and prints.

use ftwire_app::output;
use ftwire_lab::error::{EXIT_NO_ANSWER, LabError};
use ftwire_lab::robot::{self, ArmParams, NoSolution};
use ftwire_robot::{Arm, EndFrame};

use crate::cli::robot::{ArmArg, CommonArgs, FrameArg, RobotArgs, RobotCommand};

/// Runs `ftwire robot`.
pub fn run(args: RobotArgs) -> Result<(), LabError> {
    match args.command {
        RobotCommand::Fk(args) => {
            let report = robot::fk(&params(&args.common), &args.joints.0)?;
            output::print_display(&report, args.common.output.json)
        }
        RobotCommand::Ik(args) => {
            let seed = args.seed_joints.map(|j| j.0);
            let json = args.common.output.json;
            match robot::ik(&params(&args.common), &args.target.pose(), seed.as_ref()) {
                Ok(report) => output::print_display(&report, json),
                Err(error) => {
                    if error.exit_code() == EXIT_NO_ANSWER {
                        // The answer "there is none" is a result too: say so on stdout as well.
                        output::print_display(&NoSolution::new(&error), json)?;
                    }
                    Err(error)
                }
            }
        }
    }
}

/// The lab's settings of the options `fk` and `ik` share.
fn params(common: &CommonArgs) -> ArmParams {
    ArmParams {
        urdf: common.urdf.clone(),
        arm: match common.arm {
            ArmArg::Left => Arm::Left,
            ArmArg::Right => Arm::Right,
        },
        torso: common.torso,
        frame: match common.frame {
            FrameArg::Gripper => EndFrame::Gripper,
            FrameArg::Tool0 => EndFrame::Tool0,
        },
    }
}
