//! Execution noise (`NoisyRig`): the models differ as documented, the paper's increment
//! noise accumulates along a rolled-out plan, and the reported pose stays a rotation.

use ftwire_control::open_loop::roll_out;
use ftwire_control::{NoiseModel, NoiseParams, NoisyRig};
use ftwire_core::Pose;
use nalgebra::Vector6;

/// A rig that stays where it is told (for the noise statistics).
#[derive(Debug)]
struct Still(ftwire_core::GripperPoses);

impl ftwire_core::Rig for Still {
    type Error = std::convert::Infallible;
    fn read_ft(&mut self) -> Result<ftwire_core::FtSample, Self::Error> {
        Ok(ftwire_core::FtSample::default())
    }
    fn gripper_poses(&self) -> Result<ftwire_core::GripperPoses, Self::Error> {
        Ok(self.0)
    }
    fn command(&mut self, c: &ftwire_core::Command) -> Result<(), Self::Error> {
        self.0 = ftwire_core::GripperPoses {
            base: c.base,
            tip: c.tip,
        };
        Ok(())
    }
    fn time(&self) -> f64 {
        0.0
    }
}

/// The RMS position error [m] of the actual tip after `moves` commands over `runs` seeds:
/// each a zero increment from the pose the robot reports (`from_reported`, eq. 14's
/// `b_{i+1} = b_i δb_i` with `δb_i = I`), or the start pose itself.
fn rms_after(model: NoiseModel, moves: usize, runs: u64, from_reported: bool) -> f64 {
    let start = ftwire_core::GripperPoses {
        base: Pose::identity(),
        tip: Pose::translation(0.5, 0.0, 0.0),
    };
    let mut sum = 0.0;
    for seed in 0..runs {
        let mut rig =
            NoisyRig::new(Still(start), model, NoiseParams::default(), seed).expect("valid");
        for _ in 0..moves {
            let target = if from_reported {
                let Ok(poses) = ftwire_core::Rig::gripper_poses(&rig);
                poses.tip
            } else {
                start.tip
            };
            let Ok(()) = ftwire_core::Rig::move_tip(&mut rig, target);
        }
        let miss = rig.inner().0.tip.translation.vector - start.tip.translation.vector;
        sum += miss.norm_squared();
    }
    (sum / runs as f64).sqrt()
}

#[test]
fn the_noise_models_differ_as_documented() {
    // 3-D RMS of N(0, 10 mm) per axis is 17 mm; stepping from the reported pose under the
    // increment model, it grows as √moves.
    let one = rms_after(NoiseModel::Increment, 1, 400, true);
    let sixteen = rms_after(NoiseModel::Increment, 16, 400, true);
    assert!((one - 0.0173).abs() < 0.003, "{one}");
    assert!((sixteen / one - 4.0).abs() < 0.8, "{sixteen} / {one}");
    // The increment model's robot knows where it is: commanding a fixed pose again lands
    // one draw away from it, not a random walk.
    let back = rms_after(NoiseModel::Increment, 16, 400, false);
    assert!((back - 0.0173).abs() < 0.003, "{back}");
    let absolute = rms_after(NoiseModel::Absolute, 16, 400, false);
    assert!((absolute - 0.0173).abs() < 0.003, "{absolute}");
    // The robot does not know its absolute or offset error: stepping from what it reports is
    // stepping from where it commanded.
    let absolute = rms_after(NoiseModel::Absolute, 16, 400, true);
    assert!((absolute - 0.0173).abs() < 0.003, "{absolute}");
    let offset = rms_after(NoiseModel::Offset, 16, 400, true);
    // The rotation of the offset also moves the point, a little: still about one draw.
    assert!((offset - 0.0173).abs() < 0.004, "{offset}");
    // And it is there before the first command: the gripper held the wire off by it from the
    // start, so no move jumps by it.
    let held = rms_after(NoiseModel::Offset, 0, 400, true);
    assert!((held - offset).abs() < 0.001, "{held} against {offset}");
    assert_eq!(rms_after(NoiseModel::None, 5, 3, true), 0.0);
}

/// The RMS distance [m] of the actual tip from the plan's last pose after rolling out a plan of
/// `moves` moves that starts 5 cm from where the rig is, over `runs` seeds.
fn roll_out_rms(model: NoiseModel, moves: usize, runs: u64) -> f64 {
    let start = ftwire_core::GripperPoses {
        base: Pose::identity(),
        tip: Pose::translation(0.45, 0.0, 0.0),
    };
    let poses: Vec<Pose> = (0..=moves)
        .map(|k| Pose::translation(0.5, 0.01 * k as f64, 0.0))
        .collect();
    let last = poses[moves].translation.vector;
    let mut sum = 0.0;
    for seed in 0..runs {
        let mut rig =
            NoisyRig::new(Still(start), model, NoiseParams::default(), seed).expect("valid");
        let out = roll_out(
            &mut rig,
            &poses,
            None::<&ftwire_control::FtFeedback<ftwire_estimate::ft::Mounting>>,
            |_, _| {},
        )
        .expect("rolls");
        assert_eq!(out.moves, moves);
        sum += (rig.inner().0.tip.translation.vector - last).norm_squared();
    }
    (sum / runs as f64).sqrt()
}

#[test]
fn the_roll_out_goes_to_the_plan_and_the_increment_noise_accumulates_along_it() {
    // Without noise the rig ends on the plan, though it started 5 cm off its first pose.
    assert!(roll_out_rms(NoiseModel::None, 16, 1) < 1e-12);
    // The paper's noise lands every increment 17 mm (RMS) off, and the robot steps on from
    // where it reports it landed: after 16 moves about 4 draws; independent pose errors, which
    // the robot does not know, stay one draw.
    let increment = roll_out_rms(NoiseModel::Increment, 16, 300);
    assert!((increment / 0.0173 - 4.0).abs() < 0.8, "{increment}");
    let absolute = roll_out_rms(NoiseModel::Absolute, 16, 300);
    assert!((absolute - 0.0173).abs() < 0.003, "{absolute}");
}

#[test]
fn the_reported_pose_stays_a_rotation_over_many_noisy_moves() {
    // Each command is built on the reported pose and lands as the next one: without
    // renormalisation the quaternion's norm error compounded about 3× per move.
    let start = ftwire_core::GripperPoses {
        base: Pose::identity(),
        tip: Pose::translation(0.5, 0.0, 0.0),
    };
    let mut rig = NoisyRig::new(
        Still(start),
        NoiseModel::Increment,
        NoiseParams::default(),
        3,
    )
    .expect("valid");
    let step = ftwire_rod::se3::exp(&Vector6::new(0.02, -0.01, 0.03, 0.001, 0.002, -0.001));
    for _ in 0..400 {
        let Ok(now) = ftwire_core::Rig::gripper_poses(&rig);
        let Ok(()) = ftwire_core::Rig::move_tip(&mut rig, now.tip * step);
    }
    let norm = rig.inner().0.tip.rotation.quaternion().norm();
    assert!((norm - 1.0).abs() < 1e-12, "|q| = {norm}");
}
