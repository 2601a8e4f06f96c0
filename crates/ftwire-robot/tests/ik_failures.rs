//! IK failure modes: unreachable targets and bad input give errors, never panics or wrong answers;
//! the redundancy is used to stay near the requested posture.

use ftwire_robot::{
    Arm, ArmJoints, EndFrame, IkParams, IkTarget, Posture, Robot, RobotError, pose_from_vectors,
};
use nalgebra::{Translation3, UnitQuaternion, Vector3};
use proptest::prelude::*;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn robot() -> Robot {
    Robot::sda10f().expect("embedded URDF")
}

fn target(arm: Arm, pose: ftwire_core::Pose) -> IkTarget {
    IkTarget {
        arm,
        pose,
        torso: 0.0,
        frame: EndFrame::Gripper,
    }
}

#[test]
fn far_target_is_out_of_reach() {
    let robot = robot();
    let pose = pose_from_vectors(Vector3::new(2.5, 0.0, 0.3), Vector3::zeros());
    match robot.ik(&target(Arm::Left, pose), None, &IkParams::default()) {
        Err(RobotError::OutOfReach {
            distance, reach, ..
        }) => assert!(distance > reach),
        other => panic!("expected OutOfReach, got {other:?}"),
    }
}

#[test]
fn pose_beyond_the_stretched_arm_is_unreachable_with_a_residual() {
    // Near the reach bound the arm must be almost straight, so the gripper must point outward;
    // asking it to point back at the shoulder there cannot be satisfied.
    let robot = robot();
    let zero = ArmJoints::zeros();
    let straight = robot
        .fk(Arm::Left, 0.0, &zero, EndFrame::Gripper)
        .expect("fk");
    let flipped = ftwire_core::Pose::from_parts(
        straight.translation,
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), std::f64::consts::PI)
            * straight.rotation,
    );
    let params = IkParams {
        random_restarts: 8,
        ..IkParams::default()
    };
    match robot.ik(&target(Arm::Left, flipped), None, &params) {
        Err(RobotError::Unreachable {
            position_error,
            rotation_error,
            attempts,
            ..
        }) => {
            assert_eq!(attempts, 9);
            assert!(position_error > 1e-6 || rotation_error > 1e-6);
        }
        other => panic!("expected Unreachable, got {other:?}"),
    }
}

#[test]
fn bad_input_is_an_error() {
    let robot = robot();
    let q = *robot.preferred_posture(Arm::Right);
    let good = robot
        .fk(Arm::Right, 0.0, &q, EndFrame::Gripper)
        .expect("fk");
    let params = IkParams::default();

    let mut nan = good;
    nan.translation.vector.x = f64::NAN;
    assert!(matches!(
        robot.ik(&target(Arm::Right, nan), None, &params),
        Err(RobotError::Core(_))
    ));
    let bad_torso = IkTarget {
        torso: f64::INFINITY,
        ..target(Arm::Right, good)
    };
    assert!(matches!(
        robot.ik(&bad_torso, None, &params),
        Err(RobotError::Core(_))
    ));
    let far_torso = IkTarget {
        torso: 3.1,
        ..target(Arm::Right, good)
    };
    assert!(matches!(
        robot.ik(&far_torso, None, &params),
        Err(RobotError::OutOfLimit { joint: 7, .. })
    ));
    let mut seed = q;
    seed[5] = 2.5;
    assert!(matches!(
        robot.ik(&target(Arm::Right, good), Some(&seed), &params),
        Err(RobotError::OutOfLimit { joint: 5, .. })
    ));
    let zero_tol = IkParams {
        position_tolerance: 0.0,
        ..params
    };
    assert!(matches!(
        robot.ik(&target(Arm::Right, good), None, &zero_tol),
        Err(RobotError::InvalidParameter { .. })
    ));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]
    /// Arbitrary poses: a verified answer or an error, never a panic or a wrong answer.
    #[test]
    fn arbitrary_targets_never_give_a_wrong_answer(
        p in prop::array::uniform3(-1.6f64..1.6),
        r in prop::array::uniform3(-3.0f64..3.0),
        left in any::<bool>(),
    ) {
        let robot = robot();
        let arm = if left { Arm::Left } else { Arm::Right };
        let pose = pose_from_vectors(Vector3::from(p), Vector3::from(r));
        let params = IkParams { random_restarts: 3, ..IkParams::default() };
        match robot.ik(&target(arm, pose), None, &params) {
            Ok(s) => {
                robot.check_joints(arm, &s.joints).expect("within limits");
                let f = robot.fk(arm, 0.0, &s.joints, EndFrame::Gripper).expect("fk");
                prop_assert!((f.translation.vector - pose.translation.vector).norm() <= 1e-6);
                prop_assert!(f.rotation.angle_to(&pose.rotation) <= 1e-6);
            }
            Err(RobotError::Unreachable { position_error, rotation_error, .. }) => {
                prop_assert!(position_error > 1e-6 || rotation_error > 1e-6);
            }
            Err(RobotError::OutOfReach { distance, reach, .. }) => prop_assert!(distance > reach),
            Err(e) => prop_assert!(false, "unexpected error {e}"),
        }
    }
}

