//! The dual-arm robot: the shared torso joint, two arm chains, the gripper frames.

use std::path::Path;

use ftwire_core::Pose;
use nalgebra::{Translation3, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

use crate::RobotError;
use crate::arm::Arm;
use crate::chain::{ArmChain, ArmFrames, ArmJacobian, ArmJoints, ArmTorsoJacobian, RevoluteJoint};
use crate::urdf::{self, ChainNames, SDA10F_URDF};

/// Index used for the torso joint in [`RobotError::OutOfLimit`].
pub const TORSO_JOINT_INDEX: usize = 7;

/// Which frame of the arm's end a pose refers to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum EndFrame {
    /// The gripper's clamp frame (see [`GripperFrames`]): the wire's clamp frame at that end.
    #[default]
    Gripper,
    /// The URDF flange frame `arm_*_link_tool0`.
    Tool0,
}

/// Transforms from each arm's `tool0` to its gripper clamp frame.
///
/// **Direction of the flange.** In this URDF (as in ROS-Industrial's `motoman_sda10f_support`)
/// the `tool0` z axis points back *into* the arm: the outward normal of the flange, along which
/// the F/T sensor and the gripper stack up, is `−z` of `tool0`. (At the all-zero posture the left
/// arm stretches along +y and its `tool0` z axis is −y.) The stacks below therefore extend along
/// `−z` of `tool0`.
///
/// The clamp frame is where the wire is held, with its **x axis along the wire's tangent**
/// (ftwire's clamp convention). The wire leaves a gripper along the gripper's approach axis (the
/// flange's outward normal), so:
/// - left (base gripper, wire end `t = 0`): x = −z of `tool0`, out of the gripper into the wire;
/// - right (second gripper, `t = L`): x = +z of `tool0`, out of the wire into the gripper.
///
/// Both keep `tool0`'s y axis. Defaults (coarse figures, not measured on the real cell):
/// - left: F/T sensor stack `0.045` m plus chuck gripper `0.10` m: translation `(0, 0, −0.145)` m,
///   rotation `Ry(+π/2)`;
/// - right: chuck gripper `0.10` m: translation `(0, 0, −0.10)` m, rotation `Ry(−π/2)`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct GripperFrames {
    /// Left `tool0` from the left (base) gripper's clamp frame.
    pub left: Pose,
    /// Right `tool0` from the right (second) gripper's clamp frame.
    pub right: Pose,
}

/// Default length of the F/T sensor stack (sensor and adapter plates) on the left flange \[m\].
pub const DEFAULT_FT_STACK_LENGTH: f64 = 0.045;
/// Default length of the chuck gripper from its flange to the clamp point \[m\].
pub const DEFAULT_GRIPPER_LENGTH: f64 = 0.10;

impl GripperFrames {
    /// Gripper frames for given stack lengths \[m\] along the flange's outward normal (`−z` of
    /// `tool0`): the F/T sensor stack (left arm only) and the chuck gripper (both arms), with the
    /// clamp-axis convention above.
    ///
    /// # Errors
    /// [`RobotError::InvalidParameter`] if a length is negative or not finite.
    ///
    /// # Example
    /// ```
    /// use nalgebra::Vector3;
    /// let g = ftwire_robot::GripperFrames::from_lengths(0.045, 0.10)?;
    /// assert!((g.left.translation.vector - Vector3::new(0.0, 0.0, -0.145)).norm() < 1e-12);
    /// // The left clamp frame's x axis is tool0's −z axis: out of the gripper, into the wire.
    /// assert!((g.left.rotation * Vector3::x() + Vector3::z()).norm() < 1e-12);
    /// assert!((g.right.rotation * Vector3::x() - Vector3::z()).norm() < 1e-12);
    /// # Ok::<(), ftwire_robot::RobotError>(())
    /// ```
    pub fn from_lengths(ft_stack: f64, gripper: f64) -> Result<Self, RobotError> {
        for (name, value) in [("ft_stack", ft_stack), ("gripper", gripper)] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(RobotError::InvalidParameter {
                    name,
                    value,
                    allowed: "a finite length >= 0 m",
                });
            }
        }
        Ok(Self::build(ft_stack, gripper))
    }

    fn build(ft_stack: f64, gripper: f64) -> Self {
        let half_pi = std::f64::consts::FRAC_PI_2;
        Self {
            left: Pose::from_parts(
                Translation3::new(0.0, 0.0, -(ft_stack + gripper)),
                UnitQuaternion::from_axis_angle(&Vector3::y_axis(), half_pi),
            ),
            right: Pose::from_parts(
                Translation3::new(0.0, 0.0, -gripper),
                UnitQuaternion::from_axis_angle(&Vector3::y_axis(), -half_pi),
            ),
        }
    }

    /// The frame of one arm.
    pub fn get(&self, arm: Arm) -> &Pose {
        match arm {
            Arm::Left => &self.left,
            Arm::Right => &self.right,
        }
    }
}

