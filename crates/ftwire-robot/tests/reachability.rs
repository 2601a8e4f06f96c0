//! The cheap reachability query: definite answers are right, and it mostly decides near a seed.

use ftwire_robot::{Arm, ArmJoints, EndFrame, IkTarget, ReachParams, Reachability, Robot};
use nalgebra::Translation3;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

#[test]
fn near_seeds_decide_and_definite_answers_are_right() {
    let robot = Robot::sda10f().expect("embedded URDF");
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let limits = robot.chain(Arm::Right).limits();
    let params = ReachParams::default();
    let n = 200;
    let mut reachable = 0;
    for _ in 0..n {
        let q = ArmJoints::from_fn(|i, _| rng.random_range(limits[i].min..=limits[i].max));
        let seed =
            ArmJoints::from_fn(|i, _| limits[i].clamp(q[i] + rng.random_range(-0.05..=0.05)));
        let pose = robot
            .fk(Arm::Right, 0.0, &q, EndFrame::Gripper)
            .expect("fk");
        let target = IkTarget {
            arm: Arm::Right,
            pose,
            torso: 0.0,
            frame: EndFrame::Gripper,
        };
        match robot
            .reachability(&target, &seed, &params)
            .expect("valid input")
        {
            Reachability::Reachable(s) => {
                let f = robot
                    .fk(Arm::Right, 0.0, &s, EndFrame::Gripper)
                    .expect("within limits");
                assert!((f.translation.vector - pose.translation.vector).norm() <= 1e-6);
                assert!(f.rotation.angle_to(&pose.rotation) <= 1e-6);
                reachable += 1;
            }
            Reachability::Unreachable { .. } => panic!("a pose made by FK is reachable"),
            Reachability::Unknown { .. } => {}
        }
        // Far away: definitely unreachable.
        let far = IkTarget {
            pose: Translation3::new(0.0, 0.0, 3.0) * pose,
            ..target
        };
        assert!(matches!(
            robot.reachability(&far, &seed, &params).expect("valid"),
            Reachability::Unreachable { .. }
        ));
    }
    eprintln!("reachability from a seed 0.05 rad away: {reachable}/{n} decided reachable");
    assert!(reachable * 100 >= n * 95, "{reachable}/{n}");
}
