#![doc = include_str!("../README.md")]

mod arm;
mod chain;
mod collision;
mod dual_arm;
mod error;
mod ik;
mod reach;
mod robot;
mod urdf;

pub use arm::Arm;
pub use chain::{
    ARM_DOF, ArmChain, ArmJacobian, ArmJoints, ArmTorsoJacobian, JointLimit, RevoluteJoint,
    arm_joints, pose_from_vectors,
};
pub use collision::{
    Capsule, Contact, LINK_CAPSULES, LinkRadii, OrientedBox, point_box_distance,
    segment_box_distance, segment_segment_distance,
};
pub use dual_arm::{
    DualArmJoints, DualArmParams, DualArmTarget, MIN_TORSO_STEP, REFINE_DIVISIONS, TorsoChoice,
};
pub use error::RobotError;
pub use ik::{IkParams, IkSolution, IkTarget, Posture};
pub use reach::{ReachParams, Reachability};
pub use robot::{
    DEFAULT_FT_STACK_LENGTH, DEFAULT_GRIPPER_LENGTH, DEFAULT_PREFERRED_POSTURE, EndFrame,
    GripperFrames, Robot, TORSO_JOINT_INDEX,
};
pub use urdf::{ChainNames, SDA10F_URDF};
