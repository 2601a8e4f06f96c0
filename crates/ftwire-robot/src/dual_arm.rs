//! Dual-arm IK for the wire task: both grippers placed from the base gripper's world pose and
//! the wire's relative pose `b` (the second clamp frame in the base clamp frame, DESIGN.md).

use ftwire_core::Pose;
use serde::{Deserialize, Serialize};

use crate::chain::ArmJoints;
use crate::collision::{LinkRadii, capsule_sets_contact};
use crate::{Arm, EndFrame, IkParams, IkTarget, Robot, RobotError};

/// Where the wire's two clamp frames must be.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DualArmTarget {
    /// World from robot base (`torso_base_link`); identity if the world is the robot base.
    pub world_from_base: Pose,
    /// World from the base gripper's clamp frame (left arm, wire end `t = 0`).
    pub base_gripper: Pose,
    /// The relative pose `b` of the second clamp frame (right arm, `t = L`) in the base clamp
    /// frame: world from second clamp = `base_gripper · relative`.
    pub relative: Pose,
}

/// Smallest torso search step \[rad\] (bounds the number of angles tried).
pub const MIN_TORSO_STEP: f64 = 1e-3;

/// How the shared torso angle is chosen.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum TorsoChoice {
    /// Held at this angle \[rad\].
    Fixed(f64),
    /// Searched outward from `start` (or from the seed's torso angle when a seed is given) in
    /// steps of `step` \[rad\], both directions alternately, until both arms have a solution or
    /// the limits are reached.
    Search {
        /// First angle tried \[rad\].
        start: f64,
        /// Spacing of the angles tried \[rad\], at least [`MIN_TORSO_STEP`].
        step: f64,
    },
}

/// Settings of the dual-arm IK (public fields + `Default`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DualArmParams {
    /// Settings of each arm's IK (default [`IkParams::default`]).
    pub ik: IkParams,
    /// Torso angle (default: search from `0` in steps of `0.1` rad).
    pub torso: TorsoChoice,
    /// Reject solutions whose arms collide (coarse capsules; default `true`).
    pub check_collision: bool,
    /// Capsule radii for that check (default [`LinkRadii::default`]).
    pub radii: LinkRadii,
    /// When a [`TorsoChoice::Search`] finds no angle, search again between each pair of
    /// neighbouring angles where the failing arm changes (the left arm failing at one, the
    /// right at the other), in steps of [`REFINE_DIVISIONS`]ths of the search step (at least
    /// [`MIN_TORSO_STEP`]). A pose near the edge of the robot's reach can be held only in a
    /// torso window narrower than the search step: the window lies between the angles where
    /// each arm alone stops reaching. Default `false` (a planner's conservative reach);
    /// execution turns it on.
    pub refine_torso: bool,
}

/// Into how many parts [`DualArmParams::refine_torso`] divides a search step.
pub const REFINE_DIVISIONS: u32 = 20;

impl Default for DualArmParams {
    fn default() -> Self {
        Self {
            ik: IkParams::default(),
            torso: TorsoChoice::Search {
                start: 0.0,
                step: 0.1,
            },
            check_collision: true,
            radii: LinkRadii::default(),
            refine_torso: false,
        }
    }
}

/// Joint angles of the whole robot.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DualArmJoints {
    /// Torso angle \[rad\].
    pub torso: f64,
    /// Left arm \[rad\].
    pub left: ArmJoints,
    /// Right arm \[rad\].
    pub right: ArmJoints,
}

