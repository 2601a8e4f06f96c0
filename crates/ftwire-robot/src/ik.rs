//! Inverse kinematics of one 7-axis arm: damped least squares (Levenberg–Marquardt with
//! error-dependent damping, after Sugihara 2011), joint limits by projection, redundancy resolved
//! by a nullspace pull toward a reference posture, and seeded random restarts.
//!
//! A returned solution is always verified: within the position and rotation tolerances and
//! within every joint limit. Otherwise the solver returns an error that says why.

use ftwire_core::Pose;
use nalgebra::{Matrix6, SMatrix};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};

use crate::chain::{ARM_DOF, ArmJoints, pose_error};
use crate::{Arm, EndFrame, Robot, RobotError};

type Matrix7 = SMatrix<f64, ARM_DOF, ARM_DOF>;

/// What the IK's nullspace term pulls the arm toward (redundancy resolution).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub enum Posture {
    /// The seed posture if one is given (the previous solution: smooth motions), else the
    /// robot's preferred posture.
    #[default]
    Seed,
    /// Always the robot's preferred posture ([`Robot::preferred_posture`]).
    Preferred,
    /// These joint angles \[rad\].
    Joints(ArmJoints),
    /// No nullspace term.
    Free,
}

/// Settings of the IK solver (public fields + `Default`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct IkParams {
    /// Largest accepted position residual \[m\] (default `1e-6`).
    pub position_tolerance: f64,
    /// Largest accepted rotation residual, as an angle \[rad\] (default `1e-6`).
    pub rotation_tolerance: f64,
    /// Iterations per attempt (default `100`).
    pub max_iterations: usize,
    /// Random restarts after the seed and the preferred posture fail (default `30`).
    pub random_restarts: usize,
    /// Seed of the restarts' random generator (ChaCha8; default `0`). Same seed, same answer.
    pub rng_seed: u64,
    /// Redundancy target (default [`Posture::Seed`]).
    pub posture: Posture,
    /// Gain of the nullspace pull per iteration, in (0, 1] (default `0.2`).
    pub nullspace_gain: f64,
}

impl Default for IkParams {
    fn default() -> Self {
        Self {
            position_tolerance: 1e-6,
            rotation_tolerance: 1e-6,
            max_iterations: 100,
            random_restarts: 30,
            rng_seed: 0,
            posture: Posture::Seed,
            nullspace_gain: 0.2,
        }
    }
}

impl IkParams {
    fn validate(&self) -> Result<(), RobotError> {
        for (name, value) in [
            ("position_tolerance", self.position_tolerance),
            ("rotation_tolerance", self.rotation_tolerance),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(RobotError::InvalidParameter {
                    name,
                    value,
                    allowed: "a finite tolerance > 0",
                });
            }
        }
        if !(self.nullspace_gain.is_finite() && (0.0..=1.0).contains(&self.nullspace_gain)) {
            return Err(RobotError::InvalidParameter {
                name: "nullspace_gain",
                value: self.nullspace_gain,
                allowed: "a gain in [0, 1]",
            });
        }
        if let Posture::Joints(q) = &self.posture {
            ftwire_core::ensure_finite("posture", q.as_slice())?;
        }
        Ok(())
    }
}

/// A pose to reach with one arm.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct IkTarget {
    /// Which arm.
    pub arm: Arm,
    /// Target pose of `frame` in the robot base frame.
    pub pose: Pose,
    /// Torso angle \[rad\], held fixed.
    pub torso: f64,
    /// Which end frame `pose` is for.
    pub frame: EndFrame,
}

/// A verified IK solution.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct IkSolution {
    /// Joint angles \[rad\], within limits.
    pub joints: ArmJoints,
    /// Position residual \[m\], at most the tolerance.
    pub position_error: f64,
    /// Rotation residual \[rad\], at most the tolerance.
    pub rotation_error: f64,
    /// Seeds tried, this one included.
    pub attempts: usize,
    /// Iterations over all attempts.
    pub iterations: usize,
}

/// The outcome of one descent from one seed.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Descent {
    pub joints: ArmJoints,
    pub position_error: f64,
    pub rotation_error: f64,
    pub iterations: usize,
    pub converged: bool,
}

/// Smallest damping added to the normal equations (keeps them positive definite).
const DAMPING_FLOOR: f64 = 1e-9;
/// Largest joint step per iteration \[rad\].
const MAX_STEP: f64 = 0.5;

