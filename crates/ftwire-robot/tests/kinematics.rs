//! Forward kinematics at hand-checked postures, and the Jacobian against finite differences.

use approx::assert_relative_eq;
use ftwire_robot::{Arm, ArmJoints, EndFrame, Robot, RobotError, arm_joints};
use nalgebra::{Rotation3, UnitQuaternion, Vector3, Vector6};
use proptest::prelude::*;

fn robot() -> Robot {
    Robot::sda10f().expect("embedded URDF")
}

/// tool0 of the left arm at the all-zero posture, computed by hand from the URDF origins.
///
/// The joint frames alternate `Rx(1.57)` and `Rx(−1.57)`, so at zero angles the offsets of
/// joints 2, 4, 6 are seen through `Rx(1.57)` and those of joints 3, 5, 7 through the identity.
fn left_tool0_at_zero_by_hand() -> Vector3<f64> {
    let (s, c) = 1.57_f64.sin_cos();
    let through = |y: f64, z: f64| Vector3::new(0.0, y * c - z * s, y * s + z * c);
    Vector3::new(0.09996, 0.0275, 0.32214)
        + through(0.0577, -0.2255)
        + Vector3::new(0.0, 0.169, -0.0454)
        + through(-0.0085, -0.181)
        + Vector3::new(0.0, 0.1936, 0.0155)
        + through(0.008, -0.155)
        + Vector3::new(0.0, 0.168, -0.015)
}

#[test]
fn zero_posture_matches_the_hand_computation_and_the_data_readme() {
    let robot = robot();
    let p = robot
        .fk(Arm::Left, 0.0, &ArmJoints::zeros(), EndFrame::Tool0)
        .expect("fk");
    let hand = left_tool0_at_zero_by_hand();
    assert_relative_eq!(p.translation.vector, hand, epsilon = 1e-12);
    // data/README.md: about (0.10, ±1.12, 0.33) m.
    assert_relative_eq!(hand, Vector3::new(0.10, 1.12, 0.33), epsilon = 0.005);
    // Orientation: Rx(1.57) from joint 7's frame, then the flange's Rz(−3.13).
    let r = UnitQuaternion::from_euler_angles(1.57, 0.0, 0.0)
        * UnitQuaternion::from_euler_angles(0.0, 0.0, -3.13);
    assert!(p.rotation.angle_to(&r) < 1e-12);

    let right = robot
        .fk(Arm::Right, 0.0, &ArmJoints::zeros(), EndFrame::Tool0)
        .expect("fk")
        .translation
        .vector;
    // The right arm is the mirror image, up to the URDF's yaw of −3.14 instead of −π.
    assert_relative_eq!(right.y, -1.12, epsilon = 0.005);
    assert_relative_eq!(right.z, hand.z, epsilon = 1e-9);
    assert_relative_eq!(right.x, 0.10, epsilon = 0.005);
}

#[test]
fn torso_rotates_the_zero_posture_about_z() {
    let robot = robot();
    let t = 0.5;
    let p = robot
        .fk(Arm::Left, t, &ArmJoints::zeros(), EndFrame::Tool0)
        .expect("fk");
    let hand = Rotation3::from_axis_angle(&Vector3::z_axis(), t) * left_tool0_at_zero_by_hand();
    assert_relative_eq!(p.translation.vector, hand, epsilon = 1e-12);
}

