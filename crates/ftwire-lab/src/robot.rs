//! Forward and inverse kinematics of the dual-arm robot (`ftwire robot fk|ik`): the SDA10F of
//! `ftwire_robot`, or a URDF given by the user, with the answers as the command prints them.
//!
//! Guarded by this module's tests and `crates/ftwire/tests/robot_cli.rs`.

use std::fmt;
use std::path::PathBuf;

use ftwire_core::Pose;
use ftwire_robot::{Arm, ArmJoints, EndFrame, IkParams, IkTarget, Robot};
use serde::Serialize;

use crate::error::{LabError, from_robot};

/// Which robot, arm, torso angle and end frame a query is about.
#[derive(Debug, Clone, PartialEq)]
pub struct ArmParams {
    /// A URDF file of the robot; `None`: the SDA10F shipped with `ftwire_robot`.
    pub urdf: Option<PathBuf>,
    /// The arm.
    pub arm: Arm,
    /// The torso joint's angle \[rad\].
    pub torso: f64,
    /// The end frame: the gripper's clamp frame, or the URDF's flange `tool0`.
    pub frame: EndFrame,
}

impl ArmParams {
    /// The robot.
    ///
    /// # Errors
    /// Bad input for a URDF that cannot be read or is not a dual-arm robot.
    pub fn robot(&self) -> Result<Robot, LabError> {
        let robot = match &self.urdf {
            Some(path) => Robot::from_urdf_file(path, &Default::default()),
            None => Robot::sda10f(),
        };
        robot.map_err(|e| LabError::bad_input(e.to_string()))
    }
}

/// The name of an end frame in the text answers.
pub fn frame_name(frame: EndFrame) -> &'static str {
    match frame {
        EndFrame::Gripper => "gripper",
        EndFrame::Tool0 => "tool0",
    }
}

/// The pose of the end frame at arm joints `joints` \[rad\] (forward kinematics).
///
/// # Errors
/// Bad input for a robot [`ArmParams::robot`] refuses or joints outside their limits.
pub fn fk(params: &ArmParams, joints: &[f64; 7]) -> Result<FkReport, LabError> {
    let robot = params.robot()?;
    let q = ArmJoints::from_column_slice(joints);
    let pose = robot
        .fk(params.arm, params.torso, &q, params.frame)
        .map_err(|e| LabError::bad_input(e.to_string()))?;
    let m = pose.rotation.to_rotation_matrix();
    Ok(FkReport {
        position: pose.translation.vector.into(),
        rotation: std::array::from_fn(|i| std::array::from_fn(|k| m[(i, k)])),
        title: format!(
            "{} arm {} pose in the robot base frame (torso {} rad):",
            params.arm,
            frame_name(params.frame),
            params.torso
        ),
        pose,
    })
}

/// Arm joints that put the end frame at `target` (robot base frame), searched from `seed`
/// (joints \[rad\]) if given (inverse kinematics).
///
/// # Errors
/// Bad input as [`ArmParams::robot`] and for limits or settings the robot refuses; no answer
/// for a target the arm does not reach ([`from_robot`]).
pub fn ik(
    params: &ArmParams,
    target: &Pose,
    seed: Option<&[f64; 7]>,
) -> Result<IkReport, LabError> {
    let robot = params.robot()?;
    let seed = seed.map(|j| ArmJoints::from_column_slice(j));
    let target = IkTarget {
        arm: params.arm,
        pose: *target,
        torso: params.torso,
        frame: params.frame,
    };
    let solution = robot
        .ik(&target, seed.as_ref(), &IkParams::default())
        .map_err(|e| from_robot(e, "inverse kinematics"))?;
    Ok(IkReport {
        joints: solution.joints.iter().copied().collect(),
        arm: params.arm,
        residual: format!(
            "{:.2e} m, {:.2e} rad ({} attempt(s), {} iterations)",
            solution.position_error,
            solution.rotation_error,
            solution.attempts,
            solution.iterations
        ),
    })
}

/// The forward kinematics answer: with `--json` the position and the row-major rotation
/// matrix in the robot base frame; the text (its [`fmt::Display`]) adds the rotation vector.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FkReport {
    /// Position \[m\], robot base frame.
    pub position: [f64; 3],
    /// Rotation matrix, row-major, robot base frame from the end frame.
    pub rotation: [[f64; 3]; 3],
    /// The text's first line: the arm, the frame and the torso angle.
    #[serde(skip)]
    pub title: String,
    /// The pose.
    #[serde(skip)]
    pub pose: Pose,
}

impl fmt::Display for FkReport {
    fn fmt(&self, out: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(out, "{}", self.title)?;
        writeln!(
            out,
            "  position [m]:           {}",
            format_list(&self.position)
        )?;
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

/// The inverse kinematics answer: with `--json` the joints; the text (its
/// [`fmt::Display`]) adds the arm and the residual.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct IkReport {
    /// Joint angles \[rad\].
    pub joints: Vec<f64>,
    /// The arm.
    #[serde(skip)]
    pub arm: Arm,
    /// The residual in words: position and rotation error, attempts and iterations.
    #[serde(skip)]
    pub residual: String,
}

impl fmt::Display for IkReport {
    fn fmt(&self, out: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            out,
            "{} arm joints [rad]: {}",
            self.arm,
            format_list(&self.joints)
        )?;
        writeln!(out, "residual: {}", self.residual)
    }
}

/// The inverse kinematics answer when there is none (`{"error": ...}` with `--json`): "there
/// is none" is a result too.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct NoSolution {
    /// Why not.
    pub error: String,
}

impl NoSolution {
    /// The answer of `error`.
    pub fn new(error: &LabError) -> Self {
        Self {
            error: error.to_string(),
        }
    }
}

impl fmt::Display for NoSolution {
    fn fmt(&self, out: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(out, "no solution: {}", self.error)
    }
}

/// The values with nine decimals, separated by commas.
fn format_list(values: &[f64]) -> String {
    values
        .iter()
        .map(|v| format!("{v:.9}"))
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn left() -> ArmParams {
        ArmParams {
            urdf: None,
            arm: Arm::Left,
            torso: 0.0,
            frame: EndFrame::Gripper,
        }
    }

    #[test]
    fn ik_of_an_fk_pose_comes_back_to_it() {
        let joints = [0.3, -0.8, 0.5, -1.1, 0.7, 0.9, -0.4];
        let pose = fk(&left(), &joints).expect("FK within limits");
        assert!(pose.title.starts_with("left arm gripper pose"));
        let back = ik(&left(), &pose.pose, Some(&joints)).expect("IK of a reached pose");
        assert_eq!(back.joints.len(), 7);
        let again = fk(
            &left(),
            &back.joints.as_slice().try_into().expect("7 joints"),
        )
        .expect("FK of the IK answer");
        for (p, q) in again.position.iter().zip(pose.position) {
            assert!((p - q).abs() < 1e-5, "{p} vs {q}");
        }
    }

    #[test]
    fn a_missing_urdf_is_bad_input() {
        let params = ArmParams {
            urdf: Some("/nonexistent/robot.urdf".into()),
            ..left()
        };
        let error = fk(&params, &[0.0; 7]).expect_err("no such file");
        assert_eq!(error.kind(), "bad_input");
        let none = NoSolution::new(&LabError::no_answer("out of reach"));
        assert_eq!(none.to_string(), "no solution: out of reach\n");
    }
}
