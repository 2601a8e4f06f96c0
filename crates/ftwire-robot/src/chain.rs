//! One serial chain: revolute joints with fixed origins, axes and limits.

use ftwire_core::Pose;
use nalgebra::{Point3, SMatrix, SVector, Translation3, Unit, UnitQuaternion, Vector3};
use serde::{Deserialize, Serialize};

use crate::RobotError;

/// Number of joints of one arm.
pub const ARM_DOF: usize = 7;

/// Joint angles of one arm \[rad\], joint 1 (shoulder, `_1_s`) first.
pub type ArmJoints = SVector<f64, ARM_DOF>;

/// Geometric Jacobian of one arm, 6 × 7, **angular rows first** (as ftwire's twists are).
pub type ArmJacobian = SMatrix<f64, 6, ARM_DOF>;

/// Geometric Jacobian of one arm including the torso joint, 6 × 8: column 0 is the torso.
pub type ArmTorsoJacobian = SMatrix<f64, 6, 8>;

/// Builds an [`ArmJoints`] from a slice, checking the count and that every value is finite.
///
/// # Errors
/// [`RobotError::JointCount`] unless there are exactly seven values;
/// [`RobotError::Core`] naming a value that is NaN or infinite.
///
/// # Example
/// ```
/// let q = ftwire_robot::arm_joints(&[0.0, 0.1, 0.0, -0.5, 0.0, 0.3, 0.0])?;
/// assert_eq!(q[3], -0.5);
/// assert!(ftwire_robot::arm_joints(&[0.0; 6]).is_err());
/// # Ok::<(), ftwire_robot::RobotError>(())
/// ```
pub fn arm_joints(values: &[f64]) -> Result<ArmJoints, RobotError> {
    if values.len() != ARM_DOF {
        return Err(RobotError::JointCount {
            expected: ARM_DOF,
            got: values.len(),
        });
    }
    ftwire_core::ensure_finite("joints", values)?;
    Ok(ArmJoints::from_column_slice(values))
}

/// Position limits of a revolute joint \[rad\].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct JointLimit {
    /// Lower limit \[rad\].
    pub min: f64,
    /// Upper limit \[rad\].
    pub max: f64,
}

impl JointLimit {
    /// Whether `position` lies within the limits (inclusive).
    pub fn contains(&self, position: f64) -> bool {
        position >= self.min && position <= self.max
    }

    /// `position` clamped into the limits.
    pub fn clamp(&self, position: f64) -> f64 {
        position.clamp(self.min, self.max)
    }
}

/// A revolute joint: its frame at zero angle relative to the parent joint's (rotated) frame,
/// its axis in its own frame, and its limits.
#[derive(Debug, Clone, PartialEq)]
pub struct RevoluteJoint {
    /// The URDF joint name.
    pub name: String,
    /// Parent frame from this joint's frame at zero angle (URDF `origin`, with any fixed joints
    /// in between folded in).
    pub origin: Pose,
    /// Rotation axis in this joint's frame (URDF `axis`), unit length.
    pub axis: Unit<Vector3<f64>>,
    /// Position limits \[rad\].
    pub limit: JointLimit,
}

impl RevoluteJoint {
    /// Parent from child at joint angle `q` \[rad\].
    pub fn transform(&self, q: f64) -> Pose {
        self.origin * UnitQuaternion::from_axis_angle(&self.axis, q)
    }
}

/// One 7-axis arm: seven revolute joints from the torso link to link 7, then the fixed flange
/// transform to `tool0`.
#[derive(Debug, Clone, PartialEq)]
pub struct ArmChain {
    /// The seven joints, shoulder first.
    pub joints: [RevoluteJoint; ARM_DOF],
    /// Link 7 from `tool0` (the URDF's fixed flange joint).
    pub flange: Pose,
}

/// Points and axes of one arm at one posture, all in the robot base frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ArmFrames {
    /// Origin of each joint.
    pub origins: [Point3<f64>; ARM_DOF],
    /// Axis of each joint, unit length.
    pub axes: [Vector3<f64>; ARM_DOF],
    /// Pose of the end frame (tool0 composed with the requested end transform).
    pub end: Pose,
}

