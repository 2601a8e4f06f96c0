//! Dual-arm IK round trips for the wire task.

use ftwire_robot::{
    Arm, ArmJoints, DualArmJoints, DualArmParams, DualArmTarget, EndFrame, Robot, RobotError,
    TorsoChoice, pose_from_vectors,
};
use nalgebra::Vector3;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn robot() -> Robot {
    Robot::sda10f().expect("embedded URDF")
}

fn random(robot: &Robot, arm: Arm, rng: &mut ChaCha8Rng) -> ArmJoints {
    let l = robot.chain(arm).limits();
    ArmJoints::from_fn(|i, _| rng.random_range(l[i].min..=l[i].max))
}

#[test]
fn dual_arm_round_trip_in_a_world_frame() {
    let robot = robot();
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let world_from_base =
        pose_from_vectors(Vector3::new(0.3, -0.2, 0.8), Vector3::new(0.0, 0.0, 0.4));
    let n = 100;
    let mut ok = 0;
    for _ in 0..n {
        let torso = rng.random_range(-1.0..=1.0);
        let (l, r) = (
            random(&robot, Arm::Left, &mut rng),
            random(&robot, Arm::Right, &mut rng),
        );
        let base = world_from_base
            * robot
                .fk(Arm::Left, torso, &l, EndFrame::Gripper)
                .expect("fk");
        let tip = world_from_base
            * robot
                .fk(Arm::Right, torso, &r, EndFrame::Gripper)
                .expect("fk");
        let target = DualArmTarget {
            world_from_base,
            base_gripper: base,
            relative: base.inverse() * tip,
        };
        // Random postures may collide: this test is about the kinematics.
        let params = DualArmParams {
            torso: TorsoChoice::Fixed(torso),
            check_collision: false,
            ..DualArmParams::default()
        };
        match robot.dual_arm_ik(&target, None, &params) {
            Ok(s) => {
                let b = world_from_base
                    * robot
                        .fk(Arm::Left, s.torso, &s.left, EndFrame::Gripper)
                        .expect("fk");
                let t = world_from_base
                    * robot
                        .fk(Arm::Right, s.torso, &s.right, EndFrame::Gripper)
                        .expect("fk");
                assert!((b.translation.vector - base.translation.vector).norm() <= 1e-6 * 2.0);
                assert!((t.translation.vector - tip.translation.vector).norm() <= 1e-6 * 2.0);
                assert!(b.rotation.angle_to(&base.rotation) <= 2e-6);
                assert!(t.rotation.angle_to(&tip.rotation) <= 2e-6);
                let relative = b.inverse() * t;
                assert!(
                    (relative.translation.vector - target.relative.translation.vector).norm()
                        < 1e-5
                );
                ok += 1;
            }
            Err(e) => eprintln!("{e}"),
        }
    }
    eprintln!("dual-arm round trip: {ok}/{n}");
    assert!(ok * 100 >= n * 97, "{ok}/{n}");
}

#[test]
fn torso_search_finds_a_solution_away_from_its_start_and_seeds_track() {
    let robot = robot();
    let (l, r) = (
        *robot.preferred_posture(Arm::Left),
        *robot.preferred_posture(Arm::Right),
    );
    // A pair of poses made at torso 1.2: search starts at 0.
    let base = robot.fk(Arm::Left, 1.2, &l, EndFrame::Gripper).expect("fk");
    let tip = robot
        .fk(Arm::Right, 1.2, &r, EndFrame::Gripper)
        .expect("fk");
    let target = DualArmTarget {
        world_from_base: ftwire_core::Pose::identity(),
        base_gripper: base,
        relative: base.inverse() * tip,
    };
    let params = DualArmParams::default();
    let s = robot.dual_arm_ik(&target, None, &params).expect("solvable");
    assert!(
        robot
            .arms_collision(s.torso, &s.left, &s.right, &params.radii)
            .expect("valid")
            .is_none()
    );
    // Seeded with the true answer, the search starts there and returns it.
    let seed = DualArmJoints {
        torso: 1.2,
        left: l,
        right: r,
    };
    let s2 = robot
        .dual_arm_ik(&target, Some(&seed), &params)
        .expect("solvable");
    assert!((s2.torso - 1.2).abs() < 1e-12);
    assert!((s2.left - l).amax() < 1e-3 && (s2.right - r).amax() < 1e-3);
}

