//! Whether the robot can put the second gripper at a relative pose `b` (the controller asks
//! before every move).

use ftwire_core::Pose;
use ftwire_robot::{DualArmJoints, DualArmParams, DualArmTarget, Robot};

/// The answer of a [`ReachCheck`].
#[derive(Debug, Clone, PartialEq)]
pub enum Reach {
    /// The pose can be reached.
    Reachable,
    /// It cannot; why.
    Unreachable(String),
}

/// A reachability test for the second gripper's pose `b` relative to the base clamp.
pub trait ReachCheck {
    /// Whether `relative` (second clamp in the base clamp frame) is reachable. Implementations
    /// may remember the last reachable solution to seed the next query.
    fn check(&mut self, relative: &Pose) -> Reach;
}

/// Every pose is reachable: for tests and for experiments that ignore the robot's kinematics.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct AnyPose;

impl ReachCheck for AnyPose {
    fn check(&mut self, _relative: &Pose) -> Reach {
        Reach::Reachable
    }
}

/// The SDA10F's check: dual-arm IK within the joint limits and no arm–arm collision
/// (`ftwire_robot::Robot::dual_arm_ik` with `check_collision`), the base gripper held at a
/// fixed world pose; each solution seeds the next query, so that successive poses of a motion
/// stay on one IK branch, and a pose the seeded solve misses gets the full search before it is
/// called unreachable. The search refines the torso angle where one arm stops reaching and
/// the other starts ([`DualArmParams::refine_torso`]): a planner keeps to the coarse search's
/// reach, and execution, which must follow the wire wherever the noise puts it, may use the
/// narrow torso windows at the edge of the robot's reach.
#[derive(Debug, Clone)]
pub struct RobotReach {
    robot: Robot,
    world_from_base: Pose,
    base_gripper: Pose,
    params: DualArmParams,
    seed: Option<DualArmJoints>,
}

impl RobotReach {
    /// A check for `robot` with the base gripper's clamp at `base_gripper` (world frame, with
    /// the robot base at `world_from_base`), with collision checks on.
    pub fn new(robot: Robot, world_from_base: Pose, base_gripper: Pose) -> Self {
        Self {
            robot,
            world_from_base,
            base_gripper,
            params: DualArmParams {
                check_collision: true,
                refine_torso: true,
                ..DualArmParams::default()
            },
            seed: None,
        }
    }

    /// The last joint solution found (the next query's seed).
    pub fn last_solution(&self) -> Option<&DualArmJoints> {
        self.seed.as_ref()
    }
}

impl ReachCheck for RobotReach {
    fn check(&mut self, relative: &Pose) -> Reach {
        let target = DualArmTarget {
            world_from_base: self.world_from_base,
            base_gripper: self.base_gripper,
            relative: *relative,
        };
        let seeded = self
            .robot
            .dual_arm_ik(&target, self.seed.as_ref(), &self.params);
        // A seeded solve stays near the last solution's branch; when it fails, the full
        // search (restarts and the torso sweep) decides whether the pose is out of reach.
        let solved = match (seeded, &self.seed) {
            (Err(_), Some(_)) => self.robot.dual_arm_ik(&target, None, &self.params),
            (seeded, _) => seeded,
        };
        match solved {
            Ok(joints) => {
                self.seed = Some(joints);
                Reach::Reachable
            }
            Err(e) => Reach::Unreachable(e.to_string()),
        }
    }
}