impl Default for GripperFrames {
    fn default() -> Self {
        Self::build(DEFAULT_FT_STACK_LENGTH, DEFAULT_GRIPPER_LENGTH)
    }
}

/// The default preferred posture of the left arm \[rad\]: upper arm swung forward, elbow and
/// wrist bent, away from the singular stretched-out zero posture. The right arm's default is the
/// same vector (its joint axes are mirrored in the URDF, so the posture is the mirror image).
pub const DEFAULT_PREFERRED_POSTURE: [f64; 7] = [0.0, 0.6, 0.0, -1.2, 0.0, -0.6, 0.0];

/// The SDA10F dual-arm robot's kinematic model: torso joint, two 7-axis arms, gripper frames.
///
/// All poses are in the robot base frame (`torso_base_link`) unless stated otherwise.
#[derive(Debug, Clone, PartialEq)]
pub struct Robot {
    torso: RevoluteJoint,
    arms: [ArmChain; 2],
    grippers: GripperFrames,
    preferred: [ArmJoints; 2],
}

impl Robot {
    /// The SDA10F from the URDF compiled into this crate, with default gripper frames.
    ///
    /// # Errors
    /// Never in practice (the embedded URDF is tested); the `Result` is that of URDF parsing.
    ///
    /// # Example
    /// ```
    /// use ftwire_robot::{Arm, EndFrame, Robot};
    /// let robot = Robot::sda10f()?;
    /// let tool0 = robot.fk(Arm::Left, 0.0, &nalgebra::zero(), EndFrame::Tool0)?;
    /// assert!((tool0.translation.vector.y - 1.12).abs() < 0.01);
    /// # Ok::<(), ftwire_robot::RobotError>(())
    /// ```
    pub fn sda10f() -> Result<Self, RobotError> {
        Self::from_urdf_str(SDA10F_URDF, &ChainNames::default())
    }

    /// A robot from URDF text, with the arm chains bounded by `names` and default gripper frames.
    ///
    /// # Errors
    /// [`RobotError::Urdf`] if the text does not parse; [`RobotError::Model`] if the chains are
    /// not a shared revolute torso joint followed by seven revolute joints per arm.
    ///
    /// # Example
    /// ```
    /// use ftwire_robot::{ChainNames, Robot, SDA10F_URDF};
    /// let robot = Robot::from_urdf_str(SDA10F_URDF, &ChainNames::default())?;
    /// assert_eq!(robot.torso_joint().name, "torso_joint_b1");
    /// assert!(Robot::from_urdf_str("<robot name='x'/>", &ChainNames::default()).is_err());
    /// # Ok::<(), ftwire_robot::RobotError>(())
    /// ```
    pub fn from_urdf_str(text: &str, names: &ChainNames) -> Result<Self, RobotError> {
        let k = urdf::parse(text, names)?;
        let preferred = ArmJoints::from_column_slice(&DEFAULT_PREFERRED_POSTURE);
        let preferred = [k.left.clamp(&preferred), k.right.clamp(&preferred)];
        Ok(Self {
            torso: k.torso,
            arms: [k.left, k.right],
            grippers: GripperFrames::default(),
            preferred,
        })
    }