impl ArmChain {
    /// Joint limits, shoulder first.
    pub fn limits(&self) -> [JointLimit; ARM_DOF] {
        std::array::from_fn(|i| self.joints[i].limit)
    }

    /// Checks every angle against its limit.
    ///
    /// # Errors
    /// [`RobotError::OutOfLimit`] for the first joint outside its limits.
    pub fn check_limits(&self, q: &ArmJoints) -> Result<(), RobotError> {
        for (i, joint) in self.joints.iter().enumerate() {
            if !joint.limit.contains(q[i]) {
                return Err(RobotError::OutOfLimit {
                    joint: i,
                    name: joint.name.clone(),
                    position: q[i],
                    min: joint.limit.min,
                    max: joint.limit.max,
                });
            }
        }
        Ok(())
    }

    /// `q` clamped into the limits.
    pub fn clamp(&self, q: &ArmJoints) -> ArmJoints {
        ArmJoints::from_fn(|i, _| self.joints[i].limit.clamp(q[i]))
    }

    /// A guaranteed upper bound \[m\] of the distance from joint 1's origin to the origin of
    /// `tool0 · end`: the sum of the lengths of every offset along the chain.
    pub fn reach_bound(&self, end: &Pose) -> f64 {
        self.joints[1..]
            .iter()
            .map(|j| j.origin.translation.vector.norm())
            .sum::<f64>()
            + self.flange.translation.vector.norm()
            + end.translation.vector.norm()
    }

    /// Forward kinematics of all joint frames; `base_from_mount` is the pose of the arm's mount
    /// (the torso link) and `end` the transform from `tool0` to the end frame. No checks.
    pub(crate) fn frames(&self, base_from_mount: &Pose, q: &ArmJoints, end: &Pose) -> ArmFrames {
        let mut t = *base_from_mount;
        let mut origins = [Point3::origin(); ARM_DOF];
        let mut axes = [Vector3::zeros(); ARM_DOF];
        for (i, joint) in self.joints.iter().enumerate() {
            t *= joint.origin;
            origins[i] = Point3::from(t.translation.vector);
            axes[i] = t.rotation * joint.axis.into_inner();
            t.rotation *= UnitQuaternion::from_axis_angle(&joint.axis, q[i]);
        }
        ArmFrames {
            origins,
            axes,
            end: t * self.flange * end,
        }
    }
}

impl ArmFrames {
    /// The geometric Jacobian at the end frame's origin, angular rows first.
    pub(crate) fn jacobian(&self) -> ArmJacobian {
        let p = self.end.translation.vector;
        let mut j = ArmJacobian::zeros();
        for i in 0..ARM_DOF {
            let a = self.axes[i];
            let v = a.cross(&(p - self.origins[i].coords));
            j.fixed_view_mut::<3, 1>(0, i).copy_from(&a);
            j.fixed_view_mut::<3, 1>(3, i).copy_from(&v);
        }
        j
    }
}

/// The pose error `(ω, v)` that takes `current` to `target`, angular first, in the base frame:
/// `ω = log(R_target R_currentᵀ)` and `v = p_target − p_current`.
pub(crate) fn pose_error(target: &Pose, current: &Pose) -> nalgebra::Vector6<f64> {
    let w = (target.rotation * current.rotation.inverse()).scaled_axis();
    let v = target.translation.vector - current.translation.vector;
    nalgebra::Vector6::new(w.x, w.y, w.z, v.x, v.y, v.z)
}

/// Builds a pose from a translation \[m\] and a rotation vector \[rad\].
///
/// # Example
/// ```
/// use nalgebra::Vector3;
/// let p = ftwire_robot::pose_from_vectors(Vector3::new(1.0, 0.0, 0.0), Vector3::new(0.0, 0.0, 0.5));
/// assert!((p.rotation.angle() - 0.5).abs() < 1e-15);
/// ```
pub fn pose_from_vectors(translation: Vector3<f64>, rotation_vector: Vector3<f64>) -> Pose {
    Pose::from_parts(
        Translation3::from(translation),
        UnitQuaternion::from_scaled_axis(rotation_vector),
    )
}