#[test]
fn too_long_a_wire_has_no_solution_and_says_why() {
    let robot = robot();
    let l = *robot.preferred_posture(Arm::Left);
    let base = robot.fk(Arm::Left, 0.0, &l, EndFrame::Gripper).expect("fk");
    let target = DualArmTarget {
        world_from_base: ftwire_core::Pose::identity(),
        base_gripper: base,
        relative: pose_from_vectors(Vector3::new(4.0, 0.0, 0.0), Vector3::zeros()),
    };
    let params = DualArmParams {
        torso: TorsoChoice::Search {
            start: 0.0,
            step: 0.5,
        },
        ..DualArmParams::default()
    };
    match robot.dual_arm_ik(&target, None, &params) {
        Err(RobotError::DualArmUnreachable {
            torsos_tried,
            right_failures,
            collisions,
            ..
        }) => {
            assert!(torsos_tried >= 11);
            assert_eq!(collisions, 0);
            assert!(right_failures > 0);
        }
        other => panic!("expected DualArmUnreachable, got {other:?}"),
    }
    let bad = DualArmParams {
        torso: TorsoChoice::Search {
            start: 0.0,
            step: 0.0,
        },
        ..params
    };
    assert!(matches!(
        robot.dual_arm_ik(&target, None, &bad),
        Err(RobotError::InvalidParameter { .. })
    ));
}

/// The refinement of the torso search finds poses the coarse search steps over (each arm alone
/// reaches its pose in a torso window; the windows overlap between two search angles), returns
/// only true solutions, and changes nothing where the coarse search succeeds.
#[test]
fn refining_the_torso_finds_the_windows_between_search_angles() {
    let robot = robot();
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let coarse = DualArmParams {
        torso: TorsoChoice::Search {
            start: 0.0,
            step: 1.0,
        },
        check_collision: false,
        ..DualArmParams::default()
    };
    let refined = DualArmParams {
        refine_torso: true,
        ..coarse
    };
    let (mut coarse_solved, mut refined_solved) = (0, 0);
    for _ in 0..60 {
        let torso = rng.random_range(-1.5..=1.5);
        let (l, r) = (
            random(&robot, Arm::Left, &mut rng),
            random(&robot, Arm::Right, &mut rng),
        );
        let base = robot
            .fk(Arm::Left, torso, &l, EndFrame::Gripper)
            .expect("fk");
        let tip = robot
            .fk(Arm::Right, torso, &r, EndFrame::Gripper)
            .expect("fk");
        let target = DualArmTarget {
            world_from_base: ftwire_core::Pose::identity(),
            base_gripper: base,
            relative: base.inverse() * tip,
        };
        let first = robot.dual_arm_ik(&target, None, &coarse).ok();
        let second = robot.dual_arm_ik(&target, None, &refined).ok();
        if let Some(s) = &first {
            coarse_solved += 1;
            assert_eq!(
                second.as_ref(),
                Some(s),
                "the refinement runs only after a miss"
            );
        }
        if let Some(s) = &second {
            refined_solved += 1;
            let b = robot
                .fk(Arm::Left, s.torso, &s.left, EndFrame::Gripper)
                .expect("fk");
            let t = robot
                .fk(Arm::Right, s.torso, &s.right, EndFrame::Gripper)
                .expect("fk");
            assert!((b.translation.vector - base.translation.vector).norm() <= 1e-6);
            assert!((t.translation.vector - tip.translation.vector).norm() <= 1e-6);
            assert!(b.rotation.angle_to(&base.rotation) <= 1e-6);
            assert!(t.rotation.angle_to(&tip.rotation) <= 1e-6);
        }
    }
    assert!(
        refined_solved > coarse_solved,
        "refined {refined_solved}, coarse {coarse_solved} of 60"
    );
}