#[test]
fn joint_2_swings_the_stretched_arm_about_minus_z() {
    // At zero, joint 2's axis is −z in the base frame, so turning it by q2 rotates everything
    // beyond joint 2's origin by Rz(−q2) about that origin.
    let robot = robot();
    let (s, c) = 1.57_f64.sin_cos();
    let j2 = Vector3::new(0.09996, 0.0275, 0.32214)
        + Vector3::new(0.0, 0.0577 * c + 0.2255 * s, 0.0577 * s - 0.2255 * c);
    let q2 = std::f64::consts::FRAC_PI_2;
    let q = arm_joints(&[0.0, q2, 0.0, 0.0, 0.0, 0.0, 0.0]).expect("q");
    let p = robot.fk(Arm::Left, 0.0, &q, EndFrame::Tool0).expect("fk");
    let hand = j2
        + Rotation3::from_axis_angle(&Vector3::z_axis(), -q2) * (left_tool0_at_zero_by_hand() - j2);
    assert_relative_eq!(p.translation.vector, hand, epsilon = 1e-12);
    // Swung forward: the hand is now in front of the robot (x ≈ 0.1 + 0.87 m).
    assert!(p.translation.vector.x > 0.9);
}

#[test]
fn gripper_frames_follow_the_clamp_convention() {
    let robot = robot();
    for (arm, length, sign) in [(Arm::Left, 0.145, -1.0), (Arm::Right, 0.10, 1.0)] {
        let q = *robot.preferred_posture(arm);
        let tool0 = robot.fk(arm, 0.0, &q, EndFrame::Tool0).expect("fk");
        let grip = robot.fk(arm, 0.0, &q, EndFrame::Gripper).expect("fk");
        let z = tool0.rotation * Vector3::z();
        assert_relative_eq!(
            grip.translation.vector,
            tool0.translation.vector - z * length,
            epsilon = 1e-12
        );
        assert_relative_eq!(grip.rotation * Vector3::x(), z * sign, epsilon = 1e-12);
    }
}

#[test]
fn grippers_stick_out_of_the_flange() {
    // At the all-zero posture the arms stretch sideways: the grippers must lie farther out.
    let robot = robot();
    let zero = ArmJoints::zeros();
    let left = robot
        .fk(Arm::Left, 0.0, &zero, EndFrame::Gripper)
        .expect("fk");
    let right = robot
        .fk(Arm::Right, 0.0, &zero, EndFrame::Gripper)
        .expect("fk");
    let hand = left_tool0_at_zero_by_hand();
    assert_relative_eq!(left.translation.vector.y, hand.y + 0.145, epsilon = 1e-5);
    assert_relative_eq!(right.translation.vector.y, -hand.y - 0.10, epsilon = 1e-3);
    // The base clamp's x axis points away from the robot (+y), the tip clamp's toward it (+y).
    assert_relative_eq!(left.rotation * Vector3::x(), Vector3::y(), epsilon = 1e-3);
    assert_relative_eq!(right.rotation * Vector3::x(), Vector3::y(), epsilon = 1e-2);
}

#[test]
fn bad_inputs_are_errors() {
    let robot = robot();
    let mut q = ArmJoints::zeros();
    q[2] = f64::NAN;
    assert!(matches!(
        robot.fk(Arm::Left, 0.0, &q, EndFrame::Gripper),
        Err(RobotError::Core(_))
    ));
    q[2] = 2.0;
    q[1] = 2.0; // joint 2 limit is ±1.9
    match robot.fk(Arm::Left, 0.0, &q, EndFrame::Gripper) {
        Err(RobotError::OutOfLimit { joint, max, .. }) => {
            assert_eq!(joint, 1);
            assert_relative_eq!(max, 1.9);
        }
        other => panic!("expected OutOfLimit, got {other:?}"),
    }
    assert!(matches!(
        robot.fk(Arm::Left, 3.5, &ArmJoints::zeros(), EndFrame::Gripper),
        Err(RobotError::OutOfLimit { joint: 7, .. })
    ));
    assert!(matches!(
        arm_joints(&[0.0; 8]),
        Err(RobotError::JointCount {
            expected: 7,
            got: 8
        })
    ));
}

