//! A reachability query cheap enough for a planner's thousands of calls.
//!
//! Semantics: [`Reachability::Reachable`] and [`Reachability::Unreachable`] are definite;
//! [`Reachability::Unknown`] means the cheap test could not decide (the pose may still be
//! reachable from another seed: call [`Robot::ik`] with restarts to decide).

use serde::{Deserialize, Serialize};

use crate::chain::ArmJoints;
use crate::ik::ArmProblem;
use crate::{IkTarget, Robot, RobotError};

/// The answer of [`Robot::reachability`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Reachability {
    /// Definitely reachable: these joints (within limits) reach the pose within tolerance.
    Reachable(ArmJoints),
    /// Definitely unreachable: the target point is farther from the shoulder than a guaranteed
    /// bound of the arm's reach.
    Unreachable {
        /// Distance from joint 1's origin to the target point \[m\].
        distance: f64,
        /// The reach bound \[m\].
        reach: f64,
    },
    /// Undecided: a short descent from the seed did not converge.
    Unknown {
        /// Position residual reached \[m\].
        position_error: f64,
        /// Rotation residual reached \[rad\].
        rotation_error: f64,
    },
}

/// Budget and tolerances of [`Robot::reachability`] (public fields + `Default`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ReachParams {
    /// Iterations of the single descent (default `25`).
    pub max_iterations: usize,
    /// Position tolerance \[m\] (default `1e-6`).
    pub position_tolerance: f64,
    /// Rotation tolerance \[rad\] (default `1e-6`).
    pub rotation_tolerance: f64,
}

impl Default for ReachParams {
    fn default() -> Self {
        Self {
            max_iterations: 25,
            position_tolerance: 1e-6,
            rotation_tolerance: 1e-6,
        }
    }
}

impl Robot {
    /// Cheap reachability of a pose: a reach-bound pre-check, then one short IK descent from
    /// `seed` (typically a nearby configuration, e.g. a planner tree's nearest node), with the
    /// nullspace pulling toward the seed and no restarts.
    ///
    /// # Errors
    /// Non-finite input, a torso or seed outside its limits, or bad tolerances.
    ///
    /// # Example
    /// ```
    /// use ftwire_robot::{Arm, EndFrame, IkTarget, Reachability, ReachParams, Robot};
    /// use nalgebra::Translation3;
    /// let robot = Robot::sda10f()?;
    /// let q = *robot.preferred_posture(Arm::Left);
    /// let pose = robot.fk(Arm::Left, 0.0, &q, EndFrame::Gripper)?;
    /// let near = IkTarget { arm: Arm::Left, pose: Translation3::new(0.01, 0.0, 0.0) * pose, torso: 0.0, frame: EndFrame::Gripper };
    /// assert!(matches!(robot.reachability(&near, &q, &ReachParams::default())?, Reachability::Reachable(_)));
    /// let far = IkTarget { pose: Translation3::new(3.0, 0.0, 0.0) * pose, ..near };
    /// assert!(matches!(robot.reachability(&far, &q, &ReachParams::default())?, Reachability::Unreachable { .. }));
    /// # Ok::<(), ftwire_robot::RobotError>(())
    /// ```
    pub fn reachability(
        &self,
        target: &IkTarget,
        seed: &ArmJoints,
        params: &ReachParams,
    ) -> Result<Reachability, RobotError> {
        for (name, value) in [
            ("position_tolerance", params.position_tolerance),
            ("rotation_tolerance", params.rotation_tolerance),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(RobotError::InvalidParameter {
                    name,
                    value,
                    allowed: "a finite tolerance > 0",
                });
            }
        }
        self.check_joints(target.arm, seed)?;
        let problem = match ArmProblem::new(
            self,
            target,
            params.position_tolerance,
            params.rotation_tolerance,
        ) {
            Ok(p) => p,
            Err(RobotError::OutOfReach {
                distance, reach, ..
            }) => return Ok(Reachability::Unreachable { distance, reach }),
            Err(e) => return Err(e),
        };
        let d = problem.descend(seed, Some(seed), 0.2, params.max_iterations);
        Ok(if d.converged {
            Reachability::Reachable(d.joints)
        } else {
            Reachability::Unknown {
                position_error: d.position_error,
                rotation_error: d.rotation_error,
            }
        })
    }
}
