//! The SDA10F reach check: a pose the arms hold in their preferred postures is reachable, one
//! three metres away is not.

use ftwire_control::{Reach, ReachCheck, RobotReach};
use ftwire_core::Pose;
use ftwire_robot::{Arm, EndFrame, Robot};

/// The left (base) gripper's pose in the left arm's preferred posture.
fn left_gripper(robot: &Robot) -> Pose {
    robot
        .fk(
            Arm::Left,
            0.0,
            robot.preferred_posture(Arm::Left),
            EndFrame::Gripper,
        )
        .expect("fk")
}

#[test]
fn the_robot_reaches_its_own_posture_and_not_far_away() {
    let robot = Robot::sda10f().expect("the URDF parses");
    let base = left_gripper(&robot);
    let tip = robot
        .fk(
            Arm::Right,
            0.0,
            robot.preferred_posture(Arm::Right),
            EndFrame::Gripper,
        )
        .expect("fk");
    let mut reach = RobotReach::new(robot, Pose::identity(), base);
    assert_eq!(reach.check(&(base.inverse() * tip)), Reach::Reachable);
    assert!(reach.last_solution().is_some());
    let far = base.inverse() * Pose::translation(3.0, 0.0, 0.0) * tip;
    assert!(matches!(reach.check(&far), Reach::Unreachable(_)));
}

#[test]
fn whether_a_pose_is_reachable_does_not_depend_on_the_last_solution() {
    let robot = Robot::sda10f().expect("the URDF parses");
    let base = left_gripper(&robot);
    let posture = robot.preferred_posture(Arm::Right);
    // A far-off posture of the right arm: its pose is on another branch than the preferred one.
    let mut other = *posture;
    for (k, q) in other.iter_mut().enumerate() {
        *q += if k % 2 == 0 { 0.5 } else { -0.4 };
    }
    let tip = |joints: &ftwire_robot::ArmJoints| {
        base.inverse()
            * robot
                .fk(Arm::Right, 0.0, joints, EndFrame::Gripper)
                .expect("fk")
    };
    let (near, far) = (tip(posture), tip(&other));
    let fresh = RobotReach::new(robot.clone(), Pose::identity(), base).check(&far);
    let mut seeded = RobotReach::new(robot, Pose::identity(), base);
    assert_eq!(seeded.check(&near), Reach::Reachable);
    assert_eq!(
        seeded.check(&far),
        fresh,
        "the seeded check agrees with a fresh one"
    );
}