#[test]
fn urdf_loads_from_a_file_and_reports_missing_files() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/robots/sda10f.urdf");
    let from_file = Robot::from_urdf_file(path, &Default::default()).expect("file loads");
    assert_eq!(from_file, robot());
    assert!(matches!(
        Robot::from_urdf_file("/no/such/file.urdf", &Default::default()),
        Err(RobotError::Io { .. })
    ));
    let names = ftwire_robot::ChainNames {
        left_tool0: "no_such_link".into(),
        ..Default::default()
    };
    assert!(matches!(
        Robot::from_urdf_str(ftwire_robot::SDA10F_URDF, &names),
        Err(RobotError::Model { .. })
    ));
}

#[test]
fn limits_come_from_the_urdf() {
    let robot = robot();
    let l = robot.chain(Arm::Right).limits();
    assert_relative_eq!(l[3].min, -2.36);
    assert_relative_eq!(l[6].max, 3.13);
    assert_relative_eq!(robot.torso_joint().limit.max, 2.967060);
}

/// Central finite difference of the pose (angular part from the rotation's log) per joint.
fn finite_difference(robot: &Robot, arm: Arm, torso: f64, q: &ArmJoints, i: usize) -> Vector6<f64> {
    let h = 1e-6;
    let mut qp = *q;
    let mut qm = *q;
    qp[i] += h;
    qm[i] -= h;
    let fp = robot.fk(arm, torso, &qp, EndFrame::Gripper).expect("fk");
    let fm = robot.fk(arm, torso, &qm, EndFrame::Gripper).expect("fk");
    let w = (fp.rotation * fm.rotation.inverse()).scaled_axis() / (2.0 * h);
    let v = (fp.translation.vector - fm.translation.vector) / (2.0 * h);
    Vector6::new(w.x, w.y, w.z, v.x, v.y, v.z)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    #[test]
    fn jacobian_matches_finite_differences(
        raw in prop::array::uniform7(-0.98f64..0.98),
        torso in -2.0f64..2.0,
        left in any::<bool>(),
    ) {
        let robot = robot();
        let arm = if left { Arm::Left } else { Arm::Right };
        let limits = robot.chain(arm).limits();
        // Scale into the limits, with room for the finite-difference step.
        let q = ArmJoints::from_fn(|i, _| raw[i] * limits[i].max.min(-limits[i].min));
        let j = robot.jacobian(arm, torso, &q, EndFrame::Gripper).expect("jacobian");
        let j8 = robot.jacobian_with_torso(arm, torso, &q, EndFrame::Gripper).expect("jacobian");
        for i in 0..7 {
            let fd = finite_difference(&robot, arm, torso, &q, i);
            prop_assert!((j.column(i) - fd).norm() < 1e-7, "column {i}: {} vs {}", j.column(i), fd);
            prop_assert!((j8.column(i + 1) - j.column(i)).norm() < 1e-15);
        }
        // Torso column.
        let h = 1e-6;
        let fp = robot.fk(arm, torso + h, &q, EndFrame::Gripper).expect("fk");
        let fm = robot.fk(arm, torso - h, &q, EndFrame::Gripper).expect("fk");
        let w = (fp.rotation * fm.rotation.inverse()).scaled_axis() / (2.0 * h);
        let v = (fp.translation.vector - fm.translation.vector) / (2.0 * h);
        let fd = Vector6::new(w.x, w.y, w.z, v.x, v.y, v.z);
        prop_assert!((j8.column(0) - fd).norm() < 1e-7);
    }
}

#[test]
fn the_robot_can_be_shared_between_threads() {
    fn shareable<T: Send + Sync>() {}
    shareable::<Robot>();
    let robot = robot();
    let q = *robot.preferred_posture(Arm::Left);
    let here = robot.fk(Arm::Left, 0.0, &q, EndFrame::Gripper).expect("fk");
    let there = std::thread::scope(|s| {
        s.spawn(|| robot.fk(Arm::Left, 0.0, &q, EndFrame::Gripper))
            .join()
            .expect("thread")
    })
    .expect("fk");
    assert_eq!(here, there);
}