/// A validated single-arm problem: everything the descent needs, precomputed.
pub(crate) struct ArmProblem<'a> {
    robot: &'a Robot,
    arm: Arm,
    mount: Pose,
    end: Pose,
    target: Pose,
    tol_p: f64,
    tol_r: f64,
}

impl<'a> ArmProblem<'a> {
    /// Validates the target and applies the definite reach pre-check.
    pub(crate) fn new(
        robot: &'a Robot,
        target: &IkTarget,
        tol_p: f64,
        tol_r: f64,
    ) -> Result<Self, RobotError> {
        ftwire_core::ensure_finite("target position", target.pose.translation.vector.as_slice())?;
        ftwire_core::ensure_finite("target rotation", target.pose.rotation.coords.as_slice())?;
        robot.check_torso(target.torso)?;
        let mount = robot.base_from_torso(target.torso);
        let end = robot.end_transform(target.arm, target.frame);
        let chain = robot.chain(target.arm);
        let shoulder = (mount * chain.joints[0].origin).translation.vector;
        let distance = (target.pose.translation.vector - shoulder).norm();
        let reach = chain.reach_bound(&end);
        if distance > reach + tol_p {
            return Err(RobotError::OutOfReach {
                arm: target.arm,
                distance,
                reach,
            });
        }
        Ok(Self {
            robot,
            arm: target.arm,
            mount,
            end,
            target: target.pose,
            tol_p,
            tol_r,
        })
    }

    fn evaluate(&self, q: &ArmJoints) -> (crate::chain::ArmFrames, nalgebra::Vector6<f64>) {
        let frames = self.robot.chain(self.arm).frames(&self.mount, q, &self.end);
        let e = pose_error(&self.target, &frames.end);
        (frames, e)
    }

    fn converged(&self, e: &nalgebra::Vector6<f64>) -> bool {
        e.fixed_rows::<3>(3).norm() <= self.tol_p && e.fixed_rows::<3>(0).norm() <= self.tol_r
    }

    /// Levenberg–Marquardt descent from `seed`, projected onto the joint limits, with an
    /// optional nullspace pull toward `posture`.
    pub(crate) fn descend(
        &self,
        seed: &ArmJoints,
        posture: Option<&ArmJoints>,
        gain: f64,
        max_iterations: usize,
    ) -> Descent {
        let chain = self.robot.chain(self.arm);
        let mut q = chain.clamp(seed);
        let (mut frames, mut e) = self.evaluate(&q);
        let mut cost = 0.5 * e.norm_squared();
        let mut mu = 1.0;
        let mut iterations = 0;
        while iterations < max_iterations && !self.converged(&e) {
            iterations += 1;
            let j = frames.jacobian();
            let jt = j.transpose();
            let h = jt * j + Matrix7::identity() * (mu * cost + DAMPING_FLOOR);
            let Some(chol) = h.cholesky() else { break };
            let mut dq = chol.solve(&(jt * e));
            let largest = dq.amax();
            if largest > MAX_STEP {
                dq *= MAX_STEP / largest;
            }
            let null_step = posture.filter(|_| gain > 0.0).and_then(|p| {
                let jjt = j * jt + Matrix6::identity() * DAMPING_FLOOR;
                let inv = jjt.cholesky()?.inverse();
                let projector = Matrix7::identity() - jt * inv * j;
                Some(projector * ((p - q) * gain))
            });
            let mut accepted = false;
            for step in [null_step.map(|n| dq + n), Some(dq)].into_iter().flatten() {
                let candidate = chain.clamp(&(q + step));
                let (f, ec) = self.evaluate(&candidate);
                let c = 0.5 * ec.norm_squared();
                if c < cost {
                    q = candidate;
                    frames = f;
                    e = ec;
                    cost = c;
                    accepted = true;
                    break;
                }
            }
            if accepted {
                mu = (mu * 0.5).max(1e-3);
            } else {
                mu *= 10.0;
                if mu > 1e10 {
                    break;
                }
            }
        }
        Descent {
            joints: q,
            position_error: e.fixed_rows::<3>(3).norm(),
            rotation_error: e.fixed_rows::<3>(0).norm(),
            iterations,
            converged: self.converged(&e),
        }
    }
}