#[test]
fn small_target_steps_give_small_joint_steps() {
    // Tracking a straight 20 cm line in 5 mm steps, seeding with the previous solution.
    let robot = robot();
    let mut q = *robot.preferred_posture(Arm::Left);
    let start = robot.fk(Arm::Left, 0.0, &q, EndFrame::Gripper).expect("fk");
    for k in 1..=40 {
        let pose = Translation3::new(0.0, 0.0, 0.005 * f64::from(k)) * start;
        let s = robot
            .ik(&target(Arm::Left, pose), Some(&q), &IkParams::default())
            .expect("reachable");
        let step = (s.joints - q).amax();
        assert!(step < 0.05, "step {k}: joints jumped by {step} rad");
        q = s.joints;
    }
}

#[test]
fn nullspace_pull_keeps_solutions_near_the_preferred_posture() {
    let robot = robot();
    let preferred = *robot.preferred_posture(Arm::Right);
    let limits = robot.chain(Arm::Right).limits();
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let (mut pulled, mut free) = (0.0, 0.0);
    for _ in 0..40 {
        // Targets near the preferred posture's pose, seeded from a nearby random posture.
        let q =
            ArmJoints::from_fn(|i, _| limits[i].clamp(preferred[i] + rng.random_range(-0.4..=0.4)));
        let seed = ArmJoints::from_fn(|i, _| limits[i].clamp(q[i] + rng.random_range(-0.3..=0.3)));
        let pose = robot
            .fk(Arm::Right, 0.0, &q, EndFrame::Gripper)
            .expect("fk");
        let t = target(Arm::Right, pose);
        let with = IkParams {
            posture: Posture::Preferred,
            ..IkParams::default()
        };
        let without = IkParams {
            posture: Posture::Free,
            ..IkParams::default()
        };
        pulled += (robot.ik(&t, Some(&seed), &with).expect("solves").joints - preferred).norm();
        free += (robot.ik(&t, Some(&seed), &without).expect("solves").joints - preferred).norm();
    }
    eprintln!("distance to the preferred posture: pulled {pulled:.3}, free {free:.3}");
    assert!(pulled < free, "pulled {pulled} vs free {free}");
}

#[test]
fn same_rng_seed_same_answer() {
    let robot = robot();
    let q = ftwire_robot::arm_joints(&[1.0, -1.2, 2.0, 1.5, -2.0, 1.0, 0.5]).expect("q");
    let pose = robot.fk(Arm::Left, 0.0, &q, EndFrame::Gripper).expect("fk");
    let params = IkParams {
        rng_seed: 99,
        ..IkParams::default()
    };
    let a = robot
        .ik(&target(Arm::Left, pose), None, &params)
        .expect("solves");
    let b = robot
        .ik(&target(Arm::Left, pose), None, &params)
        .expect("solves");
    assert_eq!(a, b);
}

#[test]
fn a_pose_needing_the_elbow_beyond_its_limit_names_the_limit() {
    // The same robot with the left elbow (joint 4, ±2.36 rad) allowed to ±3.1 rad: fold the elbow
    // to 3.0 rad, which brings the wrist closer to the shoulder than the real limits allow.
    let widened = ftwire_robot::SDA10F_URDF.replacen(
        r#"<axis xyz="0 0 1"/>
    <limit lower="-2.36" upper="2.36""#,
        r#"<axis xyz="0 0 1"/>
    <limit lower="-3.1" upper="3.1""#,
        1,
    );
    assert_ne!(widened, ftwire_robot::SDA10F_URDF, "the edit must apply");
    let wide = Robot::from_urdf_str(&widened, &Default::default()).expect("valid URDF");
    assert!((wide.chain(Arm::Left).limits()[3].max - 3.1).abs() < 1e-12);
    let q = ftwire_robot::arm_joints(&[0.2, 0.5, 0.1, 3.0, 0.2, -0.5, 0.1]).expect("q");
    let pose = wide.fk(Arm::Left, 0.0, &q, EndFrame::Gripper).expect("fk");
    match robot().ik(&target(Arm::Left, pose), None, &IkParams::default()) {
        Err(RobotError::Unreachable { limited_joint, .. }) => assert_eq!(limited_joint, Some(3)),
        other => panic!("expected Unreachable at the elbow limit, got {other:?}"),
    }
}
