//! The SDA10F reach check: a pose the arms hold in their preferred postures is reachable, one
//! three metres away is not.

use ftwire_control::{Reach, ReachCheck, RobotReach};
use ftwire_core::Pose;
use ftwire_robot::{Arm, EndFrame, Robot};

#[test]
fn the_robot_reaches_its_own_posture_and_not_far_away() {
    let robot = Robot::sda10f().expect("the URDF parses");
    let base = robot
        .fk(
            Arm::Left,
            0.0,
            robot.preferred_posture(Arm::Left),
            EndFrame::Gripper,
        )
        .expect("fk");
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