impl Robot {
    /// Inverse kinematics of one arm: joint angles that put `target.frame` at `target.pose`
    /// (robot base frame) with the torso held at `target.torso`.
    ///
    /// Tries `seed` (if given), then the preferred posture, then `params.random_restarts`
    /// postures drawn uniformly within the limits from a ChaCha8 generator seeded with
    /// `params.rng_seed`. The first attempt that converges is returned.
    ///
    /// # Errors
    /// - [`RobotError::Core`]: a non-finite target, torso or seed;
    /// - [`RobotError::OutOfLimit`]: the torso or the seed outside its limits;
    /// - [`RobotError::InvalidParameter`]: bad `params`;
    /// - [`RobotError::OutOfReach`]: the target is beyond a guaranteed bound of the arm's reach;
    /// - [`RobotError::Unreachable`]: no attempt converged; the best residual is reported.
    ///
    /// # Example
    /// ```
    /// use ftwire_robot::{Arm, EndFrame, IkParams, IkTarget, Robot};
    /// let robot = Robot::sda10f()?;
    /// let q = ftwire_robot::arm_joints(&[0.3, 0.8, -0.2, -1.0, 0.4, -0.7, 0.2])?;
    /// let pose = robot.fk(Arm::Left, 0.0, &q, EndFrame::Gripper)?;
    /// let target = IkTarget { arm: Arm::Left, pose, torso: 0.0, frame: EndFrame::Gripper };
    /// let solution = robot.ik(&target, None, &IkParams::default())?;
    /// let reached = robot.fk(Arm::Left, 0.0, &solution.joints, EndFrame::Gripper)?;
    /// assert!((reached.translation.vector - pose.translation.vector).norm() <= 1e-6);
    /// # Ok::<(), ftwire_robot::RobotError>(())
    /// ```
    pub fn ik(
        &self,
        target: &IkTarget,
        seed: Option<&ArmJoints>,
        params: &IkParams,
    ) -> Result<IkSolution, RobotError> {
        params.validate()?;
        if let Some(s) = seed {
            self.check_joints(target.arm, s)?;
        }
        let problem = ArmProblem::new(
            self,
            target,
            params.position_tolerance,
            params.rotation_tolerance,
        )?;
        let preferred = *self.preferred_posture(target.arm);
        let posture = match params.posture {
            Posture::Seed => Some(seed.copied().unwrap_or(preferred)),
            Posture::Preferred => Some(preferred),
            Posture::Joints(q) => Some(q),
            Posture::Free => None,
        };
        let chain = self.chain(target.arm);
        let mut rng = ChaCha8Rng::seed_from_u64(params.rng_seed);
        // The preferred posture is tried second unless it is the seed itself.
        let preferred_too = seed.is_none_or(|s| *s != preferred);
        let mut seeds = seed
            .copied()
            .into_iter()
            .chain(preferred_too.then_some(preferred));
        let mut best: Option<Descent> = None;
        let mut iterations = 0;
        let total =
            usize::from(seed.is_some()) + usize::from(preferred_too) + params.random_restarts;
        for attempt in 1..=total {
            let start = seeds.next().unwrap_or_else(|| {
                ArmJoints::from_fn(|i, _| {
                    let l = chain.joints[i].limit;
                    rng.random_range(l.min..=l.max)
                })
            });
            // Restarts drop the nullspace pull: the posture target may be what traps the
            // first attempts (e.g. against a limit), and any verified solution beats none.
            let pull = if attempt <= total - params.random_restarts {
                posture.as_ref()
            } else {
                None
            };
            let d = problem.descend(&start, pull, params.nullspace_gain, params.max_iterations);
            iterations += d.iterations;
            if d.converged && chain.check_limits(&d.joints).is_ok() {
                return Ok(IkSolution {
                    joints: d.joints,
                    position_error: d.position_error,
                    rotation_error: d.rotation_error,
                    attempts: attempt,
                    iterations,
                });
            }
            let score = |d: &Descent| d.position_error.powi(2) + d.rotation_error.powi(2);
            if best.as_ref().is_none_or(|b| score(&d) < score(b)) {
                best = Some(d);
            }
        }
        let (position_error, rotation_error, limited_joint) = match best {
            Some(b) => (
                b.position_error,
                b.rotation_error,
                (0..ARM_DOF).find(|&i| {
                    let l = chain.joints[i].limit;
                    b.joints[i] <= l.min + 1e-9 || b.joints[i] >= l.max - 1e-9
                }),
            ),
            None => (f64::INFINITY, f64::INFINITY, None),
        };
        Err(RobotError::Unreachable {
            arm: target.arm,
            position_error,
            rotation_error,
            attempts: total,
            limited_joint,
        })
    }
}