impl Robot {
    /// Both arms' joints (and the torso angle) that put the base gripper at
    /// `target.base_gripper` and the second gripper at `target.base_gripper · target.relative`.
    ///
    /// With a `seed` (the previous solution), each arm starts from and is pulled toward its seed
    /// (as [`IkParams::posture`] says), so successive solutions along a motion stay close.
    ///
    /// # Errors
    /// Bad input as [`Robot::ik`]; [`RobotError::InvalidParameter`] for a bad torso search;
    /// [`RobotError::DualArmUnreachable`] with how often each arm failed and how often the arms
    /// collided when no torso angle works.
    ///
    /// # Example
    /// ```
    /// use ftwire_robot::{Arm, DualArmParams, DualArmTarget, EndFrame, Robot};
    /// let robot = Robot::sda10f()?;
    /// let (l, r) = (*robot.preferred_posture(Arm::Left), *robot.preferred_posture(Arm::Right));
    /// let base = robot.fk(Arm::Left, 0.0, &l, EndFrame::Gripper)?;
    /// let tip = robot.fk(Arm::Right, 0.0, &r, EndFrame::Gripper)?;
    /// let target = DualArmTarget {
    ///     world_from_base: ftwire_core::Pose::identity(),
    ///     base_gripper: base,
    ///     relative: base.inverse() * tip,
    /// };
    /// let s = robot.dual_arm_ik(&target, None, &DualArmParams::default())?;
    /// let reached = robot.fk(Arm::Right, s.torso, &s.right, EndFrame::Gripper)?;
    /// assert!((reached.translation.vector - tip.translation.vector).norm() <= 1e-6);
    /// # Ok::<(), ftwire_robot::RobotError>(())
    /// ```
    pub fn dual_arm_ik(
        &self,
        target: &DualArmTarget,
        seed: Option<&DualArmJoints>,
        params: &DualArmParams,
    ) -> Result<DualArmJoints, RobotError> {
        for (name, pose) in [
            ("world_from_base", &target.world_from_base),
            ("base_gripper", &target.base_gripper),
            ("relative", &target.relative),
        ] {
            ftwire_core::ensure_finite(name, pose.translation.vector.as_slice())?;
            ftwire_core::ensure_finite(name, pose.rotation.coords.as_slice())?;
        }
        if let Some(s) = seed {
            self.check_torso(s.torso)?;
            self.check_joints(Arm::Left, &s.left)?;
            self.check_joints(Arm::Right, &s.right)?;
        }
        let base_from_world = target.world_from_base.inverse();
        let left_pose = base_from_world * target.base_gripper;
        let right_pose = left_pose * target.relative;
        let torsos = self.torso_candidates(params.torso, seed.map(|s| s.torso))?;

        let try_at = |torso: f64| -> Result<Result<DualArmJoints, Failure>, RobotError> {
            let solve = |arm: Arm, pose: Pose, seed: Option<&ArmJoints>| {
                let t = IkTarget {
                    arm,
                    pose,
                    torso,
                    frame: EndFrame::Gripper,
                };
                match self.ik(&t, seed, &params.ik) {
                    Ok(s) => Ok(Some(s.joints)),
                    Err(RobotError::Unreachable { .. } | RobotError::OutOfReach { .. }) => Ok(None),
                    Err(e) => Err(e),
                }
            };
            let Some(left) = solve(Arm::Left, left_pose, seed.map(|s| &s.left))? else {
                return Ok(Err(Failure::Left));
            };
            let Some(right) = solve(Arm::Right, right_pose, seed.map(|s| &s.right))? else {
                return Ok(Err(Failure::Right));
            };
            if params.check_collision {
                let l = self.capsules_unchecked(Arm::Left, torso, &left, &params.radii);
                let r = self.capsules_unchecked(Arm::Right, torso, &right, &params.radii);
                if capsule_sets_contact(&l, &r).is_some() {
                    return Ok(Err(Failure::Collided));
                }
            }
            Ok(Ok(DualArmJoints { torso, left, right }))
        };

        let (mut left_failures, mut right_failures, mut collisions) = (0, 0, 0);
        let mut count = |failure: Failure| match failure {
            Failure::Left => left_failures += 1,
            Failure::Right => right_failures += 1,
            Failure::Collided => collisions += 1,
        };
        let mut tried = Vec::with_capacity(torsos.len());
        for &torso in &torsos {
            let failure = match try_at(torso)? {
                Ok(joints) => return Ok(joints),
                Err(failure) => failure,
            };
            count(failure);
            tried.push((torso, failure));
        }
        let mut torsos_tried = torsos.len();
        if let (true, TorsoChoice::Search { step, .. }) = (params.refine_torso, params.torso) {
            tried.sort_by(|x, y| x.0.total_cmp(&y.0));
            let fine = (step / f64::from(REFINE_DIVISIONS)).max(MIN_TORSO_STEP);
            for pair in tried.windows(2) {
                let ((lo, lo_kind), (hi, hi_kind)) = (pair[0], pair[1]);
                // Only where one arm stops reaching and the other starts can a window hide.
                let crossing = matches!(
                    (lo_kind, hi_kind),
                    (Failure::Left, Failure::Right) | (Failure::Right, Failure::Left)
                );
                if !crossing {
                    continue;
                }
                let mut torso = lo + fine;
                while torso < hi - 0.5 * fine {
                    torsos_tried += 1;
                    match try_at(torso)? {
                        Ok(joints) => return Ok(joints),
                        Err(failure) => count(failure),
                    }
                    torso += fine;
                }
            }
        }
        Err(RobotError::DualArmUnreachable {
            torsos_tried,
            left_failures,
            right_failures,
            collisions,
        })
    }

    fn torso_candidates(
        &self,
        choice: TorsoChoice,
        seed: Option<f64>,
    ) -> Result<Vec<f64>, RobotError> {
        match choice {
            TorsoChoice::Fixed(t) => {
                self.check_torso(t)?;
                Ok(vec![t])
            }
            TorsoChoice::Search { start, step } => {
                if !(step.is_finite() && step >= MIN_TORSO_STEP) {
                    return Err(RobotError::InvalidParameter {
                        name: "torso step",
                        value: step,
                        allowed: "a finite step >= 0.001 rad",
                    });
                }
                let start = seed.unwrap_or(start);
                self.check_torso(start)?;
                let limit = self.torso_joint().limit;
                let mut out = vec![start];
                for k in 1.. {
                    let up = start + step * f64::from(k);
                    let down = start - step * f64::from(k);
                    let (u, d) = (limit.contains(up), limit.contains(down));
                    if !u && !d {
                        break;
                    }
                    out.extend(u.then_some(up));
                    out.extend(d.then_some(down));
                }
                Ok(out)
            }
        }
    }
}

/// Why one torso angle gave no solution.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Failure {
    /// The left (base) arm cannot reach its pose.
    Left,
    /// The right arm cannot.
    Right,
    /// Both can, but the arms collide.
    Collided,
}