    /// A robot from a URDF file.
    ///
    /// # Errors
    /// [`RobotError::Io`] if the file cannot be read, then as [`Robot::from_urdf_str`].
    ///
    /// # Example
    /// ```
    /// use ftwire_robot::{ChainNames, Robot, RobotError};
    /// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/robots/sda10f.urdf");
    /// assert_eq!(Robot::from_urdf_file(path, &ChainNames::default())?, Robot::sda10f()?);
    /// let missing = Robot::from_urdf_file("/no/such.urdf", &ChainNames::default());
    /// assert!(matches!(missing, Err(RobotError::Io { .. })));
    /// # Ok::<(), RobotError>(())
    /// ```
    pub fn from_urdf_file(path: impl AsRef<Path>, names: &ChainNames) -> Result<Self, RobotError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(|e| RobotError::Io {
            path: path.display().to_string(),
            message: e.to_string(),
        })?;
        Self::from_urdf_str(&text, names)
    }

    /// Returns the robot with other gripper frames.
    ///
    /// # Errors
    /// [`RobotError::Core`] if a frame is not finite.
    ///
    /// # Example
    /// ```
    /// use ftwire_robot::{Arm, EndFrame, GripperFrames, Robot};
    /// // A bare flange on both arms: the gripper frame then sits at tool0.
    /// let robot = Robot::sda10f()?.with_grippers(GripperFrames::from_lengths(0.0, 0.0)?)?;
    /// let q = *robot.preferred_posture(Arm::Left);
    /// let g = robot.fk(Arm::Left, 0.0, &q, EndFrame::Gripper)?;
    /// let t = robot.fk(Arm::Left, 0.0, &q, EndFrame::Tool0)?;
    /// assert!((g.translation.vector - t.translation.vector).norm() < 1e-12);
    /// # Ok::<(), ftwire_robot::RobotError>(())
    /// ```
    #[must_use = "returns a new robot"]
    pub fn with_grippers(mut self, grippers: GripperFrames) -> Result<Self, RobotError> {
        for pose in [&grippers.left, &grippers.right] {
            ftwire_core::ensure_finite("gripper translation", pose.translation.vector.as_slice())?;
            ftwire_core::ensure_finite("gripper rotation", pose.rotation.coords.as_slice())?;
        }
        self.grippers = grippers;
        Ok(self)
    }

    /// Returns the robot with another preferred posture for one arm (the IK's default redundancy
    /// target and first seed).
    ///
    /// # Errors
    /// [`RobotError::Core`] if not finite, [`RobotError::OutOfLimit`] if the posture violates a
    /// limit.
    ///
    /// # Example
    /// ```
    /// use ftwire_robot::{Arm, Robot, arm_joints};
    /// let q = arm_joints(&[0.0, 0.8, 0.0, -1.0, 0.0, -0.8, 0.0])?;
    /// let robot = Robot::sda10f()?.with_preferred_posture(Arm::Right, q)?;
    /// assert_eq!(robot.preferred_posture(Arm::Right), &q);
    /// let beyond = arm_joints(&[0.0, 2.5, 0.0, 0.0, 0.0, 0.0, 0.0])?;
    /// assert!(Robot::sda10f()?.with_preferred_posture(Arm::Left, beyond).is_err());
    /// # Ok::<(), ftwire_robot::RobotError>(())
    /// ```
    #[must_use = "returns a new robot"]
    pub fn with_preferred_posture(mut self, arm: Arm, q: ArmJoints) -> Result<Self, RobotError> {
        ftwire_core::ensure_finite("preferred posture", q.as_slice())?;
        self.chain(arm).check_limits(&q)?;
        self.preferred[arm.index()] = q;
        Ok(self)
    }

    /// The torso joint shared by both arms.
    pub fn torso_joint(&self) -> &RevoluteJoint {
        &self.torso
    }

    /// One arm's chain (joints, limits, flange).
    pub fn chain(&self, arm: Arm) -> &ArmChain {
        &self.arms[arm.index()]
    }

    /// The gripper frames.
    pub fn grippers(&self) -> &GripperFrames {
        &self.grippers
    }

    /// One arm's preferred posture.
    pub fn preferred_posture(&self, arm: Arm) -> &ArmJoints {
        &self.preferred[arm.index()]
    }

    /// The transform from `tool0` to the requested end frame.
    pub fn end_transform(&self, arm: Arm, frame: EndFrame) -> Pose {
        match frame {
            EndFrame::Gripper => *self.grippers.get(arm),
            EndFrame::Tool0 => Pose::identity(),
        }
    }

    /// Checks a torso angle: finite and within limits.
    ///
    /// # Errors
    /// [`RobotError::Core`] if not finite, [`RobotError::OutOfLimit`] if outside the limits.
    pub fn check_torso(&self, torso: f64) -> Result<(), RobotError> {
        ftwire_core::ensure_finite("torso", &[torso])?;
        let limit = self.torso.limit;
        if limit.contains(torso) {
            Ok(())
        } else {
            Err(RobotError::OutOfLimit {
                joint: TORSO_JOINT_INDEX,
                name: self.torso.name.clone(),
                position: torso,
                min: limit.min,
                max: limit.max,
            })
        }
    }

    /// Checks an arm posture: finite and within limits.
    ///
    /// # Errors
    /// [`RobotError::Core`] or [`RobotError::OutOfLimit`].
    pub fn check_joints(&self, arm: Arm, q: &ArmJoints) -> Result<(), RobotError> {
        ftwire_core::ensure_finite("joints", q.as_slice())?;
        self.chain(arm).check_limits(q)
    }

    /// Forward kinematics: the pose of `frame` of `arm` in the robot base frame.
    ///
    /// # Errors
    /// [`RobotError::Core`] for non-finite input, [`RobotError::OutOfLimit`] for a joint or the
    /// torso outside its limits.
    ///
    /// # Example
    /// ```
    /// use ftwire_robot::{Arm, EndFrame, Robot};
    /// let robot = Robot::sda10f()?;
    /// let q = *robot.preferred_posture(Arm::Right);
    /// let tool0 = robot.fk(Arm::Right, 0.0, &q, EndFrame::Tool0)?;
    /// let grip = robot.fk(Arm::Right, 0.0, &q, EndFrame::Gripper)?;
    /// // The right gripper's clamp point is 0.10 m beyond tool0.
    /// assert!(((grip.translation.vector - tool0.translation.vector).norm() - 0.10).abs() < 1e-12);
    /// # Ok::<(), ftwire_robot::RobotError>(())
    /// ```
    pub fn fk(
        &self,
        arm: Arm,
        torso: f64,
        q: &ArmJoints,
        frame: EndFrame,
    ) -> Result<Pose, RobotError> {
        self.check_torso(torso)?;
        self.check_joints(arm, q)?;
        Ok(self
            .frames(arm, torso, q, &self.end_transform(arm, frame))
            .end)
    }

    /// The geometric Jacobian of `frame` of `arm` in the robot base frame, **angular rows
    /// first**: `(ω, v) = J q̇`, with `v` the velocity of the frame's origin.
    ///
    /// # Errors
    /// As [`Robot::fk`].
    pub fn jacobian(
        &self,
        arm: Arm,
        torso: f64,
        q: &ArmJoints,
        frame: EndFrame,
    ) -> Result<ArmJacobian, RobotError> {
        self.check_torso(torso)?;
        self.check_joints(arm, q)?;
        Ok(self
            .frames(arm, torso, q, &self.end_transform(arm, frame))
            .jacobian())
    }

    /// The 6 × 8 geometric Jacobian including the torso joint (column 0), then the arm's seven.
    ///
    /// # Errors
    /// As [`Robot::fk`].
    pub fn jacobian_with_torso(
        &self,
        arm: Arm,
        torso: f64,
        q: &ArmJoints,
        frame: EndFrame,
    ) -> Result<ArmTorsoJacobian, RobotError> {
        self.check_torso(torso)?;
        self.check_joints(arm, q)?;
        let frames = self.frames(arm, torso, q, &self.end_transform(arm, frame));
        let base_from_joint = self.torso.origin;
        let axis = base_from_joint.rotation * self.torso.axis.into_inner();
        let p = frames.end.translation.vector - base_from_joint.translation.vector;
        let mut j = ArmTorsoJacobian::zeros();
        j.fixed_view_mut::<3, 1>(0, 0).copy_from(&axis);
        j.fixed_view_mut::<3, 1>(3, 0).copy_from(&axis.cross(&p));
        j.fixed_view_mut::<6, 7>(0, 1).copy_from(&frames.jacobian());
        Ok(j)
    }

    /// The torso link's pose in the base frame at torso angle `torso`.
    pub fn base_from_torso(&self, torso: f64) -> Pose {
        self.torso.transform(torso)
    }

    /// Unchecked FK of all joint frames.
    pub(crate) fn frames(&self, arm: Arm, torso: f64, q: &ArmJoints, end: &Pose) -> ArmFrames {
        self.chain(arm).frames(&self.base_from_torso(torso), q, end)
    }
}
